"""A wall's topology on plain data: a set of faces joined edge to edge checked to be a band whose free edges
make two closed contours (the bottom and the top), and its faces ordered round it.  Every host gives its
edges (end points, samples, the faces each borders) and faces (their edges, a hole or not, their areas);
bad rings are refused in one line naming the faces."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np

from ruled.core.errors import BadInputError
from ruled.core.nurbs import Curve

# a face of area below this times the wall's size squared is a sliver (a draft's crease at a tangent join of a
# profile's line and arc): part of the ring's topology, nothing of its surface
SLIVER = 1e-6


@dataclass(frozen=True)
class RingEdge:
    """An edge of the wall's faces: its end points, samples along it (end to end), its length, the faces it
    borders (positions in the wall's face list, distinct), and whether it is a seam of its one face or
    degenerate (a point); for building a face's patch and placing a loop's start, its 3D curve (a B-spline
    from end to end, ruled.core.nurbs.Curve) and whether it is straight."""

    start: np.ndarray
    end: np.ndarray
    points: np.ndarray
    length: float
    owners: tuple = ()
    seam: bool = False
    degenerate: bool = False
    curve: Optional[Curve] = None
    straight: bool = False


def is_straight(points: np.ndarray, tol: float) -> bool:
    """Points along an edge lie within tol of its chord (and the chord is longer than tol)."""
    d = points[-1] - points[0]
    L = float(np.linalg.norm(d))
    if L <= tol:
        return False
    off = np.cross(points - points[0], d / L)
    return float(np.max(np.linalg.norm(off, axis=1))) <= tol


@dataclass
class RingOrder:
    """The faces round the ring (positions in the face list), per face its bottom and top contour edges and
    its joint with the next face (edge positions), the two contours (bottom first), the wall's size and
    which faces are slivers."""

    order: list
    bottom: list
    top: list
    joints: list
    loops: tuple
    size: float
    slivers: list


def _names(indices) -> str:
    return ",".join(str(i) for i in indices)


def _unsewn(free: list, edges: list, size: float):
    """Two faces (their positions) with free edges that lie on each other (the same ends, either way round, and
    the same points between): faces that touch but are not joined (an unsewn part), or None."""
    tol = 1e-6 * size
    for x, i in enumerate(free):
        a = edges[i]
        for j in free[x + 1:]:
            b = edges[j]
            if set(a.owners) == set(b.owners):
                continue
            same = (np.linalg.norm(a.start - b.start) <= tol and np.linalg.norm(a.end - b.end) <= tol) or \
                (np.linalg.norm(a.start - b.end) <= tol and np.linalg.norm(a.end - b.start) <= tol)
            if same and _on(a.points, b.points, 1e-4 * size):
                return a.owners[0], b.owners[0]
    return None


def _on(P: np.ndarray, Q: np.ndarray, tol: float) -> bool:
    """The points P lie within tol of the polyline Q."""
    from ruled.core.distance import to_polyline
    return to_polyline(P, Q) <= tol


def _loops(free: list, edges: list, size: float) -> list:
    """The free edges chained into closed loops by their end points."""
    tol = 1e-6 * size
    ends = np.array([p for k in free for p in (edges[k].start, edges[k].end)]).reshape(-1, 3)
    for p in ends:
        if int(np.sum(np.linalg.norm(ends - p, axis=1) <= tol)) > 2:
            raise BadInputError(f"the wall's contours cross at ({p[0]:.4g}, {p[1]:.4g}, {p[2]:.4g}): more than two "
                                f"of its free edges meet there, and a wire cannot follow a contour through its own "
                                f"crossing; fit each loop of the part as a wall of its own, or the faces one by one "
                                f"(«one_face»)")
    left = list(free)
    loops = []
    while left:
        k = left.pop(0)
        loop, start, cur = [k], edges[k].start, edges[k].end
        while np.linalg.norm(cur - start) > tol:
            nxt = None
            for j in left:
                if np.linalg.norm(edges[j].start - cur) <= tol:
                    nxt, cur = j, edges[j].end
                elif np.linalg.norm(edges[j].end - cur) <= tol:
                    nxt, cur = j, edges[j].start
                if nxt is not None:
                    break
            if nxt is None:
                raise BadInputError(f"the wall's free edges do not close into loops: one ends at ({cur[0]:.4g}, "
                                    f"{cur[1]:.4g}, {cur[2]:.4g}); pick faces that make a band between two closed "
                                    f"contours")
            left.remove(nxt)
            loop.append(nxt)
        loops.append(loop)
    return loops


def order_ring(names: list, edges: list, face_edges: list, holed: list, areas: list) -> RingOrder:
    """The ring the faces make (names: their indices in the part, for messages; face_edges: each face's edge
    positions; holed: whether each has an inner loop; areas: theirs), checked and ordered."""
    size = float(np.linalg.norm(np.ptp(np.concatenate([e.points for e in edges]), axis=0)))
    slivers = [a <= SLIVER * size * size for a in areas]
    free: list = []
    shared: dict = {}
    for i, e in enumerate(edges):
        if e.degenerate:
            continue
        if len(e.owners) == 1:
            if e.length <= 1e-6 * size:       # (a sliver face's end: a point of the contour)
                continue
            if not e.seam:                    # (a seam of one face is inside the band)
                free.append(i)
        elif len(e.owners) == 2:
            shared.setdefault(tuple(sorted(e.owners)), []).append(i)
        else:
            raise BadInputError(f"an edge of the wall borders {len(e.owners)} of its faces "
                                f"({_names(names[k] for k in e.owners)}); a wall is a band of faces, each joined to "
                                f"two others")
    unsewn = _unsewn(free, edges, size)
    if unsewn is not None:
        a, b = sorted(names[k] for k in unsewn)
        raise BadInputError(f"faces {a} and {b} share no edge: an edge of each lies on the other's, but the part does "
                            f"not join them; sew the part first (e.g. sewing in your CAD system)")
    if any(holed):
        raise BadInputError(f"face {names[holed.index(True)]} of the wall has a hole in it (an inner loop of edges); a "
                            f"wall is a band of faces between two contours: fill the hole first, or fit the face "
                            f"alone («one_face»)")
    loops = _loops(free, edges, size)
    if len(loops) != 2:
        what = ("no free contour (the faces close on themselves)" if not loops else
                "one free contour (the faces do not close into a band round the part)" if len(loops) == 1 else
                f"{len(loops)} free contours (a band has two: a hole in the ring, or faces that are not one band?)")
        raise BadInputError(f"faces {_names(names)} are not a wall: their free edges make {what}; «walls_listing»")
    n = len(face_edges)
    nb: dict = {k: [] for k in range(n)}
    for (a, b), es in shared.items():
        for e in es:
            nb[a].append((b, e))
            nb[b].append((a, e))
    if n > 1:
        wrong = [names[k] for k, v in nb.items() if len(v) != 2]
        if wrong:
            raise BadInputError(f"faces {_names(wrong)} of the wall do not each meet two others of it edge to edge "
                                f"(a wall is a ring of faces between two contours); «walls_listing»")
    order, joints = [0], []
    while len(order) < n:
        nxt = [(k, e) for k, e in nb[order[-1]] if k not in order]
        if not nxt:
            raise BadInputError(f"faces {_names(names)} do not make one ring; pick the faces of one wall")
        order.append(nxt[0][0])
        joints.append(nxt[0][1])
    joints.append(next(e for k, e in nb[order[-1]] if k == order[0] and e not in joints) if n > 1 else None)
    # the bottom: the contour lower along the axis between the contours' centres (z first)
    c = [np.mean(np.concatenate([edges[i].points for i in lp]), axis=0) for lp in loops]
    d = c[1] - c[0]
    axis = int(np.argmax(np.abs(d) > 1e-6 * size) if abs(d[2]) <= 1e-6 * size else 2)
    if d[axis] < 0:
        loops = loops[::-1]
    bottom, top = [], []
    for k in order:
        mine = [[i for i in lp if i in face_edges[k]] for lp in loops]
        bottom.append(mine[0])
        top.append(mine[1])
        if not mine[0] and not mine[1] and not slivers[k]:
            raise BadInputError(f"face {names[k]} of the wall touches neither contour; a wall's faces run from the "
                                f"bottom contour to the top one")
    return RingOrder(order, bottom, top, joints, (loops[0], loops[1]), size, slivers)


def loop_polygon(pieces: list) -> np.ndarray:
    """A contour's edges' samples (each end to end, in loop order, either way round) as one polygon."""
    out = [np.asarray(pieces[0], float)]
    if len(pieces) > 1 and min(np.linalg.norm(out[0][0] - q) for q in (pieces[1][0], pieces[1][-1])) < \
            min(np.linalg.norm(out[0][-1] - q) for q in (pieces[1][0], pieces[1][-1])):
        out[0] = out[0][::-1]
    for P in pieces[1:]:
        P = np.asarray(P, float)
        out.append(P if np.linalg.norm(P[0] - out[-1][-1]) <= np.linalg.norm(P[-1] - out[-1][-1]) else P[::-1])
    return np.concatenate(out)


def role_of(bottom: np.ndarray, point: np.ndarray, outward: np.ndarray) -> str:
    """A wall's role from its own faces: 'hole' where the part's outward normal at a point of its bottom
    contour (bottom: the contour as a polygon) points into the contour (the opening is inside it), else
    'outer'."""
    from ruled.core.region import crossings_odd
    c = bottom.mean(axis=0)
    frame = np.linalg.svd(bottom - c)[2][:2]
    n = frame @ np.asarray(outward, float)
    if not np.linalg.norm(n) > 0:
        return "outer"
    step = 1e-4 * float(np.linalg.norm(np.ptp(bottom, axis=0)))
    q = (np.asarray(point, float) - c) @ frame.T + step * n / np.linalg.norm(n)
    return "hole" if bool(crossings_odd((bottom - c) @ frame.T, q[None])[0]) else "outer"


def role_names(roles: list) -> list:
    """The walls' names by role: 'outer' (numbered 'outer 1', ... where a part has more than one outside)
    and 'hole 1', 'hole 2', ... in the walls' order."""
    out, count = [], {r: 0 for r in roles}
    total = {r: roles.count(r) for r in roles}
    for r in roles:
        count[r] += 1
        out.append(r if r == "outer" and total[r] == 1 else f"{r} {count[r]}")
    return out


WALL_WORDS = ("auto", "outer", "hole")


def pick_wall(spec: str, names: list, roles: list, faces: list) -> int:
    """Which of a part's walls (their names and roles, role_names / role_of, and face lists) the user's
    «wall» word picks: 'auto' (the only wall), 'outer', 'hole' (the only one of that role), 'hole:K' or
    'outer:K' (the K-th, from 1).  Refused in one line listing the walls where the choice is not one."""
    listing = "; ".join(f"{n} (faces {_names(f)})" for n, f in zip(names, faces))
    how = ("choose one with «wall=outer», «wall=hole»" + (", «wall=hole:2»" if roles.count("hole") > 1 else "")
           + " or its faces «wall=K,L-M»")
    if spec == "auto":
        if len(names) == 1:
            return 0
        raise BadInputError(f"the part has {len(names)} walls: {listing}; {how}")
    role, _, k = spec.partition(":")
    mine = [i for i, r in enumerate(roles) if r == role]
    if not k:
        if len(mine) == 1:
            return mine[0]
        what = f"no {role} wall" if not mine else f"{len(mine)} {role} walls"
        raise BadInputError(f"«wall={spec}»: the part has {what}: {listing}; "
                            f"{'name one with «wall=' + role + ':1»' if mine else how}")
    if not k.isdigit() or not 1 <= int(k) <= len(mine):
        raise BadInputError(f"«wall={spec}»: the part has {len(mine)} {role} wall{'s' if len(mine) != 1 else ''}: "
                            f"{listing}; {how}")
    return mine[int(k) - 1]


def is_wall_word(spec) -> bool:
    """spec names a wall by a word (auto, outer, hole, outer:K, hole:K) rather than by faces."""
    if not isinstance(spec, str):
        return False
    role, colon, k = spec.partition(":")
    return spec in WALL_WORDS or (role in ("outer", "hole") and colon == ":" and k.isdigit())


def connected(face_edges: list) -> list:
    """The faces (positions) in groups connected edge to edge (face_edges: each face's edge positions)."""
    parent = list(range(len(face_edges)))

    def root(k):
        while parent[k] != k:
            parent[k] = parent[parent[k]]
            k = parent[k]
        return k
    owners: dict = {}
    for k, es in enumerate(face_edges):
        for e in es:
            owners.setdefault(e, []).append(k)
    for own in owners.values():
        for k in own[1:]:
            parent[root(k)] = root(own[0])
    groups: dict = {}
    for k in range(len(face_edges)):
        groups.setdefault(root(k), []).append(k)
    return sorted(groups.values(), key=lambda g: g[0])


__all__ = ["RingEdge", "RingOrder", "order_ring", "connected", "is_straight", "SLIVER", "loop_polygon",
           "role_names", "role_of", "pick_wall", "is_wall_word", "WALL_WORDS"]
