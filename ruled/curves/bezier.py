"""Bezier pieces of a (u, v) curve in the surface's knot grid (Yang et al. §3): evaluation, subdivision,
polynomial algebra in the power basis, roots in [0, 1], and cutting each piece where it crosses a knot
line so that every piece lies inside one surface span (single-sided)."""

from __future__ import annotations

from dataclasses import dataclass
from math import comb

import numpy as np

from ruled.core import jit
from ruled.core.basis import find_spans
from ruled.core.errors import BadInputError
from ruled.core.knots import span_bezier
from ruled.core.nurbs import Curve, Surface
from ruled.curves import kernels as kernels_cos

_B2P: dict = {}


@dataclass(frozen=True)
class Piece:
    hom: np.ndarray    # (d + 1, 3) homogeneous Bézier control points (w u, w v, w)
    t0: float          # parameter interval on the domain curve
    t1: float

    @property
    def ctrl(self) -> np.ndarray:
        """Euclidean (u, v) control points."""
        return self.hom[:, :2] / self.hom[:, 2:]


def _hom(ctrl: np.ndarray, w=None) -> np.ndarray:
    w = np.ones(ctrl.shape[0]) if w is None else np.asarray(w, float)
    return np.concatenate([ctrl * w[:, None], w[:, None]], axis=1)


def bezier_eval(ctrl: np.ndarray, t) -> np.ndarray:
    """Points of the Bézier curve at t (de Casteljau), (N, dim)."""
    t = np.atleast_1d(np.asarray(t, float))
    c = np.broadcast_to(ctrl, (t.size,) + ctrl.shape).copy()
    for _ in range(ctrl.shape[0] - 1):
        c = (1 - t)[:, None, None] * c[:, :-1] + t[:, None, None] * c[:, 1:]
    return c[:, 0]


