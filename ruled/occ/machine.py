"""Machine outputs of a face with OCCT: fit the face (2D or 4D), make the XYUV contours or the flank
tool axes (ruled.machine.paths), and measure what the machine will cut against the design face,
independently: the surface the wire sweeps between the exported lines against the face, both ways, less the
kerf (ruled.machine.wirecut, as ``ruled replay`` measures a file); for flank milling, the tool surfaces against
the design surface.  Also the STEP for CAM: the ruled result, optionally with its rulings as edges."""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Any, Optional

import numpy as np
from OCP.TopAbs import TopAbs_REVERSED

from ruled.fit.fit2d import FitResult
from ruled.machine.envelope import cut_points, overcut_said, tool_envelope
from ruled.machine.flank import fit_points, machine_path
from ruled.machine.output import path_report
from ruled.machine.paths import Lines, MachineOptions, MachinePath
from ruled.machine.swept import swept_measure
from ruled.occ.convert import container_to_face, conversion_slack, face_to_container, segment_edge
from ruled.occ.measure import _Projector, face_points, hausdorff


@dataclass
class FaceMachine:
    fit: Optional[FitResult]      # None when the face was a ruled result already (given=True)
    surface: Any                  # the ruled surface the machine follows (ruled.Surface, rulings along v)
    path: MachinePath
    face: Any                     # the ruled result as a TopoDS_Face
    report: dict
    side: float                   # +1: the outside is the design surface's Su x Sv side
    warnings: list = field(default_factory=list)


def outward(face) -> float:
    """+1 when the face's outside (its normal in the solid) is its surface's Su x Sv, -1 when reversed."""
    return -1.0 if face.Orientation() == TopAbs_REVERSED else 1.0


def cam_shapes(face, R, u: np.ndarray, rulings: bool = False) -> list:
    """STEP for CAM: the ruled result face (R as a TopoDS_Face) and, optionally, its rulings at the
    synchronized parameters u as edges."""
    return [face] + ([segment_edge(a, b) for a, b in zip(*Lines(R, 1.0).rulings(u))] if rulings else [])


def given_ruled(S):
    """A face that is a ruled result already (linear in one parameter) as R with its rulings along v."""
    from ruled.core.errors import BadInputError
    if S.degree_v == 1:
        return S
    if S.degree_u == 1:
        return S.transposed()
    raise BadInputError(f"the face is not a ruled surface of Ruled's (degrees {S.degree_u} x {S.degree_v}, neither "
                        f"is 1): fit it instead (leave out «ruled»)")


def machine_of_patches(faces: list, names: list, opts: MachineOptions, progress=None,
                       measure_samples: Optional[int] = 30, side: float = 1.0) -> FaceMachine:
    """Machine ruled patches that follow one another (a cone spline's, in the order 'ruled cone' writes
    them) as one: one ruled surface through them all (ruled.machine.chain), one path over it, measured against
    that surface; the report adds each patch's taper and twist."""
    from ruled.machine.chain import join_patches, patch_figures
    faces, names = _whole_patches(faces, names)
    Ss = [face_to_container(f) for f in faces]
    Rs = [given_ruled(S) for S in Ss]
    slack = max(conversion_slack(f, S) for f, S in zip(faces, Ss))
    R, sign = join_patches(Rs, names)
    joined = container_to_face(R)
    fm = machine_of_face(joined, opts, progress=progress, measure_samples=measure_samples,
                         side=side * outward(faces[0]) * sign, given=True)
    fm.report["fit"]["error_bound"] = slack
    fm.report["patches"] = [{"face": nm, **f} for nm, f in
                            zip(names, patch_figures(R, fm.path.frame.axis if fm.path.frame is not None
                                                     else fm.path.axes.mean(axis=0), len(faces)))]
    return fm


