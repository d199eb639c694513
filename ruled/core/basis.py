"""B-spline basis functions (the NumPy path: spans, basis values and derivatives, the per-span power-basis
tables the kernels evaluate), knot refinement of a pole net, span-wise range maxima, and periodic knots."""

from __future__ import annotations

import numpy as np


def _as_f64(a) -> np.ndarray:
    return np.ascontiguousarray(np.asarray(a, dtype=np.float64))


def find_spans(knots: np.ndarray, degree: int, n_poles: int, x: np.ndarray) -> np.ndarray:
    """Knot span index ``i`` with ``knots[i] <= x < knots[i+1]``, clipped to ``[p, n-1]``.

    Parameters: knots (m,), x (N,).  Returns int array (N,).
    """
    i = np.searchsorted(knots, x, side="right") - 1
    return np.clip(i, degree, n_poles - 1)


def basis_derivatives(knots: np.ndarray, degree: int, spans: np.ndarray, x: np.ndarray, nder: int) -> np.ndarray:
    """Values and derivatives of the ``degree+1`` non-zero B-spline basis functions.

    Returns an array (nder+1, N, degree+1): entry [k, n, r] is the k-th
    derivative of N_{span-p+r, p} at x[n] (Piegl & Tiller A2.3, vectorized).
    """
    p = degree
    x = np.asarray(x, dtype=np.float64)
    N = x.shape[0]
    ndu = np.zeros((p + 1, p + 1, N))
    ndu[0, 0] = 1.0
    left = np.zeros((p + 1, N))
    right = np.zeros((p + 1, N))
    for j in range(1, p + 1):
        left[j] = x - knots[spans + 1 - j]
        right[j] = knots[spans + j] - x
        saved = np.zeros(N)
        for r in range(j):
            ndu[j, r] = right[r + 1] + left[j - r]
            den = ndu[j, r]
            safe = np.where(den == 0.0, 1.0, den)
            temp = np.where(den == 0.0, 0.0, ndu[r, j - 1] / safe)
            ndu[r, j] = saved + right[r + 1] * temp
            saved = left[j - r] * temp
        ndu[j, j] = saved
    ders = np.zeros((nder + 1, N, p + 1))
    for j in range(p + 1):
        ders[0, :, j] = ndu[j, p]
    if nder == 0:
        return ders
    a = np.zeros((2, p + 1, N))
    for r in range(p + 1):
        s1, s2 = 0, 1
        a[:] = 0.0
        a[0, 0] = 1.0
        for k in range(1, nder + 1):
            d = np.zeros(N)
            rk = r - k
            pk = p - k
            if r >= k:
                den = ndu[pk + 1, rk]
                a[s2, 0] = np.where(den == 0.0, 0.0, a[s1, 0] / np.where(den == 0.0, 1.0, den))
                d = a[s2, 0] * ndu[rk, pk]
            j1 = 1 if rk >= -1 else -rk
            j2 = k - 1 if r - 1 <= pk else p - r
            for j in range(j1, j2 + 1):
                den = ndu[pk + 1, rk + j]
                a[s2, j] = np.where(den == 0.0, 0.0, (a[s1, j] - a[s1, j - 1]) / np.where(den == 0.0, 1.0, den))
                d = d + a[s2, j] * ndu[rk + j, pk]
            if r <= pk:
                den = ndu[pk + 1, r]
                a[s2, k] = np.where(den == 0.0, 0.0, -a[s1, k - 1] / np.where(den == 0.0, 1.0, den))
                d = d + a[s2, k] * ndu[r, pk]
            ders[k, :, r] = d
            s1, s2 = s2, s1
    fac = float(p)
    for k in range(1, nder + 1):
        ders[k] *= fac
        fac *= p - k
    return ders


def taylor_table(knots: np.ndarray, degree: int) -> np.ndarray:
    """Per-span power-basis coefficients of the basis functions and their first two derivatives.

    Returns tab (3, n, p+1, p+1): tab[k, i, r, j] is the coefficient of (x - knots[i])^j in the
    k-th derivative of N_{i-p+r} on span i (spans p..n-1; other rows are zero).  Used by the
    numba kernels (Horner evaluation, no divisions).
    """
    p = degree
    n = knots.shape[0] - p - 1
    tab = np.zeros((3, n, p + 1, p + 1))
    spans = np.arange(p, n)
    spans = spans[knots[spans + 1] > knots[spans]]
    if spans.size == 0:
        return tab
    D = basis_derivatives(knots, p, spans, knots[spans], p)  # (p+1, S, p+1)
    fact = np.cumprod(np.concatenate([[1.0], np.arange(1, p + 1, dtype=float)]))
    c = np.transpose(D, (1, 2, 0)) / fact[None, None, :]  # (S, r, j): Taylor coefficients
    for k in range(3):
        for j in range(p + 1 - k):
            tab[k, spans, :, j] = c[:, :, j + k] * fact[j + k] / fact[j]
    return tab


