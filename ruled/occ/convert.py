"""OCCT geometry <-> the engine's plain-array containers.

Only this package imports OCP.  A face becomes a :class:`ruled.core.nurbs.Surface`
restricted to the face's UV bounds; containers become Geom_BSplineSurface /
Geom_BSplineCurve handles and faces.
"""

from __future__ import annotations

import numpy as np
from OCP.BRep import BRep_Builder, BRep_Tool
from OCP.BRepAdaptor import BRepAdaptor_Surface
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeFace, BRepBuilderAPI_NurbsConvert
from OCP.BRepTools import BRepTools
from OCP.Geom import Geom_BSplineCurve, Geom_BSplineSurface, Geom_RectangularTrimmedSurface
from OCP.Geom2d import Geom2d_BSplineCurve
from OCP.GeomAbs import GeomAbs_SurfaceType
from OCP.GeomConvert import GeomConvert
from OCP.gp import gp_Pnt, gp_Pnt2d
from OCP.TColgp import TColgp_Array1OfPnt, TColgp_Array1OfPnt2d, TColgp_Array2OfPnt
from OCP.TColStd import TColStd_Array1OfInteger, TColStd_Array1OfReal, TColStd_Array2OfReal
from OCP.TopoDS import TopoDS, TopoDS_Face

from ruled.core.errors import BadInputError
from ruled.core.hostform import bounds_slack, compress, from_kernel_form, kernel_form
from ruled.core.nurbs import Curve, Surface

SURFACE_TYPE_NAMES = {
    GeomAbs_SurfaceType.GeomAbs_Plane: "plane",
    GeomAbs_SurfaceType.GeomAbs_Cylinder: "cylinder",
    GeomAbs_SurfaceType.GeomAbs_Cone: "cone",
    GeomAbs_SurfaceType.GeomAbs_Sphere: "sphere",
    GeomAbs_SurfaceType.GeomAbs_Torus: "torus",
    GeomAbs_SurfaceType.GeomAbs_BezierSurface: "bezier",
    GeomAbs_SurfaceType.GeomAbs_BSplineSurface: "bspline",
    GeomAbs_SurfaceType.GeomAbs_SurfaceOfRevolution: "revolution",
    GeomAbs_SurfaceType.GeomAbs_SurfaceOfExtrusion: "extrusion",
    GeomAbs_SurfaceType.GeomAbs_OffsetSurface: "offset",
    GeomAbs_SurfaceType.GeomAbs_OtherSurface: "other",
}


def occ_array(values, cls=TColStd_Array1OfReal):
    """values as an OCCT 1-based array of reals (or of integers, cls=TColStd_Array1OfInteger)."""
    a = cls(1, len(values))
    for i, x in enumerate(values):
        a.SetValue(i + 1, float(x) if cls is TColStd_Array1OfReal else int(x))
    return a


def bspline_surface_to_container(s: Geom_BSplineSurface) -> Surface:
    """A Geom_BSplineSurface as a container (periodic ones are stored clamped with the flag kept)."""
    per_u, per_v = s.IsUPeriodic(), s.IsVPeriodic()
    if per_u or per_v:
        s = s.Copy()
        if per_u:
            s.SetUNotPeriodic()
        if per_v:
            s.SetVNotPeriodic()
    nu, nv = s.NbUPoles(), s.NbVPoles()
    poles = np.empty((nu, nv, 3))
    weights = np.empty((nu, nv))
    for i in range(nu):
        for j in range(nv):
            p = s.Pole(i + 1, j + 1)
            poles[i, j] = (p.X(), p.Y(), p.Z())
            weights[i, j] = s.Weight(i + 1, j + 1)
    ku = [s.UKnot(i) for i in range(1, s.NbUKnots() + 1)]
    mu = [s.UMultiplicity(i) for i in range(1, s.NbUKnots() + 1)]
    kv = [s.VKnot(i) for i in range(1, s.NbVKnots() + 1)]
    mv = [s.VMultiplicity(i) for i in range(1, s.NbVKnots() + 1)]
    return from_kernel_form(poles, weights, ku, mu, kv, mv, s.UDegree(), s.VDegree(),
                            s.IsURational() or s.IsVRational(), per_u, per_v)


def face_surface_type(face: TopoDS_Face) -> str:
    return SURFACE_TYPE_NAMES.get(BRepAdaptor_Surface(face).GetType(), "other")


