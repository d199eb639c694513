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

from dataclasses import dataclass, replace

import numpy as np

from . import kernels
from .nurbs import Curve, SpanRangeMax, Surface, _deriv_net, pieces_for
from .reparam import Boundaries, Pairing


# the second-order remainder is tried where the bound exceeds the node maximum by this factor
SECOND_ORDER_WHEN = 1.1
FEET_ITERS = 40
# the refinement rounds stop before a grid this many times the first one
GRID_GROWTH = 8
# derivative bounds come from twins of S and R with about this many knot spans per direction (the same
# surfaces, knots inserted): control-net bounds over smaller pieces are local, hence tighter
BOUND_SPANS = 24
# bounds below this fraction of the face's size are not refined further (no machine holds less)
FLOOR = 1e-6
# the second-order remainder's corner values are taken this fraction of the cell inside each corner
NUDGE = 1e-6


@dataclass(frozen=True)
class Certificate:
    bound: float        # certified upper bound of H(S, R)
    node_max: float     # largest |S - R o psi| at the grid nodes (a sampled estimate)
    remainder: float    # largest per-cell remainder term
    nodes: tuple        # grid size (nu, nv)
    map_deviation: float = 0.0   # included in bound: the fitted patch's deviation from the bounded face
    rounding: float = 0.0        # included in bound: double precision's round-off in the evaluations


# round-off of the evaluations the bound rests on (points of S and R, their differences), in units of
# the largest coordinate: a few dozen operations each, each within half an ulp (a face far from the
# origin and tiny carries its coordinates' round-off in every distance)
ROUND_ULPS = 64


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
    if Sb is not None:      # the spans of the bounding twin (the same surface, finer knots)
        S = Sb
    knots, p = (S.knots_u, S.degree_u) if direction == "u" else (S.knots_v, S.degree_v)
    n = S.poles.shape[0] if direction == "u" else S.poles.shape[1]
    lo = np.clip(np.searchsorted(knots, pts[:-1], side="right") - 1, p, n - 1)
    hi = np.clip(np.searchsorted(knots, pts[1:], side="left") - 1, p, n - 1)
    return pts, (lo - p, np.maximum(hi, lo) - p)


