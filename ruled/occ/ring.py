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


def _names(indices) -> str:
    return ",".join(str(i) for i in indices)

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


def _loops(free: list, size: float) -> list:
    """The free edges chained into closed loops by their end points (None where one does not close)."""
    tol = 1e-6 * size
    ends = [_ends(e) for e in free]
    left = list(range(len(free)))
    loops = []
    while left:
        k = left.pop(0)
        loop, start, cur = [k], ends[k][0], ends[k][1]
        while np.linalg.norm(cur - start) > tol:
            nxt = None
            for j in left:
                if np.linalg.norm(ends[j][0] - cur) <= tol:
                    nxt, cur = j, ends[j][1]
                elif np.linalg.norm(ends[j][1] - cur) <= tol:
                    nxt, cur = j, ends[j][0]
                if nxt is not None:
                    break
            if nxt is None:
                raise BadInputError(f"the wall's free edges do not close into loops: one ends at ({cur[0]:.4g}, "
                                    f"{cur[1]:.4g}, {cur[2]:.4g}); pick faces that make a band between two closed "
                                    f"contours")
            left.remove(nxt)
            loop.append(nxt)
        loops.append([free[i] for i in loop])
    return loops


def ring_of(part_faces: list, indices) -> Ring:
    """The ring the faces ``indices`` (of the part's faces) make: checked to be a band between two closed
    contours, ordered round it.  Refused in one line otherwise."""
    indices = list(dict.fromkeys(int(i) for i in indices))
    bad = [i for i in indices if not 0 <= i < len(part_faces)]
    if bad:
        raise BadInputError(f"the wall's faces {_names(bad)} are not faces of the part (it has {len(part_faces)}: "
                            f"0-{len(part_faces) - 1}); see 'ruled faces INPUT --walls'")
    faces = [part_faces[i] for i in indices]
    E = _Edges(faces)
    pts = np.concatenate([_edge_points(e, 5) for e in E.edges()])
    size = float(np.linalg.norm(np.ptp(pts, axis=0)))
    free: list = []
    shared: dict = {}
    for e in E.edges():
        if BRep_Tool.Degenerated_s(e):
            continue
        own = E.owners(e)
        if len(own) == 1:
            if _length(e) <= 1e-6 * size:     # (a sliver face's end: a point of the contour)
                continue
            if not BRep_Tool.IsClosed_s(e, faces[own[0]]):   # (a seam of one face is inside the band)
                free.append(e)
        elif len(own) == 2:
            shared.setdefault(tuple(sorted(own)), []).append(e)
        else:
            raise BadInputError(f"an edge of the wall borders {len(own)} of its faces "
                                f"({_names(indices[k] for k in own)}); a wall is a band of faces, each joined to two "
                                f"others")
    holed = [indices[k] for k, f in enumerate(faces) if _wires(f) > 1]
    if holed:
        raise BadInputError(f"face {holed[0]} of the wall has a hole in it (an inner loop of edges); a wall is a band "
                            f"of faces between two contours: fill the hole first, or fit the face alone (--face)")
    loops = _loops(free, size)
    if len(loops) != 2:
        what = ("no free contour (the faces close on themselves)" if not loops else
                "one free contour (the faces do not close into a band round the part)" if len(loops) == 1 else
                f"{len(loops)} free contours (a band has two: a hole in the ring, or faces that are not one band?)")
        raise BadInputError(f"faces {_names(indices)} are not a wall: their free edges make {what}; pick the ring "
                            f"of faces between the bottom and the top contour (see 'ruled faces INPUT --walls')")
    # the faces round the ring: each joined to the next by one shared edge
    nb: dict = {k: [] for k in range(len(faces))}
    for (a, b), es in shared.items():
        for e in es:
            nb[a].append((b, e))
            nb[b].append((a, e))
    if len(faces) > 1:
        wrong = [indices[k] for k, v in nb.items() if len(v) != 2]
        if wrong:
            raise BadInputError(f"faces {_names(wrong)} of the wall do not each meet two others of it edge to edge; "
                                f"a wall is a ring of faces between two contours")
    order, joints = [0], []
    while len(order) < len(faces):
        cur = order[-1]
        nxt = [(k, e) for k, e in nb[cur] if k not in order]
        if not nxt:
            raise BadInputError(f"faces {_names(indices)} do not make one ring; pick the faces of one wall")
        order.append(nxt[0][0])
        joints.append(nxt[0][1])
    if len(faces) > 1:
        last = [e for k, e in nb[order[-1]] if k == order[0] and not any(e.IsSame(j) for j in joints)]
        joints.append(last[0])
    else:
        joints.append(None)
    # the bottom: the contour lower along the axis between the contours' centres (z first)
    c = [np.mean(np.concatenate([_edge_points(e, 9) for e in lp]), axis=0) for lp in loops]
    d = c[1] - c[0]
    axis = int(np.argmax(np.abs(d) > 1e-6 * size) if abs(d[2]) <= 1e-6 * size else 2)
    if d[axis] < 0:
        loops = loops[::-1]
    bottom, top = [], []
    for k in order:
        f_edges = _face_edges(faces[k])
        mine = [[e for e in lp if any(e.IsSame(g) for g in f_edges)] for lp in loops]
        bottom.append(tuple(mine[0]))
        top.append(tuple(mine[1]))
        if not mine[0] and not mine[1] and not _sliver(faces[k], size):
            raise BadInputError(f"face {indices[k]} of the wall touches neither contour; a wall's faces run from the "
                                f"bottom contour to the top one")
    return Ring(tuple(indices[k] for k in order), tuple(bottom), tuple(top), tuple(joints),
                (tuple(loops[0]), tuple(loops[1])), size)


def _wires(face) -> int:
    from ruled.occ.io import shapes_of
    return len(shapes_of(face, TopAbs_ShapeEnum.TopAbs_WIRE))


def _length(edge) -> float:
    return float(np.linalg.norm(np.diff(_edge_points(edge), axis=0), axis=1).sum())


# a face of area below this times the wall's size squared is a sliver (a draft's crease at a tangent join
# of a profile's line and arc): part of the ring's topology, nothing of its surface
SLIVER = 1e-6


def _sliver(face, size: float) -> bool:
    from ruled.occ.io import face_area
    return face_area(face) <= SLIVER * size * size


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
    closed contours.  The first direction that gives walls gives them all (lists of face indices)."""
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
                walls.append(list(ring_of(faces, group).faces))
            except BadInputError:
                continue
        if walls:
            return walls
    return []


def _connected(faces: list, indices: list) -> list:
    """The faces ``indices`` in groups connected edge to edge."""
    sub = [faces[i] for i in indices]
    E = _Edges(sub)
    parent = list(range(len(sub)))

    def root(k):
        while parent[k] != k:
            parent[k] = parent[parent[k]]
            k = parent[k]
        return k
    for e in E.edges():
        own = E.owners(e)
        for k in own[1:]:
            parent[root(k)] = root(own[0])
    groups: dict = {}
    for k in range(len(sub)):
        groups.setdefault(root(k), []).append(indices[k])
    return sorted(groups.values(), key=lambda g: g[0])



__all__ = ["Ring", "ring_of", "find_walls", "SLIVER"]
