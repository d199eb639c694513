"""The pieces a certificate is made of: knot-aligned sample grids, the creases of a surface and their
jumps, per-span maxima of derivative nets, the feet of points on the fit's rulings (segment_feet), and where
a cell's rulings cross a knot or a joint of the fit."""

from __future__ import annotations

import numpy as np

from ruled.core import jit, kernels
from ruled.core.basis import SpanRangeMax, _deriv_net, pieces_for
from ruled.core.nurbs import Curve, Surface
from ruled.fit.dp.pairing import Pairing
from ruled.fit.reparam import Boundaries

# Newton iterations for the feet of points on the fit's rulings
FEET_ITERS = 40

# derivative bounds come from twins of S and R with about this many knot spans per direction (the same
# surfaces, knots inserted): control-net bounds over smaller pieces are local, hence tighter
BOUND_SPANS = 24
# a rational surface whose weights differ by more than this factor among a span's poles is graded: its
# parameter speed varies by about as much, so grids and twins get nodes at equal steps of arc length too
WEIGHT_SPREAD = 100.0
# the speed profile of graded_nodes: samples along the direction, and iso-curves across it
GRADE_SAMPLES, GRADE_ACROSS = 4096, 9


def _knot_grid(S: Surface, direction: str, target: int, extra=None, Sb: Surface = None):
    """About ``target`` grid cells over the domain in one direction (plus optional extra nodes), with a
    node at every knot where S is not C1 (multiplicity >= degree: a crease, where the interpolation
    remainder needs a node); and each cell's range of knot spans (lo, hi), inclusive.  A cell may
    straddle knots where S is C1: its second derivatives are bounded there by the largest of its
    spans' bounds, which is all the remainder needs."""
    a, b = (S.domain[0], S.domain[1]) if direction == "u" else (S.domain[2], S.domain[3])
    br = np.unique(np.concatenate([[a], S.creases(0 if direction == "u" else 1), [b]]))
    # cells per piece in proportion to its length, at least one
    k = np.maximum(1, np.round(target * np.diff(br) / (b - a))).astype(int)
    pts = np.concatenate([np.linspace(x0, x1, kk, endpoint=False) for x0, x1, kk in zip(br[:-1], br[1:], k)]
                         + [[b]])
    if extra is not None:
        pts = np.unique(np.concatenate([pts, extra[(extra > a) & (extra < b)]]))
        keep = np.concatenate([[True], np.diff(pts) > 1e-12 * (b - a)])
        keep[-1] = True
        pts = pts[keep]
        pts = pts[np.concatenate([np.diff(pts) > 0, [True]])]
    # the spans of the bounding twin (the same surface, finer knots)
    return pts, knot_spans(S if Sb is None else Sb, direction, pts)


def knot_spans(S: Surface, direction: str, pts: np.ndarray) -> tuple:
    """Each cell's range (lo, hi) of S's knot spans along direction, inclusive, for the grid nodes pts."""
    knots, p = (S.knots_u, S.degree_u) if direction == "u" else (S.knots_v, S.degree_v)
    n = S.poles.shape[0] if direction == "u" else S.poles.shape[1]
    lo = np.clip(np.searchsorted(knots, pts[:-1], side="right") - 1, p, n - 1)
    hi = np.clip(np.searchsorted(knots, pts[1:], side="left") - 1, p, n - 1)
    return lo - p, np.maximum(hi, lo) - p