def face_uv_bounds(face: TopoDS_Face) -> tuple[float, float, float, float]:
    """The face's (u, v) bounds: its pcurves' box, each end snapped in to an edge of the outer wire lying
    on an iso line there when the other edges overshoot that line only within their own tolerance in
    space (an exporter's sloppy edges running past a seam: the face ends at the seam)."""
    bounds = BRepTools.UVBounds_s(face)
    try:
        return _snapped_bounds(face, bounds)
    except Exception:  # OCCT's Standard_Failure on a malformed wire: the plain box
        return bounds


def _snapped_bounds(face, bounds) -> tuple:
    from OCP.BRepTools import BRepTools_WireExplorer
    surf = BRep_Tool.Surface_s(face)
    loops = []
    we = BRepTools_WireExplorer(BRepTools.OuterWire_s(face), face)
    while we.More():
        e = we.Current()
        if not BRep_Tool.Degenerated_s(e):
            c = BRep_Tool.CurveOnSurface_s(e, face, 0.0, 0.0)
            if c is not None:
                a, b = BRep_Tool.Range_s(e, face)
                uv = np.array([c.Value(float(t)).Coord() for t in np.linspace(a, b, 33)])
                loops.append((uv, float(BRep_Tool.Tolerance_s(e))))
        we.Next()
    if not loops:
        return bounds
    out = list(bounds)
    for d in (0, 1):
        lo, hi = bounds[2 * d], bounds[2 * d + 1]
        span = hi - lo
        if not span > 0:
            continue
        iso = [float(uv[:, d].mean()) for uv, _ in loops if np.ptp(uv[:, d]) <= 1e-9 * span]
        for end, sign in ((1, 1.0), (0, -1.0)):
            edge_at = bounds[2 * d + end]
            near = [x for x in iso if 0 < sign * (edge_at - x) <= 1e-2 * span]
            if not near:
                continue
            x = max(near, key=lambda y: sign * y)        # the outermost iso edge short of the bound
            ok = True
            for uv, tol in loops:
                past = uv[sign * (uv[:, d] - x) > 0]
                for p in past:
                    q = p.copy()
                    q[d] = x
                    if surf.Value(float(p[0]), float(p[1])).Distance(surf.Value(float(q[0]), float(q[1]))) > tol:
                        ok = False
                        break
                if not ok:
                    break
            if ok:
                out[2 * d + end] = x
    return tuple(out)


def nurbs_face(face: TopoDS_Face) -> TopoDS_Face:
    """The face itself where its surface is a B-spline or a plane, else the face converted whole to NURBS by OCCT
    (surface, pcurves and edges together): a cylinder's or a sphere's B-spline form is not parametrised
    by angle between its knots, so the face's own pcurves, in angle, do not bound the same region on it
    (0.18 off on a cylinder with a hole cut, issue 35); the converted face's pcurves do."""
    if BRepAdaptor_Surface(face).GetType() in (GeomAbs_SurfaceType.GeomAbs_BSplineSurface,
                                               GeomAbs_SurfaceType.GeomAbs_Plane):
        return face     # (a plane's B-spline form is its own parametrisation: its pcurves hold as they are)
    try:
        conv = BRepBuilderAPI_NurbsConvert(face, True)
        out = TopoDS.Face_s(conv.Shape()) if conv.IsDone() else None
    except Exception:  # OCCT raises Standard_Failure subclasses
        out = None
    if out is None or BRepAdaptor_Surface(out).GetType() != GeomAbs_SurfaceType.GeomAbs_BSplineSurface:
        raise BadInputError(f"cannot convert this {face_surface_type(face)} face to a B-spline surface; "
                            f"convert it to NURBS in your CAD system first")
    out.Orientation(face.Orientation())
    return out


def face_to_bspline(face: TopoDS_Face) -> Geom_BSplineSurface:
    """The face's surface as a Geom_BSplineSurface restricted to the face's UV bounds (a face whose
    surface is not a B-spline: its nurbs_face's)."""
    face = nurbs_face(face)
    u0, u1, v0, v1 = face_uv_bounds(face)
    surf = BRep_Tool.Surface_s(face)
    ad = BRepAdaptor_Surface(face)
    if ad.GetType() == GeomAbs_SurfaceType.GeomAbs_BSplineSurface:
        bs = ad.BSpline().Copy()
    else:  # a plane (nurbs_face converts every other surface)
        try:
            trimmed = Geom_RectangularTrimmedSurface(surf, u0, u1, v0, v1)
            bs = GeomConvert.SurfaceToBSplineSurface_s(trimmed)
        except Exception as exc:  # OCCT raises Standard_Failure subclasses
            raise BadInputError(f"cannot convert this {face_surface_type(face)} face to a B-spline "
                                f"surface ({exc}); convert it to NURBS in your CAD system first") from None
        return bs
    return _restricted(bs, (u0, u1, v0, v1))


