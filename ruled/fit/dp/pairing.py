"""The DP pairing made continuous: its refinement by golden-section search, and the smooth
reparametrization delta(s) fitted to it under bounds (Elber eq. 5; the rulings' ends as functions of one
parameter)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Optional

import numpy as np

from ruled.core.basis import bspline_basis_matrix
from ruled.core.nearest import golden
from ruled.core.nurbs import Curve, Surface
from ruled.fit.face.cost import _past_face, face_ends, face_weights, over_face, ruling_cost


@dataclass(frozen=True)
class Pairing:
    """A smooth strictly monotone pairing a(s), b(s), s in [0, 1] (normalized boundary parameters)."""

    delta: Curve          # delta(sigma) as a 1D cubic B-spline on [sigma0, sigma0 + span]
    sigma0: float
    closed: bool
    # 1: the end rulings are the patch's corners (a = b = 0 and 1); less on a face's extended patch, whose
    # end rulings may run past the face anywhere (face_ends)
    span: float = 1.0

    def ab(self, s) -> tuple[np.ndarray, np.ndarray]:
        s = np.asarray(s, float)
        sig = self.sigma0 + self.span * s
        d = self.delta(sig)[:, 0]
        return sig - d, sig + d

    def inverse(self, x: np.ndarray, which: str, dense: int = 4001) -> np.ndarray:
        """s with a(s) = x (which='a') or b(s) = x, for x in the pairing's range (unwrapped)."""
        key = f"_inverse_table_{dense}"        # the dense samples, once per pairing (it is immutable)
        table = self.__dict__.get(key)
        if table is None:
            sd = np.linspace(0.0, 1.0, dense)
            table = self.__dict__[key] = (sd,) + self.ab(sd)
        sd, a, b = table
        f = a if which == "a" else b
        sign = -1.0 if which == "a" else 1.0
        s = np.interp(np.asarray(x, float), f, sd)
        for _ in range(3):  # Newton polish on the smooth spline
            sig = self.sigma0 + self.span * s
            d0, d1 = self.delta.evaluate(sig, 1)
            s = np.clip(s - (sig + sign * d0[:, 0] - x) / (self.span * (1.0 + sign * d1[:, 0])), 0.0, 1.0)
        return s


@dataclass(frozen=True)
class RailPairing:
    """A pairing seen through another parameter: s runs linearly along one rail (which = 'a': a(s) = x0 +
    (x1 - x0) s), so that this rail of the result is its boundary curve itself (ruled.fit.reparam.
    rail_boundaries) and only the other is composed with the pairing.  The same rulings as base."""

    base: Pairing
    which: str
    x0: float
    x1: float

    @property
    def closed(self) -> bool:
        return self.base.closed

    @property
    def span(self) -> float:
        return self.base.span

    def _own(self, s) -> np.ndarray:
        """base's s of the rulings at this pairing's s."""
        return self.base.inverse(self.x0 + (self.x1 - self.x0) * np.asarray(s, float), self.which)

    def ab(self, s) -> tuple[np.ndarray, np.ndarray]:
        return self.base.ab(self._own(s))

    def inverse(self, x: np.ndarray, which: str, dense: int = 4001) -> np.ndarray:
        if which != self.which:
            a, b = self.base.ab(self.base.inverse(x, which, dense))
            x = a if self.which == "a" else b
        return np.clip((np.asarray(x, float) - self.x0) / (self.x1 - self.x0), 0.0, 1.0)


