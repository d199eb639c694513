"""FreeCAD adapter: Part.BSplineSurface / Part.Face <-> the engine's plain arrays (ruled.core.nurbs.Surface).

FreeCAD only (no OCP, no CadQuery): Debian's FreeCAD 0.20 has neither.  The array-level form is
ruled.core.hostform's, the same the OCP adapter uses, so both hosts see the same surfaces.
"""

from __future__ import annotations

import FreeCAD
import numpy as np
import Part

from ruled.core.errors import BadInputError
from ruled.core.hostform import curve_from_kernel_form
from ruled.core.nurbs import Curve, Surface
from ruled.core.region import Region

from .arrays import arrays_to_surface, surface_to_arrays  # noqa: F401  (the adapter's names for them)


def face_to_arrays(face) -> Surface:
    """A Part.Face's surface as a container restricted to the face's parameter range (faces that are
    not B-splines are converted exactly by FreeCAD's toNurbs)."""
    if not isinstance(face, Part.Face):
        raise BadInputError(f"a face is needed, not a {type(face).__name__}; select one face of a solid or shell")
    s = face.Surface
    if not isinstance(s, Part.BSplineSurface):
        try:
            s = face.toNurbs().Faces[0].Surface
        except Exception as exc:  # FreeCAD raises Part.OCCError and friends
            raise BadInputError(f"cannot convert this {type(face.Surface).__name__} face to a B-spline surface "
                                f"({exc}); convert it to NURBS first") from None
        return surface_to_arrays(s)
    u0, u1, v0, v1 = face.ParameterRange
    a0, a1, b0, b1 = s.bounds()
    tol = 1e-9 * max(1.0, abs(a1 - a0), abs(b1 - b0))
    # a periodic direction that the face goes all the way round is kept whole (its range may be shifted)
    if s.isUPeriodic() and (u1 - u0) >= a1 - a0 - tol:
        u0, u1 = a0, a1
    if s.isVPeriodic() and (v1 - v0) >= b1 - b0 - tol:
        v0, v1 = b0, b1
    if u0 > a0 + tol or u1 < a1 - tol or v0 > b0 + tol or v1 < b1 - tol:
        s = s.copy()
        if s.isUPeriodic() and (u1 - u0) < a1 - a0 - tol:
            s.setUNotPeriodic()
        if s.isVPeriodic() and (v1 - v0) < b1 - b0 - tol:
            s.setVNotPeriodic()
        s.segment(max(u0, a0) if not s.isUPeriodic() else u0, min(u1, a1) if not s.isUPeriodic() else u1,
                  max(v0, b0) if not s.isVPeriodic() else v0, min(v1, b1) if not s.isVPeriodic() else v1)
    return surface_to_arrays(s)


def _kernel_curve(bc, reversed_: bool, onto=None) -> Curve:
    """A Part.BSplineCurve / BSplineCurve2d (made non-periodic) as a container (ruled.core.hostform)."""
    if bc.isPeriodic():
        bc = bc.copy()
        bc.setNotPeriodic()
    poles = [(p.x, p.y, p.z) if hasattr(p, "z") else (p.x, p.y) for p in bc.getPoles()]
    weights = bc.getWeights() if bc.isRational() else None
    return curve_from_kernel_form(poles, weights, bc.getKnots(), bc.getMultiplicities(), bc.Degree, reversed_,
                                  onto)


def _pcurve(face, edge) -> Curve:
    got = face.curveOnSurface(edge)
    if not got:
        raise BadInputError("an edge of the face has no curve on its surface; repair the face (Part > Check "
                            "geometry, or refine the shape)")
    c2, a, b = got
    return _kernel_curve(c2.toBSpline(a, b), edge.Orientation == "Reversed")


def _curve3d(edge, pcurve: Curve):
    if edge.Degenerated:
        return None
    a, b = edge.ParameterRange
    return _kernel_curve(edge.Curve.toBSpline(a, b), edge.Orientation == "Reversed", pcurve.domain)


def outer_edges(face) -> list:
    """The outer wire's edges in wire order (the indices the engine's Region uses)."""
    return list(face.OuterWire.OrderedEdges)