def _whole_patches(faces: list, names: list) -> tuple:
    """Ruled patches trimmed by a face's edges (a cone spline of a fit trimmed like it: 'ruled cone --fit') as
    their whole patches, plane to plane, each once: the wire sweeps the patch's generators, of which the
    trimmed face is the part over the design face."""
    from OCP.BRep import BRep_Tool
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace
    from OCP.TopoDS import TopoDS

    from ruled.occ.region import rect_area_ratio
    out_f: list = []
    out_n: list = []
    last = None
    for f, nm in zip(faces, names):
        if rect_area_ratio(f) < 1.0 - 1e-3:
            surf = BRep_Tool.Surface_s(f)
            poles = np.array([surf.Pole(i, j).Coord() for i in range(1, surf.NbUPoles() + 1)
                              for j in range(1, surf.NbVPoles() + 1)]) if hasattr(surf, "NbUPoles") else None
            if poles is not None and last is not None and poles.shape == last.shape and np.array_equal(poles, last):
                continue                    # the same patch again (the face crosses it twice)
            last = poles
            u0, u1, v0, v1 = surf.Bounds()
            f = TopoDS.Face_s(BRepBuilderAPI_MakeFace(surf, u0, u1, v0, v1, 1e-7).Face().Oriented(f.Orientation()))
        out_f.append(f)
        out_n.append(nm)
    return out_f, out_n


def measure_cut(face, path: MachinePath, n: int = 30, keep=None, side: float = 1.0) -> dict:
    """What the wire cuts against the face, from the path's lines alone (ruled.machine.wirecut over OCCT's
    faces: what ``ruled replay`` measures of the file), side: +1 where the wire runs on the side of the face's
    normal in its solid; and the same points on the exact lines (the ruled surface the path follows, the kerf
    apart), so that the cut is compared with the fit where it was measured.  keep(s, t): which points of the
    exact lines (at the ruling s, the fraction t between the rails) lie over the face (a trimmed result: the
    rest of a ruling that crosses the face runs past its end edges)."""
    from ruled.machine.wirecut import wire_cut
    from ruled.occ.wirecut import FacesTarget
    lower, upper = path_lines(path)
    kerf = path.radius
    c = wire_cut(FacesTarget([face], side, "the face" if not kerf else f"the face, at the kerf {kerf:g} from it"),
                 lower, upper, np.arange(1, len(lower)), n, kerf, lead_moves(path.kinds))
    along = 11 if keep is None else 41
    exact = np.abs(_Projector(face).distances(cut_points(path, 3 * n * n, along, exact=True, keep=keep)) - kerf)
    return {**c, "fit_on_the_same_lines": float(exact.max())}


def path_lines(path: MachinePath) -> tuple:
    """(lower, upper) (M, 3): the wire's lines of an XYUV path's moves, in the part's space."""
    (h0, h1), fr = path.planes, path.frame
    return fr.point(path.moves[:, :2], h0), fr.point(path.moves[:, 2:], h1)


def lead_moves(kinds) -> tuple:
    """(moves before the first cut line, moves after the last) of an XYUV path's kinds."""
    kinds = list(kinds)
    return (sum(k == "lead-in" for k in kinds), sum(k == "lead-out" for k in kinds))


