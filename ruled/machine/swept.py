"""What a flank tool leaves of the face, measured from the face: its points' signed distances to the tool swept
through the moves (issue 61's envelope measure).  Independent of how the path was made: only the CL data (tip
points, axes, the tool's radius and taper) and points of the face are used.

The tool at one position is a cylinder (or a cone of half angle a) about the axis from its tip centre, of
radius r + h tan a at the height h along it.  Between two CL positions the machine moves the tip and the axis
linearly (the axis renormalized): the tool is placed at ``steps`` positions along every move, and from the
nearest, a search along the moves finds the nearest position of the continuous sweep.  A point's signed
distance to the tool at a position is its distance to the tool's side in the plane through the axis, (rho -
r(h)) cos a, where the foot on the side lies within the tool's length; the swept tool's is the smallest over
the positions (negative: inside the tool, the face cut away: an overcut or gouge; positive: material left: an
undercut).  A point that no position's side reaches (beyond the tool's ends) is counted apart."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, Protocol

import numpy as np

from ruled.core.nearest import golden
from ruled.machine.paths import MachinePath, flute_of
from ruled.machine.sync import tool_between

# the tool's side counts this fraction of its length past its two ends (the face's rails lie at its ends)
REACH = 1e-3


class Stations(Protocol):
    """What the sweep needs of a path: the tool's tips and tops at its stations, its radius and taper."""

    @property
    def lower(self) -> np.ndarray: ...
    @property
    def upper(self) -> np.ndarray: ...
    @property
    def radius(self) -> float: ...
    @property
    def taper_deg(self) -> float: ...
    @property
    def flute(self) -> float: ...


@dataclass(frozen=True)
class Tool:
    """A tool at stations that are not (yet) a machine path: tips (n, 3), tops (n, 3), radius, taper."""

    lower: np.ndarray
    upper: np.ndarray
    radius: float
    taper_deg: float = 0.0

    @property
    def flute(self) -> float:
        """The tool's cutting length: its longest position's."""
        return flute_of(self.lower, self.upper)


def tool_positions(path: Stations, g: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(tips, unit axes, lengths) of the tool at the path's continuous positions g (0: the first CL position, k:
    the k-th; between two, as the machine moves the tool: ruled.machine.sync.tool_between)."""
    E = np.stack([path.lower, path.upper], axis=1)
    g = np.clip(np.asarray(g, float), 0.0, E.shape[0] - 1.0)
    i = np.minimum(np.floor(g).astype(np.int64), max(E.shape[0] - 2, 0))
    j = np.minimum(i + 1, E.shape[0] - 1)
    P = tool_between(E[i], E[j], (g - i)[..., None, None])
    D = P[..., 1, :] - P[..., 0, :]
    L = np.linalg.norm(D, axis=-1)
    return P[..., 0, :], D / L[..., None], L


def _signed(path: Stations, X: np.ndarray, T: np.ndarray, A: np.ndarray, L) -> np.ndarray:
    """Signed distances of the points X (..., 3) to the tool's side at the positions (T, A; L their lengths, or
    one length for all: the flute) (broadcast); inf where the foot on the side is past the tool's ends."""
    alpha = math.radians(path.taper_deg)
    ca, sa, ta = math.cos(alpha), math.sin(alpha), math.tan(alpha)
    D = X - T
    h = np.einsum("...k,...k->...", D, A)
    rho = np.sqrt(np.maximum(np.einsum("...k,...k->...", D, D) - h * h, 0.0))
    gap = rho - (path.radius + h * ta)
    foot = h + gap * ca * sa                                          # the foot's height on the tool's side
    return np.where((foot >= -REACH * L) & (foot <= (1.0 + REACH) * L), gap * ca, np.inf)