def crease_jumps(S: Surface, axis: int, closed: bool = False) -> tuple:
    """The parameters along axis (0: u, 1: v) where S is only C0 (knots of multiplicity >= degree
    inside the domain, and the seam of a periodic direction, or of a clamped one whose ends meet when
    ``closed``: its first row of poles is its last, and a fit that goes round takes it as a seam), and for
    each a rigorous bound of the jump of the derivative along axis across it, over the whole crease.

    The one-sided derivatives at a knot of full multiplicity in the derivative's net (degree q = p - 1)
    are the net's control rows on either side of it, so the jump of the homogeneous derivative is a
    B-spline across the crease whose control points are their differences (convex hull).  Rational:
    jump(S') = (jump(A') - S jump(w')) / w = sum_ij N_i N_j (dA_i w_j - A_j dw_i) / sum_ij N_i N_j w_i w_j
    along the crease (A_j, w_j: its row of homogeneous poles), hence at most the largest
    |dA_i / w_i - (P_j - c) dw_i / w_i| over overlapping i, j, with the poles centred on the row's c (the
    jump does not depend on where the surface lies)."""
    knots = S.knots_u if axis == 0 else S.knots_v
    p = S.degree_u if axis == 0 else S.degree_v
    q_along = S.degree_v if axis == 0 else S.degree_u
    a = S.domain[0] if axis == 0 else S.domain[2]
    periodic = (S.periodic_u if axis == 0 else S.periodic_v) or closed
    inner = S.creases(axis)
    if not (inner.size or periodic):
        return np.zeros(0), np.zeros(0)
    P = np.moveaxis(S.poles, axis, 0)                            # (rows across the crease, along it, 3)
    w = np.ones(P.shape[:2]) if S.weights is None else np.moveaxis(S.weights, axis, 0)
    H = np.concatenate([P * w[..., None], w[..., None]], axis=2)
    D, kd = _deriv_net(H, knots, p, 0)
    q = p - 1
    where, left, right, row = [], [], [], []
    for x in inner:
        m = int(np.count_nonzero(knots == x))
        r = int(np.searchsorted(kd, x, side="left"))
        where.append(x)
        left.append(r - 1)
        right.append(r + int(m) - q - 1)
        row.append(int(np.searchsorted(knots, x, side="left")) - 1)   # the row of poles the crease runs on
    if periodic:                                  # the seam: the end row against the first
        where.append(a)
        left.append(D.shape[0] - 1)
        right.append(0)
        row.append(0)
    J = []
    for lo_, hi_, r in zip(left, right, row):
        jump = D[hi_] - D[lo_]                                      # (along, 4), homogeneous, not centred
        wr, Pr = w[r], P[r]
        c = Pr.mean(axis=0)
        dA = jump[:, :3] - c * jump[:, 3:]                          # the same jump with the poles centred on c
        Y, Z = dA / wr[:, None], jump[:, 3] / wr
        n = Pr.shape[0]
        best = 0.0
        for k in range(-q_along, q_along + 1):                      # overlapping i, j = i + k
            i = np.arange(max(0, -k), min(n, n - k))
            best = max(best, float(np.linalg.norm(Y[i] - (Pr[i + k] - c) * Z[i][:, None], axis=1).max()))
        J.append(best)
    return np.array(where, float), np.array(J)


def _crease_term(creases: tuple, lo: np.ndarray, hi: np.ndarray, period: float = 0.0) -> np.ndarray:
    """Per cell, the sum of the derivative jumps of the creases inside the cell's parameter range [lo, hi]
    (with their copies a period on, where the parameter is unwrapped)."""
    where, J = creases
    out = np.zeros(lo.shape)
    for x, j in zip(where, J):
        for k in ((0.0, 1.0, -1.0) if period else (0.0,)):
            out += j * ((lo <= x + k * period) & (x + k * period <= hi))
    return out


def graded_nodes(S: Surface, direction: str, count: int) -> np.ndarray:
    """Parameters at ``count`` equal steps of arc length along ``direction`` (the longest of a few
    iso-curves across it, step by step) where S is rational with extreme weights (WEIGHT_SPREAD), else
    none.  There the parameter speed varies by orders of magnitude, and cells uniform in the parameter
    are far too long where the surface rushes (a second-derivative remainder in the thousands where
    the fit is 0.01 away); any grid is valid, so the graded nodes only tighten the bound.  Cached on S
    (every certificate of a face, and the twins of each, ask for the same)."""
    if S.weights is None:
        return np.zeros(0)
    cache = S.__dict__.setdefault("_graded_cache", {})
    if (direction, count) not in cache:
        cache[(direction, count)] = _graded(S, direction, count)
    return cache[(direction, count)]


