"""Trimmed test faces built with OCCT alone (no engine code): a surface and a loop of (u, v) curves on it,
and the references the trimmed-face tests compare with (FreeCAD's Part "Ruled Surface", i.e. BRepFill,
between two edges; an untrimmed surface interpolated through the region's Coons map)."""

from __future__ import annotations

import numpy as np
from OCP.BRep import BRep_Tool
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeFace, BRepBuilderAPI_MakeWire
from OCP.BRepFill import BRepFill
from OCP.BRepLib import BRepLib
from OCP.BRepTools import BRepTools, BRepTools_WireExplorer
from OCP.Geom import Geom_BSplineSurface
from OCP.Geom2dAPI import Geom2dAPI_PointsToBSpline
from OCP.GeomAbs import GeomAbs_Shape
from OCP.GeomAPI import GeomAPI_PointsToBSplineSurface
from OCP.gp import gp_Pnt, gp_Pnt2d
from OCP.ShapeFix import ShapeFix_Face
from OCP.TColgp import TColgp_Array1OfPnt2d, TColgp_Array2OfPnt
from OCP.TColStd import TColStd_Array1OfInteger, TColStd_Array1OfReal
from OCP.TopoDS import TopoDS


def bspline_surface(poles, uknots, umults, vknots, vmults, pu, pv, uperiodic=False) -> Geom_BSplineSurface:
    poles = np.asarray(poles, float)
    nu, nv = poles.shape[:2]
    P = TColgp_Array2OfPnt(1, nu, 1, nv)
    for i in range(nu):
        for j in range(nv):
            P.SetValue(i + 1, j + 1, gp_Pnt(*poles[i, j]))
    from ruled.occ.convert import occ_array as arr
    return Geom_BSplineSurface(P, arr(uknots), arr(vknots), arr(umults, TColStd_Array1OfInteger),
                               arr(vmults, TColStd_Array1OfInteger), pu, pv, uperiodic, False)


def curve2d(points):
    """A 2D B-spline through the points (OCCT's approximation, degree 3 unless two points: a line)."""
    pts = np.asarray(points, float)
    arr = TColgp_Array1OfPnt2d(1, len(pts))
    for i, (u, v) in enumerate(pts):
        arr.SetValue(i + 1, gp_Pnt2d(float(u), float(v)))
    if len(pts) == 2:
        return Geom2dAPI_PointsToBSpline(arr, 1, 1, GeomAbs_Shape.GeomAbs_C0, 1e-9).Curve()
    return Geom2dAPI_PointsToBSpline(arr, 3, 3, GeomAbs_Shape.GeomAbs_C2, 1e-7).Curve()


def graph2d(u0: float, u1: float, f, spans: int = 16, reverse: bool = False):
    """A cubic 2D B-spline (u(t), v(t)) with u(t) = t exactly (poles at the Greville abscissae of uniform
    clamped knots) and v following f(u) (the poles' v = f at those abscissae): no overshoot in u."""
    from OCP.Geom2d import Geom2d_BSplineCurve
    knots = np.linspace(u0, u1, spans + 1)
    full = np.concatenate([[u0] * 3, knots, [u1] * 3])
    g = np.array([full[i + 1:i + 4].mean() for i in range(spans + 3)])
    P = TColgp_Array1OfPnt2d(1, g.size)
    for i, x in enumerate(g):
        P.SetValue(i + 1, gp_Pnt2d(float(x), float(f(x))))
    K = TColStd_Array1OfReal(1, knots.size)
    M = TColStd_Array1OfInteger(1, knots.size)
    for i, x in enumerate(knots):
        K.SetValue(i + 1, float(x))
        M.SetValue(i + 1, 4 if i in (0, knots.size - 1) else 1)
    c = Geom2d_BSplineCurve(P, K, M, 3)
    if reverse:
        c.Reverse()
    return c