def crease_jumps(S: Surface, axis: int) -> tuple:
    """The parameters along axis (0: u, 1: v) where S is only C0 (knots of multiplicity >= degree
    inside the domain, and the seam of a periodic direction), and for each a rigorous bound of the jump
    of the derivative along axis across it, over the whole crease.

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
    periodic = S.periodic_u if axis == 0 else S.periodic_v
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


def _twin(S: Surface, ruled: bool = False) -> Surface:
    """S with finer knot spans for its derivative bounds (ruled: R, whose t direction is linear)."""
    pu = pieces_for(S.knots_u, S.degree_u, BOUND_SPANS)
    pv = 1 if ruled else pieces_for(S.knots_v, S.degree_v, BOUND_SPANS)
    return S.subdivided(pu, pv)


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
    if kernels.enabled() and A.knots.shape == B.knots.shape and np.array_equal(A.knots, B.knots):
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


def sampled_distance(S: Surface, pairing: Pairing, bd: Boundaries, R: Surface, nu: int = 121,
                     nv: int = 41) -> float:
    """The engine's own measure of H(S, R): closest points both ways from dense grids (a sampled
    estimate, not a bound; the independent measure is ruled.occ.measure)."""
    from .distance import project_points
    closed = pairing.closed
    u0, u1, v0, v1 = S.domain
    L = u1 - u0
    x = np.linspace(0.0, 1.0, nu, endpoint=not closed)
    tau = np.linspace(0.0, 1.0, nv)
    UU, VV = np.meshgrid(u0 + L * x, v0 + (v1 - v0) * tau, indexing="ij")
    X = S(UU.ravel(), VV.ravel())
    s0 = _pairing_s(pairing, x, tau).ravel()
    d1 = np.full(X.shape[0], np.inf)
    best = np.zeros((X.shape[0], 2))
    for shift in (0.0, -0.05, 0.05, -0.15, 0.15):  # several seeds: the closest ruling is not always the nearest one
        s, t = _segment_feet(bd.A, bd.B, X, s0 + shift if closed else np.clip(s0 + shift, 0.0, 1.0), closed, iters=8)
        d = np.linalg.norm(X - R(np.mod(s, 1.0) if closed else s, t), axis=1)
        better = d < d1
        d1 = np.where(better, d, d1)
        best[better] = np.stack([s, t], axis=1)[better]
    # polish on R as a surface (both parameters at once)
    _, dp = project_points(R, X, best, 6, closed)
    d1 = np.minimum(d1, dp)
    SS, TT = np.meshgrid(x, tau, indexing="ij")
    Y = R(SS.ravel(), TT.ravel())
    a, b = pairing.ab(SS.ravel())
    xs = (1 - TT.ravel()) * a + TT.ravel() * b
    seeds = np.stack([u0 + L * (np.mod(xs, 1.0) if closed else np.clip(xs, 0.0, 1.0)),
                      v0 + (v1 - v0) * TT.ravel()], axis=1)
    _, d2 = project_points(S, Y, seeds, 8, closed)
    # and from the nearest of S's own samples (the pairing's seed can lead the projection into a local
    # minimum, or against the domain's edge, far from the closest point)
    from scipy.spatial import cKDTree
    near = cKDTree(X).query(Y)[1]
    grid = np.stack([UU.ravel(), VV.ravel()], axis=1)
    _, d2b = project_points(S, Y, grid[near], 8, closed)
    d2 = np.minimum(d2, d2b)
    return float(max(d1.max(), d2.max()))


def certify(S: Surface, pairing: Pairing, bd: Boundaries, R: Surface,
            target_u: int = 240, target_v: int = 80, rounds: int = 3, rival: float = np.inf) -> Certificate:
    """Certified bound of H(S, R) for a fit oriented along v (see the module doc); the pairing's
    normalized parameters run over S's u-domain.  Cells whose remainder dominates their bound are
    split (up to ``rounds`` times), where psi is steep (fans of rulings, twisted or lifted results),
    unless the rounds left cannot bring the bound below ``rival`` (a bound already certified)."""
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
    extra_u = u0 + L * xg
    # graded rows next to both boundaries, where a fan of rulings makes psi steep
    grade = (v1 - v0) / target_v * 0.5 ** np.arange(1, 11)
    extra_v = np.concatenate([v0 + grade, v1 - grade])
    tw = (_twin(S), _twin(R, ruled=True))
    b = tw[0].derivative_bounds()
    best = None
    for rnd in range(rounds + 1):
        us, span_u = _knot_grid(S, "u", target_u, extra_u, tw[0])
        vs, span_v = _knot_grid(S, "v", target_v, extra_v, tw[0])
        cert, guide = _grid_bound(S, b, pairing, bd, R, us, vs, span_u, span_v, target_u, tw)
        if best is None or cert.bound < best.bound:
            best = cert
        split = _cells_to_split(*guide, FLOOR * S.diagonal(), uniform=True)
        # each round about halves the excess over the node maximum: stop where even that would not
        # bring the bound below the rival's (the other side's certificate)
        hope = cert.node_max + (cert.bound - cert.node_max) / 2 ** (rounds - rnd)
        if rnd == rounds or split is None or hope >= rival:
            break
        iu, iv = split
        grown = (us.size + np.unique(iu).size) * (vs.size + np.unique(iv).size)
        if grown > GRID_GROWTH * (target_u + 1) * (target_v + 1):
            break       # the next grid would cost more than the bound is worth (an exact fit asks for ever more)
        extra_u = np.concatenate([extra_u, 0.5 * (us[iu] + us[iu + 1])])
        extra_v = np.concatenate([extra_v, 0.5 * (vs[iv] + vs[iv + 1])])
    return best


def _corner_max(f: np.ndarray) -> np.ndarray:
    """Per grid cell, the largest of the node values at its four corners."""
    return np.maximum(np.maximum(f[:-1, :-1], f[1:, :-1]), np.maximum(f[:-1, 1:], f[1:, 1:]))


def _cells_to_split(cert: Certificate, cell: np.ndarray, rem: tuple, floor: float, uniform: bool = False):
    """Grid intervals to halve in the next round, (iu, iv): those of the cells near the worst and
    dominated by their remainder, in the directions whose part of the remainder (rem = (u part,
    v part)) matters; None when the bound is tight, or when most cells qualify (the grid is coarse
    everywhere: local refinement would not pay) unless ``uniform`` (then the whole grid is halved in
    the directions that dominate: an exact fit, whose bound is all remainder); None too when the
    bound is below ``floor`` (no CAD tolerance asks for less)."""
    ru, rv = rem
    tot = ru + rv
    cut = cert.node_max + 0.5 * (cert.bound - cert.node_max)
    bad = (cell > cut) & (tot > 0.25 * cell)
    if (not bad.any() or cert.bound <= max(1.02 * cert.node_max, floor)
            or (bad.mean() > 0.05 and not uniform)):
        return None
    iu = np.unique(np.nonzero(bad & (ru >= 0.25 * tot))[0])
    iv = np.unique(np.nonzero(bad & (rv >= 0.25 * tot))[1])
    return iu, iv


def _grid_bound(S, b, pairing, bd, R, us, vs, span_u, span_v, target_u, tw):
    """Best bound over the candidate maps psi on one grid, and the map that guides the refinement
    (certificate, per-cell bound, remainder parts): the one whose bound may fall lowest, a quarter of
    its remainder above its node maximum (a map whose nodes are far from R cannot get below them)."""
    closed = pairing.closed
    u0, u1, v0, v1 = S.domain
    L = u1 - u0
    nu, nv = us.size, vs.size
    UU, VV = np.meshgrid(us, vs, indexing="ij")
    X = S(UU.ravel(), VV.ravel()).reshape(nu, nv, 3)
    x = (us - u0) / L
    tau = (vs - v0) / (v1 - v0)
    s_init = _pairing_s(pairing, x, tau)
    s_feet, t_feet = _polished_feet(bd, R, X.reshape(-1, 3), s_init.ravel(), closed)
    jump = np.abs(s_feet - s_init.ravel())
    if closed:
        jump = np.minimum(jump, 1.0 - jump)
    maps = []
    # Two maps, both valid: closest points (tight where the fit is good), and closest points kept
    # near the pairing's own correspondence (a foot that jumps, to the other sheet of a thin part
    # say, folds psi and inflates the remainder).
    prev = None
    for k, limit in enumerate((np.inf, 0.5 / target_u)):
        s, t = s_feet.copy(), t_feet.copy()
        far = jump > limit
        if k > 0 and np.array_equal(far, prev):
            continue  # the same map again
        prev = far
        if far.any():
            s0, t0 = _segment_feet(bd.A, bd.B, X.reshape(-1, 3)[far], s_init.ravel()[far], closed, iters=0)
            s[far], t[far] = s0, t0
        maps.append((s, t))
    # Smoothed closest points: where the closest ruling jumps (a twisted or lifted result), a
    # smoothed field of s keeps psi continuous at the price of slightly larger node distances.
    ds = (s_feet - s_init.ravel()).reshape(nu, nv)
    if closed:
        ds = ds - np.round(ds)
    for sweeps in (4, 16, 64):
        s = (s_init + _smooth(ds, sweeps)).ravel()
        _, t = _segment_feet(bd.A, bd.B, X.reshape(-1, 3), s, closed, iters=0)
        maps.append((s, t))
    best, which, guide = None, 0, None

    def reach(c):
        return c.node_max + 0.25 * (c.bound - c.node_max)
    for k, (s, t) in enumerate(maps):
        out = _map_bound(S, b, X, us, vs, span_u, span_v, x, s.reshape(nu, nv).copy(), t.reshape(nu, nv).copy(),
                         pairing, bd, R, tw)
        if best is None or out[0].bound < best[0].bound:
            best, which = out, k
        if guide is None or reach(out[0]) < reach(guide[0]):
            guide = out
    if best[0].bound > SECOND_ORDER_WHEN * best[0].node_max:
        # the remainder dominates (an exact or nearly exact fit): the second-order remainder may be far
        # smaller (see _remainder2); the closest points (smooth where the fit is exact) and the best map
        # again, each cell keeping the smaller of the two
        for s, t in {0: maps[0], which: maps[which]}.values():
            out = _map_bound(S, b, X, us, vs, span_u, span_v, x, s.reshape(nu, nv).copy(),
                             t.reshape(nu, nv).copy(), pairing, bd, R, tw, second=True)
            if out[0].bound < best[0].bound:
                best = out
            if reach(out[0]) < reach(guide[0]):
                guide = out
    return best[0], guide


def _smooth(f: np.ndarray, sweeps: int) -> np.ndarray:
    """Repeated 5-point averaging (edges replicated)."""
    g = f.copy()
    for _ in range(sweeps):
        p = np.pad(g, 1, mode="edge")
        g = (4.0 * g + p[:-2, 1:-1] + p[2:, 1:-1] + p[1:-1, :-2] + p[1:-1, 2:]) / 8.0
    return g


def _map_bound(S, b, X, us, vs, span_u, span_v, x, s, t, pairing, bd, R, tw, second=False):
    """The bound of the module doc for one map psi = (s, t) on the grid (us, vs); with ``second``,
    each cell's remainder is the smaller of the first- and the second-order one (_remainder2)."""
    closed = pairing.closed
    nu, nv = us.size, vs.size
    # boundary rows and columns fixed so that psi maps sides to sides
    xa = x if not closed else pairing.ab(np.array([0.0]))[0][0] + np.mod(x - pairing.ab(np.array([0.0]))[0][0], 1.0)
    xb = x if not closed else pairing.ab(np.array([0.0]))[1][0] + np.mod(x - pairing.ab(np.array([0.0]))[1][0], 1.0)
    # the boundary rows go to the boundary curves of R at their closest points (seeded by the
    # pairing): any continuous side-to-side map keeps psi onto, and lifted boundaries (4D) are not
    # where the pairing puts them
    for col, xx, C, which in ((0, xa, bd.A, "a"), (-1, xb, bd.B, "b")):
        s0 = pairing.inverse(xx, which)
        sc, _ = _segment_feet(C, C, np.ascontiguousarray(X[:, col]), s0, closed)
        if closed:
            sc = s0 + (np.mod(sc - s0 + 0.5, 1.0) - 0.5)
        s[:, col], t[:, col] = sc, (0.0 if col == 0 else 1.0)
    if not closed:
        for col, sv in ((0, 0.0), (-1, 1.0)):
            a0 = bd.A(np.array([sv]))[0]
            b0 = bd.B(np.array([sv]))[0]
            d = b0 - a0
            dd = max(float(d @ d), 1e-300)
            s[col, 1:-1] = sv
            t[col, 1:-1] = np.clip((X[col, 1:-1] - a0) @ d / dd, 0.0, 1.0)
    s = _snap(s, bd.A, closed)
    sw = np.mod(s, 1.0) if closed else s
    Rp = R(sw.ravel(), t.ravel()).reshape(nu, nv, 3)
    f = np.linalg.norm(X - Rp, axis=2)
    # per-cell remainder
    Suu = _range_max(_range_max(b["Suu"], span_u, 0), span_v, 1)
    Svv = _range_max(_range_max(b["Svv"], span_u, 0), span_v, 1)
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
    Rb = tw[1]
    if R.rational:  # quotient-rule bounds of the rational ruled surface, per span in s
        rb = Rb.derivative_bounds()
        Rss = _spanmax(Rb, rb["Suu"][:, 0], slo, shi)
        Rst = _spanmax(Rb, rb["Suv"][:, 0], slo, shi)
    else:
        Ab, Bb = _rail(Rb, 0), _rail(Rb, 1)
        diff = Curve(Bb.poles - Ab.poles, Ab.knots, Ab.degree)
        A2 = _spanmax(Rb, _local_net_max(Ab, 2), slo, shi)
        B2 = _spanmax(Rb, _local_net_max(Bb, 2), slo, shi)
        Rst = _spanmax(Rb, _local_net_max(diff, 1), slo, shi)
        Rss = (1.0 - tlo) * A2 + thi * B2
    ru = (Suu * hu ** 2 + Rss * dsu ** 2 + 2 * Rst * dsu * dtu) / 8.0
    rv = (Svv * hv ** 2 + Rss * dsv ** 2 + 2 * Rst * dsv * dtv) / 8.0
    for sk in bd.kinks:
        hit = _crossing(slo, shi, sk, closed)
        if hit.any():
            J = _joint_jumps(R, sk)[0]
            ru = ru + np.where(hit, J * dsu / 4.0, 0.0)
            rv = rv + np.where(hit, J * dsv / 4.0, 0.0)
    if second:
        r2u, r2v = _remainder2(S, us, vs, span_u, span_v, s, t, slo, shi, closed, R, bd, tw)
        use = r2u + r2v < ru + rv
        ru, rv = np.where(use, r2u, ru), np.where(use, r2v, rv)
    rem = ru + rv
    cell = _corner_max(f) + rem
    return Certificate(float(cell.max()), float(f.max()), float(rem.max()), (nu, nv)), cell, (ru, rv)


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