def nearest_along(tool: Stations, X: np.ndarray, grid: np.ndarray, place: Callable, rounds: int = 40,
                  chunk: int = 64) -> tuple[np.ndarray, np.ndarray]:
    """(signed distance (N,), the parameter (N,) of the position that gives it; inf and the grid's first where no
    position's side reaches the point) of the points X (N, 3) to the tool (its radius and taper) at the positions
    place(s) -> (tips, unit axes, lengths) of a parameter s: the nearest of the positions at the increasing
    parameters `grid`, then a golden-section search between that one's neighbours (the sweep is continuous:
    the grid's positions alone would leave scallops between them)."""
    T, A, _ = place(grid)
    L = tool.flute          # (the real tool is its cutting length at every position, not its ruling's)
    X = np.asarray(X, float).reshape(-1, 3)
    best = np.full(len(X), np.inf)
    j = np.zeros(len(X), np.int64)
    chunk = max(1, min(chunk, 2_000_000 // grid.size))       # (the temporaries: some 50 bytes a point and position)
    for s in range(0, len(X), chunk):
        sd = _signed(tool, X[s:s + chunk, None, :], T[None], A[None], L)
        j[s:s + chunk] = np.argmin(sd, axis=1)
        best[s:s + chunk] = sd[np.arange(sd.shape[0]), j[s:s + chunk]]
    at = grid[j]
    ok = np.isfinite(best)
    if grid.size > 1 and ok.any():
        Xo = X[ok]

        def f(ss):
            return _signed(tool, Xo, *place(ss)[:2], L)
        lo, hi = grid[np.maximum(j[ok] - 1, 0)], grid[np.minimum(j[ok] + 1, grid.size - 1)]
        x, fx = golden(f, lo, hi, rounds)
        better = fx < best[ok]
        best[ok] = np.where(better, fx, best[ok])
        at[ok] = np.where(better, x, at[ok])
    return best, at


def nearest_positions(path: Stations, X: np.ndarray, steps: int = 8) -> tuple[np.ndarray, np.ndarray]:
    """nearest_along the path's moves (a MachinePath or a Tool): the continuous position g (0: the first CL
    position, k: the k-th) searched from `steps` positions per move."""
    n = path.lower.shape[0]
    return nearest_along(path, X, np.arange((n - 1) * steps + 1) / steps, lambda g: tool_positions(path, g))


def swept_distances(path: MachinePath, X: np.ndarray, steps: int = 8) -> tuple[np.ndarray, np.ndarray]:
    """(signed distance (N,), the CL index nearest the tool position that gives it (N,), -1 where no position's
    side reaches the point: distance inf) of the points X (N, 3) to the tool swept through the path's moves
    (nearest_positions)."""
    best, g = nearest_positions(path, X, steps)
    return best, np.where(np.isfinite(best), np.rint(g).astype(np.int64), -1)


def axis_angles(path: MachinePath) -> np.ndarray:
    """(n - 1,) degrees between consecutive tool axes."""
    a = path.axes
    return np.degrees(np.arccos(np.clip(np.einsum("ij,ij->i", a[1:], a[:-1]), -1.0, 1.0)))


def swept_measure(path: MachinePath, X: np.ndarray, steps: int = 8) -> dict:
    """The swept tool against the points X of the face: over- and undercut (the largest depth inside the tool,
    the largest distance left), where, per CL position (the largest of each over the points it cuts), the
    points no position reaches, and the largest angle between consecutive axes."""
    d, at = swept_distances(path, X, steps)
    ok = at >= 0
    n = path.lower.shape[0]
    over, under = np.zeros(n), np.zeros(n)
    np.maximum.at(over, at[ok], np.maximum(-d[ok], 0.0))
    np.maximum.at(under, at[ok], np.maximum(d[ok], 0.0))
    X = np.asarray(X, float).reshape(-1, 3)
    out: dict = {"method": f"the face's points against the tool: the nearest of {steps} positions per move, searched "
                           "along the moves", "points": int(ok.sum()),
                 "unreached": int((~ok).sum()), "overcut": 0.0, "undercut": 0.0, "overcut_at": None,
                 "undercut_at": None}
    if ok.any():
        i, j = int(np.argmin(np.where(ok, d, np.inf))), int(np.argmax(np.where(ok, d, -np.inf)))
        out.update(overcut=float(max(0.0, -d[i])), undercut=float(max(0.0, d[j])),
                   overcut_at=X[i].tolist(), undercut_at=X[j].tolist())
    ang = axis_angles(path)
    out.update(per_position={"overcut": over.tolist(), "undercut": under.tolist()},
               axis_angle_max_deg=float(ang.max(initial=0.0)))
    return out


__all__ = ["Tool", "tool_positions", "nearest_along", "nearest_positions", "swept_distances", "swept_measure",
           "axis_angles"]
