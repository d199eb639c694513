"""The engine's own measure of a fit: closest points both ways from dense grids (a sampled estimate of the
Hausdorff distance, not a bound; the independent measure is ruled.occ.measure).  The 4D fit compares its
attempt with its 2D baseline by it (ruled.fit.fit4d)."""

from __future__ import annotations

import numpy as np

from ruled.core.nurbs import Surface
from ruled.fit.certify.bounds import _pairing_s, _segment_feet
from ruled.fit.dp.pairing import Pairing
from ruled.fit.reparam import Boundaries


def sampled_distance(S: Surface, pairing: Pairing, bd: Boundaries, R: Surface, nu: int = 121,
                     nv: int = 41) -> float:
    """The engine's own measure of H(S, R): closest points both ways from dense grids (a sampled
    estimate, not a bound; the independent measure is ruled.occ.measure)."""
    from ruled.core.distance import project_points
    closed = pairing.closed
    u0, u1, v0, v1 = S.domain
    L = u1 - u0
    x = np.linspace(0.0, 1.0, nu, endpoint=not closed)
    tau = np.linspace(0.0, 1.0, nv)
    UU, VV = np.meshgrid(u0 + L * x, v0 + (v1 - v0) * tau, indexing="ij")
    X = S(UU.ravel(), VV.ravel())
    s0 = _pairing_s(pairing, x, tau).ravel()
    d1 = np.full(X.shape[0], np.inf)
    best = np.zeros((X.shape[0], 2))
    for shift in (0.0, -0.05, 0.05, -0.15, 0.15):  # several seeds: the closest ruling is not always the nearest one
        s, t = _segment_feet(bd.A, bd.B, X, s0 + shift if closed else np.clip(s0 + shift, 0.0, 1.0), closed, iters=8)
        d = np.linalg.norm(X - R(np.mod(s, 1.0) if closed else s, t), axis=1)
        better = d < d1
        d1 = np.where(better, d, d1)
        best[better] = np.stack([s, t], axis=1)[better]
    # polish on R as a surface (both parameters at once)
    _, dp = project_points(R, X, best, 6, closed)
    d1 = np.minimum(d1, dp)
    SS, TT = np.meshgrid(x, tau, indexing="ij")
    Y = R(SS.ravel(), TT.ravel())
    a, b = pairing.ab(SS.ravel())
    xs = (1 - TT.ravel()) * a + TT.ravel() * b
    seeds = np.stack([u0 + L * (np.mod(xs, 1.0) if closed else np.clip(xs, 0.0, 1.0)),
                      v0 + (v1 - v0) * TT.ravel()], axis=1)
    _, d2 = project_points(S, Y, seeds, 8, closed)
    # and from the nearest of S's own samples (the pairing's seed can lead the projection into a local
    # minimum, or against the domain's edge, far from the closest point)
    from scipy.spatial import cKDTree
    near = cKDTree(X).query(Y)[1]
    grid = np.stack([UU.ravel(), VV.ravel()], axis=1)
    _, d2b = project_points(S, Y, grid[near], 8, closed)
    d2 = np.minimum(d2, d2b)
    return float(max(d1.max(), d2.max()))


__all__ = ["sampled_distance"]
