"""Flank tool positions fitted by the tool's envelope (issue 61): the tool axes moved from the offset rulings so
that the swept tool lies as close to the face as it can on the chosen side, its overcut held.

The offset rulings (ruled.machine.paths.Lines: each ruling offset by the tool radius along the normal, the
straight line closest to that offset curve) are exact for a cylinder or a cone and leave a twisted face: the
cylinder touching a twisted ruling along its length cuts into the face beside it.  Here the tool's tip and top
are moved across the axis by smooth functions of the ruling parameter u (cubic B-splines, periodic on a closed
path; 4 per basis function: tip and top, two directions each), so the axis between any two stations moves
smoothly too.  The path is then a continuous family of tool positions; the face's points are measured against
the tool swept through it (the swept measure's signed distance, ruled.machine.swept; the offset rulings sampled
16 times a station's move, linear between: within 1/256 of the chord tolerance of them), each point at its
nearest position: the nearest of positions at most half the tool radius apart, then a golden-section search.
A face's points are the fit's data (not the measure's: the hosts take 34 x 34 of them, the measure
its own); the coefficients are at most a quarter of the rows of points across the path (several rows of
points per function: fewer points would let the fit bend the tool between them).

The fit is a sequence of linear programs (trust region): each point's signed distance to the swept tool is
linearized in the coefficients at its nearest position (its derivative with respect to the tool's tip and top
there is exact: moving the axis by dT at the tip and dU at the top moves the tool's side at the height h by
(1 - h/L) dT + (h/L) dU; for a cone the height's change counts through the taper), and

    minimize  t + W s   subject to   -t <= d_j <= t,   d_j >= -hold - s,   |step| <= trust radius,

t the largest deviation, hold the overcut allowed to the family (the gouge tolerance less the chords the
machine's straight moves add), s what a step cannot yet hold of it.  A step is kept when the true figure (every
point measured again, its nearest position searched again) is smaller; the trust radius grows on good steps
and shrinks on bad ones; the fit stops when the last four kept steps gained less than 2 % together.  The linear
programs are solved on the points nearest to binding and then on every point a step breaks, until it breaks
none (the program of every point, on a few hundred of them)."""

from __future__ import annotations

import math
from typing import Callable

import numpy as np

from ruled.core.basis import bspline_basis_matrix, periodic_knots
from ruled.core.progress import Progress
from ruled.machine.swept import Tool, nearest_along

_W = 10.0              # weight of an overcut past the hold against the largest deviation
_ROUNDS = 40           # linear programs at most
_STEPS = 2             # positions per station's move searched before the golden section
_STALL, _STALLED = 4, 0.02   # stop when the last _STALL kept steps gained less than this fraction together
_COARSE = 20000        # positions searched first, at most
_WORKING = 150         # the points each way the linear program starts with
_FINE = 16             # the offset rulings' samples per station's move (the family linear between them)

Ends = Callable[[np.ndarray], np.ndarray]      # u (n,) -> (n, 2, 3): the tool's tip and top at u


def _reference(A: np.ndarray) -> np.ndarray:
    """A direction far from every axis of A (n, 3): the frames across the axes are built from it."""
    c = np.array([[1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 0], [1, -1, 0], [1, 0, 1], [1, 0, -1], [0, 1, 1],
                  [0, 1, -1], [1, 1, 1], [1, 1, -1], [1, -1, 1], [-1, 1, 1]], float)
    c /= np.linalg.norm(c, axis=1)[:, None]
    return c[int(np.argmin(np.abs(A @ c.T).max(axis=0)))]


