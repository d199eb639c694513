"""Curves on faces with OCCT: the engine's curve on surface for a face, as an edge carrying its
pcurve on that face, measured independently (used by the command line and the CadQuery entry)."""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Any, Optional

from ruled.core.nurbs import Curve, Surface
from ruled.core.progress import Progress
from ruled.curves.curve_on_surface import CurveOnSurface, approximate, sampled_error
from ruled.curves.domain import check_inside
from ruled.occ.convert import (
    container_to_bspline,
    container_to_face,
    curve2d_to_bspline,
    curve_to_bspline,
    edge_on_face,
    face_surface_type,
    face_to_container,
)
from ruled.occ.curve_measure import CurveMeasure, curve_on_surface_measure


@dataclass
class FaceCurve:
    edge: Any                      # TopoDS_Edge: the 3D curve with its pcurve on `host`
    host: Any                      # the face carrying the pcurve (the input face when it is a B-spline)
    surface: Surface               # the face's surface as plain arrays
    result: CurveOnSurface         # segments, bound, joints, the 3D curve and the pcurve
    measure: Optional[CurveMeasure]  # OCCT's independent measure, or None when not asked
    engine_hausdorff: float        # the engine's own sampled distance to the exact image
    warnings: list = field(default_factory=list)
    timings: dict = field(default_factory=dict)   # seconds: approximate, measure


def curve_on_face(face, D: Curve, tol: float, angle: float = 1.0, *, bound: str = "local", progress: Progress = None,
                  measure_samples: Optional[int] = 2000) -> FaceCurve:
    """The image of the (u, v) curve D on the face's surface, within tol (certified) and with joints
    within angle degrees, as an edge with its pcurve; measured with OCCT unless measure_samples is None."""
    S = face_to_container(face)
    warnings = []
    kind = face_surface_type(face)
    host = face
    if kind != "bspline":
        warnings.append(f"the face is a {kind}; (u, v) are taken in its B-spline conversion's parameters, and the "
                        f"pcurve lies on that converted surface")
        host = container_to_face(S)
    from ruled.occ.region import face_region
    check_inside(face_region(face, S), D)
    t0 = time.perf_counter()
    res = approximate(S, D, tol, angle, bound=bound, progress=progress)
    t1 = time.perf_counter()
    own = sampled_error(S, D, res)["hausdorff"]
    edge = edge_on_face(res.curve, res.pcurve, host)
    m = None
    if measure_samples:
        m = curve_on_surface_measure(container_to_bspline(S), curve2d_to_bspline(D), curve_to_bspline(res.curve),
                                     measure_samples, curve2d_to_bspline(res.pcurve))
    return FaceCurve(edge, host, S, res, m, own, warnings,
                     {"approximate": t1 - t0, "measure": time.perf_counter() - t1})
