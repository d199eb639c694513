"""A face inscribed in its surface's rectangle that no map can put rulings over (a sliver whose one edge runs
there and back along the rectangle's diagonal): the fit of the whole rectangle, untrimmed, the last result
before a refusal.  Its bound adds how far the rectangle reaches past the face (sampled on a grid, raised by
half a cell's diagonal: the distance to the face moves by at most the move) and how far the face's edges lie
off it (ruled.core.edgegap.off_face): both ways, the face is within the bound of the result."""

from __future__ import annotations

from typing import Optional

import numpy as np

from ruled.core.edgegap import off_face
from ruled.core.region import Region
from ruled.fit.face.patch import EDGE_MARGIN, FacePatch

GRID = 97   # the rectangle's grid, per direction, for how far it reaches past the face


def reach_past(region: Region, n: int = GRID) -> float:
    """An upper bound of the distance from any point of the surface's rectangle to the face (its region in the
    rectangle): grid points outside the face to the nearest point of the face's boundary on the surface, plus
    half the largest cell diagonal (bounded by the surface's derivative bounds)."""
    from scipy.spatial import cKDTree

    from ruled.core.nearest import to_polyline
    S = region.surface
    u0, u1, v0, v1 = S.domain
    us, vs = np.linspace(u0, u1, n), np.linspace(v0, v1, n)
    UU, VV = np.meshgrid(us, vs, indexing="ij")
    uv = np.stack([UU.ravel(), VV.ravel()], axis=1)
    out = ~region.contains(uv)
    worst = 0.0
    if out.any():
        B = S(*np.concatenate(region.polygon(400)).T)
        X = S(uv[out, 0], uv[out, 1])
        worst = float(np.linalg.norm(to_polyline(X, B, cKDTree(B)) - X, axis=1).max())
    b = S.derivative_bounds()
    cell = 0.5 * (float(b["Su"].max()) * (u1 - u0) + float(b["Sv"].max()) * (v1 - v0)) / (n - 1)
    return worst + cell


def inscribed_patch(region: Region, size: float) -> Optional[FacePatch]:
    """The surface's whole rectangle as the face's patch, its deviation what the module doc says; None where
    that is past the face's size (no result)."""
    edges = EDGE_MARGIN * off_face(region)
    past = reach_past(region)
    if not edges + past <= size:
        return None
    return FacePatch(region, region.surface, past + edges, True, None, None, face_size=size, edge_gap=edges,
                     inscribed=True)


__all__ = ["inscribed_patch", "reach_past"]