def _set_origin(bs: Geom_BSplineSurface, d: int, x: float, tol: float) -> None:
    """Periodic bs (in direction d) with its period starting at parameter x (a knot inserted there, the
    geometry unchanged): a face that goes round the whole period from a seam at x has the surface's
    domain for its own, its seam edges on the domain's ends."""
    k0, k1 = bs.Bounds()[2 * d: 2 * d + 2]
    if abs(x - k0) <= tol or abs(x - k1) <= tol:
        return
    insert, knots, origin = ((bs.InsertUKnot, bs.UKnots, bs.SetUOrigin) if d == 0 else
                             (bs.InsertVKnot, bs.VKnots, bs.SetVOrigin))
    insert(x, 1, tol, False)
    k = knots()
    values = np.array([k.Value(i) for i in range(1, k.Length() + 1)])
    origin(int(np.argmin(np.abs(values - x))) + 1)


def _restricted(bs: Geom_BSplineSurface, bounds: tuple) -> Geom_BSplineSurface:
    """bs restricted to the face's UV bounds, parametrised as the face's pcurves are.

    A periodic direction keeps the face's own parameters, whichever period they lie in (exporters
    shift pcurves by whole periods) and across the seam; a direction the face goes all the way round
    stays whole.  Bounds that overhang a non-periodic surface's knot range are clamped to it; a face
    whose bounds miss that range is refused."""
    ku0, ku1, kv0, kv1 = bs.Bounds()
    size = max(1.0, abs(ku1 - ku0), abs(kv1 - kv0))
    tol = 1e-9 * size
    lo, hi = list(bounds[::2]), list(bounds[1::2])
    shift = [0.0, 0.0]
    for d, (k0, k1, periodic) in enumerate(((ku0, ku1, bs.IsUPeriodic()), (kv0, kv1, bs.IsVPeriodic()))):
        name = "uv"[d]
        if not (np.isfinite(lo[d]) and np.isfinite(hi[d]) and hi[d] > lo[d]):
            raise BadInputError(f"the face's {name} bounds [{lo[d]:g}, {hi[d]:g}] are empty or not finite; "
                                f"repair the face (ShapeFix in your CAD system)")
        if periodic:
            period = k1 - k0
            n = np.floor((lo[d] - k0 + tol) / period)    # whole periods between the face and the knots
            shift[d] = n * period
            if hi[d] - lo[d] >= period - tol:           # all the way round: the whole period, from the face's seam
                _set_origin(bs, d, lo[d] - shift[d], tol)
                lo[d], hi[d] = lo[d], lo[d] + period
        else:
            if lo[d] > k1 - tol or hi[d] < k0 + tol:
                raise BadInputError(f"the face's {name} range [{lo[d]:.9g}, {hi[d]:.9g}] lies outside its surface's "
                                    f"knot range [{k0:.9g}, {k1:.9g}]; repair the face (ShapeFix in your CAD system)")
            lo[d], hi[d] = max(lo[d], k0), min(hi[d], k1)
    whole = [hi[d] - lo[d] >= ((ku1 - ku0), (kv1 - kv0))[d] - tol for d in range(2)]
    if not all(whole):
        # a periodic surface segments across its seam; the result's knots start in the period OCCT
        # picks: they are moved below to the face's own parameters
        try:
            bs.Segment(lo[0] - shift[0], hi[0] - shift[0], lo[1] - shift[1], hi[1] - shift[1])
        except Exception as exc:  # OCCT's Standard_DomainError
            raise BadInputError(f"cannot restrict the face's surface to the face's bounds u [{lo[0]:.9g}, "
                                f"{hi[0]:.9g}], v [{lo[1]:.9g}, {hi[1]:.9g}] ({exc}); repair the face "
                                f"(ShapeFix in your CAD system)") from None
    b = bs.Bounds()
    for d, get, put in ((0, bs.UKnots, bs.SetUKnots), (1, bs.VKnots, bs.SetVKnots)):
        delta = lo[d] - b[2 * d]
        if abs(delta) > tol:
            k = get()
            moved = TColStd_Array1OfReal(1, k.Length())
            for i in range(1, k.Length() + 1):
                moved.SetValue(i, k.Value(i) + delta)
            put(moved)
    return bs