def face_from_loops(surf, loops) -> object:
    """A face of surf bounded by loops (each a list of 2D curves in the surface's (u, v), end to end;
    the first is the outer loop), with 3D curves built from the pcurves."""
    wires = []
    for loop in loops:
        mk = BRepBuilderAPI_MakeWire()
        for c in loop:
            mk.Add(BRepBuilderAPI_MakeEdge(c, surf).Edge())
        wires.append(mk.Wire())
    mf = BRepBuilderAPI_MakeFace(surf, wires[0], True)
    for w in wires[1:]:
        mf.Add(w)
    face = mf.Face()
    BRepLib.BuildCurves3d_s(face)
    fix = ShapeFix_Face(face)
    fix.Perform()
    return TopoDS.Face_s(fix.Face())


def folding_face(edges: int = 4):
    """A flat face whose top side hooks back over itself (a C-shaped region): its Coons map folds.  edges: 4,
    or 5 (the bottom side in two edges, so that other rails could be picked)."""
    poles = np.array([[[0, 0, 0], [0, 10, 0]], [[10, 0, 0], [10, 10, 1]]], float)
    S = bspline_surface(poles, [0, 1], [2, 2], [0, 1], [2, 2], 1, 1)
    t = np.linspace(0, 1, 40)
    hook = np.stack([0.9 - 0.75 * np.sin(np.pi * t) ** 0.5 * (1 - t) - 0.8 * t,
                     0.9 - 0.6 * np.sin(np.pi * t)], axis=1)
    hook[0], hook[-1] = (0.9, 0.9), (0.1, 0.9)
    return face_from_loops(S, _hooked_loop(hook, edges, lambda p: p))


def _hooked_loop(hook, edges: int, at) -> list:
    bottom = ([curve2d(at([[0.1, 0.1], [0.9, 0.1]]))] if edges == 4 else
              [curve2d(at([[0.1, 0.1], [0.5, 0.1]])), curve2d(at([[0.5, 0.1], [0.9, 0.1]]))])
    return [bottom + [curve2d(at([[0.9, 0.1], [0.9, 0.9]])), curve2d(at(hook)), curve2d(at([[0.1, 0.9], [0.1, 0.1]]))]]


def folding_face_on_a_dome():
    """folding_face's C-shaped region, scaled into the middle of a bicubic dome 20 across and 2 high (curved
    both ways: no iso direction of it is ruled), its hook well inside the surface's domain."""
    x = np.linspace(0.0, 20.0, 4)
    poles = np.array([[[a, b, 2.0 * (1 - ((a - 10) / 10) ** 2) * (1 - ((b - 10) / 10) ** 2) + 0.05 * a]
                       for b in x] for a in x])
    S = bspline_surface(poles, [0, 1], [4, 4], [0, 1], [4, 4], 3, 3)
    t = np.linspace(0, 1, 40)
    hook = np.stack([0.9 - 0.75 * np.sin(np.pi * t) ** 0.5 * (1 - t) - 0.8 * t,
                     0.9 - 0.6 * np.sin(np.pi * t)], axis=1)
    hook[0], hook[-1] = (0.9, 0.9), (0.1, 0.9)
    return face_from_loops(S, _hooked_loop(hook, 4, lambda p: 0.25 + 0.5 * np.asarray(p, float)))


def outer_edges(face) -> list:
    out = []
    we = BRepTools_WireExplorer(BRepTools.OuterWire_s(face), face)
    while we.More():
        out.append(we.Current())
        we.Next()
    return out


def part_ruled(face, rail_a, rail_b) -> list:
    """FreeCAD's Part "Ruled Surface" (BRepFill::Face between edges, BRepFill::Shell between wires) between
    two sides of the face given as lists of outer-wire edge indices, in both orientations."""
    E = outer_edges(face)
    if any(BRep_Tool.Degenerated_s(E[k]) for k in list(rail_a) + list(rail_b)):
        return []

    def wire(ks, reverse):
        mk = BRepBuilderAPI_MakeWire()
        for k in ks:
            mk.Add(E[k])
        w = mk.Wire()
        return TopoDS.Wire_s(w.Reversed()) if reverse else w
    out = []
    for rev in (False, True):
        if len(rail_a) == 1 and len(rail_b) == 1:
            eb = TopoDS.Edge_s(E[rail_b[0]].Reversed()) if rev else E[rail_b[0]]
            out.append(BRepFill.Face_s(E[rail_a[0]], eb))
        else:
            out.append(BRepFill.Shell_s(wire(rail_a, False), wire(rail_b, rev)))
    return out


