"""A certified upper bound of the two-sided Hausdorff distance between S and a ruled result R.

Let psi map the domain of S into the domain (s, t) of R (a continuous,
piecewise bilinear map on a grid aligned with the knot spans of S), sending
each boundary side of S's domain into the matching side of R's domain: the
boundary v0 to t = 0 through the pairing (s = a^-1), v1 to t = 1, and for an
open face the first and last u to s = 0 and s = 1.  Such a map is onto R's
domain (its boundary map has degree one), so for every point of S and every
point of R there is a (u, v) with both S(u, v) and R(psi(u, v)) and hence

    H(S, R) <= sup |f(u, v)|,   f = S - R o psi.

On each grid cell f has bounded second derivatives (S is polynomial or rational
inside a knot span; R has a continuous first derivative away from its kink
parameters, the knots of full multiplicity), and bilinear interpolation gives

    sup_cell |f| <= max_corners |f| + (h_u^2 sup|f_uu| + h_v^2 sup|f_vv|) / 8
                   (+ |jump of R_s| (|ds_u| + |ds_v|) / 4 per kink crossed),

with f_uu bounded by the per-span control-net bounds of S_uu and by
R_ss ds^2 + 2 R_st ds dt (psi is linear along each cell edge direction; R_tt
is zero), R's bounds again from control nets (quotient rule when rational).
The derivative jump at a kink is measured from one-sided derivatives.
Interior nodes use the closest point of R (Gauss–Newton over the rulings), or
stay near the pairing's own correspondence; both maps are tried and the
smaller bound kept.  Any choice keeps the bound valid, closer ones make it
tighter.  Rows next to the boundaries are graded and extra columns follow
the pairing where it crawls (fans of rulings), so the cells stay small there.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import kernels
from .nurbs import Curve, Surface, _deriv_net, find_spans
from .reparam import Boundaries, Pairing


@dataclass(frozen=True)
class Certificate:
    bound: float        # certified upper bound of H(S, R)
    node_max: float     # largest |S - R o psi| at the grid nodes (a sampled estimate)
    remainder: float    # largest per-cell remainder term
    nodes: tuple        # grid size (nu, nv)


def _knot_grid(S: Surface, direction: str, target: int, extra=None):
    """Grid nodes aligned with the knot spans (plus optional extra nodes) and each cell's span."""
    knots = S.knots_u if direction == "u" else S.knots_v
    p = S.degree_u if direction == "u" else S.degree_v
    a, b = (S.domain[0], S.domain[1]) if direction == "u" else (S.domain[2], S.domain[3])
    br = np.unique(np.concatenate([[a], S.interior_knots(direction), [b]]))
    k = max(2, int(np.ceil(target / (br.size - 1))))
    pts = np.concatenate([np.linspace(x0, x1, k, endpoint=False) for x0, x1 in zip(br[:-1], br[1:])] + [[b]])
    if extra is not None:
        pts = np.unique(np.concatenate([pts, extra[(extra > a) & (extra < b)]]))
        keep = np.concatenate([[True], np.diff(pts) > 1e-12 * (b - a)])
        keep[-1] = True
        pts = pts[keep]
        pts = pts[np.concatenate([np.diff(pts) > 0, [True]])]
    n = S.poles.shape[0] if direction == "u" else S.poles.shape[1]
    mids = 0.5 * (pts[:-1] + pts[1:])
    span = find_spans(knots, p, n, mids) - p
    return pts, span


def _local_net_max(C: Curve, order: int) -> np.ndarray:
    """Per knot span (index i - p) bound of |C^(order)| from the local derivative control points."""
    D, k = C.poles, C.knots
    p = C.degree
    for r in range(order):
        D, k = _deriv_net(D, k, p - r, axis=0)
    n = C.poles.shape[0]
    if order > p:
        return np.zeros(n - p)
    nrm = np.linalg.norm(D, axis=1)
    win = np.lib.stride_tricks.sliding_window_view(nrm, p - order + 1)
    return win.max(axis=1)  # (n - p,)


