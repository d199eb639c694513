"""The measures' extra samples where a file's edges lie off their face's surface, for every host (OCCT through
OCP, FreeCAD's Part): the host gives each edge as plain functions (``EdgeView``) and its classifier, and both
hosts' measures take the same points.

A face is its surface's region and its own 3D edges.  Where the edges lie off the surface (within their
tolerance), they may leave it at spots a measure's n samples per edge step over: such an edge is sampled
at DENSE points.  And a result that reaches those edges (Part Ruled between them, a fit whose rails run
onto them) covers the strip between them and the surface, its points there up to half the strip's width from
the face: a grid as coarse as a measure's steps over so thin a strip, so the measure adds, on each face, rows
of points inward of its edges at ROWS of how far the other face's edges lie off its surface, and near each
edge's ends (where an edge's end lies off its neighbour's, the strip ends in a corner)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

ROWS = (0.5, 0.25)          # the rows' distances inward, as fractions of the other face's edges' offset
PER_EDGE = 129              # samples of an edge's pcurve image (the polyline its 3D points are measured to)
LOOKED = 33                 # ... and of its 3D curve
DENSE = 64                  # an edge off its surface: sampled at this many points (at least the measure's n)
OFF_EDGE = 1e-7             # edges off their surface by less than this (OCCT's confusion tolerance): none of it
RELATIVE = 1e-6             # ... or by less than this fraction of the face's size
FD = 1e-6                   # the finite-difference step, a fraction of the parameter ranges


@dataclass(frozen=True)
class EdgeView:
    """One edge of a face, as its host evaluates it: surface(u, v) -> (3,), pcurve(t) -> (u, v) on [a, b],
    curve(t) -> (3,) its 3D curve on [a3, b3], box the face's (u0, u1, v0, v1) for the difference steps."""

    surface: Callable
    pcurve: Callable
    a: float
    b: float
    curve: Callable
    a3: float
    b3: float
    box: tuple


def _to_polyline(X: np.ndarray, P: np.ndarray) -> np.ndarray:
    """Distances from the points X (N, 3) to the polyline P (M, 3)."""
    a, d = P[:-1], np.diff(P, axis=0)
    dd = np.maximum(np.einsum("ij,ij->i", d, d), 1e-300)
    w = np.clip(np.einsum("nij,ij->ni", X[:, None, :] - a[None], d) / dd, 0.0, 1.0)
    return np.linalg.norm(X[:, None, :] - (a[None] + w[..., None] * d[None]), axis=2).min(axis=1)


def offset_of(e: EdgeView) -> float:
    """How far the edge's 3D curve lies from the surface at its pcurve (geometric: its points' distance to
    the pcurve's image, so a curve parametrized otherwise than its pcurve counts nothing): to a dense polyline
    of it, then, where that is more than OFF_EDGE, to the image itself by golden sections beside the nearest
    vertex (a polyline's chords would add their sagitta)."""
    from ruled.core.nearest import golden
    ts = np.linspace(e.a, e.b, PER_EDGE)
    P = np.array([e.surface(*e.pcurve(float(t))) for t in ts])
    X = np.array([e.curve(float(t)) for t in np.linspace(e.a3, e.b3, LOOKED)])
    d = _to_polyline(X, P)
    far = np.nonzero(d > OFF_EDGE)[0]
    if far.size:
        k = np.argmin(np.linalg.norm(X[far, None, :] - P[None], axis=2), axis=1)
        lo, hi = ts[np.maximum(k - 1, 0)], ts[np.minimum(k + 1, ts.size - 1)]

        def dist(t):
            return np.array([np.linalg.norm(np.asarray(e.surface(*e.pcurve(float(x))), float) - X[far[i]])
                             for i, x in enumerate(t)])
        d[far] = np.minimum(d[far], golden(dist, lo, hi, 40)[1])
    return float(d.max())


def edge_offsets(views: list) -> list:
    """Per edge, how far it lies off the surface (offset_of), 0 where that is below OFF_EDGE or RELATIVE of the
    face's size (the diagonal of its edges' sampled box): the hosts' classifiers decide points that near the
    boundary within their own precision, and no machine holds less."""
    if not views:
        return []
    offs, box = [], []
    for e in views:
        offs.append(offset_of(e))
        box.append([e.surface(*e.pcurve(float(t))) for t in (e.a, 0.5 * (e.a + e.b), e.b)])
    B = np.asarray(box, float).reshape(-1, 3)
    least = max(OFF_EDGE, RELATIVE * float(np.linalg.norm(B.max(axis=0) - B.min(axis=0))))
    return [g if g > least else 0.0 for g in offs]


def off_edge_points(views: list, offsets: list, n: int) -> np.ndarray:
    """(N, 3) DENSE points (n where more) along each edge whose offset (edge_offsets) is not 0."""
    pts = [np.array([e.curve(float(t)) for t in np.linspace(e.a3, e.b3, max(DENSE, n))])
           for e, g in zip(views, offsets) if g > 0]
    return np.concatenate(pts) if pts else np.zeros((0, 3))