def measure(face, shape, n: int) -> float:
    """The two-sided Hausdorff distance between a face and a face or shell (OCCT's projections through
    ruled.occ.measure, which uses no engine code)."""
    from OCP.TopAbs import TopAbs_ShapeEnum
    from OCP.TopExp import TopExp_Explorer

    from ruled.occ.faceset import FaceSet, sample_faces
    from ruled.occ.measure import _Projector, face_points, hausdorff, two_sided
    faces = []
    ex = TopExp_Explorer(shape, TopAbs_ShapeEnum.TopAbs_FACE)
    while ex.More():
        faces.append(TopoDS.Face_s(ex.Current()))
        ex.Next()
    if len(faces) == 1:
        return hausdorff(face, faces[0], n).max
    return two_sided(face_points(face, n), sample_faces(faces, n), _Projector(face), FaceSet(faces)).max


def coons_reference(surf, sides, n: int = 40):
    """An untrimmed B-spline face through S(Omega(s, t)) on an n x n grid, Omega the bilinearly blended
    Coons map of the four sides (2D curves in loop order, each on [first, last], parametrized linearly),
    approximated by OCCT within 1e-6."""
    def side(c, x):
        a, b = c.FirstParameter(), c.LastParameter()
        p = c.Value(a + (b - a) * x)
        return np.array([p.X(), p.Y()])
    c0, c1, c2, c3 = sides
    P00, P10, P11, P01 = side(c0, 0), side(c1, 0), side(c2, 0), side(c3, 0)
    x = np.linspace(0, 1, n)
    arr = TColgp_Array2OfPnt(1, n, 1, n)
    for i, s in enumerate(x):
        for j, t in enumerate(x):
            uv = ((1 - t) * side(c0, s) + t * side(c2, 1 - s) + (1 - s) * side(c3, 1 - t) + s * side(c1, t)
                  - ((1 - s) * (1 - t) * P00 + s * (1 - t) * P10 + s * t * P11 + (1 - s) * t * P01))
            arr.SetValue(i + 1, j + 1, surf.Value(float(uv[0]), float(uv[1])))
    bs = GeomAPI_PointsToBSplineSurface(arr, 3, 3, GeomAbs_Shape.GeomAbs_C2, 1e-6).Surface()
    return BRepBuilderAPI_MakeFace(bs, 1e-7).Face()


