"""A wall's one closed wire path on plain arrays: the closed ruled result started where the user says on the
bottom contour (default: the middle of its longest straight edge, ties broken by a rule), running
counter-clockwise about the wall's axis, the wall's axis (the machine's, normal to
its contours' planes) and which side of the joined surface is the part's outside.  Hosts give the bottom
contour's edges (ruled.fit.wall.ring.RingEdge), the contours' points and the faces' outward normals
(ruled.occ.wallmachine for OCCT, the workbench's export for FreeCAD), so that both write the same path."""

from __future__ import annotations

import math
from typing import Callable, Optional

import numpy as np

from ruled.core.errors import BadInputError
from ruled.core.nurbs import Surface
from ruled.fit.wall.fit import piece

RAIL_SAMPLES = 4097      # samples of the result's bottom rail to place the start by
START_TOL = 1e-3         # «start» may be this fraction of the wall's size off the bottom contour


def started(R: Surface, s0: float) -> Surface:
    """The closed ruled surface R (rulings along v) running round from s = s0 (a knot of full multiplicity
    inserted there, the geometry unchanged), flagged closed."""
    from ruled.fit.wall.fit import clamped_u
    from ruled.fit.wall.join import along_u, with_knots
    R = clamped_u(R)            # (stored unwrapped: a host's periodic form)
    u0, u1 = R.domain[:2]
    if min(abs(s0 - u0), abs(s0 - u1)) <= 1e-12 * (u1 - u0):
        return R
    part = piece(along_u(R, lambda c: with_knots(c, {s0: R.degree_u})), s0, s0)
    return Surface(part.poles, part.knots_u, part.knots_v, part.degree_u, part.degree_v, part.weights,
                   periodic_u=True)


def start_parameter(R: Surface, bottom: list, size: float, start: Optional[tuple] = None) -> float:
    """R's s where the loop starts: at the bottom rail's point nearest (X, Y) (start, refused when it is
    farther than START_TOL of the wall's size from it), else nearest the middle of the bottom contour's
    longest straight edge (or of its longest edge); bottom: the bottom contour's edges (RingEdge)."""
    s = np.linspace(*R.domain[:2], RAIL_SAMPLES)
    P = R(s, np.full(s.size, R.domain[2]))
    if start is not None:
        d = np.linalg.norm(P[:, :2] - np.asarray(start, float)[None, :], axis=1)
        k = int(np.argmin(d))
        if d[k] > START_TOL * size:
            x, y = np.where(np.abs(P[k, :2]) > 1e-9 * size, P[k, :2], 0.0)      # (round-off shown as 0)
            raise BadInputError(f"«start» ({start[0]:g}, {start[1]:g}) is {d[k]:.4g} off the wall's bottom contour "
                                f"(its nearest point is ({x:.4g}, {y:.4g})); give a point on it")
        return float(s[k])
    e = longest_edge(bottom, size)
    along = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(e.points, axis=0), axis=1))])
    mid = np.array([np.interp(0.5 * along[-1], along, e.points[:, i]) for i in range(3)])   # half its length
    return float(s[int(np.argmin(np.linalg.norm(P - mid[None, :], axis=1)))])


def longest_edge(bottom: list, size: float):
    """The bottom contour's longest straight edge (or its longest edge), ties (lengths within 1e-6 of the wall's
    size) broken by a rule every host follows: the edge whose middle has the least y, then the least x, then the
    least z (each to 1e-6 of the size)."""
    pool = [e for e in bottom if e.straight] or bottom
    top = max(e.length for e in pool)
    tied = [e for e in pool if e.length >= top - 1e-6 * size]

    def key(e):
        m = 0.5 * (np.asarray(e.points[0], float) + np.asarray(e.points[-1], float)) if len(e.points) else e.start
        mid = np.asarray(e.points[len(e.points) // 2], float) if len(e.points) > 2 else m
        return tuple(np.round(mid[[1, 0, 2]] / (1e-6 * size)))
    return min(tied, key=key)


def counter_clockwise(R: Surface, axis) -> Surface:
    """R (closed, rulings along v, started: ruled.machine.wall.started) running counter-clockwise about the axis
    (seen from its tip: the right-hand rule), reversed along u where it runs the other way; the start stays where
    it was.  Every host's loop then goes the same way round."""
    s = np.linspace(*R.domain[:2], 257)
    P = R(s, np.full(s.size, R.domain[2]))
    a = np.asarray(axis, float)
    turn = float(np.sum(np.cross(P[:-1], P[1:]) @ a))          # twice the area the rail sweeps about the axis
    if turn >= 0:
        return R
    ku = R.knots_u[0] + R.knots_u[-1] - R.knots_u[::-1]
    W = None if R.weights is None else R.weights[::-1].copy()
    return Surface(R.poles[::-1].copy(), ku, R.knots_v, R.degree_u, R.degree_v, W, periodic_u=R.periodic_u)


def wall_axis(bottom: np.ndarray, top: np.ndarray) -> tuple:
    """The wall's axis from its contours' points: the normal of the plane nearest the bottom contour, from it
    towards the top one, snapped to x, y or z within 0.5 degree (the machine's axis: its guides' planes are
    parallel to the contours')."""
    c = bottom.mean(axis=0)
    n = np.linalg.svd(bottom - c)[2][-1]
    if float(n @ (top.mean(axis=0) - c)) < 0:
        n = -n
    k = int(np.argmax(np.abs(n)))
    if abs(n[k]) > math.cos(math.radians(0.5)):
        n = np.sign(n[k]) * np.eye(3)[k]
    return tuple(float(x) for x in n)


def wall_side(role: str, side=None) -> tuple:
    """(+1 where the wire runs off the material, -1 in it; the side in words, as the G-code's header, the CSV and
    the report say it) of a wall of role 'outer' or 'hole' (ruled.fit.wall.ring.role_of) for the user's side:
    None (off the material: outside a punch, inside a hole), 'outside' or 'inside' the wall's contour, or a
    number (its sign: off the material or in it)."""
    hole = role == "hole"
    if side is None:
        side = "inside" if hole else "outside"
    elif not isinstance(side, str):
        side = ("inside" if hole else "outside") if float(side) >= 0 else ("outside" if hole else "inside")
    if side not in ("outside", "inside"):
        raise BadInputError(f"«side={side}»: use outside or inside (of the wall's contour)")
    off = (side == "outside") != hole
    where = f"{side} the {'hole' if hole else 'part'}"
    return (1.0, f"{where} (off the material)") if off else (-1.0, f"{where} (in the material)")


def outside_sign(S: Surface, breaks, first: int, outward: Callable) -> float:
    """+1 when the joined surface S's normal Su x Sv points out of the part: compared at the middle of the
    face ``first`` (an index into breaks) with outward(point), that face's outward normal there."""
    u = 0.5 * (breaks[first] + breaks[first + 1])
    D = S.evaluate(np.array([u]), np.array([0.5]), 1)
    return 1.0 if float(D.normals()[0] @ np.asarray(outward(D.P[0]), float)) >= 0 else -1.0


__all__ = ["started", "start_parameter", "longest_edge", "counter_clockwise", "wall_axis", "outside_sign", "wall_side",
           "START_TOL"]