def _graded(S: Surface, direction: str, count: int) -> np.ndarray:
    p = S.degree_u if direction == "u" else S.degree_v
    w = S.weights if direction == "u" else S.weights.T
    win = np.lib.stride_tricks.sliding_window_view(w, p + 1, axis=0)
    if float((win.max(axis=2) / np.maximum(win.min(axis=2), 1e-300)).max()) <= WEIGHT_SPREAD:
        return np.zeros(0)
    u0, u1, v0, v1 = S.domain
    a, b, c, d = (u0, u1, v0, v1) if direction == "u" else (v0, v1, u0, u1)
    x = np.linspace(a, b, GRADE_SAMPLES + 1)
    y = np.linspace(c, d, GRADE_ACROSS)
    X, Y = np.meshgrid(x, y, indexing="ij")
    P = (S(X.ravel(), Y.ravel()) if direction == "u" else S(Y.ravel(), X.ravel())).reshape(x.size, y.size, 3)
    step = np.linalg.norm(np.diff(P, axis=0), axis=2).max(axis=1)
    arc = np.concatenate([[0.0], np.cumsum(step)])
    if not arc[-1] > 0.0:
        return np.zeros(0)
    return np.interp(np.linspace(0.0, arc[-1], count + 1)[1:-1], arc, x)


def _twin(S: Surface, ruled: bool = False) -> Surface:
    """S with finer knot spans for its derivative bounds (ruled: R, whose t direction is linear); a
    rational surface with extreme weights gets knots at equal steps of arc length too (graded_nodes)."""
    pu = pieces_for(S.knots_u, S.degree_u, BOUND_SPANS)
    pv = 1 if ruled else pieces_for(S.knots_v, S.degree_v, BOUND_SPANS)
    return S.subdivided(pu, pv, graded_nodes(S, "u", BOUND_SPANS),
                        None if ruled else graded_nodes(S, "v", BOUND_SPANS))


def _rail(Rb: Surface, side: int) -> Curve:
    """Boundary curve t = side of a ruled surface (degree (p, 1)) as a curve of its knots."""
    return Curve(Rb.poles[:, side], Rb.knots_u, Rb.degree_u, None if Rb.weights is None else Rb.weights[:, side])


def _range_max(T: np.ndarray, spans, axis: int = 0) -> np.ndarray:
    """Per cell, the largest entry of T over the cell's span range (lo, hi) along axis."""
    lo, hi = spans
    out = np.take(T, lo, axis=axis)
    for k in range(1, int((hi - lo).max(initial=0)) + 1):
        out = np.maximum(out, np.take(T, np.minimum(lo + k, hi), axis=axis))
    return out


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


