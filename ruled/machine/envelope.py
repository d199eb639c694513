"""What a machine path cuts: the tool's envelope against the face, and points of the exact lines for the
independent measure (the surface the wire sweeps: ruled.machine.wirecut)."""

from __future__ import annotations

import math

import numpy as np

from ruled.core.nurbs import Surface
from ruled.core.progress import Progress
from ruled.machine.paths import MachinePath
from ruled.machine.sync import _seeds, tool_between


def tool_envelope(S: Surface, side: float, path: MachinePath, slices: int = 17, moves: bool = True,
                  iters: int = 5, progress: Progress = None, keep=None) -> dict:
    """Over- and undercut of the tool against the design surface S, measured on the tool surfaces: at
    every CL position (and, with moves=True, half way through every move), on `slices` circles along
    the tool, the point of each circle deepest towards S (alternating projections onto S, exact
    Newton feet); its signed distance along S's normal on the side `side` (negative: inside the
    material, an overcut; positive: material left, an undercut).  keep(s, t): only the circles at the
    ruling s and the fraction t along the tool for which it is true count (the tool over a trimmed
    face: its rulings run past the face, and what the tool does there is not a cut of the face)."""
    from ruled.core.distance import project_points
    lo, hi, us = path.lower, path.upper, np.asarray(path.u, float)
    if moves:       # (half way through a move as the machine moves the tool: ruled.machine.sync.tool_between)
        E = np.stack([lo, hi], axis=1)
        mid = tool_between(E[:-1], E[1:], np.full((len(lo) - 1, 1, 1), 0.5))
        lo = np.concatenate([lo, mid[:, 0]])
        hi = np.concatenate([hi, mid[:, 1]])
        us = np.concatenate([us, 0.5 * (us[1:] + us[:-1])])
    n_cl = path.lower.shape[0]
    ax = hi - lo
    Lx = np.linalg.norm(ax, axis=1)
    a = ax / Lx[:, None]
    s = np.linspace(0.0, 1.0, slices)
    C = (lo[:, None] + s[None, :, None] * ax[:, None]).reshape(-1, 3)
    A = np.repeat(a, slices, axis=0)
    rho = (path.radius + s[None, :] * Lx[:, None] * math.tan(math.radians(path.taper_deg))).ravel()
    cu, cv = S.periodic_u, S.periodic_v
    uv = _seeds(S, C)
    uv, _ = project_points(S, C, uv, iters=8, closed_u=cu, closed_v=cv)
    q = C
    for k in range(iters):
        if progress:
            progress("tool envelope", k / iters)
        D = S.evaluate(uv[:, 0], uv[:, 1], 1)
        nrm = side * D.normals()
        w = -nrm - np.einsum("ij,ij->i", -nrm, A)[:, None] * A
        w /= np.maximum(np.linalg.norm(w, axis=1), 1e-300)[:, None]
        q = C + rho[:, None] * w
        uv, _ = project_points(S, q, uv, iters=6, closed_u=cu, closed_v=cv)
    D = S.evaluate(uv[:, 0], uv[:, 1], 1)
    sd = np.einsum("ij,ij->i", q - D.P, side * D.normals()).reshape(-1, slices)
    if progress:
        progress("tool envelope", 1.0)
    over = np.ones(sd.shape, bool) if keep is None else \
        np.asarray(keep(np.repeat(us, slices), np.tile(s, us.size)), bool).reshape(sd.shape)

    def ext(rows):
        x = np.where(over[rows], sd[rows], np.nan)
        if np.isnan(x).all():
            return {"overcut": 0.0, "undercut": 0.0, "overcut_at": None, "undercut_at": None}
        i_over = np.unravel_index(int(np.nanargmin(x)), x.shape)
        i_under = np.unravel_index(int(np.nanargmax(x)), x.shape)
        return {"overcut": float(max(0.0, -x[i_over])), "undercut": float(max(0.0, x[i_under])),
                "overcut_at": q.reshape(-1, slices, 3)[rows][i_over].tolist(),
                "undercut_at": q.reshape(-1, slices, 3)[rows][i_under].tolist()}

    out = {"cl_positions": ext(slice(0, n_cl)), "samples": int(over.sum())}
    if moves:
        out["with_moves"] = ext(slice(0, sd.shape[0]))
    return out


def cut_points(path: MachinePath, count: int = 2700, along: int = 11, exact: bool = False, keep=None) -> np.ndarray:
    """About `count` points of the swept lines inside the part: lines evenly inside every move (the first
    at its start), each sampled at `along` points between its part ends, whose fractions of the line are
    interpolated between those of the synchronized lines (exact there).  exact=True gives the same
    points on the exact lines (path.trace at the same parameter), the ruled surface's counterparts of
    the machine's: each machine point is within the chord tolerance of its counterpart.  keep(s, t): only the
    points at the ruling s and the fraction t between the part's ends for which it is true."""
    lo, hi = path.lower, path.upper
    d = hi - lo
    L2 = np.einsum("ij,ij->i", d, d)
    fa = np.einsum("ij,ij->i", path.part[:, 0] - lo, d) / L2
    fb = np.einsum("ij,ij->i", path.part[:, 1] - lo, d) / L2
    n = lo.shape[0]
    per_move = max(1, int(round(count / (along * max(n - 1, 1)))))
    t = np.linspace(0.0, 1.0, along)
    parts = []
    for i in range(n - 1):
        ss = np.arange(per_move) / per_move
        if i == n - 2:
            ss = np.append(ss, 1.0)
        if exact:
            E = path.trace(path.u[i] + ss * (path.u[i + 1] - path.u[i]))
            a, b = E[:, 0], E[:, 1]
        else:
            a = lo[i] + ss[:, None] * (lo[i + 1] - lo[i])
            b = hi[i] + ss[:, None] * (hi[i + 1] - hi[i])
        f0 = fa[i] + ss * (fa[i + 1] - fa[i])
        f1 = fb[i] + ss * (fb[i + 1] - fb[i])
        fr = f0[:, None] + t[None, :] * (f1 - f0)[:, None]
        pts = (a[:, None] + fr[..., None] * (b - a)[:, None]).reshape(-1, 3)
        if keep is not None:
            s = np.repeat(path.u[i] + ss * (path.u[i + 1] - path.u[i]), along)
            pts = pts[keep(s, np.tile(t, ss.size))]
        parts.append(pts)
    return np.concatenate(parts)