def face_region(face, S: Surface = None) -> Region:
    """The face as bounded by its edges: its surface (as face_to_arrays) and its outer wire's pcurves in
    wire order, its holes, seams and degenerate edges; the same Region the OCP adapter reads."""
    S = face_to_arrays(face) if S is None else S
    try:
        # a face that is not a B-spline: the converted face's pcurves, which bound the same region on S
        # (the face's own, in angle, do not: S is not parametrised by angle between its knots)
        if not isinstance(face.Surface, (Part.BSplineSurface, Part.Plane)):
            face = face.toNurbs().Faces[0]
        edges = outer_edges(face)
        loop = [_pcurve(face, e) for e in edges]
        e3 = [_curve3d(e, c) for e, c in zip(edges, loop)]
        seams = [bool(edge_is_seam(face, e)) for e in edges]
        degen = [bool(e.Degenerated) for e in edges]
        inner = [w.OrderedEdges for w in face.Wires if not w.isSame(face.OuterWire)]
        holes = [tuple(_pcurve(face, e) for e in es) for es in inner]
        holes3d = tuple(tuple(_curve3d(e, c) for e, c in zip(es, h)) for es, h in zip(inner, holes))
        hole_tols = tuple(tuple(float(e.Tolerance) for e in es) for es in inner)
    except BadInputError:
        raise
    except Exception as exc:     # Part.OCCError and friends: a boundary that cannot be read
        raise BadInputError(f"cannot read the face's boundary ({exc}); repair the face (Part > Check "
                            f"geometry)") from None
    surf = face.Surface
    u0, u1, v0, v1 = S.domain
    closed = []
    for per, period, a, b in ((surf.isUPeriodic(), "UPeriod", u0, u1), (surf.isVPeriodic(), "VPeriod", v0, v1)):
        P = getattr(surf, period)() if per else None
        closed.append(bool(per and abs((b - a) - P) <= 1e-9 * P))
    return Region(S, tuple(loop), tuple(seams), tuple(degen), tuple(holes), tuple(e3), tuple(closed), (), holes3d,
                  hole_tols)


def edge_is_seam(face, edge) -> bool:
    """The edge is the face's closing line on a closed surface (it bounds the face on both sides)."""
    n = sum(1 for e in face.OuterWire.Edges if e.isSame(edge))
    return n > 1


def surface_to_face(S: Surface):
    """A container as a Part.Face bounded by its natural boundary."""
    return arrays_to_surface(S).toShape()


def _curve_form(c: Curve) -> tuple:
    """(mults, knots, degree, weights) of a curve container as Part's buildFromPolesMultsKnots takes them."""
    from ruled.core.hostform import compress
    knots, mults = compress(c.knots)
    w = [1.0] * len(c.poles) if c.weights is None else [float(x) for x in c.weights]
    return [int(m) for m in mults], [float(k) for k in knots], int(c.degree), w


def curve2d(c: Curve):
    """A 2D curve container (poles (n, 2)) as a Part.Geom2d.BSplineCurve2d."""
    mults, knots, degree, w = _curve_form(c)
    bc = Part.Geom2d.BSplineCurve2d()
    bc.buildFromPolesMultsKnots([FreeCAD.Base.Vector2d(float(p[0]), float(p[1])) for p in c.poles], mults, knots,
                                False, degree, w)
    return bc


def _loop(curves: tuple, bs):
    return Part.Wire([curve2d(c).toShape(bs, float(c.domain[0]), float(c.domain[1])) for c in curves])


def result_face(fit):
    """The result of a fit (a FitResult or one of its candidates) as a Part.Face: the ruled surface trimmed
    by the face's edges mapped onto it (ruled.fit.face.trim.Trim) when it has them, else its natural boundary."""
    best = getattr(fit, "best", fit)
    trim = getattr(best, "trim", None)
    return surface_to_face(best.surface) if trim is None else trimmed_face(best.surface, trim)


def trim_of(face, S: Surface = None):
    """The boundary of a face on its own surface as a ruled.fit.face.trim.Trim (its loops' pcurves): what trims a
    ruled result, read back from the result face.  S: the face's arrays, when read already."""
    from ruled.fit.face.trim import Trim
    rg = face_region(face, S)
    return Trim(tuple(rg.loop), tuple(tuple(h) for h in rg.holes))


def trimmed_face(S: Surface, trim, bs=None):
    """S bounded by the trim's outer loop, less its holes (ruled.fit.face.trim.Trim: 2D curves in S's (u, v)), as a
    valid Part.Face (FiguresError where it cannot be built); bs: S as a Part surface already."""
    from ruled.core.errors import FiguresError
    bs = arrays_to_surface(S) if bs is None else bs
    try:
        face = Part.Face(bs, _loop(trim.loop(trim.outer, True), bs))
        if trim.holes:
            face = face.cutHoles([_loop(trim.loop(h, False), bs) for h in trim.holes])
        face.validate()
        ok = face.isValid()
    except Exception as exc:      # Part.OCCError and friends
        raise FiguresError(f"the result trimmed by the face's edges could not be built ({exc}); try «ends=pinned»")
    if not ok:
        raise FiguresError("the result trimmed by the face's edges is not a valid face (OCCT's check), so it is "
                           "not returned; try «ends=pinned»")
    return face


