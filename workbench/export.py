"""Export for machining (FreeCAD): the ruled results as STEP (optionally with their rulings as edges),
XYUV G-code and CSV for a 4-axis wire, or flank-milling CL data (APT and CSV).  The machine data is
made by the engine (ruled.machine.paths) from the result's arrays; the measures use FreeCAD's Part
(BRepExtrema) for what the wire cuts and the engine's exact projection for the tool envelope.
A JSON report is written beside every machine file."""

from __future__ import annotations

import json
import os
from typing import Optional

import FreeCAD
import numpy as np
import Part

from .names import short_name

# file-dialog filter -> what is written
FORMATS = {
    "STEP, ruled faces (*.step *.stp)": "step",
    "STEP with rulings (*.step *.stp)": "step-rulings",
    "XYUV wire, by its post (*.ngc *.nc *.gcode *.apt)": "xyuv",
    "Flank milling, APT (*.apt *.cls)": "flank",
}


def write_step(shape, path: str) -> None:
    """A Part shape as a STEP file, written whole or not at all (ruled.core.outputs)."""
    from ruled.core.outputs import atomic
    with atomic(path) as tmp:
        shape.exportStep(tmp)


def _faces(objects) -> list:
    return [f for o in objects if hasattr(o, "Shape") and not o.Shape.isNull() for f in o.Shape.Faces]


def result_arrays(face, R=None):
    """The ruled result of a face as arrays with its rulings along v (R: the face's arrays, when read already)."""
    from ruled.core.errors import BadInputError

    from .adapter import face_to_arrays
    R = face_to_arrays(face) if R is None else R
    if R.degree_v == 1:
        return R
    if R.degree_u == 1:
        return R.transposed()
    raise BadInputError(f"the face is not a ruled result (degrees {R.degree_u} x {R.degree_v}): select a Ruled fit")


def _one_fit(objects):
    from ruled.core.errors import BadInputError

    from .features import source_face
    if len(objects) != 1:
        raise BadInputError(f"machine data is made for one ruled fit at a time ({len(objects)} objects are "
                            f"selected): select one Ruled fit")
    obj = objects[0]
    if not (hasattr(obj, "Source") and hasattr(obj, "Shape") and len(obj.Shape.Faces) == 1):
        raise BadInputError(f"{obj.Label} is not a Ruled fit: select the result of 'Fit ruled surface'")
    return obj, source_face(obj)


def rulings_step(objects, path: str, chord_tol=None) -> int:
    """The results' faces and their rulings (as many as the chord tolerance needs) as one STEP file."""
    from ruled.machine.paths import Lines
    from ruled.machine.sync import sync_params
    shapes = []
    for f in _faces(objects):
        R = result_arrays(f)
        lines = Lines(R, 1.0)
        tol = chord_tol or 1e-4 * R.diagonal()
        u = sync_params(lambda x: np.stack(lines.rulings(x), axis=1), *lines.domain, tol)
        A, B = lines.rulings(u)
        shapes.append(f)
        shapes += [Part.LineSegment(FreeCAD.Vector(*a), FreeCAD.Vector(*b)).toShape() for a, b in zip(A, B)]
    if not shapes:
        raise ValueError("nothing to export: select a ruled result")
    write_step(Part.makeCompound(shapes), path)
    return len(shapes)


def _report(path: str, rep: dict) -> dict:
    from ruled.core.outputs import write_text
    write_text(os.path.splitext(path)[0] + ".json", json.dumps(rep, indent=1, default=float))
    return rep


def _cam_step(R, u, cam_step, face=None) -> None:
    """The ruled face (face: the result as it is, trimmed by its design face's edges; else R's whole face) and its
    rulings at the synchronized points as a STEP for CAM (``--step --rulings``)."""
    from ruled.machine.paths import Lines

    from .adapter import surface_to_face
    A, B = Lines(R, 1.0).rulings(u)
    write_step(Part.makeCompound([surface_to_face(R) if face is None else face] + [
        Part.LineSegment(FreeCAD.Vector(*a), FreeCAD.Vector(*b)).toShape() for a, b in zip(A, B)]), cam_step)


