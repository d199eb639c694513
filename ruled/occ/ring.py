"""A wall's topology: a ring of faces joined edge to edge into a band whose free edges make two closed
contours (the bottom and the top), checked and ordered round the ring; and the walls a part has (the
rings between its planar caps).  Bad rings are refused in one line naming the faces."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np
from OCP.BRep import BRep_Tool
from OCP.BRepAdaptor import BRepAdaptor_Curve, BRepAdaptor_Surface
from OCP.GeomAbs import GeomAbs_SurfaceType
from OCP.TopAbs import TopAbs_ShapeEnum
from OCP.TopExp import TopExp
from OCP.TopoDS import TopoDS
from OCP.TopTools import TopTools_IndexedDataMapOfShapeListOfShape

from ruled.core.errors import BadInputError
from ruled.fit.wall.ring import _names
from ruled.occ.io import compound, faces_of

EDGE_SAMPLES = 24      # samples per edge to tell a face's sides and the contours' order by


def _pt(p) -> np.ndarray:
    return np.array([p.X(), p.Y(), p.Z()])


def _edge_points(edge, n: int = EDGE_SAMPLES) -> np.ndarray:
    ad = BRepAdaptor_Curve(edge)
    return np.array([_pt(ad.Value(t)) for t in np.linspace(ad.FirstParameter(), ad.LastParameter(), n)])


def _ends(edge) -> tuple:
    ad = BRepAdaptor_Curve(edge)
    return _pt(ad.Value(ad.FirstParameter())), _pt(ad.Value(ad.LastParameter()))


# ------------------------------------------------------------------------------------------------ the ring
@dataclass
class Ring:
    """The wall's topology: its faces in ring order (indices into the part's faces), and per face its
    bottom and top contour edges; the two contours as closed loops of edges."""

    faces: tuple                   # part face indices, in ring order
    bottom: tuple                  # per face: its edges on the bottom contour (TopoDS_Edge), maybe none
    top: tuple                     # per face: its edges on the top contour
    joints: tuple                  # per face: the edge it shares with the next face round the ring
    loops: tuple                   # (bottom loop, top loop): each a tuple of edges
    size: float = 0.0
    slivers: tuple = ()            # per face: a sliver (a draft's crease, its topology only: ruled.fit.wall.ring)
    role: str = "outer"            # 'outer' (the part's outside) or 'hole' (a hole's wall: the opening is inside it)
    name: str = ""                 # as the walls' listing names it: 'outer', 'hole 1', ... (find_walls)

    @property
    def kept(self) -> list:
        """The positions (in ring order) of the faces that are no slivers."""
        return [k for k in range(len(self.faces)) if not self.slivers[k]]

    def contour_points(self, which: int) -> np.ndarray:
        return np.concatenate([_edge_points(e) for e in self.loops[which]])


class _Edges:
    """The edges of a set of faces and the faces (of the set) each borders."""

    def __init__(self, faces: list):
        self.faces = faces
        self.map = TopTools_IndexedDataMapOfShapeListOfShape()
        TopExp.MapShapesAndAncestors_s(compound(faces), TopAbs_ShapeEnum.TopAbs_EDGE, TopAbs_ShapeEnum.TopAbs_FACE,
                                       self.map)

    def edges(self) -> list:
        return [TopoDS.Edge_s(self.map.FindKey(i)) for i in range(1, self.map.Extent() + 1)]

    def owners(self, edge) -> list:
        """Indices (into faces) of the distinct faces the edge borders."""
        out = []
        for f in self.map.FindFromKey(edge):
            k = next(i for i, g in enumerate(self.faces) if g.IsSame(f))
            if k not in out:
                out.append(k)
        return out


def ring_of(part_faces: list, indices) -> Ring:
    """The ring the faces ``indices`` (of the part's faces) make: checked to be a band between two closed
    contours, ordered round it (ruled.fit.wall.ring.order_ring on their edges).  Refused in one line otherwise."""
    from ruled.fit.wall.ring import RingEdge, order_ring
    from ruled.occ.io import face_area
    indices = list(dict.fromkeys(int(i) for i in indices))
    bad = [i for i in indices if not 0 <= i < len(part_faces)]
    if bad:
        raise BadInputError(f"the wall's faces {_names(bad)} are not faces of the part (it has {len(part_faces)}: "
                            f"0-{len(part_faces) - 1}); see 'ruled faces INPUT --walls'")
    faces = [part_faces[i] for i in indices]
    E = _Edges(faces)
    topo = E.edges()
    edges = []
    for e in topo:
        own = tuple(E.owners(e))
        a, b = _ends(e)
        pts = _edge_points(e)
        edges.append(RingEdge(a, b, pts, float(np.linalg.norm(np.diff(pts, axis=0), axis=1).sum()), own,
                              len(own) == 1 and bool(BRep_Tool.IsClosed_s(e, faces[own[0]])),
                              bool(BRep_Tool.Degenerated_s(e))))
    face_edges = [{E.map.FindIndex(g) - 1 for g in _face_edges(f)} for f in faces]
    o = order_ring(indices, edges, face_edges, [_wires(f) > 1 for f in faces], [face_area(f) for f in faces])

    def pick(ids):
        return tuple(topo[i] for i in ids)
    return Ring(tuple(indices[k] for k in o.order), tuple(pick(b) for b in o.bottom), tuple(pick(t) for t in o.top),
                tuple(None if j is None else topo[j] for j in o.joints), (pick(o.loops[0]), pick(o.loops[1])), o.size,
                tuple(o.slivers[k] for k in o.order))


def _wires(face) -> int:
    from ruled.occ.io import shapes_of
    return len(shapes_of(face, TopAbs_ShapeEnum.TopAbs_WIRE))


def _length(edge) -> float:
    return float(np.linalg.norm(np.diff(_edge_points(edge), axis=0), axis=1).sum())


def _face_edges(face) -> list:
    from ruled.occ.io import shapes_of
    return [TopoDS.Edge_s(e) for e in shapes_of(face, TopAbs_ShapeEnum.TopAbs_EDGE)]


# ------------------------------------------------------------------------------------------- finding walls
def _planar_normal(face) -> Optional[np.ndarray]:
    ad = BRepAdaptor_Surface(face)
    if ad.GetType() != GeomAbs_SurfaceType.GeomAbs_Plane:
        return None
    return _pt(ad.Plane().Axis().Direction())


def find_walls(shape) -> list:
    """The walls of a part: for each direction of its planar faces (largest total area first), the faces
    other than the planar caps normal to it, split into edge-connected groups, each a ring between two
    closed contours.  The first direction that gives walls gives them all (their Rings)."""
    from ruled.occ.io import face_area
    faces = faces_of(shape)
    normals = [_planar_normal(f) for f in faces]
    dirs: list = []
    for i, n in enumerate(normals):
        if n is None:
            continue
        for dd in dirs:
            if abs(abs(float(n @ dd[0])) - 1.0) <= 1e-9:
                dd[1] += face_area(faces[i])
                break
        else:
            dirs.append([n, face_area(faces[i])])
    dirs.sort(key=lambda x: -x[1])
    for n, _ in dirs:
        caps = {i for i, m in enumerate(normals) if m is not None and abs(abs(float(m @ n)) - 1.0) <= 1e-9}
        rest = [i for i in range(len(faces)) if i not in caps]
        walls = []
        for group in _connected(faces, rest):
            try:
                walls.append(ring_of(faces, group))
            except BadInputError:
                continue
        if walls:
            return _named(walls, faces)
    return []


def outward_at(face, x) -> np.ndarray:
    """The part's outward normal of the face at (near) the point x."""
    from OCP.BRepAdaptor import BRepAdaptor_Surface
    from OCP.GeomAPI import GeomAPI_ProjectPointOnSurf
    from OCP.gp import gp_Pnt, gp_Vec

    from ruled.occ.machine import outward
    proj = GeomAPI_ProjectPointOnSurf(gp_Pnt(*map(float, x)), BRep_Tool.Surface_s(face))
    a, b = proj.LowerDistanceParameters()
    p, du, dv = gp_Pnt(), gp_Vec(), gp_Vec()
    BRepAdaptor_Surface(face, False).D1(a, b, p, du, dv)
    n = du.Crossed(dv)
    return np.array([n.X(), n.Y(), n.Z()]) * outward(face)


def ring_role(ring: Ring, faces: list) -> str:
    """A ring's role from its faces (ruled.fit.wall.ring.role_of): 'hole' where the opening is inside its bottom
    contour.  faces: the part's."""
    from ruled.fit.wall.ring import loop_polygon, role_of
    k = next((k for k in ring.kept if ring.bottom[k]), None)
    if k is None:
        return "outer"
    x = _edge_points(ring.bottom[k][0])[EDGE_SAMPLES // 2]
    return role_of(loop_polygon([_edge_points(e) for e in ring.loops[0]]), x, outward_at(faces[ring.faces[k]], x))


def _named(walls: list, faces: list) -> list:
    """The walls with their roles (outer, hole: ring_role) and names ('outer', 'hole 1', ...)."""
    from dataclasses import replace

    from ruled.fit.wall.ring import role_names
    roles = [ring_role(r, faces) for r in walls]
    return [replace(r, role=ro, name=nm) for r, ro, nm in zip(walls, roles, role_names(roles))]


def _connected(faces: list, indices: list) -> list:
    """The faces ``indices`` in groups connected edge to edge."""
    from ruled.fit.wall.ring import connected
    sub = [faces[i] for i in indices]
    E = _Edges(sub)
    return [[indices[k] for k in g] for g in connected([{E.map.FindIndex(e) - 1 for e in _face_edges(f)}
                                                         for f in sub])]


__all__ = ["Ring", "ring_of", "find_walls", "ring_role", "outward_at"]