class _SpanMax:
    """Max of per-span values over the spans that meet a parameter interval [lo, hi]."""

    def __init__(self, knots: np.ndarray, p: int):
        self.knots, self.p = knots, p
        self.n = knots.shape[0] - p - 1

    def lookup(self, vals: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        a, b = self.knots[self.p], self.knots[self.n]
        out_of_range = (lo < a) | (hi > b)
        i0 = find_spans(self.knots, self.p, self.n, np.clip(lo, a, b)) - self.p
        i1 = find_spans(self.knots, self.p, self.n, np.clip(hi, a, b)) - self.p
        m = vals.shape[0]
        table = np.empty((m, m))
        for i in range(m):
            table[i, i:] = np.maximum.accumulate(vals[i:])
            table[i, :i] = 0.0
        res = table[i0, np.maximum(i1, i0)]
        return np.where(out_of_range, vals.max(), res)


def _segment_feet(A: Curve, B: Curve, X: np.ndarray, s: np.ndarray, closed: bool, iters: int = 6):
    """Closest point of the ruled surface to X over the rulings, Gauss–Newton in s from s0."""
    if kernels.enabled() and A.knots.shape == B.knots.shape and np.array_equal(A.knots, B.knots):
        so = np.empty(s.shape[0])
        to = np.empty(s.shape[0])
        kernels.segment_feet(A._hom, B._hom, A.knots, A._tab, A.degree, np.ascontiguousarray(X),
                             np.ascontiguousarray(s), bool(closed), int(iters), so, to)
        return so, to
    best_s = s.copy()
    best_t = np.zeros_like(s)
    best_d = np.full(s.shape, np.inf)
    for it in range(iters + 1):
        sw = np.mod(s, 1.0) if closed else np.clip(s, 0.0, 1.0)
        a0, a1 = A.evaluate(sw, 1)
        b0, b1 = B.evaluate(sw, 1)
        d = b0 - a0
        dd = np.einsum("ij,ij->i", d, d)
        t = np.clip(np.einsum("ij,ij->i", X - a0, d) / np.where(dd > 0, dd, 1.0), 0.0, 1.0)
        F = a0 + t[:, None] * d
        r = X - F
        dist = np.linalg.norm(r, axis=1)
        better = dist < best_d
        best_d = np.where(better, dist, best_d)
        best_s = np.where(better, sw, best_s)
        best_t = np.where(better, t, best_t)
        Fs = (1 - t)[:, None] * a1 + t[:, None] * b1
        den = np.einsum("ij,ij->i", Fs, Fs)
        s = sw + np.einsum("ij,ij->i", r, Fs) / np.where(den > 0, den, 1.0)
    return best_s, best_t


def certify(S: Surface, pairing: Pairing, bd: Boundaries, R: Surface,
            target_u: int = 240, target_v: int = 80) -> Certificate:
    """Certified bound of H(S, R) for a fit oriented along v (see the module doc); the pairing's
    normalized parameters run over S's u-domain."""
    closed = pairing.closed
    u0, u1, v0, v1 = S.domain
    L = u1 - u0
    # nodes where the pairing maps the ruling grid, where a or b crawls (fans of rulings): there
    # a small step in u spans many rulings, and the cells must stay small in s
    sg = np.linspace(0.0, 1.0, 4 * target_u + 1)
    ag, bg = pairing.ab(sg)
    slow_a = np.diff(ag) < 0.5 / (4 * target_u)
    slow_b = np.diff(bg) < 0.5 / (4 * target_u)
    keep_a = np.concatenate([slow_a, [False]]) | np.concatenate([[False], slow_a])
    keep_b = np.concatenate([slow_b, [False]]) | np.concatenate([[False], slow_b])
    xg = np.concatenate([ag[keep_a][::2], bg[keep_b][::2]])
    if closed:
        xg = np.mod(xg, 1.0)
    us, span_u = _knot_grid(S, "u", target_u, u0 + L * xg)
    # graded rows next to both boundaries, where a fan of rulings makes psi steep
    grade = (v1 - v0) / target_v * 0.5 ** np.arange(1, 11)
    vs, span_v = _knot_grid(S, "v", target_v, np.concatenate([v0 + grade, v1 - grade]))
    nu, nv = us.size, vs.size
    UU, VV = np.meshgrid(us, vs, indexing="ij")
    X = S(UU.ravel(), VV.ravel()).reshape(nu, nv, 3)
    x = (us - u0) / L
    tau = (vs - v0) / (v1 - v0)
    # initial s from the pairing: (1 - tau) a(s) + tau b(s) = x
    sd = np.linspace(0.0, 1.0, 4001)
    ad, bd_ = pairing.ab(sd)
    s_init = np.empty((nu, nv))
    for j in range(nv):
        f = (1 - tau[j]) * ad + tau[j] * bd_
        xx = x
        if closed:
            xx = f[0] + np.mod(x - f[0], 1.0)
        s_init[:, j] = np.interp(xx, f, sd)
    s_feet, t_feet = _segment_feet(bd.A, bd.B, X.reshape(-1, 3), s_init.ravel(), closed)
    jump = np.abs(s_feet - s_init.ravel())
    if closed:
        jump = np.minimum(jump, 1.0 - jump)
    b = S.derivative_bounds()
    best = None
    prev = None
    # Two maps, both valid: closest points (tight where the fit is good), and closest points kept
    # near the pairing's own correspondence (a foot that jumps, to the other sheet of a thin part
    # say, folds psi and inflates the remainder).  The smaller bound is kept.
    for k, limit in enumerate((np.inf, 0.5 / target_u)):
        s, t = s_feet.copy(), t_feet.copy()
        far = jump > limit
        if k > 0 and np.array_equal(far, prev):
            continue  # the same map again
        prev = far
        if far.any():
            s0, t0 = _segment_feet(bd.A, bd.B, X.reshape(-1, 3)[far], s_init.ravel()[far], closed, iters=0)
            s[far], t[far] = s0, t0
        s = s.reshape(nu, nv)
        t = t.reshape(nu, nv)
        cert = _map_bound(S, b, X, us, vs, span_u, span_v, x, s, t, pairing, bd, R)
        if best is None or cert.bound < best.bound:
            best = cert
    return best


def _map_bound(S, b, X, us, vs, span_u, span_v, x, s, t, pairing, bd, R) -> Certificate:
    """The bound of the module doc for one map psi = (s, t) on the grid (us, vs)."""
    closed = pairing.closed
    nu, nv = us.size, vs.size
    # boundary rows and columns fixed so that psi maps sides to sides
    xa = x if not closed else pairing.ab(np.array([0.0]))[0][0] + np.mod(x - pairing.ab(np.array([0.0]))[0][0], 1.0)
    xb = x if not closed else pairing.ab(np.array([0.0]))[1][0] + np.mod(x - pairing.ab(np.array([0.0]))[1][0], 1.0)
    s[:, 0], t[:, 0] = pairing.inverse(xa, "a"), 0.0
    s[:, -1], t[:, -1] = pairing.inverse(xb, "b"), 1.0
    if not closed:
        for col, sv in ((0, 0.0), (-1, 1.0)):
            a0 = bd.A(np.array([sv]))[0]
            b0 = bd.B(np.array([sv]))[0]
            d = b0 - a0
            dd = max(float(d @ d), 1e-300)
            s[col, 1:-1] = sv
            t[col, 1:-1] = np.clip((X[col, 1:-1] - a0) @ d / dd, 0.0, 1.0)
    sw = np.mod(s, 1.0) if closed else s
    Rp = R(sw.ravel(), t.ravel()).reshape(nu, nv, 3)
    f = np.linalg.norm(X - Rp, axis=2)
    # per-cell remainder
    Suu = b["Suu"][span_u[:, None], span_v[None, :]]
    Svv = b["Svv"][span_u[:, None], span_v[None, :]]
    hu = np.diff(us)[:, None]
    hv = np.diff(vs)[None, :]

    def rel(q):
        if not closed:
            return q
        return q - np.round(q)

    s00, s10, s01, s11 = s[:-1, :-1], s[1:, :-1], s[:-1, 1:], s[1:, 1:]
    dsu = np.maximum(np.abs(rel(s10 - s00)), np.abs(rel(s11 - s01)))
    dsv = np.maximum(np.abs(rel(s01 - s00)), np.abs(rel(s11 - s10)))
    t00, t10, t01, t11 = t[:-1, :-1], t[1:, :-1], t[:-1, 1:], t[1:, 1:]
    dtu = np.maximum(np.abs(t10 - t00), np.abs(t11 - t01))
    dtv = np.maximum(np.abs(t01 - t00), np.abs(t11 - t10))
    cs = np.stack([s00, s10, s01, s11])
    if closed:
        cs = s00[None] + rel(cs - s00[None])
    slo, shi = cs.min(axis=0), cs.max(axis=0)
    ct = np.stack([t00, t10, t01, t11])
    tlo, thi = ct.min(axis=0), ct.max(axis=0)
    spans = _SpanMax(bd.A.knots, bd.A.degree)
    if R.rational:  # quotient-rule bounds of the rational ruled surface, per span in s
        rb = R.derivative_bounds()
        Rss = spans.lookup(rb["Suu"][:, 0], slo, shi)
        Rst = spans.lookup(rb["Suv"][:, 0], slo, shi)
    else:
        diff = Curve(bd.B.poles - bd.A.poles, bd.A.knots, bd.A.degree)
        A2 = spans.lookup(_local_net_max(bd.A, 2), slo, shi)
        B2 = spans.lookup(_local_net_max(bd.B, 2), slo, shi)
        Rst = spans.lookup(_local_net_max(diff, 1), slo, shi)
        Rss = (1.0 - tlo) * A2 + thi * B2
    rem = (Suu * hu ** 2 + Rss * dsu ** 2 + 2 * Rst * dsu * dtu
           + Svv * hv ** 2 + Rss * dsv ** 2 + 2 * Rst * dsv * dtv) / 8.0
    if bd.kinks.size:
        lo, hi = slo, shi
        for sk in bd.kinks:
            h = 1e-9
            ja = np.linalg.norm(np.diff(bd.A.evaluate(np.array([sk - h, sk + h]), 1)[1], axis=0))
            jb = np.linalg.norm(np.diff(bd.B.evaluate(np.array([sk - h, sk + h]), 1)[1], axis=0))
            J = float(max(ja, jb))
            hit = np.zeros(lo.shape, bool)
            for shift in ((-1.0, 0.0, 1.0) if closed else (0.0,)):
                hit |= (lo <= sk + shift) & (hi >= sk + shift)
            rem = rem + np.where(hit, J * (dsu + dsv) / 4.0, 0.0)
    fc = np.maximum(np.maximum(f[:-1, :-1], f[1:, :-1]), np.maximum(f[:-1, 1:], f[1:, 1:]))
    cell = fc + rem
    return Certificate(float(cell.max()), float(f.max()), float(rem.max()), (nu, nv))
