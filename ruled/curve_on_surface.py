"""Curves on surfaces (Yang et al. 2008): low-degree curves that lie exactly on a B-spline surface,
within a distance tolerance of the exact image of a domain curve and G1 within an angle tolerance.

The domain curve D(t) (a polynomial or rational B-spline in (u, v), or a polyline) is cut into
Bézier pieces at its knots, where it crosses a knot line of S, and where it crosses its own chord
(§3), so every piece lies in one Bézier patch of S and on one side of its chord.  A piece whose
chord distance (§4, eqs. 13–17, from the real roots of the candidate polynomials) is too large for
the tolerance is split at its farthest point (§4); then, at every joint whose mapped tangents (the
chain rule of eqs. 18–22) differ by more than the angle tolerance, the piece with the larger
deviation is split at its farthest point (§5; Theorem 1 keeps the distance bound).  Each final
chord is composed with its Bézier patch (ruled.compose): a Bézier curve of degree p + q on S exactly.

The 2D tolerance.  The paper's d = eps / (max|S_u| + max|S_v|) over the whole patch (eq. 12) is
kept as ``bound="span"``.  The default ``bound="local"`` is the same argument made tighter: a
piece, its chord and the segments between them lie in the bounding box of the piece's control
points, so the derivative bounds are taken over that box only (the patch restricted to it by
blossoming), and |S(P) - S(Q)| <= |P - Q| sqrt(Mu^2 + Mv^2) (Cauchy–Schwarz) replaces Mu + Mv.
The reported bound is the largest (chord distance x gradient bound) over the final pieces:
certified, and at most the tolerance.

Pieces are homogeneous Bézier control points (w u, w v, w); every piece of one domain curve has
the curve's degree, so the work is done on stacks of pieces at once.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from math import comb
from typing import Callable, Optional

import numpy as np

from . import kernels, kernels_cos
from .compose import SpanPatches, compose_stack
from .distance import to_polyline
from .errors import BadInputError, TooBigError, positive
from .knots import span_bezier
from .nurbs import Curve, Surface, find_spans

Progress = Optional[Callable[[str, float], None]]


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


# ---------------------------------------------------------------------------------------------
# Bézier and power-basis helpers (stacks: axis 0 runs over pieces)
# ---------------------------------------------------------------------------------------------

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


_B2P: dict = {}


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
    if kernels.enabled():
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
    seg, axis, val = [], [], []
    for ax, ks in ((0, np.unique(S.interior_knots("u"))), (1, np.unique(S.interior_knots("v")))):
        sg, kk = np.nonzero((ks[None, :] > cmin[:, ax:ax + 1]) & (ks[None, :] < cmax[:, ax:ax + 1]))
        seg.append(sg)
        axis.append(np.full(sg.size, ax))
        val.append(ks[kk])
    seg, axis, val = np.concatenate(seg), np.concatenate(axis), np.concatenate(val)
    cuts = {}
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


def polyline_curve(points) -> Curve:
    """A polyline of (u, v) points as a degree-1 domain curve, parameter t = i at point i (repeated
    points are dropped)."""
    P = np.asarray(points, float)
    if P.ndim != 2 or P.shape[1] != 2 or P.shape[0] < 2:
        raise BadInputError("a domain polyline needs at least two (u, v) points")
    if not np.all(np.isfinite(P)):
        raise BadInputError("the domain polyline has non-finite coordinates")
    keep = np.concatenate([[True], np.linalg.norm(np.diff(P, axis=0), axis=1) > 0])
    P = P[keep]
    if P.shape[0] < 2:
        raise BadInputError("the domain curve has zero length (all its points coincide); give distinct points")
    n = P.shape[0]
    return Curve(P, np.concatenate([[0.0], np.arange(n, dtype=float), [n - 1.0]]), 1)


def check_inside(region, D: Curve, n: int = 2001) -> None:
    """Refuse a domain curve that leaves a trimmed face (ruled.region.Region) as bounded by its edges
    (n samples); outside the surface's rectangle, approximate's own test names the bound it crosses."""
    if region.is_rectangle():
        return
    t = np.linspace(*D.domain, n)
    uv = D(t)[:, :2]
    u0, u1, v0, v1 = region.surface.domain
    inbox = (uv[:, 0] >= u0) & (uv[:, 0] <= u1) & (uv[:, 1] >= v0) & (uv[:, 1] <= v1)
    ok = region.contains(uv) | ~inbox
    if not ok.all():
        k = int(np.argmin(ok))
        raise BadInputError(f"the domain curve leaves the face: at t = {t[k]:.6g} it reaches (u, v) = "
                            f"({uv[k, 0]:.6g}, {uv[k, 1]:.6g}), outside the face's edges (the face is trimmed); "
                            f"keep the curve inside the face's boundary")


def parse_uv(text: str) -> Curve:
    """A polyline from "u0,v0;u1,v1;..." (the command line's --uv)."""
    try:
        pts = [[float(x) for x in item.split(",")] for item in text.replace(" ", "").strip(";").split(";")]
    except ValueError:
        raise BadInputError(f"cannot read --uv {text!r}; write points as \"u0,v0;u1,v1;...\"") from None
    if any(len(p) != 2 for p in pts):
        raise BadInputError(f"cannot read --uv {text!r}: every point needs two numbers, as \"u0,v0;u1,v1;...\"")
    return polyline_curve(pts)


def domain_curve_from_json(d) -> Curve:
    """A domain curve from {"degree": p, "knots": [full knot vector], "points": [[u, v], ...],
    "weights": [optional]} (the command line's --uv-curve)."""
    if not isinstance(d, dict) or not {"degree", "knots", "points"} <= set(d):
        raise BadInputError('the curve file needs "degree", "knots" (the full knot vector) and "points" '
                            '([[u, v], ...]); "weights" is optional')
    try:
        P = np.asarray(d["points"], float)
        K = np.asarray(d["knots"], float)
        W = None if d.get("weights") is None else np.asarray(d["weights"], float)
        p = int(d["degree"])
    except (TypeError, ValueError):
        raise BadInputError("the curve file's degree, knots, points or weights are not numbers") from None
    if P.ndim != 2 or P.shape[1] != 2:
        raise BadInputError('the curve file\'s "points" must be a list of [u, v] pairs')
    if p < 1:
        raise BadInputError(f"the curve's degree must be at least 1, got {p}")
    if W is not None and W.shape != (P.shape[0],):
        raise BadInputError(f"the curve needs one weight per point ({P.shape[0]}), got {W.size}")
    if not (np.all(np.isfinite(P)) and np.all(np.isfinite(K)) and (W is None or np.all(np.isfinite(W)))):
        raise BadInputError("the curve file holds non-finite numbers")
    if W is not None and np.any(W <= 0):
        raise BadInputError("the curve's weights must be positive")
    return Curve(P, K, p, W)


# ---------------------------------------------------------------------------------------------
# §4: chord distance
# ---------------------------------------------------------------------------------------------

def _farthest(H: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """H(C, chord) for a stack of single-sided (rational) planar Bézier pieces (N, d + 1, 3) (§4):
    the largest distance to the chord over the candidate points: the ends, tangent parallel to
    the chord (eq. 15), the crossings of the end perpendiculars, tangent perpendicular to the line
    to an end (eqs. 16–17), all real roots of polynomials.  Returns (distances, parameters)."""
    N, n1, _ = H.shape
    n = n1 - 1
    if n == 1:
        return np.zeros(N), np.full(N, 0.5)
    poly = bool(np.all(H[:, :, 2] == H[:, :1, 2]))
    if kernels.enabled():
        h, t = np.empty(N), np.empty(N)
        kernels_cos.farthest(np.ascontiguousarray(H), _b2p(n), poly, h, t)
        return h, t
    M = _b2p(n)
    A = np.zeros((N, n1, 3))                         # power coefficients, summed in order (as the twin)
    for j in range(n1):
        A += M[None, :, j, None] * H[:, None, j, :]
    Au, Av, w = A[:, :, 0], A[:, :, 1], A[:, :, 2]
    P0 = H[:, 0, :2] / H[:, 0, 2:]
    Pn = H[:, -1, :2] / H[:, -1, 2:]
    d = Pn - P0
    du, dv = d[:, :1], d[:, 1:]
    if poly:                                         # polynomial: w constant, C' = A' / w
        w0 = H[:, :1, 2]
        Cu, Cv, one = Au / w0, Av / w0, np.ones((1, 1))
        Nu, Nv = _der(Cu), _der(Cv)
    else:
        dw = _der(w)
        Nu = _add(_mul(_der(Au), w), -_mul(Au, dw))
        Nv = _add(_mul(_der(Av), w), -_mul(Av, dw))
        Cu, Cv, one = Au, Av, w
    cand = [np.zeros((N, 1)), np.ones((N, 1)), np.full((N, 1), 0.5), _roots01(_add(-Nu * dv, Nv * du))]  # eq. 15
    # the end regions (beyond the perpendiculars at the chord's ends) only matter for pieces whose
    # control points (hence the piece) reach beyond them
    L2 = (d * d).sum(axis=1)
    sc = (H[:, :, 0] / H[:, :, 2] - P0[:, :1]) * du + (H[:, :, 1] / H[:, :, 2] - P0[:, 1:]) * dv
    out = np.nonzero(~((sc >= 0).all(axis=1) & (sc <= L2[:, None]).all(axis=1)))[0]
    if out.size:
        perp, crit = [], []
        for E in (P0[out], Pn[out]):
            o1 = one if one.shape[0] == 1 else one[out]
            eu, ev = _add(Cu[out], -E[:, :1] * o1), _add(Cv[out], -E[:, 1:] * o1)
            perp.append(_add(eu * du[out], ev * dv[out]))                                # end perpendicular
            crit.append(_add(_mul(Nu[out], eu), _mul(Nv[out], ev)))                        # eqs. 16-17
        extra = np.full((N, 2 * (perp[0].shape[1] - 1) + 2 * (crit[0].shape[1] - 1)), np.nan)
        rp = _roots01(np.concatenate(perp))
        rc = _roots01(np.concatenate(crit))
        m = out.size
        extra[out] = np.concatenate([rp[:m], rp[m:], rc[:m], rc[m:]], axis=1)
        cand.append(extra)
    t = np.concatenate(cand, axis=1)
    tt = np.nan_to_num(t, nan=0.0)
    W = _polyval(w, tt)
    X = np.stack([_polyval(Au, tt) / W, _polyval(Av, tt) / W], axis=2)          # (N, m, 2)
    s = np.clip(((X[:, :, 0] - P0[:, :1]) * du + (X[:, :, 1] - P0[:, 1:]) * dv) / np.where(L2 > 0, L2, 1.0)[:, None],
                0.0, 1.0)
    s[L2 == 0] = 0.0
    dist = np.linalg.norm(X - (P0[:, None] + s[:, :, None] * d[:, None]), axis=2)
    dist[np.isnan(t)] = -1.0
    k = np.argmax(dist, axis=1)
    r = np.arange(N)
    return dist[r, k], tt[r, k]


def chord_distance(ctrl: np.ndarray, weights=None) -> tuple[float, float]:
    """H(C, chord) of a single-sided planar Bézier curve with Euclidean control points ctrl (and
    optional weights) and its chord (§4).  Returns (distance, parameter of the farthest point)."""
    h, t = _farthest(_hom(np.asarray(ctrl, float), weights)[None])
    return float(h[0]), float(t[0])


# ---------------------------------------------------------------------------------------------
# eq. 12 and its local form: gradient bounds; eqs. 21-22: the patch's derivatives
# ---------------------------------------------------------------------------------------------

def span_tolerance(S: Surface, eps: float, u: float, v: float, bounds: dict | None = None) -> float:
    """Eq. 12: the domain tolerance d of the knot span containing (u, v) so that a domain polyline
    within d of the domain curve maps within eps of its exact image: d = eps / (max|S_u| + max|S_v|)
    over the span (rigorous control-net bounds, rational surfaces included)."""
    b = bounds if bounds is not None else S.derivative_bounds()
    iu = int(find_spans(S.knots_u, S.degree_u, S.poles.shape[0], np.array([u]))[0]) - S.degree_u
    iv = int(find_spans(S.knots_v, S.degree_v, S.poles.shape[1], np.array([v]))[0]) - S.degree_v
    return float(eps / (b["Su"][iu, iv] + b["Sv"][iu, iv]))


# ---------------------------------------------------------------------------------------------
# the algorithm
# ---------------------------------------------------------------------------------------------

@dataclass
class CurveOnSurface:
    """A curve lying exactly on S that approximates the image of a domain curve."""

    curve: Curve               # 3D B-spline, degree p + q, knots of multiplicity p + q at the joints
    pcurve: Curve              # the domain polyline, degree 1 on the same knots: curve(t) = S(pcurve(t))
    degree: int
    segments: int
    control_points: int
    error_bound: float         # certified bound of the Hausdorff distance to the exact image
    max_joint_angle_deg: float  # largest tangent discrepancy at the joints (corners of the image excluded)
    corners: list              # [(t, angle_deg)] where the exact image itself turns by >= the angle tolerance
    closed: bool
    tol: float
    angle_deg: float
    bound_rule: str
    distance_segments: int     # segments after the distance phase (§4), before the angle phase (§5)
    notes: list = field(default_factory=list)


class _Stack:
    """Pieces as arrays: homogeneous control points, parameter intervals, span, chord distance,
    farthest parameter and gradient bound."""

    def __init__(self, H, t0, t1, sid, h, tf, G):
        self.H, self.t0, self.t1, self.sid, self.h, self.tf, self.G = H, t0, t1, sid, h, tf, G

    def take(self, m) -> "_Stack":
        return _Stack(*(x[m] for x in (self.H, self.t0, self.t1, self.sid, self.h, self.tf, self.G)))

    @staticmethod
    def join(parts) -> "_Stack":
        return _Stack(*(np.concatenate([getattr(p, a) for p in parts])
                        for a in ("H", "t0", "t1", "sid", "h", "tf", "G")))

    @property
    def n(self) -> int:
        return self.H.shape[0]


def _angles(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    na, nb = np.linalg.norm(a, axis=1), np.linalg.norm(b, axis=1)
    c = np.einsum("nc,nc->n", a, b) / np.where(na * nb > 0, na * nb, 1.0)
    out = np.degrees(np.arccos(np.clip(c, -1.0, 1.0)))
    out[(na == 0) | (nb == 0)] = np.nan
    return out


def _end_legs(P: np.ndarray, start: bool) -> np.ndarray:
    """Tangent directions (N, 2) of Bézier curves (N, d + 1, 2) at their start (or end): the first
    leg of non-zero length."""
    seq = P if start else P[:, ::-1]
    out = np.zeros((P.shape[0], 2))
    found = np.zeros(P.shape[0], bool)
    scale = np.abs(P).max(axis=(1, 2)) + 1e-300
    for k in range(1, P.shape[1]):
        leg = seq[:, k] - seq[:, 0]
        ok = ~found & (np.linalg.norm(leg, axis=1) > 1e-14 * scale)
        out[ok] = leg[ok]
        found |= ok
    return out if start else -out


def approximate(S: Surface, D: Curve, tol: float, angle_deg: float = 10.0, *, bound: str = "local",
                progress: Progress = None, max_segments: int = 200_000) -> CurveOnSurface:
    """Approximate the image S(D(t)) of the domain curve D by a curve of degree p + q lying on S
    exactly, within tol of it (Hausdorff, certified) and with joint tangents within angle_deg."""
    positive("--tol", tol)
    if not (np.isfinite(angle_deg) and 0 < angle_deg < 180):
        raise BadInputError(f"the angle tolerance must be between 0 and 180 degrees, got {angle_deg}")
    if bound not in ("local", "span"):
        raise BadInputError(f"unknown bound rule {bound!r}; use 'local' or 'span'")
    diag = S.diagonal()
    if tol < 1e-11 * diag:
        raise BadInputError(f"the tolerance {tol:.3g} is below round-off for this surface (diagonal "
                            f"{diag:.3g}); give at least {1e-11 * diag:.3g}")
    ext = float(np.ptp(D.poles, axis=0).max())
    if ext <= 1e-12 * max(1.0, float(np.abs(D.poles).max())):
        raise BadInputError("the domain curve has zero length (all its points coincide); give distinct points")
    spans = SpanPatches(S)
    sb = S.derivative_bounds() if bound == "span" else None

    def analyse(H, t0, t1, sid=None) -> _Stack:
        P = H[:, :, :2] / H[:, :, 2:]
        if sid is None:
            mid = _split_stack(H, np.full(H.shape[0], 0.5))[1][:, 0]
            sid = spans.of(mid[:, :2] / mid[:, 2:])
        h, tf = _farthest(H)
        if bound == "span":
            _, _, _, slo, _ = spans.arrays()
            iu = find_spans(S.knots_u, S.degree_u, S.poles.shape[0], slo[sid, 0]) - S.degree_u
            iv = find_spans(S.knots_v, S.degree_v, S.poles.shape[1], slo[sid, 1]) - S.degree_v
            G = sb["Su"][iu, iv] + sb["Sv"][iu, iv]
        else:
            G = spans.local_bounds(sid, P.min(axis=1), P.max(axis=1))
        return _Stack(H, t0, t1, sid, h, tf, G)

    def split(st: _Stack) -> _Stack:
        """Split at the farthest points, then into single-sided parts (which stay in their span)."""
        t = np.where(st.h > 0, st.tf, 0.5)
        L, R = _split_stack(st.H, t)
        tm = st.t0 + (st.t1 - st.t0) * t
        H, t0, t1, sid = _single_sided_stack(np.concatenate([L, R]), np.concatenate([st.t0, tm]),
                                             np.concatenate([tm, st.t1]), np.concatenate([st.sid, st.sid]))
        return analyse(H, t0, t1, sid)

    t_lo, t_hi = D.domain
    init = domain_pieces(D, S)
    active = analyse(np.array([p.hom for p in init]), np.array([p.t0 for p in init]),
                     np.array([p.t1 for p in init]))
    # §4: split at the farthest point until every piece's certified bound meets the tolerance
    done = []
    covered = 0.0
    while active.n:
        ok = active.h * active.G <= tol
        done.append(active.take(ok))
        covered += float((active.t1[ok] - active.t0[ok]).sum())
        if progress is not None:
            progress("distance", covered / (t_hi - t_lo))
        if ok.all():
            break
        if sum(x.n for x in done) + 2 * int((~ok).sum()) > max_segments:
            raise TooBigError(f"more than {max_segments} segments would be needed for the tolerance {tol:.3g}; "
                              f"raise the tolerance")
        active = split(active.take(~ok))
    pieces = _Stack.join(done)
    pieces = pieces.take(np.argsort(pieces.t0, kind="stable"))
    n_dist = pieces.n
    D01 = D(np.array([t_lo, t_hi]))
    closed = bool(np.linalg.norm(D01[1] - D01[0]) <= 1e-10 * max(1.0, ext))

    def joints(st: _Stack):
        """Joint pairs (i, j), chord-image angles and exact-image angles (eqs. 20–22)."""
        k = st.n
        i = np.arange(k - 1)
        if closed and k > 1:
            i = np.append(i, k - 1)
        j = (i + 1) % k
        P = st.H[:, :, :2] / st.H[:, :, 2:]
        J = spans.jacobian(np.concatenate([st.sid[i], st.sid[j]]), np.concatenate([P[i, -1], P[j, 0]]))
        Ja, Jb = J[:i.size], J[i.size:]
        chord = _angles(np.einsum("nc,ncx->nx", P[i, -1] - P[i, 0], Ja),
                        np.einsum("nc,ncx->nx", P[j, -1] - P[j, 0], Jb))
        exact = _angles(np.einsum("nc,ncx->nx", _end_legs(P[i], False), Ja),
                        np.einsum("nc,ncx->nx", _end_legs(P[j], True), Jb))
        return i, j, chord, exact

    # §5: split the piece with the larger deviation at every joint over the angle tolerance; joints
    # where the exact image itself turns by the tolerance or more are corners and stay
    rounds = 0
    i, j, chord, exact = joints(pieces)
    while True:
        corner = np.isnan(chord) | np.isnan(exact) | (exact >= angle_deg * (1 - 1e-9))
        bad = ~corner & (chord > angle_deg)
        pick = np.where(pieces.h[i] >= pieces.h[j], i, j)[bad]
        stuck = pieces.h[pick] <= 1e-15 * ext
        pick = np.unique(pick[~stuck])
        if pick.size == 0:
            break
        rounds += 1
        if pieces.n + pick.size > max_segments:
            raise TooBigError(f"more than {max_segments} segments would be needed for the angle tolerance "
                              f"{angle_deg:g} degrees; raise it")
        keep = np.ones(pieces.n, bool)
        keep[pick] = False
        pieces = _Stack.join([pieces.take(keep), split(pieces.take(pick))])
        pieces = pieces.take(np.argsort(pieces.t0, kind="stable"))
        if progress is not None:
            progress("angle", min(1.0, rounds / 20))
        i, j, chord, exact = joints(pieces)
    corner = np.isnan(chord) | np.isnan(exact) | (exact >= angle_deg * (1 - 1e-9))
    made = chord[~corner]
    corners = [(float(pieces.t0[jj]) if jj else float(pieces.t1[ii]), float(e))
               for ii, jj, e in zip(i[corner], j[corner], exact[corner])]
    notes = []
    if corners:
        notes.append(f"{len(corners)} joint(s) where the exact image itself has a corner of at least the angle "
                     f"tolerance (a polyline vertex, a kink of the domain curve or of the surface) are kept")
    curve, pcurve = _assemble(S, spans, pieces, closed)
    return CurveOnSurface(
        curve=curve, pcurve=pcurve, degree=S.degree_u + S.degree_v, segments=pieces.n,
        control_points=int(curve.poles.shape[0]), error_bound=float((pieces.h * pieces.G).max()),
        max_joint_angle_deg=float(made.max()) if made.size else 0.0, corners=corners, closed=closed,
        tol=float(tol), angle_deg=float(angle_deg), bound_rule=bound, distance_segments=n_dist, notes=notes)


def _assemble(S: Surface, spans: SpanPatches, st: _Stack, closed: bool) -> tuple[Curve, Curve]:
    """Compose every chord with its patch and join the Bézier segments into one B-spline (C0 knots of
    multiplicity p + q at the joints, parameters those of the domain curve); the pcurve is the polyline."""
    p, q = S.degree_u, S.degree_v
    deg = p + q
    nets, _, _, slo, shi = spans.arrays()
    P = st.H[:, :, :2] / st.H[:, :, 2:]
    segs = compose_stack(nets[st.sid], slo[st.sid], shi[st.sid], P[:, 0], P[:, -1])
    Hc = np.concatenate([segs[0]] + list(segs[1:, 1:]), axis=0)
    Hc[deg:-1:deg] = 0.5 * (segs[:-1, -1] + segs[1:, 0])   # the joints: both sides agree to round-off
    verts = np.concatenate([P[:, 0], P[-1:, -1]])
    if closed:
        Hc[-1] = Hc[0]
        verts[-1] = verts[0]
    ts = np.concatenate([st.t0, st.t1[-1:]])
    knots = np.concatenate([[ts[0]] * (deg + 1), np.repeat(ts[1:-1], deg), [ts[-1]] * (deg + 1)])
    w = Hc[:, 3]
    curve = Curve(Hc[:, :3] / w[:, None], knots, deg, None if S.weights is None else w)
    pcurve = Curve(verts, np.concatenate([[ts[0]], ts, [ts[-1]]]), 1)
    return curve, pcurve


def sampled_error(S: Surface, D: Curve, res: CurveOnSurface, per_segment: int = 64) -> dict:
    """The engine's own measure of a result (no OCCT): the Hausdorff distance between the result
    and the exact image S(D(t)) by dense sampling of both (distance to the other's dense polyline),
    and the largest |curve(t) - S(pcurve(t))|."""
    knots = np.unique(res.curve.knots)
    per_segment = max(per_segment, -(-4000 // (knots.size - 1)))
    s = np.linspace(0.0, 1.0, per_segment + 1)[:-1]
    t = np.concatenate([a + s * (b - a) for a, b in zip(knots[:-1], knots[1:])] + [knots[-1:]])
    C = res.curve(t)
    uv = res.pcurve(t)
    on = float(np.linalg.norm(C - S(uv[:, 0], uv[:, 1]), axis=1).max())
    lo, hi = D.domain
    kd = D.knots[(D.knots > lo) & (D.knots < hi)]
    duv = D(np.unique(np.concatenate([np.linspace(lo, hi, max(4 * t.size, 2001)), kd])))   # corners included
    E = S(duv[:, 0], duv[:, 1])
    return {"hausdorff": max(to_polyline(C, E), to_polyline(E, C)), "on_surface": on}


__all__ = ["Piece", "CurveOnSurface", "approximate", "domain_pieces", "polyline_curve", "parse_uv",
           "domain_curve_from_json", "chord_distance",
           "span_tolerance", "sampled_error", "bezier_eval", "bezier_split", "single_sided"]