def _frame(e: EdgeView, t: float) -> tuple:
    """((u, v), the step in (u, v) per unit of 3D distance across the pcurve or None where singular, the 3D
    speed along the pcurve) at t, by central differences."""
    uv = np.asarray(e.pcurve(t), float)
    h = FD * (e.b - e.a)
    duv = (np.asarray(e.pcurve(t + h), float) - np.asarray(e.pcurve(t - h), float)) / (2.0 * h)
    u0, u1, v0, v1 = e.box
    ku, kv = FD * (u1 - u0), FD * (v1 - v0)
    su = (np.asarray(e.surface(uv[0] + ku, uv[1]), float) - np.asarray(e.surface(uv[0] - ku, uv[1]), float)) / (2 * ku)
    sv = (np.asarray(e.surface(uv[0], uv[1] + kv), float) - np.asarray(e.surface(uv[0], uv[1] - kv), float)) / (2 * kv)
    speed = float(np.linalg.norm(duv[0] * su + duv[1] * sv))
    nrm = np.array([-duv[1], duv[0]])                       # across the pcurve, in (u, v)
    rate = float(np.linalg.norm(nrm[0] * su + nrm[1] * sv))
    ok = rate > 0 and np.isfinite(rate)
    return uv, (nrm / rate if ok else None), (speed if np.isfinite(speed) else 0.0)


def edge_rows(views: list, n: int, offset: float, inside: Callable) -> np.ndarray:
    """(N, 3) points of the face on rows inward of its edges at ROWS of offset (3D distances, to first order),
    n / 2 per edge and row (a strip is widest where its edge leaves the surface most, and changes slowly), and
    near each edge's ends (ROWS of offset along it, on the edge and on each row); inside(uv (N, 2)) -> booleans,
    the face's classifier (points outside it are dropped).  Empty for offset 0."""
    if not offset > 0 or not views:
        return np.zeros((0, 3))
    at, along, end = [], [], []
    for e in views:
        lo, hi = e.a + FD * (e.b - e.a), e.b - FD * (e.b - e.a)     # (the differences stay on the pcurve)
        rate = [_frame(e, x)[2] for x in (lo, hi)]
        ends = [lo + f * offset / rate[0] for f in ROWS if rate[0] > 0] + \
               [hi - f * offset / rate[1] for f in ROWS if rate[1] > 0]
        m = max(2, n // 2)
        ts = list(np.linspace(e.a, e.b, m + 2)[1:-1]) + [t for t in ends if lo < t < hi]
        for i, t in enumerate(ts):
            uv, nrm, _ = _frame(e, float(t))
            if nrm is None:
                continue
            at.append(uv)
            along.append(nrm)
            end.append(i >= m)
    if not at:
        return np.zeros((0, 3))
    uv, step, near_end = np.array(at), np.array(along), np.array(end, bool)
    cand = np.concatenate([uv + sign * f * offset * step for f in ROWS for sign in (1.0, -1.0)] + [uv[near_end]])
    cand = cand[np.asarray(inside(cand), bool)]
    surface = views[0].surface
    return np.array([surface(float(u), float(v)) for u, v in cand], float).reshape(-1, 3)


# rulings graded towards a result's corner ruling (corner_rulings): this many a side, each this factor nearer
CORNER_GRADES, CORNER_RATIO = 24, 2 ** 0.5
# ... on a result with at most this many corners (degree 1 along the ring, every knot is one: a polyline result, whose
# kinks are small)
CORNER_GRADED_MAX = 24
CORNERS = 8                 # a wall's edges and its result's corner rulings: this many times the measure's n
EDGE_SAMPLES = 512          # points along each of a wall's edges for their distance from its joined surface


def corner_rulings(knots_u, knots_v, degree_u: int, degree_v: int, bounds, n: int) -> np.ndarray:
    """(m, 2) parameters of n points along each ruling of a ruled B-spline surface (degree 1 in one direction;
    knots: full knot vectors) at its C0 knots across the rulings (its corners: where a ruled surface through a
    wall's bowed joint lies farthest from it), inside bounds (u0, u1, v0, v1); none for another surface.  And
    n // 8 points along rulings graded towards each corner from both sides (CORNER_GRADES of them a side, each
    a factor CORNER_RATIO nearer, from half the knot span beside it): a piece whose corner ruling is pinned on
    a joint's chord lies off the wall just past it, within a thousandth of its span (a die's hole: 0.00098
    there, 3e-5 on the corner ruling itself); not on a result with more than CORNER_GRADED_MAX corners."""
    u0, u1, v0, v1 = bounds
    out = []
    for knots, across, along, lo, hi, t0, t1, swap in ((knots_u, degree_u, degree_v, u0, u1, v0, v1, False),
                                                       (knots_v, degree_v, degree_u, v0, v1, u0, u1, True)):
        if along != 1:
            continue
        k, mult = np.unique(np.asarray(knots, float), return_counts=True)
        corners = k[(mult >= across) & (k >= lo) & (k <= hi)]
        for x in corners:
            uv = np.stack([np.full(n, x), np.linspace(t0, t1, n)], 1)
            m = max(8, n // 8)
            t = np.linspace(t0, t1, m)
            for side in (-1.0, 1.0) if corners.size <= CORNER_GRADED_MAX else ():
                nb = k[k < x] if side < 0 else k[k > x]
                if nb.size == 0:
                    continue
                span = abs(float(nb[-1] if side < 0 else nb[0]) - x)
                at = x + side * 0.5 * span * CORNER_RATIO ** -np.arange(CORNER_GRADES)
                at = at[(at >= lo) & (at <= hi)]
                uv = np.concatenate([uv, np.stack([np.repeat(at, m), np.tile(t, at.size)], 1)])
            out.append(uv[:, ::-1] if swap else uv)
    return np.concatenate(out) if out else np.zeros((0, 2))


__all__ = ["EdgeView", "corner_rulings", "CORNERS", "EDGE_SAMPLES",
           "edge_offsets", "edge_rows", "off_edge_points", "OFF_EDGE", "RELATIVE", "ROWS", "DENSE"]
