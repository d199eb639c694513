"""A wall's one closed wire path: the closed ruled result (ruled.occ.wall) started where the user says on the
bottom contour (default: the middle of its longest straight stretch), one synchronized XYUV loop (or one
closed flank CL path) over it with a single lead-in and lead-out there, the kerf offset round the whole
loop on the chosen side, and what the machine cuts measured against the wall's faces (each offset by the
kerf when there is one), both ways."""

from __future__ import annotations

from typing import Optional

import numpy as np

from ruled.core.errors import BadInputError
from ruled.core.nurbs import Surface
from ruled.fit.wallfit import piece
from ruled.occ.wall import Wall, WallFit

RAIL_SAMPLES = 4097      # samples of the result's bottom rail to place the start by
START_TOL = 1e-3         # --start may be this fraction of the wall's size off the bottom contour


def started(R: Surface, s0: float) -> Surface:
    """The closed ruled surface R (rulings along v) running round from s = s0 (a knot of full multiplicity
    inserted there, the geometry unchanged), flagged closed."""
    from ruled.fit.join import along_u, with_knots
    u0, u1 = R.domain[:2]
    if min(abs(s0 - u0), abs(s0 - u1)) <= 1e-12 * (u1 - u0):
        return R
    part = piece(along_u(R, lambda c: with_knots(c, {s0: R.degree_u})), s0, s0)
    return Surface(part.poles, part.knots_u, part.knots_v, part.degree_u, part.degree_v, part.weights,
                   periodic_u=True)


def _bottom_rail(R: Surface) -> tuple:
    s = np.linspace(*R.domain[:2], RAIL_SAMPLES)
    return s, R(s, np.full(s.size, R.domain[2]))