def _remainder2(S, us, vs, span_u, span_v, s, t, slo, shi, closed, R, bd, tw) -> tuple:
    """Per cell, the interpolation remainder (h_u^2 sup|f_uu| + h_v^2 sup|f_vv|) / 8 with sup|f_uu|
    bounded from its values at the cell's corners and third-derivative bounds:

        sup|f_uu| <= max_corners |f_uu| + (h_u sup|f_uuu| + h_v sup|f_uuv|) / 2   (+ jumps),

    f_uu = S_uu - (R_ss s_u^2 + 2 R_st s_u t_u) at a corner (just inside the cell: see NUDGE), with
    the cell's own (bilinear) slopes there; f_uuu and f_uuv by the chain rule (psi bilinear: s_uu = 0; R linear in
    t: R_tt = R_stt = 0) from the control-net bounds of S and R.  Where S o psi is exactly R o psi up
    to the bilinear map's own error, f_uu is that error's second derivative: the bound follows the
    fit down to round-off, where the first-order remainder stays at h^2 |S_uu| / 8.  f_uu jumps where
    R's second derivative does (knots of multiplicity p - 1): each crossing adds the jump (a straight
    path crosses such a line at most twice in a bilinear cell).  Cells where this does not hold (S
    less than C2 inside, R less than C1) get infinity."""
    nu, nv = us.size, vs.size
    hu = np.diff(us)[:, None]
    hv = np.diff(vs)[None, :]

    def rel(q):
        return q - np.round(q) if closed else q

    su_b, su_t = rel(s[1:, :-1] - s[:-1, :-1]) / hu, rel(s[1:, 1:] - s[:-1, 1:]) / hu
    tu_b, tu_t = (t[1:, :-1] - t[:-1, :-1]) / hu, (t[1:, 1:] - t[:-1, 1:]) / hu
    sv_l, sv_r = rel(s[:-1, 1:] - s[:-1, :-1]) / hv, rel(s[1:, 1:] - s[1:, :-1]) / hv
    tv_l, tv_r = (t[:-1, 1:] - t[:-1, :-1]) / hv, (t[1:, 1:] - t[1:, :-1]) / hv
    s_uv = np.abs(su_t - su_b) / hv
    t_uv = np.abs(tu_t - tu_b) / hv
    # f_uu and f_vv at a point just inside each corner (NUDGE of the cell inward): on the cell's side
    # of any knot line through the corner (S's creases are grid lines, R's knots may pass through
    # nodes), where a node's own value would be the neighbour's
    s00, t00 = s[:-1, :-1], t[:-1, :-1]
    du_s, dv_s = rel(s[1:, :-1] - s00), rel(s[:-1, 1:] - s00)
    dd_s = rel(s[1:, 1:] - s00) - du_s - dv_s
    du_t, dv_t = t[1:, :-1] - t00, t[:-1, 1:] - t00
    dd_t = t[1:, 1:] - t00 - du_t - dv_t
    Fuu = Fvv = 0.0
    ncell = (nu - 1) * (nv - 1)
    P = [(lu, lv) for lu in (NUDGE, 1.0 - NUDGE) for lv in (NUDGE, 1.0 - NUDGE)]
    uq = np.concatenate([np.broadcast_to(us[:-1, None] + lu * hu, (nu - 1, nv - 1)).ravel() for lu, lv in P])
    vq = np.concatenate([np.broadcast_to(vs[None, :-1] + lv * hv, (nu - 1, nv - 1)).ravel() for lu, lv in P])
    sq = np.concatenate([(s00 + lu * du_s + lv * dv_s + lu * lv * dd_s).ravel() for lu, lv in P])
    tq = np.concatenate([(t00 + lu * du_t + lv * dv_t + lu * lv * dd_t).ravel() for lu, lv in P])
    Dq = S.evaluate(uq, vq, 2)
    Rq = R.evaluate(np.mod(sq, 1.0) if closed else np.clip(sq, 0.0, 1.0), np.clip(tq, 0.0, 1.0), 2)
    for k, (lu, lv) in enumerate(P):
        sl = slice(k * ncell, (k + 1) * ncell)
        a_s, a_t = ((du_s + lv * dd_s) / hu).ravel(), ((du_t + lv * dd_t) / hu).ravel()   # psi_u there
        c_s, c_t = ((dv_s + lu * dd_s) / hv).ravel(), ((dv_t + lu * dd_t) / hv).ravel()   # psi_v there
        Rss, Rst = Rq.Suu[sl], Rq.Suv[sl]
        guu = Dq.Suu[sl] - (Rss * (a_s * a_s)[:, None] + 2.0 * Rst * (a_s * a_t)[:, None])
        gvv = Dq.Svv[sl] - (Rss * (c_s * c_s)[:, None] + 2.0 * Rst * (c_s * c_t)[:, None])
        Fuu = np.maximum(Fuu, np.linalg.norm(guu, axis=1).reshape(nu - 1, nv - 1))
        Fvv = np.maximum(Fvv, np.linalg.norm(gvv, axis=1).reshape(nu - 1, nv - 1))
    a_u, b_u = np.maximum(np.abs(su_b), np.abs(su_t)), np.maximum(np.abs(tu_b), np.abs(tu_t))
    a_v, b_v = np.maximum(np.abs(sv_l), np.abs(sv_r)), np.maximum(np.abs(tv_l), np.abs(tv_r))
    # S's third derivatives over the cell's spans
    Sb, Rb = tw
    b3 = Sb.third_derivative_bounds()
    M3 = {k: _range_max(_range_max(b3[k], span_u, 0), span_v, 1) for k in ("Suuu", "Suuv", "Suvv", "Svvv")}
    # R's second and third derivatives over the cell's s-range
    rb, rb3 = Rb.derivative_bounds(), Rb.third_derivative_bounds()
    Mss = _spanmax(Rb, rb["Suu"][:, 0], slo, shi)
    Mst = _spanmax(Rb, rb["Suv"][:, 0], slo, shi)
    Msss = _spanmax(Rb, rb3["Suuu"][:, 0], slo, shi)
    Msst = _spanmax(Rb, rb3["Suuv"][:, 0], slo, shi)
    r_uuu = Msss * a_u ** 3 + 3 * Msst * a_u ** 2 * b_u
    r_vvv = Msss * a_v ** 3 + 3 * Msst * a_v ** 2 * b_v
    r_uuv = ((Msss * a_v + Msst * b_v) * a_u ** 2 + 2 * Mss * a_u * s_uv + 2 * Msst * a_v * a_u * b_u
             + 2 * Mst * (s_uv * b_u + a_u * t_uv))
    r_vvu = ((Msss * a_u + Msst * b_u) * a_v ** 2 + 2 * Mss * a_v * s_uv + 2 * Msst * a_u * a_v * b_v
             + 2 * Mst * (s_uv * b_v + a_v * t_uv))
    half = 0.5 + NUDGE      # the nudged corners are a little farther from the cell's points
    Guu = Fuu + half * hu * (M3["Suuu"] + r_uuu) + half * hv * (M3["Suuv"] + r_uuv)
    Gvv = Fvv + half * hv * (M3["Svvv"] + r_vvv) + half * hu * (M3["Suvv"] + r_vvu)
    bad = np.zeros(Guu.shape, bool)
    # S less than C2 inside a cell (creases, multiplicity >= p, are grid lines already)
    u0, u1, v0, v1 = S.domain
    ku, _ = _soft_knots(S.knots_u, S.degree_u, u0, u1)
    kv, _ = _soft_knots(S.knots_v, S.degree_v, v0, v1)
    bad |= _contains(ku, us[:-1], us[1:])[:, None] | _contains(kv, vs[:-1], vs[1:])[None, :]
    # R's knots where R_ss jumps, inside a cell's s-range
    kr, mr = _soft_knots(bd.A.knots, bd.A.degree, 0.0, 1.0)
    if closed:     # the seam of a periodic result is a knot too
        kr, mr = np.concatenate([[0.0], kr]), np.concatenate([[bd.A.degree], mr])
    for sk, m in zip(kr, mr):
        _, J2, kink = _joint_jumps(R, sk)
        hit = _crossing(slo, shi, sk, closed, strict=True)   # touching cells evaluated on their side
        if m >= bd.A.degree and kink:
            bad |= hit      # a kink of R: the first-order remainder's kink term handles it
            continue
        Guu = Guu + np.where(hit, 2.0 * J2 * a_u ** 2, 0.0)
        Gvv = Gvv + np.where(hit, 2.0 * J2 * a_v ** 2, 0.0)
    return np.where(bad, np.inf, hu ** 2 * Guu / 8.0), np.where(bad, np.inf, hv ** 2 * Gvv / 8.0)


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