def built_slack(face, fit) -> float:
    """What building a trimmed result adds to its bound: its edges' tolerance (they are made from its 2D
    trim curves; ruled.occ.trimmed.built_slack is the same for OCP); 0 for a result bounded by its own sides."""
    if getattr(getattr(fit, "best", fit), "trim", None) is None:
        return 0.0
    return max((float(e.Tolerance) for e in face.Edges), default=0.0)


def curve_to_edge(c):
    """A 3D curve container (ruled.core.nurbs.Curve) as a Part edge."""
    mults, knots, degree, w = _curve_form(c)
    bc = Part.BSplineCurve()
    bc.buildFromPolesMultsKnots([FreeCAD.Vector(*map(float, p[:3])) for p in c.poles], mults, knots, False, degree, w)
    return bc.toShape()


# ------------------------------------------------------------------------------------------------ walls
RING_SAMPLES = 24        # samples per edge to tell a face's sides and the contours' order by (as ruled.occ.ring)


def _ring_edge(e, owners: tuple, seam: bool, size: float = 0.0, curve: bool = False):
    """A Part.Edge as the engine's RingEdge (ruled.fit.wall.ring); with curve, its 3D curve as a B-spline from end
    to end and whether it is straight."""
    from ruled.fit.wall.ring import RingEdge, is_straight
    a, b = e.ParameterRange
    pts = np.array([tuple(e.valueAt(float(t))) for t in np.linspace(a, b, RING_SAMPLES)])
    length = float(np.linalg.norm(np.diff(pts, axis=0), axis=1).sum())
    c3, straight = None, False
    if curve and not e.Degenerated:
        c3 = _kernel_curve(e.Curve.toBSpline(a, b), False)
        straight = isinstance(e.Curve, (Part.Line, Part.LineSegment)) or is_straight(
            np.array([tuple(e.valueAt(float(t))) for t in np.linspace(a, b, 65)]), 1e-6 * size)
    return RingEdge(pts[0], pts[-1], pts, length, owners, seam, bool(e.Degenerated), c3, straight)


def ring_order(faces: list, names: list) -> tuple:
    """(ruled.fit.wall.ring.RingOrder, the faces' edges): the faces checked to be a wall's ring and ordered round
    it (its topology only), or a BadInputError naming them."""
    from ruled.fit.wall.ring import order_ring
    edges: list = []
    owners: list = []
    face_edges = []
    for k, f in enumerate(faces):
        mine = set()
        for e in f.Edges:
            i = next((j for j, x in enumerate(edges) if x.isSame(e)), None)
            if i is None:
                i = len(edges)
                edges.append(e)
                owners.append([])
            if k not in owners[i]:
                owners[i].append(k)
            mine.add(i)
        face_edges.append(mine)
    ring = [_ring_edge(e, tuple(own), len(own) == 1 and edge_is_seam(faces[own[0]], e))
            for e, own in zip(edges, owners)]
    return order_ring(list(names), ring, face_edges, [len(f.Wires) > 1 for f in faces],
                      [float(f.Area) for f in faces]), edges