def _spanmax(Rb: Surface, vals: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Per cell, the largest per-span value of Rb (one per u-span) over the s-range [lo, hi]."""
    return SpanRangeMax(Rb.knots_u, Rb.degree_u, vals)(lo, hi)


def _segment_feet(A: Curve, B: Curve, X: np.ndarray, s: np.ndarray, closed: bool, iters: int = 6):
    """Closest point of the ruled surface to X over the rulings, Gauss–Newton in s from s0."""
    if jit.enabled() and A.knots.shape == B.knots.shape and np.array_equal(A.knots, B.knots):
        so = np.empty(s.shape[0])
        to = np.empty(s.shape[0])
        kernels.segment_feet(A._hom, B._hom, A.knots, A._tab, A.degree, np.ascontiguousarray(X),
                             np.ascontiguousarray(s), bool(closed), int(iters), so, to)
        return so, to
    best_s = s.copy()
    best_t = np.zeros_like(s)
    best_d = np.full(s.shape, np.inf)
    s = s.copy()
    # A and B share their knots (and weights) in a ruled result: one evaluation of both
    AB = None
    if np.array_equal(A.knots, B.knots) and A.degree == B.degree and (
            (A.weights is None and B.weights is None)
            or (A.weights is not None and B.weights is not None and np.array_equal(A.weights, B.weights))):
        AB = Curve(np.hstack([A.poles, B.poles]), A.knots, A.degree, A.weights, A.periodic)
    act = np.arange(s.shape[0])                    # the points still moving
    for it in range(iters + 1):
        sa = s[act]
        sw = np.mod(sa, 1.0) if closed else np.clip(sa, 0.0, 1.0)
        if AB is not None:
            e0, e1 = AB.evaluate(sw, 1)
            a0, b0, a1, b1 = e0[:, :3], e0[:, 3:], e1[:, :3], e1[:, 3:]
        else:
            a0, a1 = A.evaluate(sw, 1)
            b0, b1 = B.evaluate(sw, 1)
        d = b0 - a0
        dd = np.einsum("ij,ij->i", d, d)
        Xa = X[act]
        t = np.clip(np.einsum("ij,ij->i", Xa - a0, d) / np.where(dd > 0, dd, 1.0), 0.0, 1.0)
        F = a0 + t[:, None] * d
        r = Xa - F
        dist = np.linalg.norm(r, axis=1)
        better = dist < best_d[act]
        idx = act[better]
        best_d[idx] = dist[better]
        best_s[idx] = sw[better]
        best_t[idx] = t[better]
        Fs = (1 - t)[:, None] * a1 + t[:, None] * b1
        den = np.einsum("ij,ij->i", Fs, Fs)
        sn = sw + np.einsum("ij,ij->i", r, Fs) / np.where(den > 0, den, 1.0)
        s[act] = sn
        act = act[np.abs(sn - sw) > 1e-15]
        if act.size == 0:
            break
    return best_s, best_t


def _polished_feet(bd: Boundaries, R: Surface, X: np.ndarray, s0: np.ndarray, closed: bool):
    """_segment_feet, with more iterations for the points still moving after the usual ones (the
    iteration converges only linearly along twisted rulings; on an exact fit the node values, which
    should be round-off, are then all the bound has besides the remainder)."""
    def dist(Y, s, t):
        return np.linalg.norm(Y - R(np.mod(s, 1.0) if closed else s, t), axis=1)
    s, t = _segment_feet(bd.A, bd.B, X, s0, closed)
    d = dist(X, s, t)
    s2, t2 = _segment_feet(bd.A, bd.B, X, s, closed, iters=2)
    d2 = dist(X, s2, t2)
    better = d2 < d
    s, t, d0, d = np.where(better, s2, s), np.where(better, t2, t), d, np.minimum(d, d2)
    sel = np.nonzero((d < 0.9 * d0) & (d > 1e-12 * R.diagonal()))[0]     # still moving fast
    if sel.size:
        Xs = np.ascontiguousarray(X[sel])
        s3, t3 = _segment_feet(bd.A, bd.B, Xs, s[sel], closed, iters=FEET_ITERS)
        ok = dist(Xs, s3, t3) < d[sel]
        s[sel[ok]], t[sel[ok]] = s3[ok], t3[ok]
    return s, t


def _pairing_s(pairing: Pairing, x: np.ndarray, tau: np.ndarray) -> np.ndarray:
    """s of the pairing's own correspondence at normalized (x, tau): (1 - tau) a(s) + tau b(s) = x.
    Shape (x.size, tau.size)."""
    sd = np.linspace(0.0, 1.0, 4001)
    ad, bd_ = pairing.ab(sd)
    out = np.empty((x.size, tau.size))
    for j in range(tau.size):
        f = (1 - tau[j]) * ad + tau[j] * bd_
        xx = f[0] + np.mod(x - f[0], 1.0) if pairing.closed else x
        out[:, j] = np.interp(xx, f, sd)
    return out


_JOINT_H = 1e-9


def _joint_jumps(R: Surface, sk: float) -> tuple:
    """The jumps of R_s and R_ss across the knot s = sk (on both boundaries, t = 0 and 1), measured
    from one-sided evaluations 1e-9 away (the seam s = 0 of a periodic result from s = 1)."""
    h = _JOINT_H
    lo = sk - h if sk - h > 0.0 else 1.0 - h
    E = R.evaluate(np.array([lo, sk + h, lo, sk + h]), np.array([0.0, 0.0, 1.0, 1.0]), 2)
    J1 = max(np.linalg.norm(E.Su[1] - E.Su[0]), np.linalg.norm(E.Su[3] - E.Su[2]))
    J2 = max(np.linalg.norm(E.Suu[1] - E.Suu[0]), np.linalg.norm(E.Suu[3] - E.Suu[2]))
    # a true kink jumps by O(|R_s|); a smooth joint's difference over 2h is O(h |R_ss|)
    smooth = 1e-6 * float(np.linalg.norm(E.Su, axis=1).max()) + 4 * h * float(np.linalg.norm(E.Suu, axis=1).max())
    return float(J1), float(J2), J1 > smooth


SNAP = 1e-10


def _snap(s: np.ndarray, A: Curve, closed: bool) -> np.ndarray:
    """Node parameters within SNAP of a knot of R moved onto it (psi may be any continuous map: a node
    exactly on a knot line leaves the cells beside it on one side of it, see _crossing's strict)."""
    kv = np.unique(A.knots)
    if closed:
        kv = np.concatenate([kv - 1.0, kv, kv + 1.0])
    i = np.clip(np.searchsorted(kv, s), 1, kv.size - 1)
    near = np.where(s - kv[i - 1] < kv[i] - s, kv[i - 1], kv[i])
    return np.where(np.abs(s - near) < SNAP, near, s)


def _crossing(slo: np.ndarray, shi: np.ndarray, sk: float, closed: bool, strict: bool = False) -> np.ndarray:
    """The cells whose s-range [slo, shi] meets the knot sk (or a copy of it a period away); strict:
    whose open s-range contains it (the cell is not only on one side of it)."""
    hit = np.zeros(slo.shape, bool)
    for shift in ((-1.0, 0.0, 1.0) if closed else (0.0,)):
        if strict:
            hit |= (slo < sk + shift) & (shi > sk + shift)
        else:
            hit |= (slo <= sk + shift) & (shi >= sk + shift)
    return hit


def _soft_knots(C_knots: np.ndarray, p: int, lo: float, hi: float) -> tuple:
    """Interior knots of a degree-p spline where its second derivative may jump (multiplicity at
    least p - 1), with their multiplicities."""
    kv, mult = np.unique(C_knots, return_counts=True)
    sel = (kv > lo) & (kv < hi) & (mult >= max(p - 1, 1))
    return kv[sel], mult[sel]


def _contains(knots: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Whether some knot lies strictly inside each interval (a, b)."""
    return np.searchsorted(knots, b, side="left") > np.searchsorted(knots, a, side="right")


def _curve_feet(S: Surface, Y: np.ndarray, u: np.ndarray, v: float, closed: bool, iters: int = 8) -> np.ndarray:
    """Closest parameters u on the iso-curve S(., v) to the points Y (N, 3), Newton from u."""
    u0, u1 = S.domain[:2]
    best_u, best_d = u.copy(), np.full(u.shape, np.inf)
    for _ in range(iters + 1):
        uw = u0 + np.mod(u - u0, u1 - u0) if closed else np.clip(u, u0, u1)
        D = S.evaluate(uw, np.full(u.shape, v), 2)
        r = D.P - Y
        d = np.linalg.norm(r, axis=1)
        better = d < best_d
        best_d = np.where(better, d, best_d)
        best_u = np.where(better, u if closed else uw, best_u)
        den = np.einsum("ij,ij->i", D.Su, D.Su) + np.einsum("ij,ij->i", r, D.Suu)
        den = np.where(den > 1e-300, den, np.einsum("ij,ij->i", D.Su, D.Su) + 1e-300)
        u = (u if closed else uw) - np.einsum("ij,ij->i", r, D.Su) / den
    return best_u


def _nodes_of(prev: tuple, ss: np.ndarray, tt: np.ndarray, out: np.ndarray) -> np.ndarray:
    """The nodes of the grid (ss, tt) that the previous grid (prev = (ss, tt, values (ns, nt, k))) has
    too: their values copied into out, and the mask of them returned."""
    ps, pt, val = prev

    def where(old, x):
        i = np.minimum(np.searchsorted(old, x), old.size - 1)
        return i, old[i] == x
    i, hs = where(ps, ss)
    j, ht = where(pt, tt)
    known = hs[:, None] & ht[None, :]
    out[known] = val[i[:, None], j[None, :]][known]
    return known