def _split_stack(H: np.ndarray, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """de Casteljau split of every curve of the stack H (N, d + 1, k) at its own t (N,)."""
    n = H.shape[1] - 1
    L = np.empty_like(H)
    R = np.empty_like(H)
    c = H
    L[:, 0], R[:, n] = H[:, 0], H[:, n]
    tt = t[:, None, None]
    for r in range(1, n + 1):
        c = (1 - tt) * c[:, :-1] + tt * c[:, 1:]
        L[:, r] = c[:, 0]
        R[:, n - r] = c[:, -1]
    return L, R


def bezier_split(ctrl: np.ndarray, t: float) -> tuple[np.ndarray, np.ndarray]:
    """The two halves of a Bézier curve at t (homogeneous points split rational ones)."""
    L, R = _split_stack(np.asarray(ctrl, float)[None], np.array([float(t)]))
    return L[0], R[0]


def _b2p(n: int) -> np.ndarray:
    """Matrix taking Bernstein coefficients of degree n to ascending power coefficients."""
    M = _B2P.get(n)
    if M is None:
        M = np.zeros((n + 1, n + 1))
        for k in range(n + 1):
            for i in range(k + 1):
                M[k, i] = comb(n, k) * comb(k, i) * (-1) ** (k - i)
        _B2P[n] = M
    return M


def _mul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Products of stacked power polynomials (N, ka) x (N, kb) -> (N, ka + kb - 1)."""
    out = np.zeros((a.shape[0], a.shape[1] + b.shape[1] - 1))
    for i in range(a.shape[1]):
        out[:, i:i + b.shape[1]] += a[:, i:i + 1] * b
    return out


def _der(a: np.ndarray) -> np.ndarray:
    return a[:, 1:] * np.arange(1, a.shape[1])


def _add(*terms: np.ndarray) -> np.ndarray:
    k = max(t.shape[1] for t in terms)
    out = np.zeros((terms[0].shape[0], k))
    for t in terms:
        out[:, :t.shape[1]] += t
    return out


def _polyval(a: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Stacked power polynomials a (N, k) at t (N, m) (Horner)."""
    out = np.zeros(t.shape)
    for j in range(a.shape[1] - 1, -1, -1):
        out = out * t + a[:, j:j + 1]
    return out


def _roots01(P: np.ndarray, imag_tol: float = 1e-7) -> np.ndarray:
    """Real roots in (0, 1) of stacked power polynomials P (N, k + 1): (N, k), NaN-padded, each
    polished by two Newton steps.  Rows that vanish identically have none."""
    P = np.atleast_2d(np.asarray(P, float))
    N, k1 = P.shape
    out = np.full((N, max(k1 - 1, 1)), np.nan)
    if k1 < 2:
        return out
    scale = np.abs(P).max(axis=1)
    if np.all(np.abs(P[:, -1]) > 1e-13 * scale):
        deg = np.full(N, k1 - 1)
    else:
        big = np.abs(P) > 1e-13 * scale[:, None]
        deg = np.where(big.any(axis=1), k1 - 1 - np.argmax(big[:, ::-1], axis=1), 0)
    for d in np.unique(deg):
        if d < 1:
            continue
        rows = np.nonzero(deg == d)[0]
        a = P[rows, :d + 1] / P[rows, d:d + 1]
        if d == 1:
            r = -a[:, :1]
        elif d == 2:                      # t^2 + a1 t + a0, the stable form of the quadratic formula
            a0, a1 = a[:, 0], a[:, 1]
            disc = a1 * a1 - 4 * a0
            ok = disc >= -(imag_tol * (1 + np.abs(a1))) ** 2
            sq = np.sqrt(np.maximum(disc, 0.0))
            qq = -0.5 * (a1 + np.where(a1 >= 0, sq, -sq))
            safe = np.where(qq != 0, qq, 1.0)
            r = np.stack([qq, np.where(qq != 0, a0 / safe, 0.0)], axis=1)
            r[~ok] = np.nan
        else:
            C = np.zeros((rows.size, d, d))
            C[:, np.arange(1, d), np.arange(d - 1)] = 1.0
            C[:, :, -1] = -a[:, :d]
            ev = np.linalg.eigvals(C.astype(complex))       # zgeev, as the numba twin
            r = np.where(np.abs(ev.imag) <= imag_tol * (1 + np.abs(ev.real)), ev.real, np.nan)
        da = _der(a)
        for _ in range(2):
            f, g = _polyval(a, r), _polyval(da, r)
            step = np.divide(f, g, out=np.zeros_like(f), where=(g != 0) & np.isfinite(g))
            r = r - np.where(np.abs(step) < 1e-3, step, 0.0)
        r[~((r > 1e-9) & (r < 1 - 1e-9))] = np.nan
        out[rows, :d] = r
    return out


def _bernstein_roots01(b) -> np.ndarray:
    """Sorted real roots in (0, 1) of one scalar Bernstein polynomial."""
    b = np.asarray(b, float)
    r = _roots01((_b2p(b.shape[0] - 1) @ b)[None])[0]
    return np.unique(r[np.isfinite(r)])


def _split_many(hom: np.ndarray, t0: float, t1: float, ts, snap=None) -> list[Piece]:
    """Split one piece at the increasing parameters ts in (0, 1); snap (per split: (axis, value) or
    None) puts the split point's coordinate on the value exactly (knot lines)."""
    out, rest, lo = [], hom, 0.0
    for k, t in enumerate(ts):
        left, rest = bezier_split(rest, (t - lo) / (1.0 - lo))
        if snap is not None and snap[k] is not None:
            ax, val = snap[k]
            left[-1, ax] = val * left[-1, 2]
            rest[0] = left[-1]
        out.append(left)
        lo = t
    out.append(rest)
    b = np.concatenate([[0.0], np.asarray(ts, float), [1.0]])
    return [Piece(c, t0 + (t1 - t0) * x, t0 + (t1 - t0) * y) for c, x, y in zip(out, b[:-1], b[1:])]


def _cross_poly(H: np.ndarray) -> np.ndarray:
    """Power coefficients (N, d + 1) of the numerator of (C(t) - P0) x (Pn - P0) for a stack."""
    P0 = H[:, 0, :2] / H[:, 0, 2:]
    d = H[:, -1, :2] / H[:, -1, 2:] - P0
    b = (H[:, :, 0] - H[:, :, 2] * P0[:, :1]) * d[:, 1:] - (H[:, :, 1] - H[:, :, 2] * P0[:, 1:]) * d[:, :1]
    M = _b2p(H.shape[1] - 1)
    a = np.zeros(b.shape)
    for j in range(b.shape[1]):                       # summed in order, as the numba twin
        a += M[None, :, j] * b[:, j, None]
    return a


def _first_cross(H: np.ndarray) -> np.ndarray:
    """The first parameter in (0, 1) where each piece of the stack crosses its chord, NaN if none."""
    if jit.enabled():
        out = np.empty(H.shape[0])
        kernels_cos.first_cross(np.ascontiguousarray(H), _b2p(H.shape[1] - 1), out)
        return out
    R = _roots01(_cross_poly(H))
    has = np.isfinite(R).any(axis=1)
    out = np.full(H.shape[0], np.nan)
    out[has] = np.nanmin(R[has], axis=1)
    return out


def _single_sided_stack(H: np.ndarray, t0: np.ndarray, t1: np.ndarray, tag=None):
    """Split every piece of the stack where it crosses its own chord (§3), recursively; tag (N,) is
    carried along to the parts."""
    tag = np.zeros(H.shape[0], int) if tag is None else tag
    outH, out0, out1, outg = [], [], [], []
    while H.shape[0]:
        t = _first_cross(H)
        has = np.isfinite(t)
        outH.append(H[~has])
        out0.append(t0[~has])
        out1.append(t1[~has])
        outg.append(tag[~has])
        if not has.any():
            break
        # split each crossing piece at its first crossing and look at both parts again
        idx = np.nonzero(has)[0]
        L, Rr = _split_stack(H[idx], t[idx])
        tm = t0[idx] + (t1[idx] - t0[idx]) * t[idx]
        H = np.concatenate([L, Rr])
        t0 = np.concatenate([t0[idx], tm])
        t1 = np.concatenate([tm, t1[idx]])
        tag = np.concatenate([tag[idx], tag[idx]])
    return np.concatenate(outH), np.concatenate(out0), np.concatenate(out1), np.concatenate(outg)


def single_sided(piece: Piece) -> list[Piece]:
    """Split a piece where it crosses its own chord (§3), so every part lies on one side of its chord."""
    H, t0, t1, _ = _single_sided_stack(piece.hom[None], np.array([piece.t0]), np.array([piece.t1]))
    order = np.argsort(t0)
    return [Piece(H[k], float(t0[k]), float(t1[k])) for k in order]


def _coord_ranges(H: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Exact min and max (N, 2) of the coordinates of a stack of (rational) Bézier pieces: over the
    ends and the real roots of the derivatives' numerators A' w - A w'."""
    N, n1, _ = H.shape
    M = _b2p(n1 - 1)
    w = H[:, :, 2] @ M.T
    A = np.concatenate([H[:, :, 0] @ M.T, H[:, :, 1] @ M.T])          # u rows, then v rows
    W = np.concatenate([w, w])
    t = np.tile([0.0, 1.0], (2 * N, 1))
    if n1 > 2:                                                          # both axes in one solve
        r = _roots01(_add(_mul(_der(A), W), -_mul(A, _der(W))))
        t = np.concatenate([t, np.where(np.isfinite(r), r, 0.0)], axis=1)
    x = _polyval(A, t) / _polyval(W, t)
    lo, hi = x.min(axis=1), x.max(axis=1)
    return np.stack([lo[:N], lo[N:]], axis=1), np.stack([hi[:N], hi[N:]], axis=1)


def domain_pieces(D: Curve, S: Surface) -> list[Piece]:
    """§3: the Bézier pieces of the (2D, possibly rational) domain curve D, split at its knots, where it
    crosses an interior knot line of S, and into single-sided pieces.  Refuses a curve that leaves
    the surface's parameter domain."""
    if D.poles.shape[1] != 2:
        raise BadInputError("the domain curve must have 2D (u, v) points")
    lo, hi = D.domain
    br = np.unique(D.knots[(D.knots > lo) & (D.knots < hi)])
    edges = np.concatenate([[lo], br, [hi]])
    spans = find_spans(D.knots, D.degree, D.poles.shape[0], 0.5 * (edges[:-1] + edges[1:]))
    H = np.array([span_bezier(D._hom, D.knots, D.degree, int(i)) for i in spans])     # (K, d + 1, 3)
    dom = np.array(S.domain).reshape(2, 2)                                           # [[u0, u1], [v0, v1]]
    tol = 1e-9 * max(dom[0, 1] - dom[0, 0], dom[1, 1] - dom[1, 0])
    P = H[:, :, :2] / H[:, :, 2:]
    cmin, cmax = P.min(axis=1), P.max(axis=1)          # the control points' box holds the piece
    if np.any((cmin < dom[:, 0] - tol) | (cmax > dom[:, 1] + tol)):
        cmin, cmax = _coord_ranges(H)                    # the exact ranges decide
    bad = (cmin < dom[:, 0] - tol) | (cmax > dom[:, 1] + tol)
    if bad.any():
        k, ax = (int(x[0]) for x in np.nonzero(bad))
        x = cmin[k, ax] if cmin[k, ax] < dom[ax, 0] - tol else cmax[k, ax]
        raise BadInputError(f"the domain curve leaves the surface's parameter domain: it reaches "
                            f"{'uv'[ax]} = {x:.6g} between t = {edges[k]:.6g} and {edges[k + 1]:.6g}; keep (u, v) "
                            f"inside u in [{dom[0, 0]:.6g}, {dom[0, 1]:.6g}], v in [{dom[1, 0]:.6g}, {dom[1, 1]:.6g}]")
    # crossings of the interior knot lines that each piece's coordinate range spans, all roots at once
    segs: list = []
    axes: list = []
    vals: list = []
    for ax, ks in ((0, np.unique(S.interior_knots("u"))), (1, np.unique(S.interior_knots("v")))):
        sg, kk = np.nonzero((ks[None, :] > cmin[:, ax:ax + 1]) & (ks[None, :] < cmax[:, ax:ax + 1]))
        segs.append(sg)
        axes.append(np.full(sg.size, ax))
        vals.append(ks[kk])
    seg, axis, val = np.concatenate(segs), np.concatenate(axes), np.concatenate(vals)
    cuts: dict = {}
    if seg.size:
        b = H[seg, :, axis] - val[:, None] * H[seg, :, 2]
        R = _roots01(b @ _b2p(H.shape[1] - 1).T)
        for r, k, ax, v in zip(R, seg.tolist(), axis.tolist(), val.tolist()):
            for t in r[np.isfinite(r)]:
                cuts.setdefault(k, []).append((float(t), ax, v))
    pieces = []
    for k in range(H.shape[0]):
        c = sorted(cuts.get(k, []))
        ts = [t for i, (t, _, _) in enumerate(c) if i == 0 or t - c[i - 1][0] > 1e-12]
        snap = [(ax, v) for i, (t, ax, v) in enumerate(c) if i == 0 or t - c[i - 1][0] > 1e-12]
        pieces.extend(_split_many(H[k], float(edges[k]), float(edges[k + 1]), ts, snap))
    Hs, t0, t1, _ = _single_sided_stack(np.array([p.hom for p in pieces]), np.array([p.t0 for p in pieces]),
                                        np.array([p.t1 for p in pieces]))
    order = np.argsort(t0, kind="stable")
    return [Piece(Hs[k], float(t0[k]), float(t1[k])) for k in order]
