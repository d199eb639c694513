"""CadQuery entry points.

    import cadquery as cq
    from ruled.cq import fit_face

    face = cq.importers.importStep("part.step").faces().vals()[3]
    fit = fit_face(face, samples=40)
    print(fit.error_bound, fit.hausdorff.max)
    cq.exporters.export(cq.Workplane().add(fit.face), "ruled.step")

    from ruled.cq import curve_on_face
    c = curve_on_face(face, [(0.1, 0.2), (0.5, 0.8), (0.9, 0.3)], tol=1e-3, angle=1.0)
    print(c.result.segments, c.result.error_bound, c.measure.hausdorff)
    cq.exporters.export(cq.Workplane().add(c.edge), "curve.step")

    from ruled.cq import cone_spline_face
    cs = cone_spline_face(face, tol=0.01, fit=True)      # fit a ruled surface, then a cone spline of it
    print(len(cs.faces), cs.result.bound, cs.measure["design_to_cone"])
    cq.exporters.export(cq.Workplane().add(cs.shell), "cones.step")

The face may be a ``cadquery.Face``, an OCP ``TopoDS_Face`` or a
:class:`ruled.Surface` container.  OCP is reached only through ``ruled.occ``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Optional

import numpy as np

from .fit import FitOptions, FitResult, Progress, fit_surface
from .nurbs import Surface


@dataclass(frozen=True)
class RuledFit:
    """A ruled fit and its errors: the result face, the rulings, the certified bound and the measure."""

    face: Any                 # cadquery.Face when CadQuery is installed, else TopoDS_Face
    surface: Surface          # the result as plain arrays
    rulings: np.ndarray       # (K, 2, 3) end points of the DP rulings on the input face
    error_bound: float        # certified upper bound of the Hausdorff distance to the input face
    hausdorff: Optional[Any]  # ruled.occ.Hausdorff measured with OCCT, or None when not asked
    result: FitResult         # everything else (pairing, candidates, timings)


def _topods(face):
    wrapped = getattr(face, "wrapped", None)
    return wrapped if wrapped is not None else face


def _face_of(face):
    """An OCP face for a cadquery.Face, a TopoDS_Face or a Surface container."""
    from .occ.convert import container_to_face
    return container_to_face(face) if isinstance(face, Surface) else _topods(face)


def fit_face(face, samples: int = 40, objective: str = "sum", max_error: Optional[float] = None,
             direction: str = "auto", refine: bool = True, measure: bool = True, measure_samples: int = 40,
             progress: Progress = None, method: str = "2d", elevations: Optional[int] = None,
             step: Optional[float] = None, metric: str = "lsad") -> RuledFit:
    """Fit the best ruled surface to a face (2D-DP over boundary samples, or 4D-DP with the ruling
    ends lifted along the normal; refined, certified)."""
    from .occ.convert import container_to_face, conversion_slack, face_to_container
    from .occ.measure import hausdorff

    slack = 0.0
    if isinstance(face, Surface):
        S = face
        src = container_to_face(S)
    else:
        src = _topods(face)
        S = face_to_container(src)
        slack = conversion_slack(src, S)
    res = fit_surface(S, FitOptions(samples=samples, objective=objective, max_error=max_error,
                                    direction=direction, refine=refine, method=method, elevations=elevations,
                                    step=step, metric=metric), progress)
    out = container_to_face(res.surface)
    h = hausdorff(src, out, measure_samples) if measure else None
    try:
        import cadquery as cq
        out_face = cq.Face(out)
    except ImportError:  # plain OCP
        out_face = out
    return RuledFit(out_face, res.surface, res.best.rulings, res.error_bound + slack, h, res)


@dataclass(frozen=True)
class CurveOnFace:
    """A curve lying exactly on a face, within a tolerance of the image of a (u, v) curve."""

    edge: Any                 # cadquery.Edge when CadQuery is installed, else TopoDS_Edge; carries its pcurve
    result: Any               # ruled.curve_on_surface.CurveOnSurface: segments, bound, the curve and pcurve arrays
    measure: Optional[Any]    # ruled.occ.measure.CurveMeasure (OCCT), or None when not asked
    warnings: tuple = ()


def curve_on_face(face, uv, tol: float = 1e-3, angle: float = 1.0, bound: str = "local", measure: bool = True,
                  measure_samples: int = 2000, progress=None) -> CurveOnFace:
    """The image on the face of a (u, v) curve: uv is a polyline ((N, 2) points) or a 2D
    :class:`ruled.Curve`; the result is a curve of degree p + q on the face's surface exactly (Yang et
    al. 2008), within tol of the exact image and G1 within angle degrees at its joints."""
    from .curve_on_surface import polyline_curve
    from .nurbs import Curve
    from .occ.cos import curve_on_face as _on_face

    src = _face_of(face)
    D = uv if isinstance(uv, Curve) else polyline_curve(uv)
    fc = _on_face(src, D, tol, angle, bound=bound, progress=progress,
                  measure_samples=measure_samples if measure else None)
    try:
        import cadquery as cq
        edge = cq.Edge(fc.edge)
    except ImportError:  # plain OCP
        edge = fc.edge
    return CurveOnFace(edge, fc.result, fc.measure, tuple(fc.warnings))


@dataclass(frozen=True)
class ConeSplineFace:
    """A tangent-smooth cone spline (developable) within a tolerance of a ruled face."""

    shell: Any                # cadquery.Shape (the sewn patches) when CadQuery is installed, else the OCP shape
    faces: tuple              # one face per cone patch
    result: Any               # ruled.conespline.ConeSpline: patches (weight, apex, development), bound, pieces
    measure: Optional[dict]   # independent distances (OCCT), or None when not asked
    fit: Any = None           # the ruled fit when fit=True
    warnings: tuple = ()


def cone_spline_face(face, tol: float, step: float = 0.1, fit: bool = False, direction: str = "auto",
                     measure: bool = True, measure_samples: int = 24, allow_creases: bool = False,
                     progress=None) -> ConeSplineFace:
    """The cone spline of a ruled face within tol (Yang & Yang 2006); with fit=True the face is first
    fitted by a ruled surface (fit_face's defaults) and that fit is cone-splined, in one call."""
    from .occ.conespline import check_tolerance, cone_of_face

    src = _face_of(face)
    fc = cone_of_face(src, check_tolerance(tol), step, direction=direction, fit=fit, progress=progress,
                      measure_samples=measure_samples if measure else None, allow_creases=allow_creases)
    try:
        import cadquery as cq
        shell, faces = cq.Shape.cast(fc.shell), tuple(cq.Face(f) for f in fc.faces)
    except ImportError:  # plain OCP
        shell, faces = fc.shell, tuple(fc.faces)
    return ConeSplineFace(shell, faces, fc.result, fc.measure, fc.fit, tuple(fc.warnings))