def machine_of_face(face, opts: MachineOptions, progress=None, measure_samples: Optional[int] = 30,
                    side: float = 1.0, warnings: Optional[list] = None, given: bool = False,
                    job=None) -> FaceMachine:
    """The machine path of the face's fit on the side `side` (+1: the face's outside), measured: job, the face's
    fit as ``ruled fit`` returns it (ruled.jobs.face.FaceFit: its result, built face, certified bound and
    measure; ruled.jobs.machine makes it), or given=True: the face is a ruled result itself.
    measure_samples=None skips the OCCT measures."""
    opts = opts.checked()
    t0 = time.perf_counter()
    if given:
        S = face_to_container(face)
        slack, res, R = conversion_slack(face, S), None, given_ruled(S)
    else:
        res, R = job.fit, job.fit.surface
        if res.patch is None:               # (a surface fitted as it is: ruled.cq with a Surface)
            S = face_to_container(face)
        else:                               # the face as bounded by its edges (its own or extended patch)
            S = res.patch.surface
            warnings = list(warnings or []) + [w for w in res.patch.warnings if w not in (warnings or [])]
    trim = None if res is None else res.best.trim
    keep = None
    if trim is not None:
        # the rulings that cross the face, plane to plane; what they cut of it is where they lie in the trim
        from ruled.machine.trimmed import trimmed_lines
        R, keep = trimmed_lines(R, (trim.outer,) + tuple(trim.holes))
    out_side = outward(face) * (1.0 if side >= 0 else -1.0)
    t1 = time.perf_counter()
    pts = None
    if opts.mode == "flank" and opts.positions == "envelope":
        pts = face_points(face, fit_points(measure_samples))    # the face as bounded by its edges
    path = machine_path(R, S, opts, out_side, progress, pts, slack if res is None else job.bound)
    t2 = time.perf_counter()
    out_face = face if given else job.face
    if given:
        fit_rep: dict = {"method": "given (the face is a ruled result)", "direction": "v" if S.degree_v == 1 else "u",
                   "closed": bool(R.periodic_u), "error_bound": slack, "notes": []}
    else:
        from ruled.fit.report import region_report
        fit_rep = {"method": res.best.method, "direction": res.direction, "closed": res.best.closed,
                   "error_bound": job.bound, "notes": list(res.notes)}
        if res.patch is not None:
            fit_rep["region"] = region_report(res)
    rep: dict = {"fit": fit_rep, "machine": path_report(path), "side": "outside" if side >= 0 else "inside"}
    if trim is not None:
        rep["machine"]["trimmed"] = {
            "rulings": "those that cross the face, plane to plane (the result's rails run past the face; it is "
                       "trimmed by the face's edges)", "s_range": list(R.domain[:2])}
    warns = list(warnings or []) + list(path.warnings)
    if measure_samples:
        h = job.hausdorff if job is not None and job.hausdorff is not None else \
            hausdorff(face, out_face, measure_samples)
        rep["fit"]["measured"] = h.max
        if opts.mode == "xyuv":
            c = measure_cut(face, path, measure_samples, keep, side)
            fit_err = max(h.max, c["fit_on_the_same_lines"])
            rep["fit"].update(measured=fit_err, measured_grid=h.max)     # the grid alone can miss narrow peaks
            # certified: the fit's bound, and what the path adds (the chords, the kerf offset's deviation)
            rep["cut"] = {**c, "fit_error": fit_err, "fit_bound": fit_rep["error_bound"],
                          "bound": max(fit_rep["error_bound"], fit_err) + path.stats["cut_bound_beyond_fit"]}
        else:
            from ruled.machine.trimmed import along_tool
            X = face_points(face, measure_samples)      # (the face as bounded by its edges)
            env = tool_envelope(S, out_side, path, progress=progress,
                                keep=None if keep is None else along_tool(path, keep), near=X)
            if keep is not None:
                env["against"] = "the face as bounded by its edges (the tool where it lies over the face's trim)"
            if opts.positions == "offset":      # (the offset rulings' deviation bounds what the fit adds)
                env["bound_cl"] = h.max + path.offset_deviation
                env["bound_moves"] = h.max + path.offset_deviation + path.chord_tol
            rep["tool_envelope"] = env
            # and from the face: its points against the tool swept through the moves (ruled.machine.swept)
            rep["swept_tool"] = swept_measure(path, X)
            said = overcut_said(rep, path)
            if said:
                warns.append(said)
    rep["timings"] = {"fit": t1 - t0, "path": t2 - t1, "measure": time.perf_counter() - t2}
    rep["warnings"] = warns
    return FaceMachine(res, R, path, out_face, rep, out_side, warns)