def start_parameter(wall: Wall, R: Surface, start: Optional[tuple] = None) -> float:
    """R's s where the loop starts: at the bottom contour's point nearest (X, Y) (start, refused when it is
    farther than START_TOL of the wall's size from the contour), else the middle of the bottom contour's
    longest straight edge (or of its longest edge)."""
    from ruled.occ.ring import _edge_points, _length
    from ruled.occ.wall import _is_line
    s, P = _bottom_rail(R)
    if start is not None:
        d = np.linalg.norm(P[:, :2] - np.asarray(start, float)[None, :], axis=1)
        k = int(np.argmin(d))
        if d[k] > START_TOL * wall.size:
            x, y = np.where(np.abs(P[k, :2]) > 1e-9 * wall.size, P[k, :2], 0.0)      # (round-off shown as 0)
            raise BadInputError(f"«start» ({start[0]:g}, {start[1]:g}) is {d[k]:.4g} off the wall's bottom contour "
                                f"(its nearest point is ({x:.4g}, {y:.4g})); give a point on it")
        return float(s[k])
    edges = list(wall.ring.loops[0])
    tol = 1e-6 * wall.size
    straight = [e for e in edges if _is_line(e, tol)]
    e = max(straight or edges, key=_length)
    pts = _edge_points(e, 33)
    mid = pts[len(pts) // 2]
    return float(s[int(np.argmin(np.linalg.norm(P - mid[None, :], axis=1)))])


def outside_sign(wall: Wall) -> float:
    """+1 when the joined surface's normal Su x Sv points out of the part (its first face's outside)."""
    from OCP.BRepAdaptor import BRepAdaptor_Surface
    from OCP.GeomAPI import GeomAPI_ProjectPointOnSurf
    from OCP.gp import gp_Pnt, gp_Vec

    from ruled.occ.machine import outward
    k = wall.ring.kept[0]
    u = 0.5 * (wall.breaks[0] + wall.breaks[1])
    D = wall.surface.evaluate(np.array([u]), np.array([0.5]), 1)
    n_joined = D.normals()[0]
    face = wall.faces[k]
    from OCP.BRep import BRep_Tool
    proj = GeomAPI_ProjectPointOnSurf(gp_Pnt(*map(float, D.P[0])), BRep_Tool.Surface_s(face))
    a, b = proj.LowerDistanceParameters()
    p, du, dv = gp_Pnt(), gp_Vec(), gp_Vec()
    BRepAdaptor_Surface(face, False).D1(a, b, p, du, dv)
    n = du.Crossed(dv)
    n_face = np.array([n.X(), n.Y(), n.Z()]) * outward(face)
    return 1.0 if float(n_joined @ n_face) >= 0 else -1.0


def wall_axis(wall: Wall) -> tuple:
    """The wall's axis: the normal of the plane nearest its bottom contour, from the bottom contour towards
    the top one, snapped to x, y or z within 0.5 degree (the machine's axis: its guides' planes are parallel
    to the contours')."""
    import math
    bottom, top = wall.ring.contour_points(0), wall.ring.contour_points(1)
    c = bottom.mean(axis=0)
    n = np.linalg.svd(bottom - c)[2][-1]
    if float(n @ (top.mean(axis=0) - c)) < 0:
        n = -n
    k = int(np.argmax(np.abs(n)))
    if abs(n[k]) > math.cos(math.radians(0.5)):
        n = np.sign(n[k]) * np.eye(3)[k]
    return tuple(float(x) for x in n)


def measure_wall_cut(wall: Wall, path, kerf: float, n: int = 30) -> dict:
    """What the wire cuts against the wall, both ways, each distance less the kerf: the swept lines' points
    (inside the part) from the wall's faces, and the wall's points (about n x n a face) from the swept lines;
    the fit's own measure stands for the exact lines'.  A wire of radius k cannot
    cut an inside corner sharp: there the wall's corner is k (1 / sin(a / 2) - 1) from the cut, a the
    corner's angle, and that shows in design_to_cut."""
    from ruled.machine.envelope import cut_points
    from ruled.occ.faceset import FaceSet, SweptLines
    from ruled.occ.measure import face_points
    to_wall = FaceSet(list(wall.faces))
    cut = cut_points(path, 3 * n * n, 11)
    P = np.concatenate([face_points(wall.faces[k], n) for k in wall.ring.kept])
    design = np.abs(SweptLines(path.lower, path.upper).distances(P) - kerf)
    cut_d = np.abs(to_wall.distances(cut) - kerf)
    against = "the wall's faces" if not kerf else f"the wall's faces, at the kerf {kerf:g} from them"
    return {"against": against, "max": float(max(design.max(), cut_d.max())), "design_to_cut": float(design.max()),
            "cut_to_design": float(cut_d.max()), "samples": int(design.size + cut_d.size)}


def machine_of_wall(fit: WallFit, opts, side: float = 1.0, start: Optional[tuple] = None,
                    measure_samples: Optional[int] = 30, progress=None):
    """The wall's one closed path (ruled.occ.machine.FaceMachine): XYUV or flank (opts.mode) over its closed
    ruled result started at ``start``, on the side ``side`` (+1: outside the part, a punch; -1: inside, a
    die), measured against the wall's faces."""
    from dataclasses import replace

    from ruled.machine.output import path_report
    from ruled.machine.paths import machine_path
    from ruled.occ.convert import container_to_face
    from ruled.occ.machine import FaceMachine
    wall = fit.wall
    if opts.mode == "xyuv" and isinstance(opts.axis, str) and opts.axis == "auto":
        opts = replace(opts, axis=wall_axis(wall))
    opts = opts.checked()
    R = started(fit.surface, start_parameter(wall, fit.surface, start))
    sign = outside_sign(wall) * (1.0 if side >= 0 else -1.0)
    path = machine_path(R, wall.surface, opts, sign, progress)
    rep: dict = {"fit": {"method": fit.result[0].best.method, "closed": True, "error_bound": fit.error_bound,
                         "notes": []},
                 "machine": path_report(path), "side": "outside" if side >= 0 else "inside",
                 "wall": {"faces": list(wall.ring.faces), "pieces": len(fit.result),
                          "start": [float(x) for x in R(np.array([R.domain[0]]), np.array([R.domain[2]]))[0]]}}
    warns = list(fit.warnings) + list(path.warnings)
    if fit.hausdorff is not None:
        rep["fit"]["measured"] = fit.hausdorff.max
    if measure_samples and opts.mode == "xyuv":
        rep["cut"] = measure_wall_cut(wall, path, opts.kerf, measure_samples)
        fit_err = rep["fit"].get("measured", fit.error_bound)
        fillet = path.stats["inside_corner_fillet"]
        rep["cut"].update(fit_error=fit_err, inside_corner_fillet=fillet,
                          bound=fit_err + path.stats["cut_bound_beyond_fit"] + fillet)
    elif measure_samples:
        from ruled.machine.envelope import tool_envelope
        env = tool_envelope(wall.surface, sign, path, progress=progress)
        env["against"] = "the wall (its faces joined into one surface, exactly)"
        env["bound_cl"] = fit.error_bound + path.offset_deviation
        env["bound_moves"] = fit.error_bound + path.offset_deviation + path.chord_tol
        rep["tool_envelope"] = env
    rep["warnings"] = warns
    return FaceMachine(None, R, path, container_to_face(R), rep, sign, warns)


__all__ = ["machine_of_wall", "started", "start_parameter", "outside_sign"]