def certify_reverse(S: Surface, pairing: Pairing, R: Surface, target_s: int = 240, target_t: int = 40,
                    rounds: int = 3) -> Certificate:
    """Certified bound of H(S, R) from the other side: phi maps R's domain (s, t) into S's
    (closest points on S, seeded by the pairing's correspondence), sides to sides, so

        H(S, R) <= sup |f|,  f = R - S o phi,

    and on each grid cell (aligned with R's knot spans, so R is smooth inside; phi bilinear)

        sup_cell |f| <= max_corners |f| + (h_s^2 |R_ss| + q(du_s, dv_s) + q(du_t, dv_t)) / 8,

    q(du, dv) = Muu du^2 + 2 Muv |du dv| + Mvv dv^2 with S's second-derivative bounds over the
    cell's u-range and du, dv the largest parameter change of phi along the cell's edges (R_tt = 0).
    The closest-point map onto the smooth input is continuous where R folds (fans, lifted ends),
    which is where the forward map of ``certify`` loses its tightness."""
    from .distance import project_points
    closed = pairing.closed
    u0, u1, v0, v1 = S.domain
    L, V = u1 - u0, v1 - v0
    Sb, Rb = _twin(S), _twin(R, ruled=True)
    bS = Sb.derivative_bounds()
    M = {k: SpanRangeMax(Sb.knots_u, Sb.degree_u, bS[k].max(axis=1)) for k in ("Suu", "Suv", "Svv")}
    Rss_span = Rb.derivative_bounds()["Suu"][:, 0]
    creases = (crease_jumps(S, 0), crease_jumps(S, 1))
    extra_s = np.zeros(0)
    tt = np.linspace(0.0, 1.0, target_t + 1)
    best = None
    for rnd in range(rounds + 1):
        ss, span_s = _knot_grid(R, "u", target_s, extra_s, Rb)
        ns, nt = ss.size, tt.size
        SS, TT = np.meshgrid(ss, tt, indexing="ij")
        Y = R(SS.ravel(), TT.ravel()).reshape(ns, nt, 3)
        a, b = pairing.ab(ss)
        xs = (1 - TT) * a[:, None] + TT * b[:, None]
        useed = u0 + L * (xs if closed else np.clip(xs, 0.0, 1.0))
        vseed = v0 + V * TT
        uv, _ = project_points(S, Y.reshape(-1, 3), np.stack([useed.ravel(), vseed.ravel()], axis=1), 8, closed)
        U = uv[:, 0].reshape(ns, nt)
        W = uv[:, 1].reshape(ns, nt)
        if closed:  # continuous (unwrapped) u
            U = useed + (np.mod(U - useed + 0.5 * L, L) - 0.5 * L)
        # sides to sides
        U[:, 0] = _curve_feet(S, Y[:, 0], useed[:, 0], v0, closed)
        U[:, -1] = _curve_feet(S, Y[:, -1], useed[:, -1], v1, closed)
        W[:, 0], W[:, -1] = v0, v1
        if closed:
            for col in (0, -1):
                U[:, col] = useed[:, col] + (np.mod(U[:, col] - useed[:, col] + 0.5 * L, L) - 0.5 * L)
        else:
            St = S.transposed()
            for row, uu in ((0, u0), (-1, u1)):
                W[row, 1:-1] = _curve_feet(St, Y[row, 1:-1], W[row, 1:-1], uu, False)
                U[row, :] = uu
            W[:, 0], W[:, -1] = v0, v1
        F = S((u0 + np.mod(U - u0, L) if closed else U).ravel(), W.ravel()).reshape(ns, nt, 3)
        f = np.linalg.norm(Y - F, axis=2)
        hs = np.diff(ss)[:, None]
        du_s = np.maximum(np.abs(np.diff(U, axis=0)[:, :-1]), np.abs(np.diff(U, axis=0)[:, 1:]))
        dv_s = np.maximum(np.abs(np.diff(W, axis=0)[:, :-1]), np.abs(np.diff(W, axis=0)[:, 1:]))
        du_t = np.maximum(np.abs(np.diff(U, axis=1)[:-1]), np.abs(np.diff(U, axis=1)[1:]))
        dv_t = np.maximum(np.abs(np.diff(W, axis=1)[:-1]), np.abs(np.diff(W, axis=1)[1:]))
        cu = np.stack([U[:-1, :-1], U[1:, :-1], U[:-1, 1:], U[1:, 1:]])
        lo, hi = cu.min(axis=0), cu.max(axis=0)
        if closed:
            sh = L * np.floor((lo - u0) / L)
            lo, hi = lo - sh, hi - sh
        Muu, Muv, Mvv = M["Suu"](lo, hi), M["Suv"](lo, hi), M["Svv"](lo, hi)
        rs = (hs ** 2 * _range_max(Rss_span, span_s)[:, None] + Muu * du_s ** 2 + 2 * Muv * du_s * dv_s
              + Mvv * dv_s ** 2) / 8.0
        rt = (Muu * du_t ** 2 + 2 * Muv * du_t * dv_t + Mvv * dv_t ** 2) / 8.0
        if creases[0][0].size or creases[1][0].size:
            # S o phi has a kink where phi crosses a crease of S: linear interpolation across a kink of
            # slope jump J along an edge of parameter change d errs by up to J d / 4 more
            cv = np.stack([W[:-1, :-1], W[1:, :-1], W[:-1, 1:], W[1:, 1:]])
            Ju = _crease_term(creases[0], lo, hi, L if closed else 0.0)
            Jv = _crease_term(creases[1], cv.min(axis=0), cv.max(axis=0))
            rs = rs + (Ju * du_s + Jv * dv_s) / 4.0
            rt = rt + (Ju * du_t + Jv * dv_t) / 4.0
        rem = rs + rt
        cell = _corner_max(f) + rem
        cert = Certificate(float(cell.max()), float(f.max()), float(rem.max()), (ns, nt))
        if best is None or cert.bound < best.bound:
            best = cert
        split = _cells_to_split(cert, cell, (rs, rt), FLOOR * S.diagonal())
        if rnd == rounds or split is None:
            break
        iu, iv = split
        extra_s = np.concatenate([extra_s, 0.5 * (ss[iu] + ss[iu + 1])])
        if np.unique(iv).size > 0 and nt < 8 * target_t:
            tt = np.unique(np.concatenate([tt, 0.5 * (tt[iv] + tt[iv + 1])]))
    return best


def certified_bound(S: Surface, pairing: Pairing, bd: Boundaries, R: Surface, target_u: int = 240,
                    target_v: int = 80, cutoff: float = np.inf) -> Certificate:
    """The smaller of the two certified bounds (both valid): from R's side (certify_reverse) and,
    unless that one is already within 2 % of its own node maximum or its node maximum (a sampled
    distance of the fit) is already at least ``cutoff`` (another candidate's bound: this one cannot
    win), from S's side (certify)."""
    rnd = ROUND_ULPS * np.finfo(float).eps * max(float(np.abs(S.poles).max()), float(np.abs(R.poles).max()))
    rev = certify_reverse(S, pairing, R, target_u, max(16, target_v // 2))
    if not (rev.bound <= 1.02 * rev.node_max or rev.node_max >= cutoff):
        fwd = certify(S, pairing, bd, R, target_u, target_v, rival=min(rev.bound, cutoff))
        rev = fwd if fwd.bound < rev.bound else rev
    return replace(rev, bound=rev.bound + rnd, rounding=rnd)
