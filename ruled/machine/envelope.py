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
                  iters: int = 5, progress: Progress = None, keep=None, near=None) -> dict:
    """Over- and undercut of the tool against the design surface S, measured on the tool surfaces: at
    every CL position (and, with moves=True, half way through every move), on `slices` circles along
    the tool, the point of each circle deepest towards S (alternating projections onto S, exact
    Newton feet); its signed distance along S's normal on the side `side` (negative: inside the
    material, an overcut; positive: material left, an undercut), where its foot is an orthogonal foot (a circle
    beside the face, its nearest point held at the surface's edge, does not cut it).  keep(s, t): only the
    circles at the ruling s and the fraction t along the tool for which it is true count (the tool over a
    trimmed face: its rulings run past the face, and what the tool does there is not a cut of the face).
    near (N, 3): points of the face as bounded by its edges, the feet's first guesses (S may run far past the
    face: a trimmed fit's extended patch, whose nearest point to a wide tool's axis can lie out there); a
    circle counts only where its foot lies among them (within their spacing of one).
    The circles run along the tool's whole cutting length at every position (path.flute)."""
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
    # the circles along the tool's whole cutting length (the APT CUTTER's h) at every position: t their fractions
    # of the position's own line (past 1 where that is shorter)
    t = np.linspace(0.0, 1.0, slices)[None, :] * (path.flute / Lx)[:, None]
    C = (lo[:, None] + t[:, :, None] * ax[:, None]).reshape(-1, 3)
    A = np.repeat(a, slices, axis=0)
    rho = (path.radius + t * Lx[:, None] * math.tan(math.radians(path.taper_deg))).ravel()
    cu, cv = S.periodic_u, S.periodic_v
    tree = None
    if near is not None and len(near) > 5:
        # seeded from the face's points (S may run far past the face: a trimmed fit's extended patch, whose
        # nearest point to a wide tool's axis can lie out there)
        from scipy.spatial import cKDTree
        near = np.asarray(near, float)
        tree = cKDTree(near)
        uv_near, _ = project_points(S, near, _seeds(S, near), iters=8, closed_u=cu, closed_v=cv)
        uv = uv_near[tree.query(C)[1]]
    else:
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
    nrm = side * D.normals()
    r = q - D.P
    sd = np.einsum("ij,ij->i", r, nrm)
    # a circle whose deepest point's foot is held at the surface's edge and is no orthogonal foot there (the tool
    # beside the face, past it) does not cut the face there: the face's points against the swept tool see its edges
    tang = np.linalg.norm(r - sd[:, None] * nrm, axis=1)
    u0, u1, v0, v1 = S.domain
    eu, ev = 1e-9 * (u1 - u0), 1e-9 * (v1 - v0)
    held = np.zeros(len(uv), bool)
    if not cu:
        held |= (uv[:, 0] <= u0 + eu) | (uv[:, 0] >= u1 - eu)
    if not cv:
        held |= (uv[:, 1] <= v0 + ev) | (uv[:, 1] >= v1 - ev)
    orthogonal = (~held | (tang <= 1e-3 * np.abs(sd) + 1e-7 * S.diagonal())).reshape(-1, slices)
    if tree is not None:
        # a foot out on the extended patch, away from the face's points (a circle whose deepest point went
        # sideways, its axis along the normal there), is no point of the face: within the points' spacing
        # (their fourth neighbours': a grid's coarser direction too) of one of them
        reach = float(tree.query(near, k=5)[0][:, 4].max())
        orthogonal &= (tree.query(D.P)[0] <= reach).reshape(orthogonal.shape)
    sd = sd.reshape(-1, slices)
    if progress:
        progress("tool envelope", 1.0)
    over = orthogonal if keep is None else \
        orthogonal & np.asarray(keep(np.repeat(us, slices), t.ravel()), bool).reshape(sd.shape)

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


def overcut_said(rep: dict, path: MachinePath) -> str | None:
    """The flank measures' overcut held to the gouge tolerance, or said: rep["overcut"] gets the two independent
    figures (the face's points against the swept tool, rep["swept_tool"]; the tool's circles against the face,
    rep["tool_envelope"] with the moves), whether they agree within 10 %, and the larger, the figure; and the
    warning (None: held) where that larger figure is past the path's gouge tolerance (envelope positions)."""
    sw = (rep.get("swept_tool") or {}).get("overcut")
    en = ((rep.get("tool_envelope") or {}).get("with_moves") or {}).get("overcut")
    figs = [x for x in (sw, en) if x is not None]
    if not figs:
        return None
    larger = max(figs)
    floor = 1e-3 * max(path.chord_tol, 1e-12)       # (two figures at the round-off both agree)
    rep["overcut"] = {"swept_tool": sw, "tool_envelope": en, "larger": larger,
                      "agree": len(figs) < 2 or min(figs) >= 0.9 * larger or larger <= floor}
    gouge = (path.stats.get("positions") or {}).get("gouge_tol")
    if gouge is None or larger <= gouge * (1.0 + 1e-9):
        return None
    both = "; ".join(f"{w} {x:.3g}" for w, x in (("the face against the swept tool", sw),
                                                   ("the tool's circles against the face", en)) if x is not None)
    return (f"the tool overcuts the face by {larger:.3g} ({both}), past the gouge tolerance {gouge:.3g}: raise "
            f"«gouge_tol», or use a smaller tool or the offset positions")


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
