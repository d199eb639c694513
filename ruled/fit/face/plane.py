"""A planar face: the plane itself is ruled, whatever the face's shape or its surface's parametrization.

A surface whose control points all lie within d of a plane lies within d of it (a B-spline, rational with
positive weights, is in the convex hull of its poles).  Where d is below PLANAR of the face's size, the face is
fitted over a rectangle of that plane covering its boundary (a bilinear patch, its rulings straight lines of
the plane), the face its mask (ruled.fit.face.extend.FaceMask: its boundary's points in the rectangle's (s, t))
and the result trimmed by its edges (ruled.fit.face.trim); d is added to the bound.  The faces it is for have no
four-sided map or one that folds (a sliver of a plane with a single edge round it, parametrized a thousand times
faster one way than the other), and every planar face is answered at once, exactly."""

from __future__ import annotations

from typing import Optional

import numpy as np

from ruled.core.edgegap import off_face
from ruled.core.nurbs import Surface
from ruled.core.region import Region
from ruled.fit.fit2d import FitResult

PLANAR = 1e-9      # a surface whose poles lie within this fraction of the face's size of one plane is planar
MARGIN = 0.02      # the rectangle runs past the face's boundary by this fraction of its extent each way
TRIM = 1e-5        # a plane's result whose trim adds more than this fraction of the size is not kept


def planar_offset(S: Surface) -> tuple:
    """(d, centre, axes): the largest distance of S's poles from their best plane (a bound of S's own distance
    from it), the plane's centre and its axes (rows: two in the plane, then its normal)."""
    P = S.poles.reshape(-1, 3)
    if S.weights is not None and not np.all(S.weights > 0):
        return np.inf, None, None
    c = P.mean(axis=0)
    axes = np.linalg.svd(P - c, full_matrices=False)[2]
    return float(np.abs((P - c) @ axes[2]).max()), c, axes


def plane_patch(region: Region, size: float):
    """The face's planar patch (a FacePatch with its mask, rulings along v), or None where the face is not planar
    within PLANAR of its size, has holes, is its surface's whole rectangle (fitted exactly as it is) or lies on a
    closed surface."""
    from ruled.fit.face.extend import PER_EDGE, FaceMask, masked
    from ruled.fit.face.patch import EDGE_MARGIN, FacePatch
    from ruled.fit.face.trimfit import _extension, _trimmed_open
    if region.holes or not _trimmed_open(region):
        return None
    d, c, axes = planar_offset(region.surface)
    if not d <= PLANAR * size:
        return None
    S = region.surface
    edges = [S(*crv(np.linspace(crv.domain[0], crv.domain[1], PER_EDGE)).T) for crv in region.loop]
    xy = [(X - c) @ axes[:2].T for X in edges]
    allxy = np.concatenate(xy)
    lo, hi = allxy.min(axis=0), allxy.max(axis=0)
    span = np.maximum(hi - lo, 1e-300)
    lo, span = lo - MARGIN * span, span * (1.0 + 2.0 * MARGIN)
    corners = [[c + (lo[0] + i * span[0]) * axes[0] + (lo[1] + j * span[1]) * axes[1] for j in (0, 1)] for i in (0, 1)]
    k = np.array([0.0, 0.0, 1.0, 1.0])
    E = Surface(np.array(corners), k, k.copy(), 1, 1)
    outer = tuple(np.clip((p - lo) / span, 0.0, 1.0) for p in xy)
    mask = FaceMask((np.concatenate(outer),), outer, (), 0.0)
    E = masked(E, mask)
    gap = EDGE_MARGIN * off_face(region)
    return FacePatch(region, E, d + gap, False, None, "v", (1, 1), size, (), gap, 0.0, mask=mask,
                     extension=_extension(E, mask, [MARGIN, MARGIN]), plane=True)


def plane_fit(region: Region, size: float, opts, progress=None) -> Optional[FitResult]:
    """The fit of the face's planar patch trimmed by its edges, with a note; None where it has none."""
    from dataclasses import replace

    from ruled.fit.face.trimfit import fit_patch
    patch = plane_patch(region, size)
    if patch is None:
        return None
    got, _ = fit_patch(patch, opts, progress)
    # the plane is the face's own surface: its bound is the plane's offset and the edges' gap, and the trim's part
    # where its curves follow the face's boundary (a sliver far thinner than long bends them more than that: no)
    if got is None or got.error_bound > 2.0 * patch.deviation + TRIM * size:
        return None
    note = f"the face is planar: the result is its plane trimmed by its edges, bound {got.error_bound:.4g}"
    return replace(got, notes=tuple(got.notes) + (note,))


__all__ = ["planar_offset", "plane_patch", "plane_fit", "PLANAR"]