def wall_export(obj, path: str, kind: str, chord_tol=None, kerf: float = 0.0, tool_radius=None, taper: float = 0.0,
                side: str = "auto", planes=None, feed: float = 100.0, lead=None, units: str = "mm", cam_step=None,
                measure_samples: int = 20, progress=None, start=None, positions: str = "envelope",
                gouge_tol=None, settings=None) -> dict:
    """A RuledWall's one closed path, as ``ruled machine --wall`` makes it (ruled.machine.wall): its closed
    result started on the bottom contour (start (X, Y), or the middle of its longest straight edge), one XYUV
    loop (axis: the wall's) or one flank CL path, the kerf round the whole loop on the chosen side (outside or
    inside the wall's contour; auto: off the material, ruled.machine.wall.wall_side); what the wire sweeps
    measured against the wall's faces, each distance less the kerf (ruled.machine.wirecut over FreeCAD's faces:
    the command line's measure)."""
    from dataclasses import replace

    from ruled.machine.flank import machine_path
    from ruled.machine.output import path_report, write_checked
    from ruled.machine.paths import MachineOptions
    from ruled.machine.wall import counter_clockwise, outside_sign, start_parameter, started, wall_axis, wall_side

    from .features import value
    from .walls import wall_source
    if obj.Shape.isNull() or not obj.Shape.Faces:
        from ruled.core.errors import BadInputError
        raise BadInputError(f"{obj.Label} has no result yet (see its Status); recompute it first")
    from .adapter import Wall
    faces, names = wall_source(obj)
    wall = Wall(faces, names)
    R = result_arrays(obj.Shape.Faces[0])
    axis = wall_axis(wall.contour_points(0), wall.contour_points(1))
    R = counter_clockwise(started(R, start_parameter(R, wall.contour_edges(0), wall.size, start)), axis)
    first = wall.faces[wall.kept[0]]

    def outward(x):
        u, v = first.Surface.parameter(FreeCAD.Vector(*map(float, x)))
        n = first.Surface.normal(u, v)
        return np.array([n.x, n.y, n.z]) * (-1.0 if first.Orientation == "Reversed" else 1.0)
    off, where = wall_side(wall.role_of(outward), None if side == "auto" else side)
    sign = outside_sign(wall.surface, wall.breaks, 0, outward) * off
    opts = MachineOptions(kind, chord_tol, planes, "auto", None, kerf, tool_radius, taper, lead, feed,
                          positions=positions, gouge_tol=gouge_tol)
    if kind == "xyuv":
        opts = replace(opts, axis=axis)
    mp = machine_path(R, wall.surface, opts.checked(), sign, progress, None, value(obj.ErrorBound))
    title = f"{obj.Label} ({obj.Source[0].Label}: {', '.join(wall.names)})"
    program = write_checked(mp, path, settings, units, where)
    if cam_step:
        _cam_step(R, mp.u, cam_step)
    fit = {"error_bound": value(obj.ErrorBound), "measured": value(obj.Hausdorff), "closed": True}
    rep = {"object": obj.Label, "source": title, "output": path, "csv": program["csv"], "units": units,
           "step": cam_step, "machine": path_report(mp), "fit": fit, "side": where, "program": program,
           "wall": {"faces": wall.names, "start": [float(x) for x in R(np.array([R.domain[0]]),
                                                                        np.array([R.domain[2]]))[0]]}}
    if kind == "xyuv" and measure_samples:
        fillet = mp.stats["inside_corner_fillet"]
        rep["cut"] = {**_wire_cut([wall.faces[i] for i in wall.kept], off, mp, measure_samples,
                                  "the wall's faces" + (f", at the kerf {kerf:g} from them" if kerf else "")),
                      "inside_corner_fillet": fillet, "fit_bound": fit["error_bound"],
                      "bound": max(fit["error_bound"], fit["measured"]) + mp.stats["cut_bound_beyond_fit"] + fillet}
    rep["warnings"] = list(mp.warnings)
    return _report(path, rep)


