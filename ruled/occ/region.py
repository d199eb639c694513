"""A face's boundary as the engine's Region: the outer wire's pcurves in wire order (with the edges'
orientation), its inner wires, seams and degenerate edges."""

from __future__ import annotations

from OCP.BRep import BRep_Tool
from OCP.BRepAdaptor import BRepAdaptor_Curve
from OCP.BRepTools import BRepTools, BRepTools_WireExplorer
from OCP.GCPnts import GCPnts_AbscissaPoint
from OCP.Geom import Geom_RectangularTrimmedSurface, Geom_TrimmedCurve
from OCP.Geom2d import Geom2d_TrimmedCurve
from OCP.Geom2dConvert import Geom2dConvert
from OCP.GeomConvert import GeomConvert
from OCP.TopAbs import TopAbs_Orientation, TopAbs_ShapeEnum
from OCP.TopExp import TopExp_Explorer
from OCP.TopoDS import TopoDS

from ruled.core.errors import BadInputError, RuledError
from ruled.core.hostform import curve_from_kernel_form
from ruled.core.nurbs import Curve
from ruled.core.region import Region
from ruled.occ.convert import face_to_container, nurbs_face


def _kernel_curve(bs, reversed_: bool, onto=None) -> Curve:
    """A Geom(2d)_BSplineCurve (made non-periodic) as a container (ruled.core.hostform)."""
    if bs.IsPeriodic():
        bs = bs.Copy()
        bs.SetNotPeriodic()
    n = bs.NbPoles()
    poles = [bs.Pole(i).Coord() for i in range(1, n + 1)]
    weights = [bs.Weight(i) for i in range(1, n + 1)] if bs.IsRational() else None
    return curve_from_kernel_form(poles, weights, [bs.Knot(i) for i in range(1, bs.NbKnots() + 1)],
                                  [bs.Multiplicity(i) for i in range(1, bs.NbKnots() + 1)], bs.Degree(),
                                  reversed_, onto)


def _reversed(edge) -> bool:
    return edge.Orientation() == TopAbs_Orientation.TopAbs_REVERSED


def _pcurve(edge, face) -> Curve:
    """The edge's pcurve on the face as a 2D B-spline container, running in the edge's direction in
    its wire (reversed edges reversed)."""
    c2 = BRep_Tool.CurveOnSurface_s(edge, face, 0.0, 0.0)
    if c2 is None:
        raise BadInputError("an edge of the face has no curve on its surface; repair the face (e.g. "
                            "ShapeFix in your CAD system)")
    a, b = BRep_Tool.Range_s(edge, face)
    return _kernel_curve(Geom2dConvert.CurveToBSplineCurve_s(Geom2d_TrimmedCurve(c2, a, b)), _reversed(edge))


def _curve3d(edge, pcurve: Curve):
    """The edge's 3D curve as a container on its pcurve's parameter (running the same way), or None
    for an edge without one."""
    if BRep_Tool.Degenerated_s(edge):
        return None
    a, b = BRep_Tool.Range_s(edge)
    c3 = BRep_Tool.Curve_s(edge, 0.0, 0.0)
    if c3 is None:
        return None
    bs = GeomConvert.CurveToBSplineCurve_s(Geom_TrimmedCurve(c3, a, b))
    return _kernel_curve(bs, _reversed(edge), pcurve.domain)


def _wire_edges(wire, face) -> list:
    out = []
    we = BRepTools_WireExplorer(wire, face)
    while we.More():
        out.append(we.Current())
        we.Next()
    return out


def outer_edges(face) -> list:
    """The outer wire's edges in wire order (the indices 'ruled faces --edges' lists and --rails takes)."""
    return _wire_edges(BRepTools.OuterWire_s(face), face)


def face_region(face, S=None) -> Region:
    """The face's Region: its surface (the container, restricted to the face's UV bounds) and its
    boundary as pcurves."""
    S = face_to_container(face) if S is None else S
    try:
        return _face_region(nurbs_face(face), S)
    except RuledError:
        raise
    except Exception as exc:     # OCCT's Standard_Failure and friends: a face whose boundary cannot be read
        raise BadInputError(f"cannot read the face's boundary ({type(exc).__name__}: {exc}); repair the face "
                            f"(ShapeFix in your CAD system)") from None


