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


def _interpolated_face(S, n: int, m: int, s0: float = 0.0, s1: float = 1.0):
    """The face of OCCT's cubic interpolation (GeomAPI_PointsToBSplineSurface) of S(s, t) on an n x m grid of
    [s0, s1] x [0, 1]: a B-spline that says nothing of the ruled surface it was sampled from."""
    import numpy as np
    from OCP.GeomAPI import GeomAPI_PointsToBSplineSurface
    from OCP.TColgp import TColgp_Array2OfPnt
    P = S(np.linspace(s0, s1, n)[:, None], np.linspace(0.0, 1.0, m)[None, :])
    arr = TColgp_Array2OfPnt(1, n, 1, m)
    for i in range(n):
        for j in range(m):
            arr.SetValue(i + 1, j + 1, gp_Pnt(*map(float, P[i, j])))
    surf = GeomAPI_PointsToBSplineSurface(arr, 3, 3, GeomAbs_Shape.GeomAbs_C2, 1e-9).Surface()
    return BRepBuilderAPI_MakeFace(surf, 1e-7).Face()


def skewed_conic_ruled_face():
    """A ruled surface between an ellipse arc and a hyperbola arc (both conics), reparametrized by maps in both
    of its parameters so that its rulings are no iso-curves, given as OCCT's interpolation of it (41 x 21)."""
    import numpy as np

    def S(s, t):
        u = s + 0.12 * np.sin(np.pi * t) * s * (1 - s) + 0.05 * t * s * (1 - s)
        v = t + 0.1 * s * t * (1 - t)
        th, x = 0.2 + 2.2 * u, -1.0 + 2.0 * u
        C0 = np.stack([40 * np.cos(th), 25 * np.sin(th), 0 * th], -1)
        C1 = np.stack([30 * np.cosh(x) - 10, 20 * np.sinh(x) + 5, 60 + 8 * x], -1)
        return (1 - v)[..., None] * C0 + v[..., None] * C1
    return _interpolated_face(S, 41, 21)


def twisted_blade_face():
    """A twisted blade: ruled between a cambered airfoil section (chord 60, a round leading edge) and a smaller
    one turned by 0.5 rad 120 above, the rulings pairing other points of the two sections, around the leading
    edge from 2 % to 98 % of the loop; OCCT's interpolation of it (81 x 11)."""
    import numpy as np

    def airfoil(x):
        th = np.pi * (1 - 2 * x)
        xc = 0.5 * (1 + np.cos(th))
        yt = 0.6 * (0.2969 * np.sqrt(xc) - 0.126 * xc - 0.3516 * xc ** 2 + 0.2843 * xc ** 3 - 0.1036 * xc ** 4)
        return np.stack([xc, 0.16 * xc * (1 - xc) - np.sign(np.sin(th)) * yt], -1)

    def section(x, chord, twist, z):
        p = airfoil(x) * chord
        c, s = np.cos(twist), np.sin(twist)
        return np.stack([c * p[..., 0] - s * p[..., 1], s * p[..., 0] + c * p[..., 1], np.full(p.shape[:-1], z)], -1)

    def S(s, t):
        s, t = np.broadcast_arrays(s, t)
        u1 = np.clip(s + 0.04 * np.sin(2 * np.pi * s), 0, 1)
        return (1 - t)[..., None] * section(s, 60, 0.0, 0.0) + t[..., None] * section(u1, 40, 0.5, 120.0)
    return _interpolated_face(S, 81, 11, 0.02, 0.98)


def sheared_elliptic_hyperboloid():
    """Elber 2011's Figure 6 recreated: a closed hyperbolic surface that is no surface of revolution (the
    revolved hyperbola of hyperbola_revolution squeezed to 0.6 along y and sheared in z by 0.3 x: an affine
    image, its poles mapped, still doubly ruled and rational), whose rulings are no iso-curves."""
    bs = hyperbola_revolution(2 * 3.141592653589793)
    for i in range(1, bs.NbUPoles() + 1):
        for j in range(1, bs.NbVPoles() + 1):
            p = bs.Pole(i, j)
            bs.SetPole(i, j, gp_Pnt(p.X(), 0.6 * p.Y(), p.Z() + 0.3 * p.X()))
    return bs