def swept_blade_face(profile: int = 200, stations: int = 40):
    """A closed blade: a NACA-like profile (chord 30) swept half a turn along a helix (radius 40, rise 60),
    interpolated by OCCT into a bicubic of about 130 x 12 poles.  No ruled surface comes near it."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace
    t = np.linspace(0, 2 * np.pi, profile)
    x = 15 * (1 + np.cos(t))
    c = x / 30
    yt = 18 * (0.2969 * np.sqrt(c + 1e-12) - 0.126 * c - 0.3516 * c ** 2 + 0.2843 * c ** 3 - 0.1015 * c ** 4)
    y = np.where(t < np.pi, yt, -yt)
    P = TColgp_Array2OfPnt(1, profile, 1, stations)
    for j, s in enumerate(np.linspace(0, 1, stations)):
        a = np.pi * s
        centre = np.array([40 * np.cos(a), 40 * np.sin(a), 60 * s])
        tan = np.array([-40 * np.pi * np.sin(a), 40 * np.pi * np.cos(a), 60.0])
        tan /= np.linalg.norm(tan)
        rad = np.array([np.cos(a), np.sin(a), 0.0])
        b = np.cross(tan, rad)
        for i in range(profile):
            p = centre + 0.3 * (x[i] - 15) * rad + (y[i] + 0.9 * (x[i] - 15)) * b
            P.SetValue(i + 1, j + 1, gp_Pnt(*map(float, p)))
    bs = GeomAPI_PointsToBSplineSurface(P, 3, 3, GeomAbs_Shape.GeomAbs_C2, 1e-3).Surface()
    return BRepBuilderAPI_MakeFace(bs, 1e-7).Face()


def ruled_sheet_face(hole: float = 0.0, curved: float = 0.0):
    """A twisted sheet that is ruled exactly along v (z = 3 sin(3u) v + 2u^2 over 40 x 30, a bicubic), trimmed by a
    wavy bottom, a sloping top and two v-lines (curved > 0: two sides bowed that far in u, four curved edges);
    hole: the radius (in (u, v)) of a round hole at (0.45, 0.5), or 0 for none.  Its ruled fit is within
    round-off of it (where it spans no hole)."""
    s, t = np.meshgrid(np.linspace(0, 1, 5), np.linspace(0, 1, 4), indexing="ij")
    S = bspline_surface(np.stack([40 * s, 30 * t, 3 * np.sin(3 * s) * t + 2 * s * s], -1),
                        [0, 0.5, 1], [4, 1, 4], [0, 1], [4, 4], 3, 3)

    def bot(u):
        return 0.1 + 0.05 * np.sin(6 * u)

    def top(u):
        return 0.9 - 0.05 * u * u
    def side(u, a, b):          # from v = a to v = b at u, bowed by `curved` in u between
        if not curved:
            return curve2d([[u, a], [u, b]])
        f = np.linspace(0.0, 1.0, 9)
        return curve2d(np.stack([u + curved * np.sin(np.pi * f), a + (b - a) * f], 1))
    loops = [[graph2d(0.05, 0.95, bot), side(0.95, bot(0.95), top(0.95)),
              graph2d(0.05, 0.95, top, reverse=True), side(0.05, top(0.05), bot(0.05))]]
    if hole:
        a = np.linspace(0, 2 * np.pi, 25)
        loops.append([curve2d(np.stack([0.45 + hole * np.cos(-a), 0.5 + hole * np.sin(-a)], 1))])
    return face_from_loops(S, loops)


def hub_surface() -> Geom_BSplineSurface:
    """An exact hub: a flared profile (radius 6 to 12 over a height of 18) revolved, rational and periodic
    round the axis (eight poles, knots of multiplicity 2, weights 1 and 1/sqrt(2): each quarter an exact
    circular arc)."""
    from OCP.TColStd import TColStd_Array2OfReal

    from ruled.occ.convert import occ_array as arr
    k = np.arange(8)
    ang, far = k * np.pi / 4, np.where(k % 2 == 0, 1.0, np.sqrt(2.0))
    w = np.where(k % 2 == 0, 1.0, np.sqrt(0.5))
    profile = [(6.0, 0.0), (6.5, 6.0), (8.5, 12.0), (12.0, 18.0)]
    P = TColgp_Array2OfPnt(1, 8, 1, len(profile))
    W = TColStd_Array2OfReal(1, 8, 1, len(profile))
    for i in range(8):
        for j, (r, z) in enumerate(profile):
            P.SetValue(i + 1, j + 1, gp_Pnt(r * far[i] * np.cos(ang[i]), r * far[i] * np.sin(ang[i]), z))
            W.SetValue(i + 1, j + 1, float(w[i]))
    return Geom_BSplineSurface(P, W, arr([0, 0.25, 0.5, 0.75, 1]), arr([0, 1]), arr([2] * 5, TColStd_Array1OfInteger),
                               arr([4, 4], TColStd_Array1OfInteger), 2, 3, True, False)


def band_face(kind: str):
    """A band that goes once round a cylinder-like surface (radius about 10, height 20, wavy), between a
    wavy bottom and a wavy top, its seam at u = 0.3 (not the surface's own).  kind: 'seam' (OCCT's seam
    edge, the face made from its two closed loops), 'four' (four edges: the two v-lines at u = 0.3 and
    1.3 are separate edges), both on a periodic surface; 'crease' (four edges on a clamped surface whose
    first and last rows of poles meet at a crease); 'hub' (a blade root wrapping a hub: the band between the
    footprint of a blade's root fillet, a lobe, and a wavy top, once round the exact rational hub of
    hub_surface, with OCCT's seam edge at u = 0.3)."""
    if kind == "hub":
        def lobe(u):
            return np.exp(-4.0 * (1.0 - np.cos(2 * np.pi * (u - 0.65))))
        b = graph2d(0.3, 1.3, lambda u: 0.15 + 0.25 * lobe(u), spans=24)
        t = graph2d(0.3, 1.3, lambda u: 0.8 - 0.15 * lobe(u) + 0.03 * np.sin(6 * np.pi * u), spans=24, reverse=True)
        return face_from_loops(hub_surface(), [[b], [t]])
    n = 8 if kind != "crease" else 9
    th = np.linspace(0, 2 * np.pi, n, endpoint=kind == "crease")
    rows = []
    for j, z in enumerate(np.linspace(0, 20, 4)):
        r = 10 + np.sin(2 * th + j)
        rows.append(np.stack([r * np.cos(th), r * np.sin(th), z + 0.5 * np.cos(th) * j], 1))
    P = np.stack(rows, 1)
    if kind == "crease":
        P[-1] = P[0]
        S = bspline_surface(P, np.linspace(0, 1, n - 2), [4] + [1] * (n - 4) + [4], [0, 1], [4, 4], 3, 3)
    else:
        S = bspline_surface(P, np.arange(n + 1) / n, [1] * (n + 1), [0, 1], [4, 4], 3, 3, uperiodic=True)
    a = 0.0 if kind == "crease" else 0.3

    def bot(u):
        return 0.15 + 0.05 * np.sin(2 * np.pi * u)

    def top(u):
        return 0.85 + 0.05 * np.cos(2 * np.pi * u)
    b, t = graph2d(a, a + 1, bot), graph2d(a, a + 1, top, reverse=True)
    if kind == "seam":
        return face_from_loops(S, [[b], [t]])
    return face_from_loops(S, [[b, curve2d([[a + 1, bot(a + 1)], [a + 1, top(a + 1)]]), t,
                                curve2d([[a, top(a)], [a, bot(a)]])]])


def classifier(face, per_edge: int = 400):
    """inside(u, v): whether a (u, v) point lies in the face as bounded by its edges, by OCCT alone.
    BRepClass_FaceClassifier decides, unless BRepTopAdaptor_FClass2d disagrees: then the even-odd rule over
    the face's pcurves (sampled by OCCT, per_edge points each) does.  The ray classifier alone puts a wedge
    of a face read back from STEP outside it (2d:2068108334:k0, a sheet with a hole: the wedge runs from its
    left edge towards the hole, and BRepExtrema, which classifies the same way, measured 23 where the face
    is 0.13 away)."""
    from OCP.BRepAdaptor import BRepAdaptor_Curve2d
    from OCP.BRepClass import BRepClass_FaceClassifier
    from OCP.BRepTopAdaptor import BRepTopAdaptor_FClass2d
    from OCP.TopAbs import TopAbs_ShapeEnum, TopAbs_State
    from OCP.TopExp import TopExp_Explorer

    fclass = BRepTopAdaptor_FClass2d(face, 1e-9)
    keep = (TopAbs_State.TopAbs_IN, TopAbs_State.TopAbs_ON)
    chains = []             # each edge's pcurve as a polyline: the even-odd rule needs no order of edges
    edges = TopExp_Explorer(face, TopAbs_ShapeEnum.TopAbs_EDGE)
    while edges.More():
        c = BRepAdaptor_Curve2d(TopoDS.Edge_s(edges.Current()), face)
        chains.append(np.array([(q.X(), q.Y()) for q in (c.Value(float(t)) for t in
                                np.linspace(c.FirstParameter(), c.LastParameter(), per_edge))]))
        edges.Next()

    def odd(u, v):
        crossings = 0
        for P in chains:
            a, b = P[:-1], P[1:]
            up = (a[:, 1] > v) != (b[:, 1] > v)
            x = a[up, 0] + (v - a[up, 1]) * (b[up, 0] - a[up, 0]) / (b[up, 1] - a[up, 1])
            crossings += int((x > u).sum())
        return crossings % 2 == 1

    def inside(u, v):
        p = gp_Pnt2d(float(u), float(v))
        ray = BRepClass_FaceClassifier(face, p, 1e-7).State() in keep
        return ray if ray == (fclass.Perform(p) in keep) else odd(u, v)
    return inside


def extrema_measure(face_a, face_b, n: int = 16) -> tuple:
    """(A to B, B to A): the largest distance from points of each face as bounded by its edges to the other,
    by OCCT alone (no product code): an n x n (u, v) grid of the face's bounds kept where OCCT's classifiers
    (classifier) put it inside the face, and n points along every edge, each projected by BRepExtrema onto
    the other face.  Each value is a distance to an actual point, so the measure is at most the true Hausdorff
    distance, the samples' resolution below it (where BRepExtrema's foot is not the nearest, the surface's own
    projections and Newton's feet from a grid count too, where the classifiers put the foot inside the face:
    each is still an actual distance)."""
    from OCP.BRepAdaptor import BRepAdaptor_Curve
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeVertex
    from OCP.BRepExtrema import BRepExtrema_DistShapeShape
    from OCP.GeomAPI import GeomAPI_ProjectPointOnSurf
    from OCP.gp import gp_Vec
    from OCP.TopAbs import TopAbs_ShapeEnum
    from OCP.TopExp import TopExp_Explorer
    from scipy.spatial import cKDTree

    def points(face):
        surf = BRep_Tool.Surface_s(face)
        u0, u1, v0, v1 = BRepTools.UVBounds_s(face)
        inside = classifier(face)
        out = []
        for u in np.linspace(u0, u1, n):
            for v in np.linspace(v0, v1, n):
                if inside(float(u), float(v)):
                    out.append(surf.Value(float(u), float(v)))
        ex = TopExp_Explorer(face, TopAbs_ShapeEnum.TopAbs_EDGE)
        while ex.More():
            e = TopoDS.Edge_s(ex.Current())
            if not BRep_Tool.Degenerated_s(e):
                ad = BRepAdaptor_Curve(e)
                out += [ad.Value(float(x)) for x in np.linspace(ad.FirstParameter(), ad.LastParameter(), n)]
            ex.Next()
        return out

    def newton(surf, p, u, v, box):
        """Gauss-Newton on |S(u, v) - p| from (u, v), kept in the box: the foot (u, v) and its distance."""
        q, du, dv = gp_Pnt(), gp_Vec(), gp_Vec()
        x = np.array([p.X(), p.Y(), p.Z()])
        for _ in range(30):
            surf.D1(u, v, q, du, dv)
            r = np.array([q.X(), q.Y(), q.Z()]) - x
            J = np.array([[du.X(), dv.X()], [du.Y(), dv.Y()], [du.Z(), dv.Z()]])
            step = np.linalg.lstsq(J, -r, rcond=None)[0]
            un, vn = float(np.clip(u + step[0], box[0], box[1])), float(np.clip(v + step[1], box[2], box[3]))
            if abs(un - u) + abs(vn - v) <= 1e-15 * (1 + abs(u) + abs(v)):
                break
            u, v = un, vn
        return u, v, surf.Value(u, v).Distance(p)

    def far(pts, face):
        surf = BRep_Tool.Surface_s(face)
        box = BRepTools.UVBounds_s(face)
        inside = classifier(face)
        g = [(float(u), float(v)) for u in np.linspace(box[0], box[1], 48) for v in np.linspace(box[2], box[3], 48)]
        tree = cKDTree(np.array([[q.X(), q.Y(), q.Z()] for q in (surf.Value(u, v) for u, v in g)]))
        worst = 0.0
        for p in pts:
            d = BRepExtrema_DistShapeShape(BRepBuilderAPI_MakeVertex(p).Vertex(), face).Value()
            # BRepExtrema misses the interior foot on some faces (a tiny periodic one: 2e-4 for 4e-6; a kj66
            # face: 3e-3 for 8e-7): the surface's own projections too, and Newton's from the nearest points of
            # a 48 x 48 grid, where OCCT's classifier puts their foot inside the face
            proj = GeomAPI_ProjectPointOnSurf(p, surf)
            feet = [proj.Parameters(k) + (proj.Distance(k),) for k in range(1, proj.NbPoints() + 1)]
            for i in tree.query([p.X(), p.Y(), p.Z()], k=4)[1]:
                feet.append(newton(surf, p, *g[i], box))
            for u, v, dist in feet:
                if dist < d and inside(u, v):
                    d = dist
            worst = max(worst, d)
        return worst
    return far(points(face_a), face_b), far(points(face_b), face_a)


def many_edged_face(edges: int = 160):
    """The ruled sheet of ruled_sheet_face with its wavy bottom cut into many edges: every grouping of them into
    four sides is a Coons map to try, which takes its parametrization about 20 s at 160 edges."""
    s, t = np.meshgrid(np.linspace(0, 1, 5), np.linspace(0, 1, 4), indexing="ij")
    S = bspline_surface(np.stack([40 * s, 30 * t, 3 * np.sin(3 * s) * t + 2 * s * s], -1),
                        [0, 0.5, 1], [4, 1, 4], [0, 1], [4, 4], 3, 3)

    def bot(u):
        return 0.2 + 0.08 * np.sin(6 * np.pi * u)
    xs = np.linspace(0.05, 0.95, edges + 1)
    bottom = [graph2d(a, b, bot, spans=4) for a, b in zip(xs[:-1], xs[1:])]
    return face_from_loops(S, [bottom + [curve2d([[0.95, bot(0.95)], [0.95, 0.9]]), curve2d([[0.95, 0.9], [0.05, 0.9]]),
                                         curve2d([[0.05, 0.9], [0.05, bot(0.05)]])]])


def bow_edges(face, offset: float, count: int = 1, way: str = "up", spike: float = 0.0):
    """The face with the 3D curves of its first count edges bowed up to offset off the surface (a sine arch
    along each, along the surface's normal at its middle; way 'out' or 'in': across the edge, in the plane
    of a flat face, away from its middle or towards it; spike > 0: a bell that wide, a fraction of the edge,
    at its middle instead), within the edge's tolerance (2 x offset), as exporters write edges: the pcurve on
    the surface, the 3D curve near it."""
    from OCP.BRep import BRep_Builder
    from OCP.BRepAdaptor import BRepAdaptor_Surface
    from OCP.GeomAPI import GeomAPI_PointsToBSpline
    from OCP.gp import gp_Vec
    from OCP.TColgp import TColgp_Array1OfPnt
    from OCP.TopLoc import TopLoc_Location
    ad = BRepAdaptor_Surface(face)
    u0, u1, v0, v1 = BRepTools.UVBounds_s(face)
    p, du, dv = gp_Pnt(), gp_Vec(), gp_Vec()
    ad.D1(0.5 * (u0 + u1), 0.5 * (v0 + v1), p, du, dv)
    n = du.Crossed(dv)
    n.Normalize()
    for e in [x for x in outer_edges(face) if not BRep_Tool.Degenerated_s(x)][:count]:
        a, b = BRep_Tool.Range_s(e)
        c = BRep_Tool.Curve_s(e, 0.0, 1.0)
        if way != "up":
            mid = gp_Vec(p, c.Value(0.5 * (a + b)))
            n = mid.Subtracted(n.Multiplied(mid.Dot(n)))
            n.Normalize()
            if way == "in":
                n.Reverse()
        t = np.linspace(a, b, 201 if spike <= 0 else 2001)
        pts = TColgp_Array1OfPnt(1, t.size)
        for i, x in enumerate(t):
            f = (x - a) / (b - a)
            h = np.sin(np.pi * f) if spike <= 0 else np.exp(-((f - 0.5) / spike) ** 2)
            q = c.Value(float(x)).Translated(n.Multiplied(offset * h))
            pts.SetValue(i + 1, q)
        par = TColStd_Array1OfReal(1, t.size)
        for i, x in enumerate(t):
            par.SetValue(i + 1, float(x))
        bowed = GeomAPI_PointsToBSpline(pts, par, 3, 8, GeomAbs_Shape.GeomAbs_C2, 1e-3 * offset).Curve()
        BRep_Builder().UpdateEdge(e, bowed, TopLoc_Location(), 2 * offset)
    return face


def sloppy_face(offset: float = 5e-4, way: str = "up", spike: float = 0.0):
    """A flat 10 x 10 face, its surface's whole rectangle, whose first edge's 3D curve bows up to offset off the
    surface within its tolerance (bow_edges: up off the plane, or out of the face or into it in the plane)."""
    S = bspline_surface(np.array([[(0, 0, 0), (0, 10, 0)], [(10, 0, 0), (10, 10, 0)]], float),
                        [0, 1], [2, 2], [0, 1], [2, 2], 1, 1)
    return bow_edges(BRepBuilderAPI_MakeFace(S, 1e-7).Face(), offset, way=way, spike=spike)