def face_to_container(face: TopoDS_Face) -> Surface:
    """Convert a face to a :class:`Surface` restricted to its UV bounds."""
    return bspline_surface_to_container(face_to_bspline(face))


def conversion_slack(face: TopoDS_Face, S: Surface) -> float:
    """Upper bound of the distance from the container to the face (ruled.core.hostform.bounds_slack)."""
    return bounds_slack(S, face_uv_bounds(nurbs_face(face)))


def container_to_bspline(s: Surface) -> Geom_BSplineSurface:
    """Build a Geom_BSplineSurface from a container (periodic ones become OCCT-periodic)."""
    f = kernel_form(s)
    poles, weights = f["poles"], f["weights"]
    nu, nv = poles.shape[:2]
    P = TColgp_Array2OfPnt(1, nu, 1, nv)
    W = TColStd_Array2OfReal(1, nu, 1, nv)
    for i in range(nu):
        for j in range(nv):
            P.SetValue(i + 1, j + 1, gp_Pnt(*map(float, poles[i, j])))
            W.SetValue(i + 1, j + 1, 1.0 if weights is None else float(weights[i, j]))
    ints = TColStd_Array1OfInteger
    return Geom_BSplineSurface(P, W, occ_array(f["uknots"]), occ_array(f["vknots"]), occ_array(f["umults"], ints),
                               occ_array(f["vmults"], ints), f["udegree"], f["vdegree"], f["uperiodic"], f["vperiodic"])


def container_to_face(s: Surface) -> TopoDS_Face:
    """A face bounded by the container's natural boundary."""
    bs = container_to_bspline(s)
    u0, u1, v0, v1 = s.domain
    mk = BRepBuilderAPI_MakeFace(bs, u0, u1, v0, v1, 1e-7)
    if not mk.IsDone():
        raise BadInputError("could not build a face from the result surface")
    return mk.Face()


def curve_to_bspline(c: Curve) -> Geom_BSplineCurve:
    k, m = compress(c.knots)
    n = c.poles.shape[0]
    P = TColgp_Array1OfPnt(1, n)
    for i in range(n):
        P.SetValue(i + 1, gp_Pnt(*map(float, c.poles[i, :3])))
    if c.weights is None:
        return Geom_BSplineCurve(P, occ_array(k), occ_array(m, TColStd_Array1OfInteger), c.degree,
                                 False)
    return Geom_BSplineCurve(P, occ_array(c.weights), occ_array(k), occ_array(m, TColStd_Array1OfInteger),
                             c.degree, False)


def curve2d_to_bspline(c: Curve) -> Geom2d_BSplineCurve:
    """A 2D (u, v) curve container as a Geom2d_BSplineCurve (a domain curve or a pcurve)."""
    k, m = compress(c.knots)
    n = c.poles.shape[0]
    P = TColgp_Array1OfPnt2d(1, n)
    for i in range(n):
        P.SetValue(i + 1, gp_Pnt2d(float(c.poles[i, 0]), float(c.poles[i, 1])))
    if c.weights is None:
        return Geom2d_BSplineCurve(P, occ_array(k), occ_array(m, TColStd_Array1OfInteger), c.degree,
                                   False)
    return Geom2d_BSplineCurve(P, occ_array(c.weights), occ_array(k), occ_array(m, TColStd_Array1OfInteger),
                               c.degree, False)


def edge_on_face(curve: Curve, pcurve: Curve, face: TopoDS_Face, tol: float = 1e-7):
    """An edge with the 3D curve and its pcurve on the face (the same parameter: curve(t) is the
    face's surface at pcurve(t)), so it can split or bound the face."""
    mk = BRepBuilderAPI_MakeEdge(curve_to_bspline(curve))
    if not mk.IsDone():
        raise BadInputError("could not build an edge from the curve")
    edge = mk.Edge()
    b = BRep_Builder()
    b.UpdateEdge(edge, curve2d_to_bspline(pcurve), face, tol)
    b.SameParameter(edge, True)
    b.SameRange(edge, True)
    return edge


def segment_edge(a, b):
    """A straight edge between two points (for rulings in STEP output)."""
    return BRepBuilderAPI_MakeEdge(gp_Pnt(*map(float, a)), gp_Pnt(*map(float, b))).Edge()
