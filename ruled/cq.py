"""CadQuery entry points.

    import cadquery as cq
    from ruled.cq import fit_face

    face = cq.importers.importStep("part.step").faces().vals()[3]
    fit = fit_face(face, samples=40)
    print(fit.error_bound, fit.hausdorff.max)
    cq.exporters.export(cq.Workplane().add(fit.face), "ruled.step")

    from ruled.cq import replace_face
    part = cq.importers.importStep("part.step")
    rp = replace_face(part, 3, samples=40)                 # the part, its face 3 ruled and sewn back
    cq.exporters.export(rp.part, "part-ruled.step"); print(rp.closed_solid, rp.fit.error_bound)

    from ruled.cq import curve_on_face
    c = curve_on_face(face, [(0.1, 0.2), (0.5, 0.8), (0.9, 0.3)], tol=1e-3, angle=1.0)
    print(c.result.segments, c.result.error_bound, c.measure.hausdorff)
    cq.exporters.export(cq.Workplane().add(c.edge), "curve.step")

    from ruled.cq import cone_spline_face
    cs = cone_spline_face(face, tol=0.01, fit=True)      # fit a ruled surface, then a cone spline of it
    print(len(cs.faces), cs.result.bound, cs.measure["design_to_cone"])
    cq.exporters.export(cq.Workplane().add(cs.shell), "cones.step")

    from ruled.cq import split_face, xyuv_face, flank_face
    sp = split_face(face)                                  # the best split for ruling, two faces and their fits
    wire = xyuv_face(face, chord_tol=0.01, kerf=0.15)      # 4-axis wire: synchronized XY / UV contours
    wire.write("part.ngc"); print(wire.report["cut"])     # G-code for LinuxCNC, its CSV beside
    wire.write("part.gcode", post="grbl", power=800)      # a GRBL foam cutter: lower X Y, upper Z A
    mill = flank_face(face, tool_radius=3.0)               # flank milling: CL points and tool axes
    mill.write_apt("part.apt"); print(mill.report["tool_envelope"])

    import ruled.cq; ruled.cq.register()                   # opt in: chainable Workplane methods
    cq.Workplane().add(face).ruledXYUV("part.ngc", chord_tol=0.01)   # also ruledFit, ruledSplit,
                                                          # ruledConeSpline, ruledCurveOnFace, ruledFlank

The face may be a ``cadquery.Face``, an OCP ``TopoDS_Face`` or a
:class:`ruled.Surface` container.  OCP is reached only through ``ruled.occ``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Optional

import numpy as np

from ruled.core.errors import BadInputError, RuledError
from ruled.core.nurbs import Surface
from ruled.core.progress import Progress
from ruled.fit.fit2d import FitResult
from ruled.fit.options import FitOptions
from ruled.fit.surface import fit_surface


@dataclass(frozen=True)
class RuledFit:
    """A ruled fit and its errors: the result face, the rulings, the certified bound and the measure."""

    face: Any                 # cadquery.Face when CadQuery is installed, else TopoDS_Face
    surface: Surface          # the result as plain arrays
    rulings: np.ndarray       # (K, 2, 3) end points of the DP rulings on the input face
    error_bound: float        # certified upper bound of the Hausdorff distance to the input face
    hausdorff: Optional[Any]  # ruled.occ.Hausdorff measured with OCCT, or None when not asked
    result: FitResult         # everything else (pairing, candidates, timings)
    warnings: tuple = ()      # what the fit and the measure say (a hole spanned, a face far from ruled, a loose bound)
    job: Any = None           # ruled.jobs.face.FaceFit: what the machine data and cone spline of this fit start from


def _topods(face):
    wrapped = getattr(face, "wrapped", None)
    return wrapped if wrapped is not None else face


def _face_of(face):
    """An OCP face for a cadquery.Face, a TopoDS_Face or a Surface container."""
    from ruled.occ.convert import container_to_face
    return container_to_face(face) if isinstance(face, Surface) else _topods(face)


def _cq(shape, kind: str = "Face"):
    """The CadQuery wrapper of an OCP shape when CadQuery is installed, else the shape itself."""
    try:
        import cadquery as cq
    except ImportError:  # plain OCP
        return shape
    return getattr(cq, kind)(shape) if kind != "Shape" else cq.Shape.cast(shape)


def fit_face(face, samples: int = 40, objective: str = "sum", max_error: Optional[float] = None,
             direction: str = "auto", refine: bool = True, measure: bool = True, measure_samples: int = 40,
             progress: Progress = None, method: str = "2d", elevations: Optional[int] = None,
             step: Optional[float] = None, metric: str = "lsad", rails=None, ends: str = "auto") -> RuledFit:
    """Fit the best ruled surface to a face as bounded by its edges (2D-DP over boundary samples, or
    4D-DP with the ruling ends lifted along the normal; refined, certified).  rails: two edge indices
    of the face's outer wire (as 'ruled faces --edges' lists them) for the rulings to join.  ends:
    'auto' (default: the smaller certified bound of) 'pinned' (the end rulings at the face's corners) and
    'trimmed' (the rails run past the face, the result trimmed by its edges)."""
    from ruled.jobs.face import fit_job
    from ruled.occ.convert import container_to_face
    from ruled.occ.region import fit_face as _fit_face

    opts = FitOptions.of(samples=samples, objective=objective, max_error=max_error, direction=direction,
                         refine=refine, method=method, elevations=elevations, step=step, metric=metric, ends=ends)
    if isinstance(face, Surface):
        src = container_to_face(face)
        fitted = (fit_surface(face, opts, progress), 0.0)
    else:
        src = _topods(face)
        fitted = _fit_face(src, opts, progress, rails)
    ff = fit_job(src, opts, progress, measure_samples=measure_samples if measure else None, fitted=fitted)
    res = ff.fit
    return RuledFit(_cq(ff.face), res.surface, res.best.rulings, ff.bound, ff.hausdorff, res, ff.warnings, ff)


def fit_wall(faces, samples: int = 40, objective: str = "sum", method: str = "2d", measure: bool = True,
             measure_samples: int = 40, progress: Progress = None, wall: str = "auto"):
    """A part's wall as one closed ruled surface (ruled.occ.wall): faces is a part (a solid; its wall is found:
    the ring of faces between two planar caps; wall: which, 'auto' (its only one), 'outer', 'hole', 'hole:K')
    or the wall's faces (a list, of one part, in any order).
    samples: per face.  Returns ruled.occ.wall.WallFit: .face (the closed ruled face), .error_bound
    (certified), .hausdorff (measured against the wall's faces, both ways), .report()."""
    from dataclasses import replace

    from ruled.occ.wall import fit_wall as _fit_wall
    from ruled.occ.wall import wall_of
    if isinstance(faces, (list, tuple)):
        topo = [_topods(f) for f in faces]
        wall_ = wall_of(None, list(range(len(topo))), topo)
    else:
        wall_ = wall_of(getattr(faces, "wrapped", faces), wall)
    opts = FitOptions.of(samples=samples * len(wall_.faces), objective=objective, method=method).checked()
    fit = _fit_wall(wall_, opts, progress, measure, measure_samples)
    return replace(fit, face=_cq(fit.face))


@dataclass(frozen=True)
class ReplacedFace:
    """A part with one face replaced by its ruled fit, sewn to the face's neighbours."""

    part: Any                 # the whole part (cadquery.Shape when CadQuery is installed, else TopoDS_Shape)
    face: Any                 # the ruled face as sewn into the part (cadquery.Face, else TopoDS_Face)
    index: int                # its index among the part's faces (the replaced face's: the order is kept)
    fit: RuledFit             # the fit: its bound, measure and result
    sewing_tolerance: float
    closed_solid: bool        # the face's solid is a valid closed solid (checked by OCCT)


def replace_face(part, face, **fit_options) -> ReplacedFace:
    """The part with its face replaced by the face's best ruled surface (fit_face, with fit_options), sewn
    to its neighbours within 1.1x the fit's bound.  part: a cadquery.Shape or Workplane, or an OCP shape;
    face: the face's index among the part's faces, or the face itself.  Raises RuledError, naming the
    face's edges that did not meet, where the sewn part is not closed where it was."""
    from ruled.occ.io import compound, faces_of
    from ruled.occ.replace import replaced_part, sewing_tolerance
    if hasattr(part, "vals") and hasattr(part, "objects"):        # a Workplane: its shapes as one compound
        part = part.val() if len(part.vals()) == 1 else compound([_topods(x) for x in part.vals()])
    shape = _topods(part)
    faces = faces_of(shape)
    if isinstance(face, (int, np.integer)):
        index = int(face)
        if not 0 <= index < len(faces):
            raise BadInputError(f"face {index} is not in the part ({len(faces)} faces, from 0)")
    else:
        index = next((i for i, f in enumerate(faces) if f.IsSame(_topods(face))), -1)
        if index < 0:
            raise BadInputError("the face is not a face of the part; pass one of its faces, or its index")
    fit = fit_face(faces[index], **fit_options)
    new = _topods(fit.face)
    r = replaced_part(shape, index, new, sewing_tolerance(fit.error_bound, faces[index], new))
    return ReplacedFace(_cq(r.shape, "Shape"), _cq(r.face), r.index, fit, r.tolerance, r.solid)


@dataclass(frozen=True)
class CurveOnFace:
    """A curve lying exactly on a face, within a tolerance of the image of a (u, v) curve."""

    edge: Any                 # cadquery.Edge when CadQuery is installed, else TopoDS_Edge; carries its pcurve
    result: Any               # ruled.curves.curve_on_surface.CurveOnSurface: segments, bound, curve, pcurve arrays
    measure: Optional[Any]    # ruled.occ.measure.CurveMeasure (OCCT), or None when not asked
    warnings: tuple = ()


def curve_on_face(face, uv, tol: float = 1e-3, angle: float = 1.0, bound: str = "local", measure: bool = True,
                  measure_samples: int = 2000, progress=None) -> CurveOnFace:
    """The image on the face of a (u, v) curve: uv is a polyline ((N, 2) points) or a 2D
    :class:`ruled.Curve`; the result is a curve of degree p + q on the face's surface exactly (Yang et
    al. 2008), within tol of the exact image and G1 within angle degrees at its joints."""
    from ruled.core.nurbs import Curve
    from ruled.curves.domain import polyline_curve
    from ruled.occ.cos import curve_on_face as _on_face

    src = _face_of(face)
    D = uv if isinstance(uv, Curve) else polyline_curve(uv)
    fc = _on_face(src, D, tol, angle, bound=bound, progress=progress,
                  measure_samples=measure_samples if measure else None)
    return CurveOnFace(_cq(fc.edge, "Edge"), fc.result, fc.measure, tuple(fc.warnings))


@dataclass(frozen=True)
class ConeSplineFace:
    """A tangent-smooth cone spline (developable) within a tolerance of a ruled face."""

    shell: Any                # cadquery.Shape (the sewn patches) when CadQuery is installed, else the OCP shape
    faces: tuple              # one face per cone patch
    result: Any               # ruled.cone.conespline.ConeSpline: patches (weight, apex, development), bound, pieces
    measure: Optional[dict]   # independent distances (OCCT), or None when not asked
    fit: Any = None           # the ruled fit when fit=True
    warnings: tuple = ()
    bound: float = 0.0        # certified against the face: the cone spline's (eq. 9), plus the fit's when fitted

    def xyuv(self, **kw) -> "MachineData":
        """Its patches cut as one wire path (xyuv_patches): the report gives each patch's taper."""
        return xyuv_patches(self.faces, **kw)


def cone_spline_face(face, tol: float, step: float = 0.1, fit=False, direction: str = "auto",
                     measure: bool = True, measure_samples: int = 24, allow_creases: bool = False,
                     progress=None) -> ConeSplineFace:
    """The cone spline of a ruled face within tol (Yang & Yang 2006); with fit=True the face is first
    fitted by a ruled surface (fit_face's defaults) and that fit is cone-splined, in one call; fit=a RuledFit
    of this face (fit_face's result) cone-splines that fit.  A fit trimmed by the face's edges gives patches
    trimmed by them too; .bound is the cone spline's bound plus the fit's."""
    from ruled.jobs.cone import cone_job

    src = _face_of(face)
    fc = cone_job(src, tol, step, direction=direction, fit=fit, progress=progress,
                  measure_samples=measure_samples if measure else None, allow_creases=allow_creases)
    return ConeSplineFace(_cq(fc.shell, "Shape"), tuple(_cq(f) for f in fc.faces), fc.result, fc.measure, fc.fit,
                          tuple(fc.warnings), fc.bound)


@dataclass(frozen=True)
class SplitFace:
    """The best split of a face for ruling (Wang & Elber): its two faces and their ruled fits."""

    faces: tuple              # the two faces of the chosen split (cadquery.Face), sharing the split edge
    fits: tuple               # the ruled fit of each side (cadquery.Face)
    chosen: str               # optimal | best-iso | iso-0.5: the candidate with the lowest measured error
    measured: tuple           # per side: the measured Hausdorff distance of its fit (dicts)
    result: Any               # ruled.occ.split.FaceSplit: every candidate, bounds, checks
    warnings: tuple = ()
    kept: bool = True         # False: the face needs no split (its own fit is better): faces, fits are the face's
    verdict: Optional[str] = None   # what is said when the split is not kept
    bound: float = 0.0        # the result's certified bound against the face (the split's worse side, or the fit's)


def split_face(face, dims: int = 4, samples: int = 30, interior: int = 10, objective: str = "max",
               fit_samples: int = 40, measure_samples: int = 30, progress=None, fit=None) -> SplitFace:
    """Split a face in two along the curve whose two ruled fits are best (optimal M-curve, best iso and
    middle candidates are built, fitted and measured; the lowest measured error is kept).  The split is
    kept only where it is better than the face's own fit (fit: a RuledFit of it, else fitted as fit_face
    fits it); else .kept is False, .verdict says so, and .faces and .fits are the face and that fit."""
    from ruled.jobs.split import split_job
    from ruled.split.partition import SplitOptions
    opts = SplitOptions(samples=samples, interior=interior, objective=objective, dims=dims,
                        fit=FitOptions(samples=fit_samples).checked()).checked()
    src = _face_of(face)
    job = split_job(src, opts, progress, measure_samples, fit)
    fs, k = job.split, job.split.chosen
    if not job.kept:
        h = job.whole.hausdorff
        return SplitFace((_cq(src),), (_cq(job.whole.face),), k, ({"max": None if h is None else h.max},), fs,
                         tuple(fs.warnings), False, job.verdict, job.whole.bound)
    return SplitFace(tuple(_cq(f) for f in fs.faces[k].faces), tuple(_cq(f) for f in fs.fits[k]), k,
                     tuple(fs.measured[k]), fs, tuple(fs.warnings), True, None, job.bound)


@dataclass(frozen=True)
class MachineData:
    """Machine data of a face's ruled fit: the synchronized path, the ruled face, the measured report."""

    path: Any                 # ruled.machine.paths.MachinePath (plain arrays)
    face: Any                 # the ruled result (cadquery.Face)
    report: dict              # fit, machine figures, measured cut error / tool envelope, warnings
    fit: FitResult
    surface: Surface          # the ruled surface followed (rulings along v)
    warnings: tuple = ()

    def write(self, filename: str, post: Optional[str] = None, units: str = "mm", csv: Optional[str] = None,
              **settings) -> dict:
        """The machine file by a post (a name 'ruled posts' lists, or your own post's .toml; default linuxcnc for
        a wire, apt for flank) and its CSV (default beside it), as 'ruled machine' writes them, the same bytes;
        settings: ruled.machine.program.PostSettings's (feed_mode, power, dwell, letters, home, origin,
        compensation, program, corner_radius).  A LinuxCNC file is checked by LinuxCNC's own interpreter where it
        is installed.  Returns {"post", "file", "csv", "check"}."""
        from ruled.machine.output import write_checked
        from ruled.machine.program import PostSettings
        return write_checked(self.path, filename, PostSettings(post=post, **settings), units,
                             self.report.get("side"), csv)

    def write_gcode(self, filename: str, title: str = "", units: str = "mm", post: Optional[str] = None,
                    **settings) -> str:
        """The wire's G-code by a G-code post (default linuxcnc; see write)."""
        from ruled.machine.output import write_gcode
        from ruled.machine.program import PostSettings
        write_gcode(self.path, filename, title, units, self.report.get("side"), PostSettings(post=post, **settings))
        return filename

    def write_apt(self, filename: str, title: str = "", units: str = "mm", corner_radius: float = 0.0) -> str:
        """Flank milling's APT CL data (the 7-parameter CUTTER, a corner radius where given)."""
        from ruled.machine.output import write_apt
        from ruled.machine.program import PostSettings
        write_apt(self.path, filename, title, units, PostSettings(corner_radius=corner_radius))
        return filename

    def write_csv(self, filename: str, units: str = "mm") -> str:
        from ruled.machine.output import write_csv
        write_csv(self.path, filename, units)
        return filename

    def write_step(self, filename: str, rulings: bool = False) -> str:
        """STEP for CAM: the ruled face, with its rulings at the synchronized points as edges if asked."""
        from ruled.occ.io import write_step
        from ruled.occ.machine import cam_shapes
        write_step(cam_shapes(_topods(self.face), self.surface, self.path.u, rulings), filename)
        return filename

    def plot(self, filename: str) -> str:
        from ruled.machine.output import plot_path
        plot_path(self.path, filename, "", self.report.get("swept_tool"))
        return filename


def _side_sign(side: str) -> float:
    if side not in ("outside", "inside"):
        raise BadInputError(f"side must be 'outside' or 'inside', not {side!r}")
    return 1.0 if side == "outside" else -1.0


def _machine(face, opts, side, method, samples, fit, measure, measure_samples, progress) -> MachineData:
    """The machine data of the face's fit as fit_face returns it (fit: that RuledFit, reused), its warnings
    also issued as Python warnings (a fallback to the corner-pinned fit names both figures)."""
    import warnings

    from ruled.jobs.machine import machine_job
    sign = _side_sign(side)
    src = _face_of(face)
    fm = machine_job(src, opts, FitOptions.of(samples=samples, method=method, ends="auto"), progress,
                     measure_samples if measure else None, sign, fit)
    if "fallback" in fm.report:
        warnings.warn(str(fm.warnings[0]), stacklevel=3)
    return MachineData(fm.path, _cq(fm.face), fm.report, fm.fit, fm.surface, tuple(fm.warnings))


def xyuv_face(face, chord_tol: Optional[float] = None, planes=None, axis="auto", kerf: float = 0.0,
              lead: Optional[float] = None, feed: float = 100.0, side: str = "outside", method: str = "2d",
              samples: int = 40, fit=None, measure: bool = True, measure_samples: int = 30,
              progress=None) -> MachineData:
    """Synchronized XYUV contours of the face's ruled fit for a 4-axis wire (EDM or hot wire): the lower
    guide on one plane (XY), the upper on the other (UV); fit=a RuledFit (or FitResult) of this face
    reuses it.  The report's "cut" is what the wire sweeps against the design face (offset by the kerf)."""
    from ruled.machine.paths import MachineOptions
    opts = MachineOptions("xyuv", chord_tol, planes, axis, None, kerf, None, 0.0, lead, feed)
    return _machine(face, opts, side, method, samples, fit, measure, measure_samples, progress)


def xyuv_patches(faces, chord_tol: Optional[float] = None, planes=None, axis="auto", kerf: float = 0.0,
                 lead: Optional[float] = None, feed: float = 100.0, side: str = "outside", measure: bool = True,
                 measure_samples: int = 30, progress=None) -> MachineData:
    """XYUV contours of ruled patches that follow one another (a cone spline's faces, in their order) as
    one wire path; the report's "patches" gives each patch's taper against the machine axis and its twist
    (0 on a developable patch).  fit is None: the patches are cut as they are."""
    from ruled.machine.paths import MachineOptions
    from ruled.occ.machine import machine_of_patches
    sign = _side_sign(side)
    src = [_face_of(f) for f in faces]
    opts = MachineOptions("xyuv", chord_tol, planes, axis, None, kerf, None, 0.0, lead, feed)
    fm = machine_of_patches(src, [f"patch {k}" for k in range(len(src))], opts, progress,
                            measure_samples if measure else None, sign)
    return MachineData(fm.path, _cq(fm.face), fm.report, fm.fit, fm.surface, tuple(fm.warnings))


def xyuv_wall(faces, chord_tol: Optional[float] = None, planes=None, axis="auto", kerf: float = 0.0,
              lead: Optional[float] = None, feed: float = 100.0, side: Optional[str] = None, start=None,
              method: str = "2d", samples: int = 40, fit=None, measure: bool = True, measure_samples: int = 30,
              progress=None, wall: str = "auto") -> MachineData:
    """One closed XYUV loop round a part's wall (fit_wall: a part and which wall, or its wall's faces): a
    single lead-in and lead-out at start (X, Y on the bottom contour; default the middle of its longest
    straight stretch), the kerf round the whole loop on side 'outside' or 'inside' the wall's contour
    (default: off the material, outside a punch, inside a hole: ruled.machine.wall.wall_side), the machine's
    axis the contours' normal.  fit: a WallFit of the same wall reuses it.  The report's "cut" is what the
    wire sweeps against the wall's faces, each distance less the kerf."""
    from ruled.machine.paths import MachineOptions
    from ruled.occ.wallmachine import machine_of_wall
    wf = fit if fit is not None else fit_wall(faces, samples, method=method, measure=False, progress=progress,
                                              wall=wall)        # (measured with the path it cuts)
    opts = MachineOptions("xyuv", chord_tol, planes, axis, None, kerf, None, 0.0, lead, feed)
    fm = machine_of_wall(wf, opts, side, start, measure_samples if measure else None, progress)
    return MachineData(fm.path, _cq(fm.face), fm.report, None, fm.surface, tuple(fm.warnings))


def flank_face(face, tool_radius: float, taper: float = 0.0, chord_tol: Optional[float] = None, feed: float = 100.0,
               side: str = "outside", tip: str = "auto", method: str = "2d", samples: int = 40, fit=None,
               measure: bool = True, measure_samples: int = 30, progress=None, positions: str = "envelope",
               gouge_tol: Optional[float] = None) -> MachineData:
    """Flank-milling CL data of the face's ruled fit: the tool tip centre and axis at every CL point for a
    cylindrical tool (or a conical one of half angle `taper` degrees), the positions fitted so the swept
    tool fits the face with its overcut within gouge_tol (default: the fit's bound), or positions="offset":
    each ruling offset by the radius.  The report's "tool_envelope" (the tool's circles against the face) and
    "swept_tool" (the face's points against the tool swept through the moves, with the axis's largest turn)
    give the measured overcut and undercut."""
    from ruled.machine.paths import MachineOptions
    opts = MachineOptions("flank", chord_tol, None, "auto", None, 0.0, tool_radius, taper, None, feed, tip=tip,
                          positions=positions, gouge_tol=gouge_tol)
    return _machine(face, opts, side, method, samples, fit, measure, measure_samples, progress)


# ------------------------------------------------------------------------- opt-in Workplane methods

def _selected_faces(wp) -> list:
    import cadquery as cq
    faces = [o for o in wp.vals() if isinstance(o, cq.Face)]
    if not faces:
        raise RuledError("no face selected: select faces first, e.g. .faces('>Z') or .add(face)")
    return faces


def _one_face(wp):
    faces = _selected_faces(wp)
    if len(faces) != 1:
        raise RuledError(f"{len(faces)} faces are selected; machine data is made for one face at a time")
    return faces[0]


def _ruledFit(self, **kw):
    """Replace each selected face by its ruled fit."""
    return self.newObject([fit_face(f, **kw).face for f in _selected_faces(self)])


def _ruledSplit(self, **kw):
    """Replace each selected face by the two faces of its best split for ruling."""
    return self.newObject([g for f in _selected_faces(self) for g in split_face(f, **kw).faces])


def _ruledConeSpline(self, tol: float, **kw):
    """Replace each selected face by its cone spline (a sewn shell) within tol."""
    return self.newObject([cone_spline_face(f, tol, **kw).shell for f in _selected_faces(self)])


def _ruledCurveOnFace(self, uv, **kw):
    """The curve on each selected face within a tolerance of the image of a (u, v) polyline or curve."""
    return self.newObject([curve_on_face(f, uv, **kw).edge for f in _selected_faces(self)])


def _ruledXYUV(self, filename: str, csv: Optional[str] = None, post: Optional[str] = None, **kw):
    """Write the XYUV G-code by a post (default linuxcnc; and its CSV, default beside it) of the selected face; the
    ruled fit follows."""
    m = xyuv_face(_one_face(self), **kw)
    m.write(filename, post, csv=csv)
    return self.newObject([m.face])


def _ruledFlank(self, filename: str, tool_radius: float, csv: Optional[str] = None, **kw):
    """Write the flank-milling APT CL data (and its CSV) of the selected face; the ruled fit follows."""
    m = flank_face(_one_face(self), tool_radius, **kw)
    m.write(filename, csv=csv)
    return self.newObject([m.face])


WORKPLANE_METHODS = {"ruledFit": _ruledFit, "ruledSplit": _ruledSplit, "ruledConeSpline": _ruledConeSpline,
                     "ruledCurveOnFace": _ruledCurveOnFace, "ruledXYUV": _ruledXYUV, "ruledFlank": _ruledFlank}


def register() -> None:
    """Add the chainable methods of WORKPLANE_METHODS to cadquery.Workplane (opt in; idempotent)."""
    import cadquery as cq
    for name, fn in WORKPLANE_METHODS.items():
        setattr(cq.Workplane, name, fn)


def unregister() -> None:
    """Remove what register() added."""
    import cadquery as cq
    for name in WORKPLANE_METHODS:
        if getattr(cq.Workplane, name, None) is WORKPLANE_METHODS[name]:
            delattr(cq.Workplane, name)
