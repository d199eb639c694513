"""Cone splines by fat conic spline fitting (Yang & Yang 2006), the planar building blocks.

A ruled surface between two parallel planes projects onto a planar "fat curve" bounded by two
curves b0(v), b1(v).  A cone patch between the planes projects onto a fat conic arc: two rational
quadratic arcs with the same middle weight whose control triangles have parallel sides
(Theorem 2).  Here: the conic arcs, the interpolation of the two boundaries by piecewise parallel
polygons (§3.1), the common tangents by local convexity and reflection (eqs. 3–4), the control
triangles and the shared weight by the discrete form of eq. 5 (§3.2), the boundary error (eq. 6),
the check of Theorem 1 on a patch's generator lines, the skew error (eqs. 7–8), the sequential
fitting loop (§3.3) with the total of eq. 9, the cone patches as rational surfaces and the trim of
§5.  Still to come (issue 5): input from faces, the independent 3D measure, the shell, the CLI.

Boundary curves are callables v -> (N, 2) points with a derivative callable, v in [0, 1].
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .distance import to_polyline
from .errors import BadInputError


def conic(P0, R, P2, w: float, t) -> np.ndarray:
    """Points (N, dim) of the standard rational quadratic Bézier arc (P0, R with weight w, P2)."""
    t = np.atleast_1d(np.asarray(t, float))[:, None]
    b0, b1, b2 = (1 - t) ** 2, 2 * w * t * (1 - t), t ** 2
    return (b0 * np.asarray(P0, float) + b1 * np.asarray(R, float) + b2 * np.asarray(P2, float)) / (b0 + b1 + b2)


def _cross(a, b) -> float:
    return float(a[0] * b[1] - a[1] * b[0])


def tangent_lines_meet(A, TA, B, TB):
    """(point, s, u) with point = A + s TA = B + u TB, or None when the lines are parallel."""
    den = _cross(TA, TB)
    scale = np.linalg.norm(TA) * np.linalg.norm(TB)
    if abs(den) <= 1e-14 * scale:
        return None
    d = np.asarray(B, float) - np.asarray(A, float)
    s = _cross(d, TB) / den
    u = _cross(d, TA) / den
    return np.asarray(A, float) + s * np.asarray(TA, float), s, u


def locally_convex(A, TA, B, TB) -> bool:
    """§3.2's first rule for the chord A -> B: the turn from TA to the chord and from the chord to TB
    have the same sign, and the tangent lines meet ahead of A and behind B (the control triangle)."""
    c = np.asarray(B, float) - np.asarray(A, float)
    s1, s2 = _cross(TA, c), _cross(c, TB)
    if not (s1 * s2 > 0):
        return False
    m = tangent_lines_meet(A, TA, B, TB)
    return m is not None and m[1] > 0 and m[2] < 0


def reflect(V, U) -> np.ndarray:
    """Eq. 4: V reflected about the chord direction U."""
    U = np.asarray(U, float) / np.linalg.norm(U)
    W = 2 * (np.asarray(V, float) @ U) * U - np.asarray(V, float)
    return W / np.linalg.norm(W)


def choose_tangent(A, TA, B, V):
    """The tangent at B after the chord A -> B (§3.2): V (eq. 3) when the triangle is locally convex;
    V reflected about the chord (eq. 4) when the turns have opposite signs; otherwise the one
    closest to it, moved towards the circular-arc tangent (TA mirrored about the chord), that is.
    None when no tangent is (TA turns by 90 degrees or more from the chord: the step is too long)."""
    V = np.asarray(V, float) / np.linalg.norm(V)
    if locally_convex(A, TA, B, V):
        return V
    U = np.asarray(B, float) - np.asarray(A, float)
    if _cross(TA, U) * _cross(U, V) < 0:
        V = reflect(V, U)
        if locally_convex(A, TA, B, V):
            return V
    circ = reflect(TA, U)                      # isosceles triangle: convex whenever TA turns < 90 deg to U
    if not locally_convex(A, TA, B, circ):
        return None
    lo, hi = 0.0, 1.0                          # blend V -> circ, keep the convex end
    for _ in range(50):
        m = 0.5 * (lo + hi)
        T = (1 - m) * V + m * circ
        if np.linalg.norm(T) > 0 and locally_convex(A, TA, B, T / np.linalg.norm(T)):
            hi = m
        else:
            lo = m
    T = (1 - hi) * V + hi * circ
    return T / np.linalg.norm(T)


def barycentric(P, A, R, B) -> np.ndarray:
    """Barycentric coordinates (N, 3) of the points P (N, 2) in the triangle (A, R, B)."""
    P = np.atleast_2d(np.asarray(P, float))
    A, R, B = (np.asarray(x, float) for x in (A, R, B))
    det = _cross(R - A, B - A)
    tr = ((R[0] - P[:, 0]) * (B[1] - P[:, 1]) - (R[1] - P[:, 1]) * (B[0] - P[:, 0])) / det
    tb = ((A[0] - P[:, 0]) * (R[1] - P[:, 1]) - (A[1] - P[:, 1]) * (R[0] - P[:, 0])) / det
    return np.stack([tr, 1 - tr - tb, tb], axis=1)


def shared_weight(tri0, pts0, tri1, pts1, default: float = 2.0) -> float:
    """The discrete eq. 5: the weight w with sum over the boundary samples inside their triangle of
    4 w^2 tau0 tau2 - tau1^2 = 0 (Floater's implicit form of the conic), i.e. w^2 = sum tau1^2 /
    (4 sum tau0 tau2); the paper's default 2 when no sample lies inside either triangle."""
    num = den = 0.0
    for tri, pts in ((tri0, pts0), (tri1, pts1)):
        if tri is None or len(pts) == 0:
            continue
        tau = barycentric(pts, *tri)
        inside = np.all(tau >= -1e-12, axis=1)
        num += float((tau[inside, 1] ** 2).sum())
        den += float(4 * (tau[inside, 0] * tau[inside, 2]).sum())
    if den <= 0 or num <= 0:
        return default
    return float(np.sqrt(num / den))


def _crossing(b, X, c, lo, hi, n=64):
    """The smallest v in (lo, hi] where the curve b crosses the line through X with direction c."""
    v = np.linspace(lo, hi, n + 1)
    g = (b(v) - X) @ np.array([-c[1], c[0]])      # b(lo) is on the line itself: only later crossings count
    for k in range(n):
        if g[k + 1] == 0.0:
            return float(v[k + 1])
        if (g[k] < 0 < g[k + 1]) or (g[k] > 0 > g[k + 1]):
            from scipy.optimize import brentq
            nrm = np.array([-c[1], c[0]])
            return float(brentq(lambda x: float((b(np.array([x]))[0] - X) @ nrm), v[k], v[k + 1], xtol=1e-15))
    return None


@dataclass
class ParallelStep:
    v: float            # new parameter on b0
    vb: float           # new parameter on b1
    collapsed: int      # -1: none, 0: the b0 side stayed, 1: the b1 side stayed


def parallel_step(b0, b1, v: float, vb: float, delta: float, kf: float = 1.5) -> ParallelStep:
    """§3.1: advance the boundary with the smaller parameter by delta, then find the other boundary's
    point on the line through its current point parallel to the new chord, within (its parameter,
    its parameter + kf delta]; the smallest solution, or no move (that side collapses)."""
    if v <= vb:
        nv = min(1.0, v + delta)
        L0, L1 = b0(np.array([v, nv]))
        X = b1(np.array([vb]))[0]
        hit = _crossing(b1, X, L1 - L0, vb, min(1.0, vb + kf * delta))
        return ParallelStep(nv, vb if hit is None else hit, 1 if hit is None else -1)
    nvb = min(1.0, vb + delta)
    M0, M1 = b1(np.array([vb, nvb]))
    X = b0(np.array([v]))[0]
    hit = _crossing(b0, X, M1 - M0, v, min(1.0, v + kf * delta))
    return ParallelStep(v if hit is None else hit, nvb, 0 if hit is None else -1)


def hausdorff_2d(A: np.ndarray, B: np.ndarray) -> float:
    """Eq. 6 by dense samples: the two-sided distance between two densely sampled planar curves
    (each point to the other's polyline)."""
    return max(to_polyline(A, B), to_polyline(B, A))


def generators_concurrent(P: np.ndarray, Q: np.ndarray, rel: float = 1e-9) -> bool:
    """Theorem 1: the generator lines P_i Q_i (i = 0, 1, 2) of a cone patch meet at one point (the
    apex) or are parallel (a cylinder), to rel of the patch's size."""
    P, Q = np.asarray(P, float), np.asarray(Q, float)
    D = Q - P
    size = max(np.ptp(np.vstack([P, Q]), axis=0).max(), 1e-300)
    u = D / np.linalg.norm(D, axis=1)[:, None]
    if np.abs(np.cross(u[0], u[1])).max() <= rel and np.abs(np.cross(u[0], u[2])).max() <= rel:
        return True                                   # parallel
    # the apex from lines 0 and 1 (least squares), then the distance of all three lines to it
    A = np.zeros((3, 3))
    b = np.zeros(3)
    for p, d in zip(P, u):
        M = np.eye(3) - np.outer(d, d)
        A += M
        b += M @ p
    X = np.linalg.lstsq(A, b, rcond=None)[0]
    dist = [np.linalg.norm((np.eye(3) - np.outer(d, d)) @ (X - p)) for p, d in zip(P, u)]
    return max(dist) <= rel * max(size, np.linalg.norm(X - P[0]))


@dataclass
class FatArc:
    """One fat conic arc: control triangles on both boundaries (a collapsed side repeats its point),
    the shared middle weight, the boundary parameters it covers and its boundary error (eq. 6)."""

    A: np.ndarray       # (3, 2): L_{i-1}, R_i, L_i on the b0 side
    B: np.ndarray       # (3, 2) on the b1 side
    w: float
    v: tuple            # (v_{i-1}, v_i) on b0
    vb: tuple           # on b1
    err: float


def _unit(x) -> np.ndarray:
    x = np.asarray(x, float)
    return x / np.linalg.norm(x)


def _side(b, a: float, z: float, L, R, N, samples: int):
    """Control triangle (or a collapsed point), the boundary samples and the boundary error of one side."""
    pts = b(np.linspace(a, z, samples))
    if z <= a or np.linalg.norm(N - L) == 0:
        return np.array([L, L, L]), pts, float(np.linalg.norm(pts - L, axis=1).max())
    return np.array([L, R, N]), pts, None


def _line_distances(P, D, Q, E) -> np.ndarray:
    """Distances between the lines P + s D and Q + u E in 3D, row by row (N, 3) arrays."""
    n = np.cross(D, E)
    nn = np.linalg.norm(n, axis=1)
    d = Q - P
    skew = np.abs((d * n).sum(axis=1)) / np.where(nn > 0, nn, 1.0)
    par = np.linalg.norm(d - ((d * D).sum(axis=1) / np.maximum((D * D).sum(axis=1), 1e-300))[:, None] * D, axis=1)
    small = nn <= 1e-14 * np.linalg.norm(D, axis=1) * np.linalg.norm(E, axis=1)
    return np.where(small, par, skew)


def _second(f, x, eps=1e-5):
    """Numerical second derivatives of f at x (N,) (central differences)."""
    return (f(x + eps) - 2 * f(x) + f(x - eps)) / eps ** 2


def _nearest_params(f, lo, hi, X, n=400):
    """For each point of X, the parameter in [lo, hi] of the nearest of n samples of f."""
    if hi <= lo:
        return np.full(X.shape[0], lo)
    t = np.linspace(lo, hi, n)
    F = f(t)
    k = np.argmin(((X[:, None, :] - F[None]) ** 2).sum(axis=2), axis=1)
    return t[k]


def skew_error(arc: "FatArc", b0, b1, h0: float, h1: float, m: int = 25) -> float:
    """Eqs. 7–8: max(d0, d1), the bound of the distance between the rulings of the two surfaces once
    the boundaries agree: for a cone generator A(t)B(t), the nearest boundary parameters v_A, v_B,
    the bilinear quadrangle of the ruled surface between them (its thickness: the distance between
    its diagonals) plus the chord heights dv^2/8 sup|b''|; and the same from every ruled generator
    b0(v)b1(v) to the cone."""
    (v0, v1), (w0, w1) = arc.v, arc.vb
    t = np.linspace(0.0, 1.0, m)

    def A(x):
        return conic(*arc.A, arc.w, x)

    def B(x):
        return conic(*arc.B, arc.w, x)

    def up(X, h):
        return np.concatenate([X, np.full((X.shape[0], 1), h)], axis=1)
    lo, hi = min(v0, w0), max(v1, w1)
    vs = np.linspace(lo, hi, 200)
    edge = np.clip(np.concatenate([vs, [lo + 1e-5, hi - 1e-5]]), lo + 1e-5, hi - 1e-5) if hi - lo > 3e-5 else vs
    sup_b = max(np.linalg.norm(_second(b0, edge), axis=1).max(), np.linalg.norm(_second(b1, edge), axis=1).max())
    vA = _nearest_params(b0, v0, v1, A(t))
    vB = _nearest_params(b1, w0, w1, B(t))
    P0, Q1, P1, Q0 = up(b0(vA), h0), up(b1(vB), h1), up(b1(vA), h1), up(b0(vB), h0)
    d0 = float((0.125 * (vB - vA) ** 2 * sup_b + _line_distances(P0, Q1 - P0, P1, Q0 - P1)).max())
    tc = np.clip(t, 1e-5, 1 - 1e-5)
    sup_c = max(np.linalg.norm(_second(A, tc), axis=1).max(), np.linalg.norm(_second(B, tc), axis=1).max())
    d1 = 0.0
    a_, z_ = max(v0, w0), min(v1, w1)
    if z_ > a_:
        vv = np.linspace(a_, z_, m)
        tA = _nearest_params(A, 0.0, 1.0, b0(vv))
        tB = _nearest_params(B, 0.0, 1.0, b1(vv))
        P0, Q1, P1, Q0 = up(A(tB), h0), up(B(tA), h1), up(A(tA), h0), up(B(tB), h1)
        d1 = float((0.125 * (tA - tB) ** 2 * sup_c + _line_distances(P0, Q1 - P0, P1, Q0 - P1)).max())
    return float(max(d0, d1))


def _try_arc(b0, db0, b1, db1, v, vb, L, Lb, T, delta, kf, samples, h0, h1):
    """One candidate fat arc from (v, vb) with step delta: (arc, its end state) or None when no locally
    convex tangent exists for this step."""
    st = parallel_step(b0, b1, v, vb, delta, kf)
    N, Nb = b0(np.array([st.v]))[0], b1(np.array([st.vb]))[0]
    V = _unit(db0(np.array([st.v]))[0] + db1(np.array([st.vb]))[0])
    a, z = (L, N) if np.linalg.norm(N - L) >= np.linalg.norm(Nb - Lb) else (Lb, Nb)
    Tn = choose_tangent(a, T, z, V)
    if Tn is None:
        return None
    R = tangent_lines_meet(L, T, N, Tn)
    Rb = tangent_lines_meet(Lb, T, Nb, Tn)
    triA, ptsA, eA = _side(b0, v, st.v, L, None if R is None else R[0], N, samples)
    triB, ptsB, eB = _side(b1, vb, st.vb, Lb, None if Rb is None else Rb[0], Nb, samples)
    w = shared_weight(None if eA is not None else tuple(triA), ptsA, None if eB is not None else tuple(triB), ptsB)
    t = np.linspace(0.0, 1.0, 4 * samples)
    if eA is None:
        eA = hausdorff_2d(conic(*triA, w, t), ptsA)
    if eB is None:
        eB = hausdorff_2d(conic(*triB, w, t), ptsB)
    arc = FatArc(triA, triB, w, (v, st.v), (vb, st.vb), max(eA, eB))
    arc.err = arc.err + skew_error(arc, b0, b1, h0, h1)          # eq. 9
    return arc, (st.v, st.vb, N, Nb, Tn)


def _sequential(b0, db0, b1, db1, tol, delta0, target, args, ks, grow, max_arcs):
    """One pass of the §3.3 loop; with a target count, each arc's first step is the remaining range
    spread over the arcs left (None when the pass would need more arcs than the target)."""
    arcs = []
    v = vb = 0.0
    L, Lb = b0(np.array([0.0]))[0], b1(np.array([0.0]))[0]
    T = _unit(db0(np.array([0.0]))[0] + db1(np.array([0.0]))[0])
    while v < 1.0 or vb < 1.0:
        if target is not None:
            if len(arcs) >= target:
                return None
            delta = max(1.05 * (1.0 - min(v, vb)) / (target - len(arcs)), 1e-6)
        else:
            delta = delta0
        while True:
            got = _try_arc(b0, db0, b1, db1, v, vb, L, Lb, T, delta, *args)
            if got is not None and got[0].err <= tol:
                break
            delta *= ks
            if delta < 1e-9:
                if target is not None:
                    return None
                raise BadInputError(f"no fat conic arc within {tol:g} from v = {v:.6g}, {vb:.6g}; the boundaries "
                                    f"have a corner there or the tolerance is too small")
        while grow and max(got[0].v[1], got[0].vb[1]) < 1.0:
            nxt = _try_arc(b0, db0, b1, db1, v, vb, L, Lb, T, delta / ks, *args)
            if nxt is None or nxt[0].err > tol:
                break
            got, delta = nxt, delta / ks
        arc, (v, vb, L, Lb, T) = got
        arcs.append(arc)
        if len(arcs) > max_arcs:
            raise BadInputError(f"more than {max_arcs} arcs needed; raise the tolerance")
    return arcs


def fit_fat_conic(b0, db0, b1, db1, tol: float, delta0: float, *, h0: float = 0.0, h1: float = 1.0,
                  ks: float = 0.9, kf: float = 1.5, samples: int = 41, grow: bool = True, balance: bool = True,
                  max_arcs: int = 10_000) -> list:
    """The sequential fitting loop of §3.3: from the start, a parallel step of delta, the common
    tangent, the control triangles, the shared weight; the error of eq. 9 (boundary + skew, with the
    boundaries' planes at heights h0 and h1); accept within tol, else shrink delta by ks.  Beyond the
    paper: with grow an accepted arc is lengthened by 1 / ks steps for as long as it stays within tol;
    with balance the fit is repeated with one arc fewer (the remaining range spread over the arcs
    left) for as long as that succeeds, so a short leftover arc at the end disappears."""
    if not (tol > 0 and delta0 > 0):
        raise BadInputError("the tolerance and the step must be positive")
    args = (kf, samples, h0, h1)
    arcs = _sequential(b0, db0, b1, db1, tol, delta0, None, args, ks, grow, max_arcs)
    while balance and len(arcs) > 1:
        fewer = _sequential(b0, db0, b1, db1, tol, delta0, len(arcs) - 1, args, ks, grow, max_arcs)
        if fewer is None:
            break
        arcs = fewer
    return arcs


def patch_surface(arc: FatArc, h0: float = 0.0, h1: float = 1.0):
    """The cone patch of a fat arc: its boundary triangles lifted to the planes z = h0 and z = h1, as a
    rational B-spline surface, linear in u (from the b0 side to the b1 side), quadratic in v."""
    from .nurbs import Surface
    P = np.zeros((2, 3, 3))
    P[0, :, :2], P[0, :, 2] = arc.A, h0
    P[1, :, :2], P[1, :, 2] = arc.B, h1
    W = np.array([[1.0, arc.w, 1.0], [1.0, arc.w, 1.0]])
    return Surface(P, [0, 0, 1, 1], [0, 0, 0, 1, 1, 1], 1, 2, W)


def trim_arc(arc: FatArc, s0: float, s1: float) -> FatArc:
    """§5, extension and trim: the fat arc between the planes at fractions s0 < s1 of the way from the
    b0 plane to the b1 plane.  A plane section of a cone patch interpolates its two boundary conics
    linearly (same weight, same parameter), so the trimmed triangles are (1 - s) A + s B."""
    A = (1 - s0) * arc.A + s0 * arc.B
    B = (1 - s1) * arc.A + s1 * arc.B
    return FatArc(A, B, arc.w, arc.v, arc.vb, arc.err)
