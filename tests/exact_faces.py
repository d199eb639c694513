"""Exactly ruled faces cut out of larger ruled surfaces by curved edges (none of them a ruling), built with
OCCT alone (no engine code): the class of issue 35's first acceptance point, open and closed, rational and
not, and given so that nothing in their representation says they are ruled."""

from __future__ import annotations

from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeFace, BRepBuilderAPI_MakeWire
from OCP.BRepLib import BRepLib
from OCP.GeomAbs import GeomAbs_Shape
from OCP.gp import gp_Pnt, gp_Pnt2d
from OCP.TopoDS import TopoDS
from trimmed_faces import bspline_surface, curve2d, face_from_loops, graph2d


def diamond_on_ruled_face(elevated: bool = False):
    """A face cut out of an exactly ruled surface (degree 3 x 1: its rulings are its v-lines) by four
    curved edges in its (u, v), none of them a ruling: a rounded diamond, each side a quadratic arc.
    elevated: the same surface given as degree 3 x 3 (OCCT's degree elevation), so that nothing in its
    representation says it is ruled."""
    A = [(0, 0, 0), (30, 10, 5), (70, -10, 10), (100, 0, 0)]
    B = [(0, 40, 20), (35, 50, -10), (65, 30, 25), (100, 45, 10)]
    poles = [[A[i], B[i]] for i in range(4)]
    surf = bspline_surface(poles, [0.0, 1.0], [4, 4], [0.0, 1.0], [2, 2], 3, 1)
    if elevated:
        surf.IncreaseDegree(3, 3)
    return diamond_face(surf)


def diamond_face(surf):
    """The rounded diamond of diamond_on_ruled_face in surf's (u, v) bounds, scaled from the unit square."""
    u0, u1, v0, v1 = surf.Bounds()

    def at(p):
        return (u0 + p[0] * (u1 - u0), v0 + p[1] * (v1 - v0))
    corners = [(0.5, 0.08), (0.92, 0.45), (0.55, 0.93), (0.1, 0.5)]
    bulge = [(0.78, 0.2), (0.8, 0.78), (0.25, 0.8), (0.22, 0.22)]
    loop = [curve2d([at(corners[k]), at(bulge[k]), at(corners[(k + 1) % 4])]) for k in range(4)]
    return face_from_loops(surf, [loop])


def hyperboloid_surface(turn: float, elevated: bool = True):
    """A hyperboloid of one sheet (a line skew to the z axis revolved about it: rational, its rulings the
    line's positions), the angles 0 .. turn, as a B-spline; elevated: given as degree 3 in the line's
    direction too (OCCT's degree elevation), so that nothing in its representation says it is ruled."""
    from OCP.Geom import Geom_Line, Geom_RectangularTrimmedSurface, Geom_SurfaceOfRevolution, Geom_TrimmedCurve
    from OCP.GeomConvert import GeomConvert
    from OCP.gp import gp_Ax1, gp_Dir, gp_Lin
    line = Geom_Line(gp_Lin(gp_Pnt(10, 0, -10), gp_Dir(0, 0.6, 1)))
    rev = Geom_SurfaceOfRevolution(Geom_TrimmedCurve(line, 0, 20), gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)))
    bs = GeomConvert.SurfaceToBSplineSurface_s(Geom_RectangularTrimmedSurface(rev, 0, turn, 0, 20))
    if elevated:
        bs.IncreaseDegree(max(bs.UDegree(), 3), 3)
    return bs


