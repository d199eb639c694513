"""How far an edge's own 3D curve lies from the surface at its pcurve, both ways: the polylines of dense
samples of each, and where that exceeds the edge's tolerance, the curves themselves (one parameter where
the two agree, else the nearest points searched on each), no less than the tolerance (within which the file
says where the face ends).  The face's outer edges (ruled.core.region.Region.edge_gap) and its holes'."""

from __future__ import annotations

from typing import Callable

import numpy as np

from ruled.core.nearest import to_curve, to_polyline
from ruled.core.nurbs import Curve


def gap_of(on_surface: Callable, t: np.ndarray, c3: Curve, tol: float) -> tuple:
    """(gap, agree, near): on_surface(t), the surface at the pcurve's parameters t ((N, 3)); c3, the edge's 3D
    curve on the same parameters; agree: the two agree parameter for parameter; near: per t, the vector from
    the surface's point to the 3D curve's polyline."""
    from scipy.spatial import cKDTree
    P = on_surface(t)
    ts = np.linspace(c3.domain[0], c3.domain[1], 4001)
    X = c3(ts)
    near = to_polyline(P, X, cKDTree(X)) - P
    back = float(np.linalg.norm(to_polyline(X, P, cKDTree(P)) - X, axis=1).max())
    gap = max(float(np.linalg.norm(near, axis=1).max()), back)
    same = c3(np.clip(t, *c3.domain)) - P          # the same parameter on both curves
    agree = bool(np.linalg.norm(same, axis=1).max() <= 1.5 * max(float(np.linalg.norm(near, axis=1).max()), 1e-300))
    if gap > tol:
        # the gap to the curves themselves, not to their polylines, whose sagitta (at a leading edge's tight
        # turn) can be far more than the gap
        far = (float(np.linalg.norm(same, axis=1).max()) if agree else
               max(float(to_curve(P, c3, ts, X, cKDTree(X)).max()),
                   float(to_curve(X, on_surface, t, P, cKDTree(P)).max())))
        gap = max(min(gap, far), tol)
    return gap, agree, near



def off_face(region, n: int = 257) -> float:
    """How far the face's edges' 3D curves (the outer loop's and the holes') lie from the face itself, at most
    (sampled at n points per edge): each point's distance to its closest point on the surface where that lies
    inside the face, else to the surface's image of the edge's pcurve.  An edge that strays off its pcurve but
    stays on the surface inside the face (a planar face's edge bowed inward) is on the face: what a result
    within its bound of the face's surface must also come near is only how far the edges leave it."""
    cache = region.__dict__
    if "_off_face" in cache:
        return cache["_off_face"]
    from scipy.spatial import cKDTree

    from ruled.core.distance import project_points
    from ruled.core.nearest import to_curve
    S = region.surface
    pairs = [(c, c3) for c, c3, bad in zip(region.loop, region.edges3d or (), region.degenerate)
             if c3 is not None and not bad]
    pairs += [(c, c3) for h, h3 in zip(region.holes, region.hole_edges3d) for c, c3 in zip(h, h3) if c3 is not None]
    worst = 0.0
    for c, c3 in pairs:
        tp = np.linspace(c.domain[0], c.domain[1], 4 * n)
        uv = region.inside(c(tp))
        P = S(uv[:, 0], uv[:, 1])
        X = c3(np.linspace(c3.domain[0], c3.domain[1], n))
        tree = cKDTree(P)
        foot, d = project_points(S, X, uv[tree.query(X)[1]], 8, *region.closed)
        on = region.contains(foot) & np.isfinite(d)
        # off the face: to the edge's image on the surface itself (its polyline's chords would add their sagitta)
        d[~on] = to_curve(X[~on], lambda x, c=c: S(*region.inside(c(x)).T), tp, P, tree) if (~on).any() else 0.0
        worst = max(worst, float(d.max()))
    cache["_off_face"] = worst
    return worst


__all__ = ["gap_of", "off_face"]
