"""A trimmed result as a host face: the ruled surface bounded by the face's edges mapped onto it
(ruled.fit.trim.Trim: 2D curves in the result's (s, t))."""

from __future__ import annotations

import numpy as np
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeFace, BRepBuilderAPI_MakeWire
from OCP.BRepCheck import BRepCheck_Analyzer
from OCP.BRepLib import BRepLib
from OCP.ShapeFix import ShapeFix_Face
from OCP.TopoDS import TopoDS_Face

from ruled.core.errors import BadInputError, FiguresError
from ruled.core.nurbs import Curve, Surface
from ruled.occ.convert import container_to_bspline, container_to_face, curve2d_to_bspline


def _reversed(c: Curve) -> Curve:
    a, b = c.domain
    return Curve(c.poles[::-1].copy(), (a + b) - c.knots[::-1], c.degree,
                 None if c.weights is None else c.weights[::-1].copy())


def _signed_area(curves: tuple) -> float:
    P = np.concatenate([c(np.linspace(c.domain[0], c.domain[1], 65)) for c in curves])
    x, y = P[:, 0], P[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def _oriented(curves: tuple, ccw: bool) -> tuple:
    """The loop running counter-clockwise in (s, t) (ccw) or clockwise."""
    if (_signed_area(curves) > 0) == ccw:
        return curves
    return tuple(_reversed(c) for c in reversed(curves))


def _wire(curves: tuple, surf):
    mk = BRepBuilderAPI_MakeWire()
    for c in curves:
        me = BRepBuilderAPI_MakeEdge(curve2d_to_bspline(c), surf)
        if not me.IsDone():
            raise BadInputError("could not build an edge of the trimmed result; try «ends=pinned»")
        mk.Add(me.Edge())
    if not mk.IsDone():
        raise BadInputError("the face's edges on the result do not close into a loop; try «ends=pinned»")
    return mk.Wire()


def trimmed_face(R: Surface, trim) -> TopoDS_Face:
    """R bounded by the trim's outer loop, less its holes, with 3D edges built from the 2D ones."""
    surf = container_to_bspline(R)
    outer = _wire(_oriented(trim.outer, True), surf)
    mk = BRepBuilderAPI_MakeFace(surf, outer, True)
    for h in trim.holes:
        mk.Add(_wire(_oriented(h, False), surf))
    if not mk.IsDone():
        raise BadInputError("could not build the trimmed result face; try «ends=pinned»")
    face = mk.Face()
    BRepLib.BuildCurves3d_s(face)
    fix = ShapeFix_Face(face)
    fix.Perform()
    face = fix.Face()
    if not BRepCheck_Analyzer(face).IsValid():
        raise FiguresError("the result trimmed by the face's edges is not a valid face (OCCT's check), so it is "
                           "not returned (please report the face); try «ends=pinned»")
    return face


def result_face(fit) -> TopoDS_Face:
    """The result of a fit (a FitResult or one of its candidates) as a face: trimmed by the face's edges
    when it has a trim, else bounded by its own four sides."""
    best = getattr(fit, "best", fit)
    trim = getattr(best, "trim", None)
    return container_to_face(best.surface) if trim is None else trimmed_face(best.surface, trim)


__all__ = ["trimmed_face", "result_face"]