def closed_band_face(bs, flo, fhi):
    """A band of a surface closed in u (over its whole u range) between two closed curves v = flo(u) and
    v = fhi(u), cut at its seam u = u0: the seam an edge twice, the band's loop bottom, seam, top, seam."""
    from OCP.BRep import BRep_Builder
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeVertex
    from OCP.BRepCheck import BRepCheck_Analyzer
    from OCP.GCE2d import GCE2d_MakeSegment
    from OCP.TopLoc import TopLoc_Location
    u0, u1 = bs.Bounds()[:2]
    lo, hi = graph2d(u0, u1, flo), graph2d(u0, u1, fhi, reverse=True)
    Vlo = BRepBuilderAPI_MakeVertex(bs.Value(u0, flo(u0))).Vertex()
    Vhi = BRepBuilderAPI_MakeVertex(bs.Value(u0, fhi(u0))).Vertex()
    e_lo = BRepBuilderAPI_MakeEdge(lo, bs, Vlo, Vlo, lo.FirstParameter(), lo.LastParameter()).Edge()
    e_hi = BRepBuilderAPI_MakeEdge(hi, bs, Vhi, Vhi, hi.FirstParameter(), hi.LastParameter()).Edge()
    right = GCE2d_MakeSegment(gp_Pnt2d(u1, flo(u0)), gp_Pnt2d(u1, fhi(u0))).Value()
    left = GCE2d_MakeSegment(gp_Pnt2d(u0, flo(u0)), gp_Pnt2d(u0, fhi(u0))).Value()
    seam = BRepBuilderAPI_MakeEdge(right, bs, Vlo, Vhi).Edge()
    BRep_Builder().UpdateEdge(seam, right, left, bs, TopLoc_Location(), 1e-7)
    w = BRepBuilderAPI_MakeWire()
    for e in (e_lo, seam, e_hi, TopoDS.Edge_s(seam.Reversed())):
        w.Add(e)
    face = BRepBuilderAPI_MakeFace(bs, w.Wire(), True).Face()
    BRepLib.BuildCurves3d_s(face, 1e-7, GeomAbs_Shape.GeomAbs_C1, 14, 200)
    assert BRepCheck_Analyzer(face).IsValid()
    return face


def saddle_band_face():
    """A band across a hyperbolic paraboloid (z = 40 u v over 100 x 100, given as degree 3 x 3 so that nothing
    says it is ruled, let alone doubly), along its diagonal: both families of its rulings (its u- and
    v-lines) cross from one long side of the band to the other, and none is an edge; the short sides are
    arcs.  Its long sides are slight arcs too."""
    poles = [[(0, 0, 0), (0, 100, 0)], [(100, 0, 0), (100, 100, 40)]]
    surf = bspline_surface(poles, [0.0, 1.0], [2, 2], [0.0, 1.0], [2, 2], 1, 1)
    surf.IncreaseDegree(3, 3)
    c = [(0.28, 0.08), (0.92, 0.7), (0.72, 0.92), (0.08, 0.28)]
    mid = [(0.62, 0.36), (0.86, 0.86), (0.36, 0.62), (0.14, 0.14)]
    loop = [curve2d([c[k], mid[k], c[(k + 1) % 4]]) for k in range(4)]
    return face_from_loops(surf, [loop])


def hyperbola_revolution(turn: float, a: float = 10.0, c: float = 15.0, t: float = 1.0):
    """A hyperboloid of one sheet as OCCT makes it from a hyperbola (x = a cosh, z = c sinh, in the xz plane)
    revolved about z by the angle turn: rational in both directions, its rulings no iso-curves of it
    (Elber 2011's Figure 4: the surface of revolution of a conic section)."""
    from OCP.Geom import Geom_Hyperbola, Geom_RectangularTrimmedSurface, Geom_SurfaceOfRevolution, Geom_TrimmedCurve
    from OCP.GeomConvert import GeomConvert
    from OCP.gp import gp_Ax1, gp_Ax2, gp_Dir
    h = Geom_Hyperbola(gp_Ax2(gp_Pnt(0, 0, 0), gp_Dir(0, -1, 0), gp_Dir(1, 0, 0)), a, c)
    rev = Geom_SurfaceOfRevolution(Geom_TrimmedCurve(h, -t, t), gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)))
    return GeomConvert.SurfaceToBSplineSurface_s(Geom_RectangularTrimmedSurface(rev, 0, turn, -t, t))
