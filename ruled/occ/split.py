"""Split faces with OCCT: the strips of a face as real faces of its surface, sharing their split edges,
and the independent measure of ruled fits against them.

Every edge is the exact image of a domain curve under the surface (ruled.curves.curve_on_surface: degree
p + q pieces composed with the surface, within a distance tolerance of the smooth domain curve); its
pcurve is the domain polyline, the same for the faces on both sides, so the faces share the edge
and the surface itself.  The faces are checked with BRepCheck, sewn, and their areas compared.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Optional

import numpy as np
from OCP.BRep import BRep_Builder
from OCP.BRepAdaptor import BRepAdaptor_Curve, BRepAdaptor_Curve2d
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeVertex, BRepBuilderAPI_Sewing
from OCP.BRepCheck import BRepCheck_Analyzer
from OCP.BRepGProp import BRepGProp
from OCP.gp import gp_Pnt
from OCP.GProp import GProp_GProps
from OCP.TopAbs import TopAbs_EDGE, TopAbs_FORWARD, TopAbs_REVERSED
from OCP.TopExp import TopExp_Explorer
from OCP.TopLoc import TopLoc_Location
from OCP.TopoDS import TopoDS, TopoDS_Face, TopoDS_Wire

from ruled.core.hostform import Hausdorff
from ruled.core.nurbs import Curve, Surface
from ruled.curves.curve_on_surface import approximate
from ruled.occ.convert import container_to_bspline, curve2d_to_bspline, curve_to_bspline
from ruled.occ.measure import _Projector, hausdorff
from ruled.split.strips import EDGE_TOL, input_curve, iso_curve


@dataclass
class SplitFaces:
    faces: list                # TopoDS_Face per strip, in order from v0 to v1 (oriented coordinates)
    edges: list                # the shared split edges (TopoDS_Edge), between faces k and k + 1
    curves: list               # CurveOnSurface of each split edge
    surface: Any               # the Geom_BSplineSurface every face lies on
    edge_tol: float


def _edge(curve: Curve, pcurve: Curve, surf, V0, V1, tol: float):
    c3 = curve_to_bspline(curve)
    t0, t1 = curve.domain
    mk = BRepBuilderAPI_MakeEdge(c3, V0, V1, t0, t1)
    if not mk.IsDone():
        raise RuntimeError("could not build a split edge")
    e = mk.Edge()
    b = BRep_Builder()
    b.UpdateEdge(e, curve2d_to_bspline(pcurve), surf, TopLoc_Location(), tol)
    b.Range(e, surf, TopLoc_Location(), t0, t1)
    b.SameParameter(e, True)
    b.SameRange(e, True)
    return e


def _on_surface(S: Surface, D: Curve, tol: float):
    """The exact image of the domain curve D on S within tol: (3D curve, pcurve)."""
    r = approximate(S, D, tol, 10.0)
    return r, r.curve, r.pcurve


def build_split_faces(S: Surface, curves: list, transposed: bool, tol: Optional[float] = None,
                      closed: bool = False) -> SplitFaces:
    """Faces of S between consecutive domain curves (given on the oriented surface: graphs v = c(u) from
    its u0 side to its u1 side; transposed says the input's u and v are exchanged), with the surface's
    own v0 and v1 sides outermost.  closed: the surface closes up along u (u0 and u1 are one seam): each
    curve is a closed edge, and each face's sides are one seam edge with a pcurve on either side."""
    Sin = S
    So = S.transposed() if transposed else S
    u0, u1, v0, v1 = So.domain
    tol = EDGE_TOL * S.diagonal() if tol is None else tol
    all_curves = [iso_curve(u0, u1, v0)] + list(curves) + [iso_curve(u0, u1, v1)]
    surf = container_to_bspline(Sin)
    imgs, verts, edges = [], [], []
    for c in all_curves:
        D = input_curve(c, transposed)
        r, c3, pc = _on_surface(Sin, D, tol)
        imgs.append(r)
        a, b = c3.domain
        P = c3(np.array([a, b]))
        V0 = BRepBuilderAPI_MakeVertex(gp_Pnt(*map(float, P[0]))).Vertex()
        V1 = V0 if closed else BRepBuilderAPI_MakeVertex(gp_Pnt(*map(float, P[1]))).Vertex()
        verts.append((V0, V1))
        edges.append(_edge(c3, pc, surf, V0, V1, 1e-7))
    # the side edges: straight domain segments along u = u0 and u = u1 between consecutive curves
    sides = []
    for k in range(len(all_curves) - 1):
        row = []
        pcs = []
        for end, x in ((0, u0), (1, u1)):
            ya = float(all_curves[k](np.array([x]))[0, 1])
            yb = float(all_curves[k + 1](np.array([x]))[0, 1])
            seg = Curve(np.array([[x, ya], [x, yb]]), np.array([0.0, 0.0, 1.0, 1.0]), 1)
            D = input_curve(seg, transposed)
            r, c3, pc = _on_surface(Sin, D, tol)
            pcs.append(pc)
            if not closed:
                row.append(_edge(c3, pc, surf, verts[k][end], verts[k + 1][end], 1e-7))
        if closed:   # one seam edge: its forward use runs up the u1 side (down it when transposed)
            e = _edge(c3, pcs[1], surf, verts[k][0], verts[k + 1][0], 1e-7)
            fw, rv = (pcs[0], pcs[1]) if transposed else (pcs[1], pcs[0])
            BRep_Builder().UpdateEdge(e, curve2d_to_bspline(fw), curve2d_to_bspline(rv), surf, TopLoc_Location(),
                                      1e-7)
            row = [e, e]
        sides.append(row)
    b = BRep_Builder()
    faces = []
    F, R = TopAbs_FORWARD, TopAbs_REVERSED
    for k in range(len(all_curves) - 1):
        # counter-clockwise in the oriented (u, v): bottom, right side, top reversed, left side reversed
        loop = [(edges[k], F), (sides[k][1], F), (edges[k + 1], R), (sides[k][0], R)]
        if transposed:   # exchanging u and v turns the loop clockwise: walk it backwards
            loop = [(e, R if o == F else F) for e, o in reversed(loop)]
        w = TopoDS_Wire()
        b.MakeWire(w)
        for e, o in loop:
            b.Add(w, e.Oriented(o))
        f = TopoDS_Face()
        b.MakeFace(f, surf, 1e-7)
        b.Add(f, w)
        faces.append(f)
    return SplitFaces(faces, edges[1:-1], imgs[1:-1], surf, tol)


@dataclass
class SplitCheck:
    valid: list                # BRepCheck per face
    sewn_free_edges: int       # free edges of the sewn shell (the outer boundary only)
    sewn_faces: int
    max_gap: float             # largest distance between a shared edge's 3D curve and each face's trace of it
    edge_on_surface: float     # largest distance of split-edge points from the surface (OCCT projection)
    area_sum: float
    area_input: float

    @property
    def area_rel(self) -> float:
        return abs(self.area_sum - self.area_input) / self.area_input


def check_split_faces(sf: SplitFaces, input_face, samples: int = 200) -> SplitCheck:
    valid = [bool(BRepCheck_Analyzer(f).IsValid()) for f in sf.faces]
    sew = BRepBuilderAPI_Sewing(1e-7)
    for f in sf.faces:
        sew.Add(f)
    sew.Perform()
    shape = sew.SewedShape()
    nfaces = 0
    from OCP.TopAbs import TopAbs_FACE
    ex = TopExp_Explorer(shape, TopAbs_FACE)
    while ex.More():
        nfaces += 1
        ex.Next()
    free = sew.NbFreeEdges()
    # gaps: each face's own trace of every edge (surface at the pcurve) against the edge's 3D curve
    gap = 0.0
    surf = sf.surface
    for f in sf.faces:
        ex = TopExp_Explorer(f, TopAbs_EDGE)
        while ex.More():
            e = TopoDS.Edge_s(ex.Current())
            c3 = BRepAdaptor_Curve(e)
            pc = BRepAdaptor_Curve2d(e, f)
            a, b = pc.FirstParameter(), pc.LastParameter()
            for t in np.linspace(a, b, 41):
                p2 = pc.Value(float(t))
                ps = surf.Value(p2.X(), p2.Y())
                gap = max(gap, ps.Distance(c3.Value(float(t))))
            ex.Next()
    # the split edges against the input surface (OCCT projection of their points)
    pr = _Projector(input_face)
    pts = []
    for e in sf.edges:
        c3 = BRepAdaptor_Curve(e)
        a, b = c3.FirstParameter(), c3.LastParameter()
        pts += [(lambda p: (p.X(), p.Y(), p.Z()))(c3.Value(float(t))) for t in np.linspace(a, b, samples)]
    on = float(pr.distances(np.array(pts)).max()) if pts else 0.0
    return SplitCheck(valid, free, nfaces, gap, on, sum(_area(f) for f in sf.faces), _area(input_face))


def _area(face) -> float:
    props = GProp_GProps()
    BRepGProp.SurfaceProperties_s(face, props, 1e-9)
    return props.Mass()


# ------------------------------------------------------------------------------ whole jobs
@dataclass
class FaceSplit:
    result: Any                # ruled.split.partition.SplitResult
    chosen: str                # the candidate with the lowest measured error
    faces: dict                # name -> SplitFaces
    fits: dict                 # name -> [TopoDS_Face of each side's ruled fit]
    measured: dict             # name -> [per side Hausdorff as dicts]
    checks: dict               # name -> SplitCheck
    timings: dict
    warnings: list = field(default_factory=list)
    deviation: float = 0.0     # how far the surface split (the face's four-sided patch) is from the face

    def edge_bounds(self) -> dict:
        """name -> how far its split faces' edges are from the exact split curve (certified)."""
        return {k: edge_bound(sf) for k, sf in self.faces.items()}


def edge_bound(sf: SplitFaces) -> float:
    """How far the split faces' split edges are from the exact images of the smooth split curves (their
    own certified bound): the faces differ from the strips the fits were certified against by this."""
    return max((c.error_bound for c in sf.curves), default=0.0)


def _hd(h: Hausdorff) -> dict:
    return {"max": h.max, "mean": h.mean, "split_to_fit": h.max_a_to_b, "fit_to_split": h.max_b_to_a,
            "samples": h.samples}


def measure_strips(S: Surface, strip_fits: list, transposed: bool, curves: list, n: int):
    """Build the split faces between the curves, check them (against the face's whole UV rectangle, which
    they cover), and measure each strip's ruled fit against its split face.
    Returns (SplitFaces, SplitCheck, fit faces, per strip Hausdorff dicts)."""
    from ruled.occ.convert import container_to_face
    closed = bool(strip_fits[0].fit.best.closed)
    sf = build_split_faces(S, curves, transposed, closed=closed)
    ck = check_split_faces(sf, container_to_face(S))
    fits = [container_to_face(s.fit.surface) for s in strip_fits]
    meas = [_hd(hausdorff(f, g, n)) for f, g in zip(sf.faces, fits)]
    return sf, ck, fits, meas


def split_of_face(face, opts=None, progress=None, measure_samples: int = 30) -> FaceSplit:
    """Split a face (Wang & Elber §4): the optimal, best iso-parametric and middle splits, each built as
    real faces, fitted and measured; the one with the lowest measured error is chosen."""
    import time

    from ruled.split.partition import SplitOptions, split_face
    t0 = time.perf_counter()
    S, warnings, dev = face_patch_surface(face, deviation=True)
    res = split_face(S, opts or SplitOptions(), progress)
    t1 = time.perf_counter()
    faces, fits, measured, checks = {}, {}, {}, {}
    for k, (name, c) in enumerate(res.candidates.items()):
        if progress is not None:
            progress("building and measuring the splits", k / len(res.candidates))
        faces[name], checks[name], fits[name], measured[name] = measure_strips(
            S, list(c.sides), res.transposed, [c.curve], measure_samples)
    chosen = min(measured, key=lambda k: max(m["max"] for m in measured[k]))
    return FaceSplit(res, chosen, faces, fits, measured, checks,
                     {**res.timings, "faces_and_measure": time.perf_counter() - t1, "total": time.perf_counter() - t0},
                     warnings, dev)


@dataclass
class FacePartition:
    partition: Any             # ruled.split.partition.Partition
    faces: SplitFaces
    check: SplitCheck
    fits: list
    measured: list
    warnings: list = field(default_factory=list)


def partition_of_face(face, tol: float, opts=None, progress=None, measure_samples: int = 24) -> FacePartition:
    """Partition a face into strips whose ruled fits are within tol (ruled.split.partition), built and measured."""
    from ruled.split.partition import SplitOptions, partition
    S, warnings = face_patch_surface(face)
    # the strips' split edges follow the split curves within EDGE_TOL of the size, which the faces' bound
    # adds: the fits aim that much inside tol (unless tol is not much larger)
    inner = tol - EDGE_TOL * S.diagonal()
    p = partition(S, inner if inner >= 0.5 * tol else tol, opts or SplitOptions(), progress)
    curves = [s.strip.hi for s in p.strips[:-1]]
    sf, ck, fits, meas = measure_strips(S, p.strips, p.transposed, curves, measure_samples)
    return FacePartition(p, sf, ck, fits, meas, warnings)


def face_patch_surface(face, deviation: bool = False):
    """The surface a split works on: the face's own surface when the face is its whole (u, v) rectangle,
    else its four-sided patch (ruled.fit.face.fit); and the warnings to show (and, with deviation, how far
    that surface is from the face as bounded by its edges)."""
    from ruled.fit.face.fit import face_patch
    from ruled.occ.convert import face_to_container
    from ruled.occ.region import face_region
    S = face_to_container(face)
    patch = face_patch(face_region(face, S))
    warnings = list(patch.warnings)
    if not patch.identity:
        warnings.append(f"the face is trimmed: it is split as its own four-sided patch, a B-spline within "
                        f"{patch.deviation:.3g} of it (the split faces lie on that patch)")
    return (patch.surface, warnings, float(patch.deviation)) if deviation else (patch.surface, warnings)