def refine_axis(H: np.ndarray, knots: np.ndarray, p: int, pieces: int, axis: int = 0, extra=None) -> tuple:
    """Coefficients H (homogeneous) and knots with every non-empty knot span of the domain split into
    ``pieces`` equal spans, and knots inserted at ``extra`` too: the same spline in the finer space, whose
    basis spans the old one, so the old basis functions are exact combinations T of the new (solved on
    collocation points inside the domain, several per new span)."""
    a, b = knots[p], knots[-p - 1]
    kv = np.unique(knots)
    kv = kv[(kv >= a) & (kv <= b)]
    pieces = max(pieces, 1)
    new = (kv[:-1, None] + np.diff(kv)[:, None] * (np.arange(1, pieces) / pieces)[None, :]).ravel()
    if extra is not None and len(extra):
        # apart from every knot (a span far shorter than its neighbours makes the collocation ill-posed)
        gap = 1e-9 * (b - a)
        extra = np.unique(np.asarray(extra, float))
        extra = extra[(extra > a + gap) & (extra < b - gap)]
        have = np.unique(np.concatenate([kv, new]))
        at = np.clip(np.searchsorted(have, extra), 1, have.size - 1)
        extra = extra[np.minimum(extra - have[at - 1], have[at] - extra) > gap]
        new = np.concatenate([new, extra])
    if new.size == 0:
        return H, knots
    k2 = np.sort(np.concatenate([knots, new]))
    br = np.unique(k2[(k2 >= a) & (k2 <= b)])
    x = (br[:-1, None] + np.diff(br)[:, None] * ((np.arange(p + 2) + 0.5) / (p + 2))[None, :]).ravel()
    T = np.linalg.lstsq(bspline_basis_matrix(k2, p, x), bspline_basis_matrix(knots, p, x), rcond=None)[0]
    return np.moveaxis(np.tensordot(T, np.moveaxis(H, axis, 0), axes=1), 0, axis), k2


def pieces_for(knots: np.ndarray, p: int, spans: int) -> int:
    """How many pieces each knot span of the domain is split into for about ``spans`` spans in all."""
    a, b = knots[p], knots[-p - 1]
    kv = np.unique(knots)
    have = int(np.count_nonzero((kv > a) & (kv <= b)))
    return max(1, int(np.ceil(spans / max(have, 1))))


class SpanRangeMax:
    """Max of per-knot-span values (one per span, index i - p) over the spans that meet [lo, hi];
    the global max for intervals reaching outside the domain."""

    def __init__(self, knots: np.ndarray, p: int, vals: np.ndarray):
        self.knots, self.p = knots, p
        self.n = knots.shape[0] - p - 1
        # a sparse table: T[k, i] = max(vals[i : i + 2^k]) (padded); a range's max is that of two overlapping
        # power-of-two runs (exact: a max rounds nothing)
        m = vals.shape[0]
        T = [np.asarray(vals, float)]
        while (2 << (len(T) - 1)) <= m:
            h = 1 << (len(T) - 1)
            T.append(np.concatenate([np.maximum(T[-1][:-h], T[-1][h:]), T[-1][m - h:]]))
        self.T = np.stack(T)
        self.vmax = float(vals.max())

    def __call__(self, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        a, b = self.knots[self.p], self.knots[self.n]
        out = (lo < a) | (hi > b)
        i0 = find_spans(self.knots, self.p, self.n, np.clip(lo, a, b)) - self.p
        i1 = np.maximum(i0, find_spans(self.knots, self.p, self.n, np.clip(hi, a, b)) - self.p)
        k = np.floor(np.log2(i1 - i0 + 1)).astype(np.int64)         # (exact at powers of two)
        return np.where(out, self.vmax, np.maximum(self.T[k, i0], self.T[k, i1 - (1 << k) + 1]))


def _deriv_net(D: np.ndarray, knots: np.ndarray, p: int, axis: int):
    """Control net of the first derivative along ``axis`` of a B-spline of degree p."""
    if p == 0:
        shape = list(D.shape)
        shape[axis] -= 1
        return np.zeros(shape), knots[1:-1]
    n = D.shape[axis]
    den = knots[p + 1: p + n] - knots[1:n]
    fac = np.where(den > 0, p / np.where(den > 0, den, 1.0), 0.0)
    diff = np.diff(D, axis=axis)
    shape = [1] * D.ndim
    shape[axis] = n - 1
    return diff * fac.reshape(shape), knots[1:-1]


def bspline_basis_matrix(knots: np.ndarray, degree: int, x: np.ndarray, nder: int = 0) -> np.ndarray:
    """Dense collocation matrix (N, n_basis) of the nder-th derivative of the basis at x."""
    n = knots.shape[0] - degree - 1
    x = _as_f64(x)
    spans = find_spans(knots, degree, n, x)
    B = basis_derivatives(knots, degree, spans, x, nder)[nder]
    M = np.zeros((x.shape[0], n))
    rows = np.repeat(np.arange(x.shape[0]), degree + 1)
    cols = (spans[:, None] - degree + np.arange(degree + 1)[None, :]).ravel()
    np.add.at(M, (rows, cols), B.ravel())
    return M


def periodic_knots(breaks: np.ndarray, degree: int) -> np.ndarray:
    """Full unwrapped knot vector of a periodic spline with the given break points.

    breaks: (m+1,) strictly increasing, breaks[-1] - breaks[0] is the period,
    every interior break a simple knot.  Returns (m + 2p + 1,) knots; the spline
    has m unique poles, stored as m + p poles with the first p repeated.
    """
    T = breaks[-1] - breaks[0]
    m = breaks.shape[0] - 1
    core = breaks[:-1]
    before = core[m - degree:] - T if degree > 0 else np.zeros(0)
    after = breaks[1: degree + 1] + T
    # when degree > m the period must repeat several times; not needed here
    return np.concatenate([before, core, [breaks[-1]], after])


def wrap_periodic_poles(unique: np.ndarray, degree: int) -> np.ndarray:
    """Unique periodic poles (m, ...) -> unwrapped poles (m + p, ...)."""
    return np.concatenate([unique, unique[:degree]], axis=0)