class Wall:
    """A wall of FreeCAD faces (ruled.fit.wall.ring's ring of them, in ring order), joined into one closed B-spline
    surface by the engine (ruled.fit.wall.join), as ruled.occ.wall.Wall is for OCCT: faces (ring order), names
    (the caller's, ring order), the joined surface, its breaks and corners, the slack (edge tolerances)."""

    def __init__(self, faces: list, names: list):
        from ruled.fit.wall.join import joined, wall_patch
        o, edges = ring_order(faces, names)
        self.order = o
        self.faces = [faces[k] for k in o.order]
        self.names = [names[k] for k in o.order]
        self.size = o.size
        self.slivers = [o.slivers[k] for k in o.order]
        self.kept = [i for i, s in enumerate(self.slivers) if not s]
        self._edges, self._curved = edges, {}
        n = len(faces)
        patches, lengths, devs = [], [], []
        for i in self.kept:
            k = o.order[i]
            f = faces[k]
            near = [None if j is None else self._curve(j)
                    for j in ((o.joints[i - 1], o.joints[i]) if n > 1 else (None, None))]
            contour = [[self._curve(j) for j in c] for c in (o.bottom[i], o.top[i])]
            S = None if isinstance(f.Surface, Part.Plane) else _clamped_arrays(f)
            tol = max((float(edges[j].Tolerance) for j in o.bottom[i] + o.top[i]), default=0.0)
            P, L, dev = wall_patch(names[k], S, contour[0], contour[1], near[0], near[1], o.size, tol,
                                   self._loose(f, [edges[j] for j in o.bottom[i]], [edges[j] for j in o.top[i]],
                                               names[k]))
            patches.append(P)
            lengths.append(L)
            devs.append(dev)
        self.surface, self.breaks, self.corners, slack = joined(patches, lengths, [self.names[i] for i in self.kept],
                                                                o.size, devs)
        tol = max((float(e.Tolerance) for e in edges), default=0.0)
        if tol > 0.0:       # or the edges' measured distance from the joined surface (as ruled.occ.wall._slack)
            from ruled.core.edgerows import EDGE_SAMPLES

            from .measure import screened_distances
            E = np.array([tuple(p) for f in self.faces for e in f.Edges if not e.Degenerated
                          for p in e.discretize(Number=EDGE_SAMPLES)], float).reshape(-1, 3)
            tol = max(tol, float(screened_distances(E, surface_to_face(self.surface)).max(initial=0.0)))
        self.slack = tol + slack
        slivers = [f for f, s in zip(self.faces, self.slivers) if s]
        if slivers:       # a sliver's distance from the faces kept, measured (as ruled.occ.wall._slack)
            from .measure import distances, face_points
            kept = Part.Compound([self.faces[i] for i in self.kept])
            for f in slivers:
                self.slack = max(self.slack, float(distances(face_points(f, 20), kept).max()))

    @staticmethod
    def _loose(face, bottom: list, top: list, name):
        """The face's Coons patch from its contour edges (ruled.fit.wall.patch), as a callable."""
        def patch():
            from ruled.fit.wall.patch import contour_patch
            loop = outer_edges(face)
            ids = [[k for k, g in enumerate(loop) if any(g.isSame(e) for e in c)] for c in (bottom, top)]
            return contour_patch(face_region(face), ids[0], ids[1], name)
        return patch

    def _curve(self, j: int):
        """Edge j as the engine's RingEdge with its curve (read once: a joint borders two faces)."""
        if j not in self._curved:
            self._curved[j] = _ring_edge(self._edges[j], (), False, self.size, True)
        return self._curved[j]

    def pieces(self, R: Surface) -> list:
        """The closed ruled result R in one piece per face kept (ring order), cut along the faces' joints
        (ruled.fit.wall.pieces), each a Part.Face."""
        from ruled.fit.wall.pieces import JOINT_SAMPLES, piece_trims
        keep, n = self.kept, len(self.faces)
        joints = []
        for i in range(len(keep)):
            e = self._edges[self.order.joints[(keep[(i + 1) % len(keep)] - 1) % n]]
            a, b = e.ParameterRange
            joints.append(np.array([tuple(e.valueAt(float(t))) for t in np.linspace(a, b, JOINT_SAMPLES)]))
        bs = arrays_to_surface(R)
        if not bs.isUPeriodic():
            bs.setUPeriodic()
        return [trimmed_face(R, trim, bs) for trim in piece_trims(R, joints)]

    def role_of(self, outward) -> str:
        """'hole' where the opening is inside the bottom contour (ruled.fit.wall.ring.role_of), else 'outer';
        outward(x): the part's outward normal of the first face kept at (near) the point x."""
        from ruled.fit.wall.ring import loop_polygon, role_of
        k = next((k for k in self.kept if self.order.bottom[k]), None)
        if k is None:
            return "outer"
        x = self._curve(self.order.bottom[k][0]).points[RING_SAMPLES // 2]
        return role_of(loop_polygon([e.points for e in self.contour_edges(0)]), x, outward(x))

    def contour_edges(self, which: int) -> list:
        """The bottom (0) or top (1) contour's edges as the engine's RingEdges, with their curves."""
        return [self._curve(j) for j in self.order.loops[which]]

    def contour_points(self, which: int) -> np.ndarray:
        return np.concatenate([e.points for e in self.contour_edges(which)])


def _clamped_arrays(face) -> Surface:
    """The face's surface (a B-spline: converted exactly where it is not) restricted to the face's parameter
    range, not periodic and clamped (as ruled.occ.wall reads a wall's face)."""
    if not isinstance(face.Surface, Part.BSplineSurface):
        face = face.toNurbs().Faces[0]
    s = face.Surface.copy()
    if s.isUPeriodic():
        s.setUNotPeriodic()
    if s.isVPeriodic():
        s.setVNotPeriodic()
    u0, u1, v0, v1 = face.ParameterRange
    a0, a1, b0, b1 = s.bounds()
    s.segment(max(u0, a0), min(u1, a1), max(v0, b0), min(v1, b1))
    return surface_to_arrays(s)
