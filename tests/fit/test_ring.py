"""A wall's topology on plain data (ruled.fit.wall.ring, what every host's wall comes to): the four sides of a box
given in a shuffled order come back ordered round the ring, their bottom and top edges and their joints the
box's; a side missing or a hole is refused in one line."""

from __future__ import annotations

import numpy as np
import pytest

from ruled.core.errors import BadInputError
from ruled.fit.wall.ring import RingEdge, order_ring


def _box_sides():
    """Edges and faces of the four sides of the unit box (z from 0 to 1), faces in the order 2, 0, 3, 1."""
    corners = [np.array(c, float) for c in ((0, 0), (1, 0), (1, 1), (0, 1))]
    edges, face_edges = [], [set() for _ in range(4)]
    side_of = [2, 0, 3, 1]             # side k of the box is face side_of.index(k)

    def add(a, b, owners):
        pts = a + np.linspace(0.0, 1.0, 9)[:, None] * (b - a)
        edges.append(RingEdge(a, b, pts, float(np.linalg.norm(b - a)), tuple(owners)))
        for o in owners:
            face_edges[o].add(len(edges) - 1)
    for k in range(4):
        p, q = corners[k], corners[(k + 1) % 4]
        f = side_of.index(k)
        add(np.r_[p, 0.0], np.r_[q, 0.0], [f])                       # bottom
        add(np.r_[p, 1.0], np.r_[q, 1.0], [f])                       # top
    for k in range(4):                                               # the joint at corner k: sides k-1 and k
        p = corners[k]
        add(np.r_[p, 0.0], np.r_[p, 1.0], [side_of.index((k - 1) % 4), side_of.index(k)])
    return edges, face_edges


def test_the_sides_of_a_box_come_back_ordered_round_the_ring():
    edges, face_edges = _box_sides()
    o = order_ring([10, 11, 12, 13], edges, face_edges, [False] * 4, [1.0] * 4)
    sides = [[2, 0, 3, 1].index(k) for k in range(4)]
    ring = [o.order[(o.order.index(sides[0]) + i) % 4] for i in range(4)]
    assert ring in (sides, [sides[0]] + sides[:0:-1])                # round the box, one way or the other
    for k, bottom, top in zip(o.order, o.bottom, o.top):
        assert len(bottom) == 1 and len(top) == 1
        assert all(edges[i].start[2] == 0.0 for i in bottom) and all(edges[i].start[2] == 1.0 for i in top)
        assert bottom[0] in face_edges[k] and top[0] in face_edges[k]
    for k, nxt, j in zip(o.order, o.order[1:] + o.order[:1], o.joints):
        assert set(edges[j].owners) == {k, nxt}
    assert len(o.loops[0]) == len(o.loops[1]) == 4 and o.size == pytest.approx(np.sqrt(3.0))


def test_a_side_missing_or_a_hole_is_refused_in_one_line():
    edges, face_edges = _box_sides()
    with pytest.raises(BadInputError, match=r"^face 12 of the wall has a hole in it"):
        order_ring([10, 11, 12, 13], edges, face_edges, [False, False, True, False], [1.0] * 4)
    keep = [0, 1, 2]                      # three sides: their free edges make one contour
    sub_edges, index = [], {}
    for i, e in enumerate(edges):
        own = tuple(keep.index(o) for o in e.owners if o in keep)
        if own:
            index[i] = len(sub_edges)
            sub_edges.append(RingEdge(e.start, e.end, e.points, e.length, own))
    sub_faces = [{index[i] for i in face_edges[k]} for k in keep]
    with pytest.raises(BadInputError, match=r"^faces 10,11,12 are not a wall: their free edges make one free contour"):
        order_ring([10, 11, 12], sub_edges, sub_faces, [False] * 3, [1.0] * 3)
