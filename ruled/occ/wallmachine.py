"""A wall's one closed wire path: the closed ruled result (ruled.occ.wall) started where the user says on the
bottom contour (default: the middle of its longest straight stretch), one synchronized XYUV loop (or one
closed flank CL path) over it with a single lead-in and lead-out there, the kerf offset round the whole
loop on the chosen side, and what the machine cuts measured against the wall's faces (each offset by the
kerf when there is one), both ways."""

from __future__ import annotations

from typing import Optional

import numpy as np

from ruled.core.nurbs import Surface
from ruled.machine.wall import counter_clockwise, started
from ruled.occ.wall import Wall, WallFit


def start_parameter(wall: Wall, R: Surface, start: Optional[tuple] = None) -> float:
    """ruled.machine.wall.start_parameter on the wall's bottom contour."""
    from ruled.machine.wall import start_parameter as on_rail
    from ruled.occ.wall import contour_edge
    return on_rail(R, [contour_edge(e, wall.size) for e in wall.ring.loops[0]], wall.size, start)


def outside_sign(wall: Wall) -> float:
    """+1 when the joined surface's normal Su x Sv points out of the part (its first face's outside)."""
    from ruled.machine.wall import outside_sign as sign
    from ruled.occ.ring import outward_at
    face = wall.faces[wall.ring.kept[0]]
    return sign(wall.surface, wall.breaks, 0, lambda x: outward_at(face, x))


def wall_axis(wall: Wall) -> tuple:
    """ruled.machine.wall.wall_axis of the wall's contours."""
    from ruled.machine.wall import wall_axis as axis
    return axis(wall.ring.contour_points(0), wall.ring.contour_points(1))


def measure_wall_cut(wall: Wall, path, kerf: float, n: int = 30, side: float = 1.0) -> dict:
    """What the wire cuts against the wall's faces, from the path's lines alone (ruled.machine.wirecut over OCCT's
    faces: what ``ruled replay`` measures of the file), each distance less the kerf, the wire off the material
    (side +1) or in it (-1).  A wire of radius k cannot cut an inside corner sharp: there the wall's corner is
    k (1 / sin(a / 2) - 1) from the cut, a the corner's angle, and that shows in design_to_cut."""
    from ruled.machine.wirecut import wire_cut
    from ruled.occ.machine import lead_moves, path_lines
    from ruled.occ.wirecut import FacesTarget
    against = "the wall's faces" if not kerf else f"the wall's faces, at the kerf {kerf:g} from them"
    lower, upper = path_lines(path)
    return wire_cut(FacesTarget([wall.faces[k] for k in wall.ring.kept], side, against), lower, upper,
                    np.arange(1, len(lower)), n, kerf, lead_moves(path.kinds))


