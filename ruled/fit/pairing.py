"""The DP pairing made continuous: its refinement by golden-section search, and the smooth
reparametrization delta(s) fitted to it under bounds (Elber eq. 5; the rulings' ends as functions of one
parameter)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Optional

import numpy as np

from ruled.core.basis import bspline_basis_matrix
from ruled.core.distance import ruling_distances
from ruled.core.nurbs import Curve, Surface

_GOLD = 0.5 * (np.sqrt(5.0) - 1.0)


@dataclass(frozen=True)
class Pairing:
    """A smooth strictly monotone pairing a(s), b(s), s in [0, 1] (normalized boundary parameters)."""

    delta: Curve          # delta(sigma) as a 1D cubic B-spline on [sigma0, sigma0 + 1]
    sigma0: float
    closed: bool

    def ab(self, s) -> tuple[np.ndarray, np.ndarray]:
        s = np.asarray(s, float)
        sig = self.sigma0 + s
        d = self.delta(sig)[:, 0]
        return sig - d, sig + d

    def inverse(self, x: np.ndarray, which: str, dense: int = 4001) -> np.ndarray:
        """s with a(s) = x (which='a') or b(s) = x, for x in the pairing's range (unwrapped)."""
        sd = np.linspace(0.0, 1.0, dense)
        a, b = self.ab(sd)
        f = a if which == "a" else b
        sign = -1.0 if which == "a" else 1.0
        s = np.interp(np.asarray(x, float), f, sd)
        for _ in range(3):  # Newton polish on the smooth spline
            sig = self.sigma0 + s
            d0, d1 = self.delta.evaluate(sig, 1)
            s = np.clip(s - (sig + sign * d0[:, 0] - x) / (1.0 + sign * d1[:, 0]), 0.0, 1.0)
        return s


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

    def cost(d):
        _, c = ruling_distances(S, u0 + L * (sig - d), u0 + L * (sig + d), m, iters, closed)
        return c

    c_dp = cost(d_dp)
    x1 = hi - _GOLD * (hi - lo)
    x2 = lo + _GOLD * (hi - lo)
    f1, f2 = cost(x1), cost(x2)
    for r in range(rounds):
        left = f1 <= f2  # minimum in [lo, x2]
        hi = np.where(left, x2, hi)
        lo = np.where(left, lo, x1)
        nx1 = hi - _GOLD * (hi - lo)
        nx2 = lo + _GOLD * (hi - lo)
        # reuse one evaluation per side
        newx = np.where(left, nx1, nx2)
        fn = cost(newx)
        x2, f2, x1, f1 = (np.where(left, x1, nx2), np.where(left, f1, fn),
                          np.where(left, nx1, x2), np.where(left, fn, f2))
        if progress is not None:
            progress(r + 1, rounds)
    xb = np.where(f1 <= f2, x1, x2)
    fb = np.minimum(f1, f2)
    # keep the DP pairing unless the search really improves it (flat costs, e.g. on a plane)
    noise = 1e-12 * S.diagonal()
    use_dp = c_dp <= fb + noise
    return sig, np.where(use_dp, d_dp, xb), np.where(use_dp, c_dp, fb)


# ----------------------------------------------------------------------------- smooth pairing
def _clamped_knots(n_coef: int, p: int, a: float, b: float) -> np.ndarray:
    inner = np.linspace(a, b, n_coef - p + 1)[1:-1]
    return np.concatenate([np.full(p + 1, a), inner, np.full(p + 1, b)])


# the smooth pairing's coefficients at most (uniform knots; a pairing that follows exact rulings may
# halve its spans up to four times this many)
MAX_DELTA_COEFS = 48


def delta_coefs(n: int) -> int:
    """Coefficients of the smooth pairing delta(sigma) for n boundary samples."""
    return int(min(max(8, n // 2 + 4), MAX_DELTA_COEFS))


def fit_delta(sig: np.ndarray, delta: np.ndarray, closed: bool, n_coef: int, eps: float = 0.01,
              weights: Optional[np.ndarray] = None, interior: Optional[np.ndarray] = None) -> Pairing:
    """Least-squares cubic delta(sigma) with |delta'| <= 1 - eps (strictly monotone pairing); uniform
    knots, or the given interior knots (then n_coef is ignored)."""
    p = 3
    s0 = float(sig[0])
    s1 = s0 + 1.0
    if interior is None:
        n = max(n_coef, p + 2)
        t = _clamped_knots(n, p, s0, s1)
    else:
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
    if closed:
        lb[0], ub[0] = -1.0, 1.0
        sol = bounded_lstsq(A, rhs, lb, ub)
    else:
        sol = np.concatenate([[0.0], bounded_lstsq(A[:, 1:], rhs, lb[1:], ub[1:])])
    c = T @ sol
    if closed:
        c[-1] = c[0]
    else:
        c[0] = 0.0
        c[-1] = 0.0
    return Pairing(Curve(c[:, None], t, p), s0, closed)


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