def machine_export(objects, path: str, kind: str, chord_tol=None, kerf: float = 0.0, tool_radius=None,
                   taper: float = 0.0, side: str = "auto", planes=None, feed: float = 100.0, lead=None,
                   units: str = "mm", cam_step=None, measure_samples: int = 20, progress=None, axis="auto",
                   gouge_tol=None, positions: str = "envelope", settings=None) -> dict:
    """XYUV G-code (kind "xyuv") or APT CL data (kind "flank") of one selected Ruled fit, with a CSV and
    a JSON report beside (and, with cam_step, a STEP for CAM: the ruled face and its rulings at the
    synchronized points, like ``ruled machine --cam-step --rulings``); returns the report.  The path follows
    the fit's own result (trimmed by the face's edges where it is), or, where that cannot be machined, the
    fit pinned to the face's corners with a warning naming both figures (the report's "fallback")."""
    from ruled.core.errors import BadInputError
    from ruled.fit.face.fit import face_patch
    from ruled.machine.envelope import overcut_said, tool_envelope
    from ruled.machine.flank import fit_points, machine_path
    from ruled.machine.output import path_report, write_checked
    from ruled.machine.paths import MachineOptions
    from ruled.machine.trimmed import along_tool, fallback_warning, figure, swapped, trimmed_lines

    from .adapter import face_region, face_to_arrays, surface_to_arrays
    from .features import value
    from .measure import face_points, trimmed
    if len(objects) == 1 and type(getattr(objects[0], "Proxy", None)).__name__ == "RuledWall":
        if str(axis) != "auto":
            raise BadInputError("a wall's machine axis is the normal of its contours: leave the machine axis empty "
                                "(auto)")
        return wall_export(objects[0], path, kind, chord_tol, kerf, tool_radius, taper, side, planes, feed, lead,
                           units, cam_step, measure_samples, progress, None, positions, gouge_tol, settings)
    obj, src = _one_fit(objects)
    fit_figures = {"error_bound": value(obj.ErrorBound), "measured": value(obj.Hausdorff)}
    warnings: list = []
    fallback = None
    region = face_region(src, face_to_arrays(src))
    result = obj.Shape.Faces[0]
    A = face_to_arrays(result)
    R, S, keep = result_arrays(result, A), face_patch(region).surface, None   # S: the face as bounded by its edges
    if trimmed(result):
        # the result trimmed by the face's edges (what 'ruled fit' returns): the wire or tool sweeps its rulings
        # that cross the face, plane to plane, and what they cut of it is where they lie inside its edges
        rg = face_region(result, A)
        loops = ((rg.loop,) + tuple(rg.holes)) if A.degree_v == 1 else \
            tuple(tuple(swapped(c) for c in lp) for lp in (rg.loop,) + tuple(rg.holes))   # rulings along u
        # the whole ruled surface, rail to rail (as 'ruled machine' sweeps it), not the face's (u, v) box
        R, keep = trimmed_lines(result_arrays(result, surface_to_arrays(result.Surface)), loops)
    side = "outside" if side == "auto" else side        # (a face's: its normal's side)
    out_side = (-1.0 if src.Orientation == "Reversed" else 1.0) * (1.0 if side == "outside" else -1.0)
    opts = MachineOptions(kind, chord_tol, planes, axis, None, kerf, tool_radius, taper, lead, feed,
                          positions=positions, gouge_tol=gouge_tol).checked()
    pts = face_points(src, fit_points(measure_samples)) if kind == "flank" else None  # (the bounded face)
    try:
        mp = machine_path(R, S, opts, out_side, progress, pts, fit_figures["error_bound"])
    except BadInputError as exc:
        if keep is None:
            raise
        # the trimmed result's rulings cannot be machined: the fit pinned to the face's corners, saying so
        R, S, keep, pinned = _pinned(obj, region, progress)
        mp = machine_path(R, S, opts, out_side, progress, pts, pinned)
        shown = figure(fit_figures["error_bound"], fit_figures["measured"] or None)     # (0: not measured)
        warnings.append(fallback_warning(kind, figure(pinned), exc, shown))
        fallback = {"followed": "pinned", "pinned_bound": pinned, "trimmed_bound": fit_figures["error_bound"],
                    "trimmed_measured": fit_figures["measured"], "why": str(exc)}
        fit_figures = {"error_bound": pinned, "measured": pinned}
    title = f"{obj.Label} ({obj.Source[0].Label}.{short_name(obj.Source[1][0])})"
    program = write_checked(mp, path, settings, units, side)
    if cam_step:
        _cam_step(R, mp.u, cam_step, result if keep is not None else None)
    rep = {"object": obj.Label, "source": title, "output": path, "csv": program["csv"], "units": units,
           "step": cam_step, "machine": path_report(mp), "fit": fit_figures, "program": program}
    if kind == "xyuv":
        if measure_samples:
            rep["cut"] = {**_wire_cut([src], 1.0 if side == "outside" else -1.0, mp, measure_samples,
                                      "the face" + (f", at the kerf {kerf:g} from it" if kerf else "")),
                          "fit_bound": fit_figures["error_bound"],
                          "bound": max(fit_figures["error_bound"], fit_figures["measured"])
                          + mp.stats["cut_bound_beyond_fit"]}
    elif measure_samples:
        from ruled.machine.swept import swept_measure
        X = face_points(src, measure_samples)      # (the face as bounded by its edges)
        rep["tool_envelope"] = tool_envelope(S, out_side, mp, keep=None if keep is None else along_tool(mp, keep),
                                             near=X)
        # and from the face: its points against the tool swept through the moves (as ruled machine --flank)
        rep["swept_tool"] = swept_measure(mp, X)
        said = overcut_said(rep, mp)
        if said:
            warnings.append(said)
    rep["warnings"] = warnings + list(mp.warnings)
    if fallback:
        rep["fallback"] = fallback
    return _report(path, rep)