def machine_of_wall(fit: WallFit, opts, side=None, start: Optional[tuple] = None,
                    measure_samples: Optional[int] = 30, progress=None):
    """The wall's one closed path (ruled.occ.machine.FaceMachine): XYUV or flank (opts.mode) over its closed
    ruled result started at ``start``, on the side ``side`` (ruled.machine.wall.wall_side: None, off the
    material, outside a punch and inside a hole; 'outside' or 'inside' the wall's contour; +1 / -1 off the
    material or in it), measured against the wall's faces."""
    from dataclasses import replace

    from ruled.machine.flank import machine_path
    from ruled.machine.output import path_report
    from ruled.machine.wall import wall_side
    from ruled.occ.convert import container_to_face
    from ruled.occ.machine import FaceMachine
    wall = fit.wall
    if opts.mode == "xyuv" and isinstance(opts.axis, str) and opts.axis == "auto":
        opts = replace(opts, axis=wall_axis(wall))
    opts = opts.checked()
    off, where = wall_side(wall.ring.role, side)
    sign = outside_sign(wall) * off

    def path_of(surface, bound):
        R = counter_clockwise(started(surface, start_parameter(wall, surface, start)), wall_axis(wall))
        return R, machine_path(R, wall.surface, opts, sign, progress, None, bound)
    R, path = path_of(fit.surface, fit.error_bound)
    note = None
    if fit.crossed and fit.plain is not None and (opts.mode == "flank" or opts.kerf > 0):
        # a corner crossed twists its rulings through the corner's angle: their offset by the kerf or the tool
        # is not ruled there, and the corners' own rulings can cut the nearer
        R2, path2 = path_of(*fit.plain)
        mine, other = _cut_bound(path, fit.error_bound), _cut_bound(path2, fit.plain[1])
        what = f"the kerf {opts.kerf:g}" if opts.mode == "xyuv" else f"the tool radius {opts.tool_radius:g}"
        if other < mine:
            note = (f"the corners' own rulings are cut (fit bound {fit.plain[1]:.6g}), not the rulings paired across "
                    f"{fit.crossed} corner{'s' if fit.crossed > 1 else ''} (fit bound {fit.error_bound:.6g}): at "
                    f"{what} the wire's offset of a crossed corner twists with it (cut bound {other:.6g} against "
                    f"{mine:.6g})")
            fit = _plain_fit(fit)
            R, path = R2, path2
        else:
            note = (f"the rulings paired across {fit.crossed} corner{'s' if fit.crossed > 1 else ''} are cut (cut "
                    f"bound {mine:.6g} against {other:.6g} with the corners' own rulings, fit bound "
                    f"{fit.plain[1]:.6g})")
    if fit.hausdorff is None and measure_samples:
        from ruled.occ.wall import measured
        fit = measured(fit, measure_samples)
    rep: dict = {"fit": {"method": fit.result[0].best.method, "closed": True, "error_bound": fit.error_bound,
                         "notes": []},
                 "machine": path_report(path), "side": where,
                 "wall": {"faces": list(wall.ring.faces), "pieces": len(fit.result), "role": wall.ring.role,
                          "start": [float(x) for x in R(np.array([R.domain[0]]), np.array([R.domain[2]]))[0]],
                          "crossed_corners": fit.crossed}}
    if note:
        rep["wall"]["corners_note"] = note
    warns = list(fit.warnings) + list(path.warnings)
    if fit.hausdorff is not None:
        rep["fit"]["measured"] = fit.hausdorff.max
    if measure_samples and opts.mode == "xyuv":
        rep["cut"] = measure_wall_cut(wall, path, opts.kerf, measure_samples, off)
        fit_err = rep["fit"].get("measured", fit.error_bound)
        fillet = path.stats["inside_corner_fillet"]
        rep["cut"].update(fit_error=fit_err, fit_bound=fit.error_bound, inside_corner_fillet=fillet,
                          bound=max(fit.error_bound, fit_err) + path.stats["cut_bound_beyond_fit"] + fillet)
    elif measure_samples:
        from ruled.machine.envelope import overcut_said, tool_envelope
        from ruled.occ.measure import face_points
        env = tool_envelope(wall.surface, sign, path, progress=progress,
                            near=np.concatenate([face_points(wall.faces[k], measure_samples) for k in wall.ring.kept]))
        env["against"] = "the wall (its faces joined into one surface, exactly)"
        if opts.positions == "offset":          # (the offset rulings' deviation bounds what the fit adds)
            env["bound_cl"] = fit.error_bound + path.offset_deviation
            env["bound_moves"] = fit.error_bound + path.offset_deviation + path.chord_tol
        rep["tool_envelope"] = env
        said = overcut_said(rep, path)
        if said:
            warns.append(said)
    rep["warnings"] = warns
    return FaceMachine(None, R, path, container_to_face(R), rep, sign, warns)


def _cut_bound(path, fit_bound: float) -> float:
    """What a path's cut is certified within: the fit's bound, the chord tolerance and the kerf offset's deviation,
    the round the wire leaves in inside corners (XYUV); the fit's bound and the tool's offset deviation (flank)."""
    if path.mode == "xyuv":
        return fit_bound + path.stats["cut_bound_beyond_fit"] + path.stats["inside_corner_fillet"]
    return fit_bound + path.offset_deviation + path.chord_tol


def _plain_fit(fit: WallFit) -> WallFit:
    """The wall's fit with the corners' own rulings (WallFit.plain), built as fit_wall builds it (unmeasured)."""
    from dataclasses import replace

    from ruled.occ.convert import container_to_face
    surface, bound = fit.plain
    return replace(fit, face=container_to_face(surface), error_bound=bound, hausdorff=None, area_ratio=None,
                   warnings=(), surface=surface, crossed=0, plain=None)


__all__ = ["machine_of_wall", "start_parameter", "outside_sign", "wall_axis"]
