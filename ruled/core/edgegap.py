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
    within its bound of the face's surface must also come near is only how far the edges leave it.  A foot
    the classifier cannot tell from the boundary (Region.contains counts points within a hair of its polylines
    inside, and their chords stray from a curved pcurve by their sagitta) takes the larger of the two: an edge
    that strays off its pcurve along the surface, out of the face by less than that, is off the face."""
    cache = region.__dict__
    if "_off_face" in cache:
        return cache["_off_face"]
    from scipy.spatial import cKDTree

    from ruled.core.distance import project_points
    from ruled.core.nearest import to_curve
    S = region.surface
    u0, u1, v0, v1 = S.domain
    b = S.derivative_bounds()
    speed = max(float(b["Su"].max()), float(b["Sv"].max()))
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
        image = to_curve(X, lambda x, c=c: S(*region.inside(c(x)).T), tp, P, tree)
        # the band the classifier cannot decide in, in space: its hair and the polygon's chords' sagitta
        t200 = np.linspace(c.domain[0], c.domain[1], 200)
        q = c(t200)
        sag = float(np.linalg.norm(c(0.5 * (t200[1:] + t200[:-1])) - 0.5 * (q[1:] + q[:-1]), axis=1).max())
        band = 2.0 * (1e-7 * max(u1 - u0, v1 - v0) + sag) * speed
        along = np.sqrt(np.maximum(image * image - np.where(np.isfinite(d), d, 0.0) ** 2, 0.0))
        unsure = on & (along <= band)
        if unsure.any():        # decided by the side of the pcurve itself the foot lies on
            unsure[unsure] = ~_inner_side(region, lambda x, c=c: region.inside(c(x)), c.domain, foot[unsure])
        d = np.where(on & ~unsure, d, image)
        worst = max(worst, float(d.max()))
    cache["_off_face"] = worst
    return worst


def _inner_side(region, c, domain, uv: np.ndarray) -> np.ndarray:
    """Whether each (u, v) point lies on the face's side of the pcurve c (t -> (u, v) in the surface's domain, on
    `domain`) or on it: the sign of the cross product of c's tangent at its nearest point with the way to the
    point, against the side a probe beside the middle of c lies on (Region.contains, far outside its hair)."""
    from ruled.core.nearest import golden
    t0, t1 = domain
    ts = np.linspace(t0, t1, 2049)
    Q = c(ts)
    k = np.argmin(np.linalg.norm(uv[:, None, :] - Q[None], axis=2), axis=1)
    lo, hi = ts[np.maximum(k - 1, 0)], ts[np.minimum(k + 1, ts.size - 1)]
    t, _ = golden(lambda x: np.linalg.norm(c(x) - uv, axis=1), lo, hi, 60)
    h = 1e-6 * (t1 - t0)
    T = c(np.minimum(t + h, t1)) - c(np.maximum(t - h, t0))
    w = uv - c(t)
    cross = T[:, 0] * w[:, 1] - T[:, 1] * w[:, 0]
    tm = 0.5 * (t0 + t1)
    Tm = c(np.array([tm + h])) - c(np.array([tm - h]))
    left = np.array([-Tm[0, 1], Tm[0, 0]]) / max(float(np.linalg.norm(Tm)), 1e-300)
    u0, u1, v0, v1 = region.surface.domain
    probe = c(np.array([tm]))[0] + 1e-4 * max(u1 - u0, v1 - v0) * left
    side = 1.0 if bool(region.contains(probe[None])[0]) else -1.0
    scale = 1e-12 * max(u1 - u0, v1 - v0)
    return (side * cross >= 0.0) | (np.linalg.norm(w, axis=1) <= scale)


__all__ = ["gap_of", "off_face"]
