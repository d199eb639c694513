"""A trimmed result as a host face: the ruled surface bounded by the face's edges mapped onto it
(ruled.fit.face.trim.Trim: 2D curves in the result's (s, t))."""

from __future__ import annotations

from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeFace, BRepBuilderAPI_MakeWire
from OCP.BRepCheck import BRepCheck_Analyzer
from OCP.BRepLib import BRepLib
from OCP.GeomAbs import GeomAbs_Shape
from OCP.ShapeFix import ShapeFix_Face
from OCP.TopoDS import TopoDS_Face

from ruled.core.errors import BadInputError, FiguresError
from ruled.core.nurbs import Surface
from ruled.occ.convert import container_to_bspline, container_to_face, curve2d_to_bspline

EDGE_TOL = 1e-7


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


def trimmed_face(R: Surface, trim, surf=None) -> TopoDS_Face:
    """R bounded by the trim's outer loop, less its holes, with 3D edges built from the 2D ones (surf: R as
    OCCT's surface, when the caller has made it, periodic say)."""
    surf = container_to_bspline(R) if surf is None else surf
    outer = _wire(trim.loop(trim.outer, True), surf)
    mk = BRepBuilderAPI_MakeFace(surf, outer, True)
    for h in trim.holes:
        mk.Add(_wire(trim.loop(h, False), surf))
    if not mk.IsDone():
        raise BadInputError("could not build the trimmed result face; try «ends=pinned»")
    face = mk.Face()
    # the 3D edges within EDGE_TOL of the 2D ones on R (OCCT's default, 1e-5, put a plate's edges 2.4e-6 off)
    BRepLib.BuildCurves3d_s(face, EDGE_TOL, GeomAbs_Shape.GeomAbs_C1, 14, 200)
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


def built_slack(face, fit) -> float:
    """What building a trimmed result adds to its bound: its 3D edges, made from its 2D trim curves on the
    ruled surface, lie within their tolerance of those curves' image (OCCT's edge tolerance), and the
    measure samples those edges.  0 for a result bounded by its own four sides (exact iso curves)."""
    from OCP.BRep import BRep_Tool
    from OCP.TopAbs import TopAbs_EDGE
    from OCP.TopoDS import TopoDS

    from ruled.occ.io import shapes_of
    if getattr(getattr(fit, "best", fit), "trim", None) is None:
        return 0.0
    return max((float(BRep_Tool.Tolerance_s(TopoDS.Edge_s(e))) for e in shapes_of(face, TopAbs_EDGE)), default=0.0)

