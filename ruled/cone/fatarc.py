"""Cone splines by fat conic spline fitting (Yang & Yang 2006), the planar building blocks.

A ruled surface between two parallel planes projects onto a planar "fat curve" bounded by two
curves b0(v), b1(v).  A cone patch between the planes projects onto a fat conic arc: two rational
quadratic arcs with the same middle weight whose control triangles have parallel sides
(Theorem 2).  Here: the conic arcs, the interpolation of the two boundaries by piecewise parallel
polygons (§3.1), the common tangents by local convexity and reflection (eqs. 3–4), the control
triangles and the shared weight by the discrete form of eq. 5 (§3.2), the boundary error (eq. 6),
the check of Theorem 1 on a patch's generator lines, the skew error (eqs. 7–8), the sequential
fitting loop (§3.3) with the total of eq. 9, the cone patches as rational surfaces and the trim of
§5.  Surfaces in space, faces and the shell: conespline.py and occ/conespline.py.

Boundary curves are callables v -> (N, 2) points with a derivative callable, v in [0, 1]; the fit
tabulates them once (Track) and evaluates the table.  Closest points are numba kernels
(cone/kernels.py) with NumPy twins here (Track, Conic, project), bit-identical.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ruled.cone import kernels as kernels_cone
from ruled.cone.conic import _cross, _grid, _unit_grid, choose_tangent, shared_weight, tangent_lines_meet
from ruled.core import jit
from ruled.core.distance import to_polyline
from ruled.core.errors import BadInputError, ToleranceError, positive

_NOT, _NOP, _NOQ = np.zeros(2), np.zeros((2, 2)), np.zeros((3, 2))     # unused arguments of the kernel


class Track:
    """A planar boundary curve v -> (x, y), v in [0, 1], tabulated once (points and first derivatives at
    a uniform grid plus the curve's own breaks) and evaluated by piecewise cubic Hermite interpolation:
    every query of the fitting loop is then a few array operations, whatever the curve is.  With the
    breaks (knots) in the grid each table interval lies inside one smooth piece, and the interpolation
    error is h^4 / 384 sup |b^(4)| (about 1e-12 of the size for h = 1/1024 on the paper's spiral)."""

    def __init__(self, f, df, breaks=(), m: int = 1024):
        t = np.linspace(0.0, 1.0, m + 1)
        br = np.asarray([b for b in np.ravel(breaks) if 0.0 < b < 1.0], float)
        t = np.unique(np.concatenate([t, br]))
        self.fast = jit.enabled()              # numba kernels (decided once: the env lookup is not free)
        self.t = t
        self.P = np.ascontiguousarray(f(t), dtype=float)
        self.D = np.ascontiguousarray(df(t), dtype=float)
        self.h = np.diff(t)

    def _at(self, v):
        v = np.minimum(np.maximum(np.atleast_1d(np.asarray(v, float)), 0.0), 1.0)
        i = np.minimum(np.searchsorted(self.t, v, side="right") - 1, len(self.t) - 2)
        h = self.h[i]
        return i, h[:, None], ((v - self.t[i]) / h)[:, None]

    def __call__(self, v) -> np.ndarray:
        if self.fast:
            return kernels_cone.evaluate(0, self.t, self.P, self.D, self.h, _NOQ, 0.0, v, 0)[0]
        i, h, s = self._at(v)
        s2, s3 = s * s, s * s * s
        return ((2 * s3 - 3 * s2 + 1) * self.P[i] + (s3 - 2 * s2 + s) * h * self.D[i]
                + (-2 * s3 + 3 * s2) * self.P[i + 1] + (s3 - s2) * h * self.D[i + 1])

    def d(self, v) -> np.ndarray:
        return self.all3(v)[1]

    def dd(self, v) -> np.ndarray:
        return self.all3(v)[2]

    def all3(self, v):
        """Point, first and second derivative at v."""
        if self.fast:
            return tuple(kernels_cone.evaluate(0, self.t, self.P, self.D, self.h, _NOQ, 0.0, v, 2))
        i, h, s = self._at(v)
        s2, s3 = s * s, s * s * s
        P0, P1, D0, D1 = self.P[i], self.P[i + 1], h * self.D[i], h * self.D[i + 1]
        dP = P1 - P0
        X = P0 + s * D0 + s2 * (3 * dP - 2 * D0 - D1) + s3 * (D0 + D1 - 2 * dP)
        X1 = (D0 + 2 * s * (3 * dP - 2 * D0 - D1) + 3 * s2 * (D0 + D1 - 2 * dP)) / h
        X2 = (2 * (3 * dP - 2 * D0 - D1) + 6 * s * (D0 + D1 - 2 * dP)) / (h * h)
        return X, X1, X2


class Conic:
    """The rational quadratic arc (P0, R with weight w, P2) with its first and second derivatives."""

    def __init__(self, P0, R, P2, w: float):
        self.P0, self.R, self.P2 = (np.asarray(x, float) for x in (P0, R, P2))
        self.Q = np.ascontiguousarray(np.array([self.P0, self.R, self.P2]))
        self.w = float(w)
        self.fast = jit.enabled()

    def __call__(self, t) -> np.ndarray:
        if self.fast:
            return kernels_cone.evaluate(1, _NOT, _NOP, _NOP, _NOT, self.Q, self.w, t, 0)[0]
        t = np.atleast_1d(np.asarray(t, float))[:, None]
        a, b, c = (1 - t) ** 2, 2 * self.w * t * (1 - t), t * t
        return (a * self.P0 + b * self.R + c * self.P2) / (a + b + c)

    def d(self, t) -> np.ndarray:
        return self.all3(t)[1]

    def dd(self, t) -> np.ndarray:
        return self.all3(t)[2]

    def all3(self, t):
        """Point, first and second derivative at t."""
        if self.fast:
            return tuple(kernels_cone.evaluate(1, _NOT, _NOP, _NOP, _NOT, self.Q, self.w, t, 2))
        t = np.atleast_1d(np.asarray(t, float))[:, None]
        w, P0, R, P2 = self.w, self.P0, self.R, self.P2
        u = 1 - t
        N = u * u * P0 + 2 * w * t * u * R + t * t * P2
        D = u * u + 2 * w * t * u + t * t
        N1 = -2 * u * P0 + 2 * w * (1 - 2 * t) * R + 2 * t * P2
        D1 = -2 * u + 2 * w * (1 - 2 * t) + 2 * t
        C = N / D
        C1 = (N1 - C * D1) / D
        C2 = (2 * P0 - 4 * w * R + 2 * P2 - 2 * C1 * D1 - C * (4.0 - 4.0 * w)) / D
        return C, C1, C2


def project(c, lo: float, hi: float, X: np.ndarray, n: int = 33, iters: int = 3):
    """Exact closest points on the curve c (a Track or a Conic) over [lo, hi] to the points X (N, 2):
    the nearest of n samples, then Newton steps on (c - X) . c' = 0 kept inside the samples'
    neighbouring interval.  Returns (parameters, distances)."""
    X = np.atleast_2d(X)
    if hi <= lo:
        x = np.full(X.shape[0], float(lo))
        return x, np.linalg.norm(c(x) - X, axis=1)
    t = _grid(lo, hi, n)
    if c.fast:
        if isinstance(c, Track):
            return kernels_cone.project(0, c.t, c.P, c.D, c.h, _NOQ, 0.0, t, X, iters)
        return kernels_cone.project(1, _NOT, _NOP, _NOP, _NOT, c.Q, c.w, t, X, iters)
    d2 = ((X[:, None, :] - c(t)[None]) ** 2).sum(axis=2)
    k = np.argmin(d2, axis=1)
    x0 = t[k]
    a, b = t[np.maximum(k - 1, 0)], t[np.minimum(k + 1, n - 1)]
    x = x0
    for _ in range(iters):
        P, d1, d2_ = c.all3(x)
        r = P - X
        g = (r * d1).sum(axis=1)
        gp = (d1 * d1).sum(axis=1) + (r * d2_).sum(axis=1)
        ok = gp > 0
        x = np.minimum(np.maximum(x - np.where(ok, g / np.where(ok, gp, 1.0), 0.0), a), b)
    dist = np.sqrt(((c(x) - X) ** 2).sum(axis=1))
    d0 = np.sqrt(d2[np.arange(X.shape[0]), k])
    worse = dist > d0
    return np.where(worse, x0, x), np.where(worse, d0, dist)


def one_sided(src, lo: float, hi: float, dst, dlo: float, dhi: float, n: int = 33):
    """max over s in [lo, hi] of the distance from src(s) to dst over [dlo, dhi] (one side of eq. 6):
    n samples, exact projections, then two steps of successive parabolic interpolation about the
    largest sample (the sampled maximum alone can fall short of the true one by the curvature of the
    distance between samples).  Returns (max, sample parameters, their closest parameters on dst)."""
    s = _grid(lo, hi, n)
    if hi <= lo:
        s = s[:1]
    x, d = project(dst, dlo, dhi, src(s))
    best = float(d.max())
    if len(s) >= 3:
        k = int(np.clip(np.argmax(d), 1, len(s) - 2))
        pts = [(s[k - 1], d[k - 1]), (s[k], d[k]), (s[k + 1], d[k + 1])]
        for _ in range(2):
            (a, fa), (b, fb), (c, fc) = sorted(pts)
            den = (b - a) * (fb - fc) - (b - c) * (fb - fa)
            if den == 0:
                break
            t = b - 0.5 * ((b - a) ** 2 * (fb - fc) - (b - c) ** 2 * (fb - fa)) / den
            if not (a < t < c):
                break
            ft = float(project(dst, dlo, dhi, src(t))[1][0])
            best = max(best, ft)
            pts = sorted(pts + [(t, ft)], key=lambda p: -p[1])[:3]
    return best, s, x


def _crossing(b, X, c, lo, hi, n=64):
    """The smallest v in (lo, hi] where the curve b crosses the line through X with direction c."""
    nrm = np.array([-c[1], c[0]])
    v = np.linspace(lo, hi, n + 1)
    g = (b(v) - X) @ nrm                            # b(lo) is on the line itself: only later crossings count
    for k in range(n):
        if g[k + 1] == 0.0:
            return float(v[k + 1])
        if (g[k] < 0 < g[k + 1]) or (g[k] > 0 > g[k + 1]):
            x0, x1, g0, g1 = v[k], v[k + 1], g[k], g[k + 1]
            for _ in range(60):                    # Illinois (regula falsi), on the tabulated curve
                x = x1 - g1 * (x1 - x0) / (g1 - g0)
                gx = float((b(x)[0] - X) @ nrm)
                if gx == 0.0 or abs(x1 - x0) <= 1e-15:
                    return float(x)
                if (gx > 0) == (g1 > 0):
                    g0 *= 0.5
                else:
                    x0, g0 = x1, g1
                x1, g1 = x, gx
            return float(x1)
    scale = np.linalg.norm(c) * max(float(np.abs(b(v) - X).max()), 1e-300)
    if abs(g[-1]) <= 1e-10 * scale:                # the window's end is on the line, to round-off
        return float(v[-1])
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
    def snap(x):
        return None if x is None else (1.0 if x >= 1.0 - 1e-10 else x)
    if v <= vb:
        nv = min(1.0, v + delta)
        L0, L1 = b0(np.array([v, nv]))
        X = b1(np.array([vb]))[0]
        hit = snap(_crossing(b1, X, L1 - L0, vb, min(1.0, vb + kf * delta)))
        return ParallelStep(nv, vb if hit is None else hit, 1 if hit is None else -1)
    nvb = min(1.0, vb + delta)
    M0, M1 = b1(np.array([vb, nvb]))
    X = b0(np.array([v]))[0]
    hit = snap(_crossing(b0, X, M1 - M0, v, min(1.0, v + kf * delta)))
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
    the shared middle weight, the boundary parameters it covers, its boundary error (eq. 6) and its
    total error bound (eq. 9: boundary + skew)."""

    A: np.ndarray       # (3, 2): L_{i-1}, R_i, L_i on the b0 side
    B: np.ndarray       # (3, 2) on the b1 side
    w: float
    v: tuple            # (v_{i-1}, v_i) on b0
    vb: tuple           # on b1
    err: float          # eq. 9
    boundary: float = 0.0
    skew: float = 0.0


def _unit(x) -> np.ndarray:
    x = np.asarray(x, float)
    return x / np.linalg.norm(x)


def _line_distances(P, D, Q, E) -> np.ndarray:
    """Distances between the lines P + s D and Q + u E in 3D, row by row (N, 3) arrays."""
    n = np.cross(D, E)
    nn = np.linalg.norm(n, axis=1)
    d = Q - P
    skew = np.abs((d * n).sum(axis=1)) / np.where(nn > 0, nn, 1.0)
    par = np.linalg.norm(d - ((d * D).sum(axis=1) / np.maximum((D * D).sum(axis=1), 1e-300))[:, None] * D, axis=1)
    small = nn <= 1e-14 * np.linalg.norm(D, axis=1) * np.linalg.norm(E, axis=1)
    return np.where(small, par, skew)


def _up(X, h):
    return np.concatenate([X, np.full((X.shape[0], 1), float(h))], axis=1)


def _quad_error(c0, c1, x, y, h0, h1) -> np.ndarray:
    """Eqs. 7 and 8 for the segments c0(x) -> c1(y) against the ruled surface c0(s) c1(s) between the
    generators at s = x and s = y: the quadrangle's thickness plus the chord heights
    (y - x)^2 / 8 sup |c''| of both curves (the sup over [x, y], sampled).  The thickness is the
    distance between the quadrangle's diagonals (the paper) or a quarter of its twist vector, which
    bounds the distance from the diagonal x -> y to the bilinear patch exactly, whichever is smaller."""
    P00, P11 = _up(c0(x), h0), _up(c1(y), h1)
    P10, P01 = _up(c1(x), h1), _up(c0(y), h0)
    thick = np.minimum(_line_distances(P00, P11 - P00, P10, P01 - P10),
                       0.25 * np.linalg.norm(P00 + P11 - P10 - P01, axis=1))
    s = x[:, None] + (y - x)[:, None] * _unit_grid(9)[None]
    sup = np.maximum(np.linalg.norm(c0.dd(s.ravel()), axis=1), np.linalg.norm(c1.dd(s.ravel()), axis=1))
    return 0.125 * (y - x) ** 2 * sup.reshape(s.shape).max(axis=1) + thick


def _try_arc(tr0: Track, tr1: Track, state, delta, tol, kf, samples, h0, h1):
    """One candidate fat arc from the state (v, vb, L, Lb, T) with step delta: (arc, its end state), or
    None when no locally convex tangent exists for this step.  The skew error is only computed when
    the boundary error leaves room for it."""
    v, vb, L, Lb, T = state
    st = parallel_step(tr0, tr1, v, vb, delta, kf)
    N, Nb = tr0(st.v)[0], tr1(st.vb)[0]
    V = _unit(tr0.d(st.v)[0] + tr1.d(st.vb)[0])
    a, z = (L, N) if np.linalg.norm(N - L) >= np.linalg.norm(Nb - Lb) else (Lb, Nb)
    Tn = choose_tangent(a, T, z, V)
    if Tn is None:
        return None
    tris, pts = [], []
    for tr, lo, hi, P, Q in ((tr0, v, st.v, L, N), (tr1, vb, st.vb, Lb, Nb)):
        R = tangent_lines_meet(P, T, Q, Tn) if hi > lo and np.linalg.norm(Q - P) > 0 else None
        tris.append(np.array([P, R[0], Q]) if R is not None else np.array([P, P, P]))
        pts.append(tr(_grid(lo, hi, samples)) if R is not None else np.zeros((0, 2)))
    w = shared_weight(tuple(tris[0]) if len(pts[0]) else None, pts[0], tuple(tris[1]) if len(pts[1]) else None,
                      pts[1])
    arc = FatArc(tris[0], tris[1], w, (v, st.v), (vb, st.vb), 0.0)
    A, B = Conic(arc.A[0], arc.A[1], arc.A[2], w), Conic(arc.B[0], arc.B[1], arc.B[2], w)
    eA, _, vA = one_sided(A, 0.0, 1.0, tr0, v, st.v, samples)          # eq. 6, both ways
    eB, _, vB = one_sided(B, 0.0, 1.0, tr1, vb, st.vb, samples)
    err = max(eA, eB, one_sided(tr0, v, st.v, A, 0.0, 1.0, samples)[0] if len(pts[0]) else 0.0,
              one_sided(tr1, vb, st.vb, B, 0.0, 1.0, samples)[0] if len(pts[1]) else 0.0)
    arc.boundary = arc.err = float(err)
    if err <= tol:
        d0 = _quad_error(tr0, tr1, vA, vB, h0, h1).max()          # eq. 7: cone generators -> ruled surface
        d1 = 0.0
        lo, hi = max(v, vb), min(st.v, st.vb)
        if hi > lo:                                                # eq. 8: rulings -> cone
            vv = _grid(lo, hi, samples)
            tA = project(A, 0.0, 1.0, tr0(vv))[0]
            tB = project(B, 0.0, 1.0, tr1(vv))[0]
            d1 = _quad_error(A, B, tA, tB, h0, h1).max()
        arc.skew = float(max(d0, d1))
        arc.err = arc.boundary + arc.skew                          # eq. 9
    return arc, (st.v, st.vb, N, Nb, Tn)


def _next_arc(tr0, tr1, state, delta, tol, args, search, ks, cap=None):
    """The next accepted arc from state, starting with the step delta: the paper's loop (shrink by ks
    until accepted) or, with search = "longest", also grow an accepted step (x 1.6) and bisect (in log
    scale, 5 rounds) between the longest accepted and the shortest refused step (at most cap)."""
    def attempt(d):
        got = _try_arc(tr0, tr1, state, d, tol, *args)
        return got if got is not None and got[0].err <= tol else None
    remaining = 1.0 - min(state[0], state[1])
    if cap is not None:
        remaining = min(remaining, cap)
    good = bad = None
    d = delta
    while good is None:
        got = attempt(d)
        if got is not None:
            good = (d, got)
        else:
            bad = d
            d *= ks if search == "paper" else 0.5
            if d < 1e-9:
                return None
    if search == "paper":
        return good[1]
    while bad is None and good[0] < remaining:
        d = min(good[0] * 1.6, remaining)
        got = attempt(d)
        if got is None:
            bad = d
        else:
            good = (d, got)
    if bad is not None:
        for _ in range(5):
            d = np.sqrt(good[0] * bad)
            got = attempt(d)
            if got is None:
                bad = d
            else:
                good = (d, got)
    return good[1]


def _sequential(tr0, tr1, tol, delta0, target, args, search, ks, max_arcs, progress=None, even=False, pace=None):
    """One pass of the §3.3 loop; with a target count, each arc's first step is the remaining range
    spread over the arcs left (None when the pass would need more arcs than the target); with even, that
    spread is also the longest step tried, so the arcs come out of similar lengths (None as soon as an arc
    falls short of it).  pace: the progress of an earlier pass after each arc; a pass that falls behind it
    gives up (the earlier pass took the longest arc at every step)."""
    arcs = []
    state = (0.0, 0.0, tr0(0.0)[0], tr1(0.0)[0], _unit(tr0.d(0.0)[0] + tr1.d(0.0)[0]))
    while state[0] < 1.0 or state[1] < 1.0:
        if target is not None:
            if len(arcs) >= target:
                return None
            delta = max((1.0 if even else 1.05) * (1.0 - min(state[0], state[1])) / (target - len(arcs)), 1e-6)
        else:
            delta = delta0
        got = _next_arc(tr0, tr1, state, delta, tol, args, search, ks, delta if even else None)
        if got is None:
            if target is not None:
                return None
            a, b = tr0.d(state[0])[0], tr1.d(state[1])[0]
            turn = float(np.degrees(np.arctan2(abs(_cross(a, b)), a @ b)))
            raise ToleranceError(f"no fat conic arc within {tol:g} from v = {state[0]:.6g}, {state[1]:.6g}: the two "
                                 f"boundaries' tangents differ by {turn:.1f} deg there (the surface twists, or has a "
                                 f"corner)")
        arc, state = got
        arcs.append(arc)
        if even and max(arc.v[1] - arc.v[0], arc.vb[1] - arc.vb[0]) < 0.98 * delta and min(state[:2]) < 1.0:
            return None
        if pace is not None and len(arcs) <= len(pace) and min(state[:2]) < pace[len(arcs) - 1] - 1e-12:
            return None
        if progress is not None:
            progress("fitting fat conic arcs", min(state[0], state[1]))
        covered = min(state[0], state[1])
        projected = len(arcs) / max(covered, 1e-12)
        if len(arcs) > max_arcs or (len(arcs) >= EARLY_ARCS and projected > 1.5 * max_arcs and covered < 1.0):
            raise ToleranceError(f"more than {max_arcs} fat conic arcs would be needed within {tol:g} ({len(arcs)} "
                                 f"arcs cover {covered:.1%} of the boundaries)")
    return arcs


EARLY_ARCS = 200        # after this many arcs, a pass whose pace projects past 1.5 x max_arcs stops at once


def fit_fat_conic(b0, db0, b1, db1, tol: float, delta0: float, *, h0: float = 0.0, h1: float = 1.0,
                  ks: float = 0.9, kf: float = 1.5, samples: int = 33, search: str = "longest",
                  balance: bool = True, breaks=(), max_arcs: int = 10_000, progress=None) -> list:
    """The sequential fitting loop of §3.3 on the fat curve between b0 and b1 (callables v -> (N, 2)
    with their derivatives db0, db1, v in [0, 1]; breaks: parameters where they are not smooth): from
    the start, a parallel step of delta, the common tangent, the control triangles, the shared weight;
    the error of eq. 9 (boundary + skew, with the boundaries' planes at heights h0 and h1); accept within
    tol, else shrink delta by ks (search = "paper").  Beyond the paper: search = "longest" grows an
    accepted step and bisects for the longest accepted one; with balance the fit is repeated with one
    arc fewer (the remaining range spread over the arcs left) for as long as that succeeds."""
    positive("tol", tol)
    positive("arc_step", delta0)
    if search not in ("longest", "paper"):
        raise BadInputError(f"unknown search {search!r}: use 'longest' or 'paper'")
    tr0, tr1 = Track(b0, db0, breaks), Track(b1, db1, breaks)
    args = (kf, samples, h0, h1)
    arcs = _sequential(tr0, tr1, tol, delta0, None, args, search, ks, max_arcs, progress)
    while balance and len(arcs) > 1:
        pace = [min(a.v[1], a.vb[1]) for a in arcs]
        fewer = _sequential(tr0, tr1, tol, delta0, len(arcs) - 1, args, search, ks, max_arcs, pace=pace)
        if fewer is None:
            break
        arcs = fewer
    if balance and len(arcs) > 1:                      # the same count, spread evenly, when that fits too
        even = _sequential(tr0, tr1, tol, delta0, len(arcs), args, search, ks, max_arcs, even=True)
        if even is not None:
            arcs = even
    return arcs


def patch_surface(arc: FatArc, h0: float = 0.0, h1: float = 1.0):
    """The cone patch of a fat arc: its boundary triangles lifted to the planes z = h0 and z = h1, as a
    rational B-spline surface, linear in u (from the b0 side to the b1 side), quadratic in v."""
    from ruled.core.nurbs import Surface
    P = np.zeros((2, 3, 3))
    P[0, :, :2], P[0, :, 2] = arc.A, h0
    P[1, :, :2], P[1, :, 2] = arc.B, h1
    W = np.array([[1.0, arc.w, 1.0], [1.0, arc.w, 1.0]])
    return Surface(P, np.array([0.0, 0.0, 1.0, 1.0]), np.array([0.0, 0.0, 0.0, 1.0, 1.0, 1.0]), 1, 2, W)


def trim_arc(arc: FatArc, s0: float, s1: float) -> FatArc:
    """§5, extension and trim: the fat arc between the planes at fractions s0 < s1 of the way from the
    b0 plane to the b1 plane.  A plane section of a cone patch interpolates its two boundary conics
    linearly (same weight, same parameter), so the trimmed triangles are (1 - s) A + s B."""
    A = (1 - s0) * arc.A + s0 * arc.B
    B = (1 - s1) * arc.A + s1 * arc.B
    return FatArc(A, B, arc.w, arc.v, arc.vb, arc.err)