def _face_region(face, S) -> Region:
    outer = BRepTools.OuterWire_s(face)
    if outer.IsNull():
        raise BadInputError("the face has no outer wire; pick a face bounded by edges (see 'ruled faces')")
    edges = _wire_edges(outer, face)
    loop = [_pcurve(e, face) for e in edges]
    e3 = [_curve3d(e, c) for e, c in zip(edges, loop)]
    seams = [bool(BRep_Tool.IsClosed_s(e, face)) for e in edges]
    degen = [bool(BRep_Tool.Degenerated_s(e)) for e in edges]
    holes, holes3d, hole_tols = [], [], []
    exp = TopExp_Explorer(face, TopAbs_ShapeEnum.TopAbs_WIRE)
    while exp.More():
        w = TopoDS.Wire_s(exp.Current())
        if not w.IsSame(outer):
            hedges = _wire_edges(w, face)
            holes.append(tuple(_pcurve(e, face) for e in hedges))
            holes3d.append(tuple(_curve3d(e, c) for e, c in zip(hedges, holes[-1])))
            hole_tols.append(tuple(float(BRep_Tool.Tolerance_s(e)) for e in hedges))
        exp.Next()
    surf = BRep_Tool.Surface_s(face)
    if isinstance(surf, Geom_RectangularTrimmedSurface):   # a periodic surface trimmed to a whole period
        surf = surf.BasisSurface()
    u0, u1, v0, v1 = S.domain
    closed = (bool(surf.IsUPeriodic() and abs((u1 - u0) - surf.UPeriod()) <= 1e-9 * surf.UPeriod()),
              bool(surf.IsVPeriodic() and abs((v1 - v0) - surf.VPeriod()) <= 1e-9 * surf.VPeriod()))
    tols = tuple(float(BRep_Tool.Tolerance_s(e)) for e in edges)
    return Region(S, tuple(loop), tuple(seams), tuple(degen), tuple(holes), tuple(e3), closed, tols, tuple(holes3d),
                  tuple(hole_tols))


def edge_lines(face) -> list:
    """One line per outer-wire edge: index, curve type, 3D length, end points, seam or degenerate."""
    out = []
    for i, e in enumerate(outer_edges(face)):
        if BRep_Tool.Degenerated_s(e):
            out.append(f"  edge {i:3d}  degenerate (a point of the surface)")
            continue
        ad = BRepAdaptor_Curve(e)
        length = GCPnts_AbscissaPoint.Length_s(ad)
        a, b = ad.FirstParameter(), ad.LastParameter()
        if e.Orientation() == TopAbs_Orientation.TopAbs_REVERSED:
            a, b = b, a
        p, q = ad.Value(a), ad.Value(b)
        kind = str(ad.GetType()).split(".")[-1].replace("GeomAbs_", "").lower()
        seam = "  seam" if BRep_Tool.IsClosed_s(e, face) else ""
        out.append(f"  edge {i:3d}  {kind:<10s} length {length:<10.6g} from ({p.X():.4g}, {p.Y():.4g}, {p.Z():.4g}) "
                   f"to ({q.X():.4g}, {q.Y():.4g}, {q.Z():.4g}){seam}")
    return out




def fit_face(face, options, progress=None, rails=None, S=None):
    """The ruled fit of the face as bounded by its edges: (FitResult, conversion slack), the slack (the
    container's round-off overhang of the face's bounds) to be added to the bound.  S: the face's
    container when the caller has it already."""
    from ruled.fit.face.fit import fit_region
    from ruled.occ.convert import conversion_slack
    face = nurbs_face(face)         # (once: the container, the region and the slack each read it)
    S = face_to_container(face) if S is None else S
    return fit_region(face_region(face, S), options, progress, rails), conversion_slack(face, S)


def rect_area_ratio(face, S=None, area=None) -> float:
    """The face's area (given, or OCCT's) over its surface's (u, v) rectangle's area (1: untrimmed)."""
    from ruled.fit.fit2d import surface_area
    from ruled.occ.io import face_area
    S = face_to_container(face) if S is None else S
    a = surface_area(S)
    return (face_area(face) if area is None else area) / a if a > 0 else 1.0


__all__ = ["face_region", "outer_edges", "edge_lines", "fit_face", "rect_area_ratio"]