# ----------------------------------------------------------------------------- refinement
def refine_pairing(S: Surface, u0: float, L: float, closed: bool, path_ab: np.ndarray, step: float,
                   grid: int, m: int = 11, iters: int = 3, rounds: int = 18,
                   progress: Optional[Callable] = None,
                   at: Optional[np.ndarray] = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Continuous refinement of a DP path (normalized (a, b) pairs, (K, 2)).

    Returns (sigma (G,), delta (G,), cost (G,)) on a uniform sigma grid (or at the given sigmas).
    """
    sig_p = 0.5 * (path_ab[:, 0] + path_ab[:, 1])
    del_p = 0.5 * (path_ab[:, 1] - path_ab[:, 0])
    s0 = sig_p[0]
    if at is not None:
        sig = np.asarray(at, float)
    elif closed:
        sig = s0 + np.arange(grid) / grid
    else:
        sig = np.linspace(0.0, 1.0, grid)
    d_dp = np.interp(sig, sig_p, del_p)
    if closed:
        lo, hi = d_dp - step, d_dp + step
    else:
        lim = np.minimum(sig, 1.0 - sig)
        lo = np.maximum(d_dp - step, -lim)
        hi = np.minimum(d_dp + step, lim)

    # on a masked patch a ruling the DP's pairing puts over the face must stay over it: one that escapes
    # past the face's corner costs 0 (ruling_cost) without covering anything
    free = ~over_face(S, u0 + L * (sig - d_dp), u0 + L * (sig + d_dp), m)

    def cost(sg, d):
        out = 0.0
        if not free.all():
            i = np.clip(np.searchsorted(sig, sg), 0, sig.size - 1)
            out = np.where(free[i], 0.0, np.inf)
        return ruling_cost(S, u0 + L * (sg - d), u0 + L * (sg + d), m, iters, closed, out)

    c_dp = cost(sig, d_dp)
    xb, fb = golden(lambda d: cost(sig, d), lo, hi, rounds, progress)
    if at is None and sig.size > 2:
        xb, fb = _one_branch(cost, sig, lo, hi, xb, fb, rounds)
    # keep the DP pairing unless the search really improves it (flat costs, e.g. on a plane)
    noise = 1e-12 * S.diagonal()
    use_dp = c_dp <= fb + noise
    d, c = np.where(use_dp, d_dp, xb), np.where(use_dp, c_dp, fb)
    if at is None and not closed:
        d = _past_face(S, sig, d)
    return sig, d, c


# the refinement's bracket is scanned at this many points for further valleys of the cost, of which
# the BRANCHES - 1 lowest are searched too
SCAN = 25
BRANCHES = 3


def _one_branch(cost: Callable, sig: np.ndarray, lo: np.ndarray, hi: np.ndarray, xb: np.ndarray,
                fb: np.ndarray, rounds: int) -> tuple[np.ndarray, np.ndarray]:
    """The refined rulings (delta xb at each sigma, cost fb) made one family.  A surface close to ruled
    in two ways (a doubly ruled one: a hyperbolic paraboloid, a hyperboloid, a blade designed as one)
    has two narrow valleys of the cost within the bracket, a sample apart, and a search per sigma
    lands in either: the pairing through both jumps between them, and every ruling it interpolates
    across a jump is far from the surface.  Every valley of the bracket is searched (a scan, then
    golden sections), and the rulings are chosen along sigma by dynamic programming: the sum of their
    costs and of the costs of the rulings halfway between consecutive ones (which a jump makes large),
    the steps keeping a and b monotone."""
    G = sig.size
    x = np.linspace(0.0, 1.0, SCAN)
    xs = lo[:, None] + (hi - lo)[:, None] * x[None, :]
    fs = cost(np.repeat(sig, SCAN), xs.ravel()).reshape(G, SCAN)
    pad = np.pad(fs, ((0, 0), (1, 1)), constant_values=np.inf)
    valley = (fs <= pad[:, :-2]) & (fs <= pad[:, 2:])
    # the search's own valley (within a scan step of xb) is the first candidate already
    step = (hi - lo) / (SCAN - 1)
    valley &= np.abs(xs - xb[:, None]) > 1.5 * step[:, None]
    order = np.argsort(np.where(valley, fs, np.inf), axis=1, kind="stable")[:, :BRANCHES - 1]
    ok = np.take_along_axis(valley, order, axis=1)
    if not ok.any():
        return xb, fb
    k, j = np.nonzero(ok)
    jj = order[k, j]
    a = xs[k, np.maximum(jj - 1, 0)]
    b = xs[k, np.minimum(jj + 1, SCAN - 1)]
    xv, fv = golden(lambda d: cost(sig[k], d), a, b, rounds)
    D = np.full((G, BRANCHES), np.nan)
    F = np.full((G, BRANCHES), np.inf)
    D[:, 0], F[:, 0] = xb, fb
    D[k, 1 + j], F[k, 1 + j] = xv, fv
    # the rulings halfway between consecutive candidates (every pair of branches)
    C = BRANCHES
    i0, c0, c1 = np.meshgrid(np.arange(G - 1), np.arange(C), np.arange(C), indexing="ij")
    d0, d1 = D[i0, c0], D[i0 + 1, c1]
    live = np.isfinite(d0) & np.isfinite(d1) & (np.abs(d1 - d0) <= np.abs(sig[i0 + 1] - sig[i0]))
    E = np.full(i0.shape, np.inf)
    E[live] = cost(0.5 * (sig[i0] + sig[i0 + 1])[live], 0.5 * (d0 + d1)[live])
    total = F[0].copy()
    back = np.zeros((G, C), np.int64)
    for i in range(1, G):
        t = total[:, None] + E[i - 1]            # (from, to)
        back[i] = np.argmin(t, axis=0)
        total = t[back[i], np.arange(C)] + F[i]
    pick = np.empty(G, np.int64)
    pick[-1] = int(np.argmin(total))
    if not np.isfinite(total[pick[-1]]):
        return xb, fb
    for i in range(G - 1, 0, -1):
        pick[i - 1] = back[i, pick[i]]
    rows = np.arange(G)
    d, f = D[rows, pick], F[rows, pick]
    mid = E[np.arange(G - 1), pick[:-1], pick[1:]]
    best = (d, f, max(float(f.max()), float(mid.max())))
    # where two valleys come within a scan step of each other, the scan sees one, and the path may still
    # jump there: the jump-free run that is longest, continued along its own valley to both ends
    jump = mid > JUMP * np.maximum(f[:-1], f[1:]) + 1e-12 * max(float(f.max()), 1e-300)
    if jump.any():
        cd, cf, cm = _continued(cost, sig, lo, hi, d, f, jump, rounds)
        if cm < best[2]:
            best = (cd, cf, cm)
    return best[0], best[1]


# a step between consecutive rulings whose halfway ruling is this many times farther than both: a jump
JUMP = 4.0


def _continued(cost: Callable, sig: np.ndarray, lo: np.ndarray, hi: np.ndarray, d: np.ndarray, f: np.ndarray,
               jump: np.ndarray, rounds: int) -> tuple:
    """(delta, cost, worst) of the rulings d (costs f, a jump after each True of jump) with the longest
    run free of jumps continued to both ends, each next ruling searched in a narrow bracket about the
    run's linear extrapolation; worst: the largest cost of the rulings and of those halfway between."""
    G = sig.size
    cuts = np.concatenate([[0], np.nonzero(jump)[0] + 1, [G]])
    k = int(np.argmax(np.diff(cuts)))
    a, b = int(cuts[k]), int(cuts[k + 1])          # the run: rulings a .. b - 1
    d, f = d.copy(), f.copy()
    floor = 1e-3 * float(np.abs(hi - lo).max())
    for start, stop, way in ((b, G, 1), (a - 1, -1, -1)):
        for i in range(start, stop, way):
            p1 = d[i - way]
            slope = d[i - way] - d[i - 2 * way] if 0 <= i - 2 * way < G else 0.0
            w = max(3.0 * abs(slope), floor)
            x0, x1 = np.array([max(p1 + slope - w, lo[i])]), np.array([min(p1 + slope + w, hi[i])])
            if x1[0] <= x0[0]:
                x0, x1 = np.array([lo[i]]), np.array([hi[i]])
            xv, fv = golden(lambda x: cost(np.array([sig[i]]), x), x0, x1, rounds)
            d[i], f[i] = xv[0], fv[0]
    mid = cost(0.5 * (sig[:-1] + sig[1:]), 0.5 * (d[:-1] + d[1:]))
    return d, f, max(float(f.max()), float(mid.max()))


# ----------------------------------------------------------------------------- smooth pairing
def _end_knots(sig: np.ndarray, weights: np.ndarray, k: int = 3) -> np.ndarray:
    """k knots in each run of light rulings (weights below 1: past the face) at the ends of an open
    pairing, where it turns to meet the patch's corners: the turn is free, and these let it be sharp
    without bending the pairing over the face."""
    heavy = np.nonzero(weights >= 1.0)[0]
    if heavy.size == 0:
        return np.empty(0)
    out = []
    for a, b in ((float(sig[0]), float(sig[heavy[0]])), (float(sig[heavy[-1]]), float(sig[-1]))):
        if b - a > 1e-9:
            out.append(np.linspace(a, b, k + 2)[1:-1])
    return np.concatenate(out) if out else np.empty(0)


def _clamped_knots(n_coef: int, p: int, a: float, b: float) -> np.ndarray:
    inner = np.linspace(a, b, n_coef - p + 1)[1:-1]
    return np.concatenate([np.full(p + 1, a), inner, np.full(p + 1, b)])


# the smooth pairing's coefficients at most (uniform knots; a pairing that follows exact rulings may
# halve its spans up to four times this many)
MAX_DELTA_COEFS = 48


def delta_coefs(n: int) -> int:
    """Coefficients of the smooth pairing delta(sigma) for n boundary samples."""
    return int(min(max(8, n // 2 + 4), MAX_DELTA_COEFS))


def smooth_pairing(S: Surface, sig: np.ndarray, delta: np.ndarray, closed: bool, n_coef: int,
                   interior: Optional[np.ndarray] = None) -> Pairing:
    """fit_delta of the refined rulings (sigma, delta); on a face's extended patch, the rulings past the
    face light (face_weights), and the end rulings free where the face allows (face_ends)."""
    weights = face_weights(S, sig, delta)
    ends = None if closed or weights is None else face_ends(S, sig, delta)
    if ends is not None:
        keep = (sig >= ends[0]) & (sig <= ends[2])
        sig, delta, weights = sig[keep], delta[keep], weights[keep]
        if interior is not None:
            interior = interior[(interior > ends[0]) & (interior < ends[2])]
    return fit_delta(sig, delta, closed, n_coef, weights=weights, interior=interior, ends=ends)


def fit_delta(sig: np.ndarray, delta: np.ndarray, closed: bool, n_coef: int, eps: float = 0.01,
              weights: Optional[np.ndarray] = None, interior: Optional[np.ndarray] = None,
              ends: Optional[tuple] = None) -> Pairing:
    """Least-squares cubic delta(sigma) with |delta'| <= 1 - eps (strictly monotone pairing); uniform
    knots, or the given interior knots (then n_coef is ignored)."""
    p = 3
    free = ends is not None and not closed
    s0 = float(ends[0]) if free else float(sig[0])
    s1 = float(ends[2]) if free else s0 + 1.0
    if interior is None:
        interior = _clamped_knots(max(n_coef, p + 2), p, s0, s1)[p + 1:-p - 1]
        if weights is not None and not closed:      # (given interior knots hold them already)
            interior = np.concatenate([interior, _end_knots(sig, weights)])
    t = np.concatenate([np.full(p + 1, s0), np.sort(interior), np.full(p + 1, s1)])
    n = t.size - p - 1
    g = (t[p + 1: p + n] - t[1:n]) / p  # c_{i+1} - c_i = g_i d_i
    Nmat = bspline_basis_matrix(t, p, sig)
    y = delta
    if closed:
        # append the closing sample so both ends are fitted
        Nmat = np.vstack([Nmat, bspline_basis_matrix(t, p, np.array([s1]))])
        y = np.concatenate([y, y[:1]])
    w = np.ones(len(y)) if weights is None else np.concatenate([weights, weights[:1]] if closed else [weights])
    # c = T x, x = (c0, d_0..d_{n-2})
    T = np.zeros((n, n))
    T[:, 0] = 1.0
    for i in range(1, n):
        T[i, 1:i + 1] = g[:i]
    A = (Nmat @ T) * w[:, None]
    rhs = y * w
    W = 1e4 * np.sqrt(len(y))
    if free:
        # the end values: c_0 = delta_a, c_last = c_0 + sum g d = delta_b
        rows = [np.eye(1, n)[0] * W, np.concatenate([[1.0], g]) * W]
        vals = [float(ends[1]), float(ends[3])]
    else:
        rows = [np.concatenate([[0.0], g]) * W]  # sum g d = 0 : c_last = c_0
        vals = [0.0]
    if closed:
        r = np.zeros(n)
        r[1] = 1.0
        r[n - 1] = -1.0
        rows.append(r * W)  # equal end slopes
        vals.append(0.0)
        h0 = (t[p + 2] - t[2]) / (p - 1)
        h1 = (t[n + p - 1] - t[n - 1]) / (p - 1)
        r2 = np.zeros(n)
        r2[1], r2[2] = -1.0 / h0, 1.0 / h0
        r2[n - 2] -= -1.0 / h1
        r2[n - 1] -= 1.0 / h1
        rows.append(r2 * W * 1e-2)
        vals.append(0.0)
    A = np.vstack([A] + [np.array(rows)])
    rhs = np.concatenate([rhs, np.array(vals) * W])
    lim = 1.0 - eps
    lb = np.full(n, -lim)
    ub = np.full(n, lim)
    if closed or free:
        lb[0], ub[0] = -1.0, 1.0
        sol = bounded_lstsq(A, rhs, lb, ub)
    else:
        sol = np.concatenate([[0.0], bounded_lstsq(A[:, 1:], rhs, lb[1:], ub[1:])])
    c = T @ sol
    if closed:
        c[-1] = c[0]
    elif free:
        c[0], c[-1] = float(ends[1]), float(ends[3])
    else:
        c[0] = 0.0
        c[-1] = 0.0
    return Pairing(Curve(c[:, None], t, p), s0, closed, s1 - s0)


def bounded_lstsq(A: np.ndarray, b: np.ndarray, lb: np.ndarray, ub: np.ndarray) -> np.ndarray:
    """min |A x - b| with lb <= x <= ub, by a primal active-set method (the problems are small: the
    pairing's coefficients).  From the unconstrained solution clipped to the box: solve for the free
    variables with the others at their bounds; step towards that solution until a bound blocks (it
    joins the bound set), or, where it is feasible, release the bound variable whose gradient points
    most into the box, until none does (the KKT conditions; the problem is convex, so that is the
    optimum).  scipy's bounded-variable least squares only if this does not settle (its import costs
    0.4 s)."""
    n = A.shape[1]
    x = np.clip(np.linalg.lstsq(A, b, rcond=None)[0], lb, ub)
    at_lo, at_hi = x <= lb, x >= ub
    tol = 1e-12 * max(1.0, float(np.abs(b).max(initial=0.0)))
    for _ in range(10 * n + 10):
        free = ~(at_lo | at_hi)
        y = x.copy()
        if free.any():
            y[free] = np.linalg.lstsq(A[:, free], b - A[:, ~free] @ x[~free], rcond=None)[0]
        lo_hit, hi_hit = free & (y < lb), free & (y > ub)
        if lo_hit.any() or hi_hit.any():
            # step towards y until the first bound blocks
            d = y - x
            with np.errstate(divide="ignore", invalid="ignore"):
                r = np.where(lo_hit, (lb - x) / d, np.where(hi_hit, (ub - x) / d, np.inf))
            alpha = float(np.clip(r.min(), 0.0, 1.0))
            x = np.clip(x + alpha * d, lb, ub)
            at_lo |= free & (x <= lb + 1e-15 * np.abs(lb))
            at_hi |= free & (x >= ub - 1e-15 * np.abs(ub))
            continue
        x = y
        g = A.T @ (A @ x - b)
        # a variable at its lower bound whose gradient is negative (or at its upper bound, positive)
        # would lower the objective by moving into the box
        viol = np.where(at_lo, -g, 0.0) + np.where(at_hi, g, 0.0)
        k = int(np.argmax(viol))
        if viol[k] <= tol:
            return x
        at_lo[k] = at_hi[k] = False
    from scipy.optimize import lsq_linear
    return lsq_linear(A, b, bounds=(lb, ub), method="bvls").x
