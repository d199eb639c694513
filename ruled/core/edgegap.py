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


__all__ = ["gap_of"]