def _frames(E: np.ndarray, ref: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit directions across each axis of the (n, 2, 3) tips and tops, smooth in the axis."""
    A = E[:, 1] - E[:, 0]
    A /= np.linalg.norm(A, axis=1)[:, None]
    e1 = np.cross(ref, A)
    e1 /= np.linalg.norm(e1, axis=1)[:, None]
    return e1, np.cross(A, e1)


def _basis(u: np.ndarray, u0: float, u1: float, k: int, closed: bool) -> np.ndarray:
    """(n, k) cubic B-spline basis in u: uniform, periodic on a closed path, clamped at the ends otherwise."""
    if closed:
        knots = periodic_knots(np.linspace(u0, u1, k + 1), 3)
        x = u0 + np.mod(np.asarray(u, float) - u0, u1 - u0)
        B = bspline_basis_matrix(knots, 3, x)
        B[:, :3] += B[:, k:]
        return B[:, :k]
    knots = np.concatenate([[u0] * 4, np.linspace(u0, u1, k - 2)[1:-1], [u1] * 4])
    return bspline_basis_matrix(knots, 3, np.clip(np.asarray(u, float), u0, u1))


def _moved(E: np.ndarray, e1: np.ndarray, e2: np.ndarray, B: np.ndarray, C: np.ndarray) -> np.ndarray:
    """The tips and tops E (n, 2, 3) moved across their axes (frames e1, e2) by the basis B (n, k) times the
    coefficients C (k, 4)."""
    d = B @ C
    out = E.copy()
    out[:, 0] += d[:, :1] * e1 + d[:, 1:2] * e2
    out[:, 1] += d[:, 2:3] * e1 + d[:, 3:4] * e2
    return out


class Corrected:
    """The tool's tips and tops at u: the offset rulings' moved across their axes by the B-spline
    coefficients C (k, 4) (tip e1, tip e2, top e1, top e2)."""

    def __init__(self, base: Ends, u0: float, u1: float, closed: bool, ref: np.ndarray, C: np.ndarray):
        self.base, self.u0, self.u1, self.closed, self.ref, self.C = base, u0, u1, closed, ref, C

    def parts(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        E = self.base(u)
        e1, e2 = _frames(E, self.ref)
        return E, e1, e2, _basis(u, self.u0, self.u1, self.C.shape[0], self.closed)

    def __call__(self, u: np.ndarray) -> np.ndarray:
        return _moved(*self.parts(np.asarray(u, float).ravel()), self.C)


def _gradients(T: np.ndarray, A: np.ndarray, L: np.ndarray, X: np.ndarray, taper_deg: float):
    """(N, 3) x 2: the derivatives of each point's signed distance to the tool (tip T, unit axis A, length L)
    with respect to the tool's tip and its top."""
    D = X - T
    h = np.einsum("ij,ij->i", D, A)
    R = D - h[:, None] * A
    rho = np.linalg.norm(R, axis=1)
    n = R / np.where(rho > 0, rho, 1.0)[:, None]
    s, q = (h / L)[:, None], (rho / L)[:, None]
    a = math.radians(taper_deg)
    ca, ta = math.cos(a), math.tan(a)
    return ca * (-(1.0 - s) * n + ta * (A + q * n)), ca * (-s * n - ta * q * n)


class _Family:
    """The family as the fit sees it: the offset rulings' tips and tops linear between samples _FINE times denser
    than the stations (whose moves are within the chord tolerance of it: these within 1 / _FINE^2 of that;
    linear, so a wall's corners, where the offset turns or jumps, are followed without overshoot), moved across
    the axes by the coefficients; the points' nearest positions along it."""

    def __init__(self, base: Ends, u: np.ndarray, closed: bool, ref: np.ndarray, k: int, tool: Tool):
        m = u.size
        uf = np.unique(np.interp(np.arange(_FINE * (m - 1) + 1) / _FINE, np.arange(m), u))
        self.uf, self.Ef = uf, base(uf).reshape(-1, 6)
        self.u0, self.u1, self.closed, self.ref, self.k, self.tool = u[0], u[-1], closed, ref, k, tool
        # the positions searched first: _STEPS a station's move, and more where the tool moves by more than half
        # its radius in one (a long straight move: the side of a point far from both its ends reaches it only
        # from the positions near it)
        E = base(u)
        travel = np.linalg.norm(np.diff(E, axis=0), axis=2).max(axis=1)
        steps = np.maximum(_STEPS, np.ceil(travel / (0.5 * tool.radius)))
        if steps.sum() > _COARSE:               # (a thin tool on a long path: as many as the memory allows)
            steps = np.maximum(_STEPS, np.floor(steps * _COARSE / steps.sum()))
        steps = steps.astype(np.int64)
        self.coarse = np.concatenate([np.linspace(a, b, n, endpoint=False) for a, b, n in zip(u[:-1], u[1:], steps)]
                                     + [u[-1:]])

    def at(self, uu: np.ndarray, C: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(tips and tops (n, 2, 3), e1, e2, basis) at the parameters uu."""
        uu = np.asarray(uu, float)
        i = np.clip(np.searchsorted(self.uf, uu, side="right") - 1, 0, self.uf.size - 2)
        w = np.clip((uu - self.uf[i]) / (self.uf[i + 1] - self.uf[i]), 0.0, 1.0)[:, None]
        E = (self.Ef[i] + w * (self.Ef[i + 1] - self.Ef[i])).reshape(-1, 2, 3)
        e1, e2 = _frames(E, self.ref)
        B = _basis(uu, self.u0, self.u1, self.k, self.closed)
        return _moved(E, e1, e2, B, C), e1, e2, B

    @staticmethod
    def _tal(E: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        D = E[..., 1, :] - E[..., 0, :]
        L = np.linalg.norm(D, axis=-1)
        return E[..., 0, :], D / L[..., None], L

    def nearest(self, X: np.ndarray, C: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(signed distances, parameters u of the positions that give them) of the points X to the tool swept
        through the family: the nearest of the coarse positions, then a golden-section search beside it."""
        return nearest_along(self.tool, X, self.coarse, lambda uu: self._tal(self.at(uu, C)[0]), 30)

    def jacobian(self, X: np.ndarray, uu: np.ndarray, C: np.ndarray) -> np.ndarray:
        """(N, 4k): the signed distances' derivatives with respect to the coefficients (tip e1, tip e2, top e1,
        top e2 blocks) at the positions uu (the nearest: the distance is a minimum over u, so its derivative is
        the one at the position that gives it)."""
        E, e1, e2, B = self.at(uu, C)
        gT, gU = _gradients(*self._tal(E), X, self.tool.taper_deg)
        return np.hstack([np.einsum("ij,ij->i", g, e)[:, None] * B for g in (gT, gU) for e in (e1, e2)])


def _cuts(d: np.ndarray) -> dict:
    d = d[np.isfinite(d)]
    return {"overcut": float(max(0.0, -d.min(initial=0.0))), "undercut": float(max(0.0, d.max(initial=0.0)))}


def _merit(d: np.ndarray, hold: float) -> float:
    """The largest deviation and the weighted overcut past the hold (inf: no point reached)."""
    if d.size == 0:
        return math.inf
    return float(np.abs(d).max() + _W * max(0.0, float(-d.min()) - hold))


def _top(x: np.ndarray, n: int) -> np.ndarray:
    """A mask of the n largest of x."""
    m = np.zeros(x.size, bool)
    m[np.argpartition(-x, n - 1)[:n] if n < x.size else slice(None)] = True
    return m


def _step(d: np.ndarray, J: np.ndarray, hold: float, trust: float) -> tuple[np.ndarray, float]:
    """The linear program's step (4k,) and its predicted merit.  Solved on the points nearest to binding (the
    largest deviations each way), then again with every point whose constraint the step breaks, until it
    breaks none: the program of every point, solved on a few hundred."""
    from scipy.optimize import linprog
    N, m = J.shape
    n0 = min(N, _WORKING)
    act = [_top(d, n0), _top(-d, n0), _top(-d - hold, n0)]
    c = np.zeros(m + 2)
    c[m], c[m + 1] = 1.0, _W
    eps = 1e-12 * (1.0 + float(np.abs(d).max()))
    for _ in range(20):
        rows, rhs = [], []
        for sel, sign, slack in zip(act, (1.0, -1.0, -1.0), (False, False, True)):
            tcol = np.zeros((int(sel.sum()), 2))
            tcol[:, 1 if slack else 0] = -1.0
            rows.append(np.hstack([sign * J[sel], tcol]))
            rhs.append(d[sel] + hold if slack else -sign * d[sel])
        res = linprog(c, A_ub=np.vstack(rows), b_ub=np.concatenate(rhs),
                      bounds=[(-trust, trust)] * m + [(0, None), (0, None)], method="highs-ds")
        if res.status != 0 or res.x is None:
            return np.zeros(m), math.inf
        x, t, sl = res.x[:m], res.x[m], res.x[m + 1]
        v = d + J @ x
        broken = [(v > t + eps) & ~act[0], (-v > t + eps) & ~act[1], (-v > hold + sl + eps) & ~act[2]]
        if not any(b.any() for b in broken):
            return x, float(res.fun)
        act = [a | b for a, b in zip(act, broken)]
    return np.zeros(m), math.inf


def envelope_positions(base: Ends, u: np.ndarray, closed: bool, radius: float, taper_deg: float, X: np.ndarray,
                       hold: float, progress: Progress = None) -> tuple[Corrected, dict]:
    """The tool's tips and tops as functions of u (a Corrected) fitted to the points X (N, 3) of the face, from
    the offset rulings `base`, on the grid u of stations (its moves within a fraction of the chord tolerance
    of the family), the overcut held at `hold`; and the fit's figures."""
    u, X = np.asarray(u, float), np.asarray(X, float).reshape(-1, 3)
    u0, u1 = float(u[0]), float(u[-1])
    E0 = base(u)
    ref = _reference(E0[:, 1] - E0[:, 0])
    k = int(np.clip(min(u.size // 6, math.sqrt(X.shape[0]) / 4), 4, 24))    # several rows of points per function
    fam = Corrected(base, u0, u1, closed, ref, np.zeros((k, 4)))
    model = _Family(base, u, closed, ref, k, Tool(E0[:, 0], E0[:, 1], radius, taper_deg))
    C = fam.C
    d, g = model.nearest(X, C)
    ok = np.isfinite(d)
    X, d, g = X[ok], d[ok], g[ok]
    before = _cuts(d)
    if X.shape[0] == 0:
        return fam, {"method": "offset rulings (no point of the face within the tool's reach)", "rounds": 0}
    merit = _merit(d, hold)
    trust = max(min(float(np.abs(d).max()), radius), 1e-9 * (1.0 + radius))
    floor = 1e-3 * trust
    rounds, history = 0, [merit]
    for it in range(_ROUNDS):
        if progress:
            progress("tool positions fitted to the envelope", it / _ROUNDS)
        f = np.isfinite(d)
        step, predicted = _step(d[f], model.jacobian(X[f], g[f], C), hold, trust)
        if not math.isfinite(predicted):        # (the solver's numerical trouble: a smaller region)
            trust *= 0.3
            if trust < floor:
                break
            continue
        if not predicted < merit * (1.0 - 1e-3):
            break
        rounds += 1
        d2, g2 = model.nearest(X, C + step.reshape(4, k).T)
        new = _merit(d2[np.isfinite(d2)], hold)
        if new < merit:
            gain = (merit - new) / (merit - predicted)
            C, d, g, merit = C + step.reshape(4, k).T, d2, g2, new
            history.append(merit)
            if len(history) > _STALL and history[-1] > (1.0 - _STALLED) * history[-1 - _STALL]:
                break           # (gaining less than 2 % in the last rounds: the positions' noise, not the fit)
            if gain > 0.5:
                trust = min(2.0 * trust, radius)
        else:
            trust *= 0.3
            if trust < floor:
                break
    if progress:
        progress("tool positions fitted to the envelope", 1.0)
    fam.C = C
    return fam, {"method": "envelope: the tool's tip and top moved across its axis by cubic B-splines in u, fitted "
                           "by linear programs to the face's points against the swept tool",
                 "basis_functions": k, "rounds": rounds, "points": int(X.shape[0]), "hold": hold,
                 "before": before, "after": _cuts(d)}


__all__ = ["Corrected", "envelope_positions"]
