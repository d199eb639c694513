"""A face's edges and bounds as OCCT evaluates them: its edges with a 3D curve, its (u, v) bounds, and its edges
as ruled.core.edgerows.EdgeView for the measure's extra samples where a file's edges lie off their face's
surface (ruled.core.edgerows says which and why)."""

from __future__ import annotations

from OCP.BRep import BRep_Tool
from OCP.BRepAdaptor import BRepAdaptor_Curve, BRepAdaptor_Curve2d
from OCP.BRepTools import BRepTools
from OCP.TopAbs import TopAbs_ShapeEnum
from OCP.TopExp import TopExp_Explorer
from OCP.TopoDS import TopoDS

from ruled.core.edgerows import EdgeView
from ruled.core.hostform import clipped_bounds
from ruled.occ.curve_measure import _p3


def face_bounds(face):
    """The face's UV bounds, clipped to its surface's own range (faces may overhang it by round-off)."""
    surf = BRep_Tool.Surface_s(face)
    return clipped_bounds(BRepTools.UVBounds_s(face), surf.Bounds(), (surf.IsUPeriodic(), surf.IsVPeriodic()))


def face_edges(face):
    """The face's edges with a 3D curve (every wire, degenerate edges left out)."""
    out = []
    ex = TopExp_Explorer(face, TopAbs_ShapeEnum.TopAbs_EDGE)
    while ex.More():
        e = TopoDS.Edge_s(ex.Current())
        if not BRep_Tool.Degenerated_s(e):
            out.append(e)
        ex.Next()
    return out


def edge_views(face) -> list:
    """The face's edges with a 3D curve and a pcurve, as EdgeViews (OCCT's evaluation)."""
    surf = BRep_Tool.Surface_s(face)
    box = face_bounds(face)

    def surface(u, v):
        return _p3(surf.Value(float(u), float(v)))
    out = []
    for e in face_edges(face):
        a, b = BRep_Tool.Range_s(e, face)
        if BRep_Tool.CurveOnSurface_s(e, face, a, b) is None:
            continue
        c2, c3 = BRepAdaptor_Curve2d(e, face), BRepAdaptor_Curve(e)

        def pcurve(t, c2=c2):
            q = c2.Value(float(t))
            return (q.X(), q.Y())

        def curve(t, c3=c3):
            return _p3(c3.Value(float(t)))
        out.append(EdgeView(surface, pcurve, c2.FirstParameter(), c2.LastParameter(), curve, c3.FirstParameter(),
                            c3.LastParameter(), box))
    return out


__all__ = ["edge_views", "face_bounds", "face_edges"]