def _wire_cut(faces, side: float, mp, n: int, against: str) -> dict:
    """What the wire sweeps along the path's moves against the faces (ruled.machine.wirecut over FreeCAD's faces,
    as the command line and 'ruled replay' measure it), less the kerf."""
    from ruled.machine.wirecut import wire_cut

    from .wirecut import FreeCADFaces
    (h0, h1), fr = mp.planes, mp.frame
    lower, upper = fr.point(mp.moves[:, :2], h0), fr.point(mp.moves[:, 2:], h1)
    kinds = list(mp.kinds)
    return wire_cut(FreeCADFaces(faces, side, against), lower, upper, np.arange(1, len(lower)), n, mp.radius,
                    (kinds.count("lead-in"), kinds.count("lead-out")))


def _pinned(obj, region, progress) -> tuple:
    """(R, the face's patch, no trim, the certified bound) of the fit of obj's face pinned to its corners."""
    from dataclasses import replace

    from ruled.fit.face.fit import fit_region
    res = fit_region(region, replace(obj.Proxy.options(obj), ends="pinned").checked(), progress)
    R = res.surface if res.surface.degree_v == 1 else res.surface.transposed()
    return R, res.patch.surface, None, float(res.error_bound)


def export_step(objects, path: str) -> None:
    """The objects' shapes (ruled results) as one STEP file."""
    import Part
    shapes = [o.Shape for o in objects if hasattr(o, "Shape") and not o.Shape.isNull()]
    if not shapes:
        raise ValueError("nothing to export: select a ruled result")
    write_step(Part.makeCompound(shapes), path)


def export(objs, path: str, kind: str, **params) -> Optional[dict]:
    """Write the objects in the chosen format (see workbench.export.FORMATS); machine data's report."""
    from .features import _Progress, in_our_terms
    if kind == "step":
        export_step(objs, path)
    elif kind == "step-rulings":
        rulings_step(objs, path, params.get("chord_tol"))
    else:
        bar = _Progress("Ruled: machine data")
        try:
            rep = machine_export(objs, path, kind, progress=bar, **params)
        finally:
            bar.stop()
        for w in rep["warnings"]:
            FreeCAD.Console.PrintWarning(f"Ruled: {in_our_terms(w)}\n")
        return rep
    return None
