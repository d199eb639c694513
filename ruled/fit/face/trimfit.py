"""The face fitted over a longer span: its rails run past the face (ruled.fit.face.extend), and each candidate
is trimmed by the face's edges (ruled.fit.face.trim).  ruled.fit.face.fit.fit_region compares it with the fit
pinned to the face's corners."""

from __future__ import annotations

import time
from dataclasses import replace
from typing import Optional

import numpy as np

from ruled.core.edgegap import off_face
from ruled.core.errors import RuledError
from ruled.core.nurbs import Curve, Surface
from ruled.core.progress import Progress
from ruled.core.region import Region, Sides, four_sides
from ruled.fit.face.patch import (
    EDGE_MARGIN,
    PATCH_ACCEPT,
    PATCH_MAX_SPANS,
    PATCH_TOL,
    FacePatch,
    region_size,
    with_deviation,
    with_iso,
)
from ruled.fit.face.sampled import side_surface
from ruled.fit.options import Direction, FitOptions
from ruled.fit.surface import fit_surface


def _rotated(sides: Sides) -> Sides:
    """The same sides with sides 1 and 3 as the rails."""
    p = sides.pieces
    return replace(sides, pieces=(p[1], p[2], p[3], p[0]))


def extended_patch(region: Region, sides: Sides, size: float) -> Optional[FacePatch]:
    """The face's extended patch with rails on sides 0 and 2 (ruled.fit.face.extend), sampled like the pinned
    patch, or None where no extension covers the face."""
    from ruled.fit.face.extend import extended_map, masked
    got = extended_map(region, sides)
    if got is None:
        return None
    m, mask = got
    side = sampled_past(region, m, size)
    if side is None:
        return None
    E = masked(side.surface, mask)
    gap = EDGE_MARGIN * off_face(region)
    # the loop's points a hair past the rails were clipped onto them: the face runs past the patch by so much
    gap += mask.overshoot * float(E.derivative_bounds()["Sv"].max())
    ext = _extension(E, mask, [float(m.A.a), float(1.0 - m.A.b)])
    return FacePatch(region, E, float(side.deviation) + gap, False, sides, "v", side.spans, size, (), gap, 0.0,
                     mask=mask, extension=ext)


def sampled_past(region: Region, m, size: float):
    """side_surface of a map that runs past the face (onto the surface's natural extension), or None where it
    cannot be sampled within PATCH_ACCEPT of the size or leaves finite numbers (a rational surface's extension
    can reach a zero weight)."""
    try:
        with np.errstate(divide="raise", over="raise", invalid="raise"):
            side = side_surface(region.surface, m, PATCH_TOL * max(size, 1e-300), PATCH_MAX_SPANS,
                                PATCH_ACCEPT * size)
    except (RuledError, ArithmeticError):
        return None
    return side if np.all(np.isfinite(side.surface.poles)) else None


def _extension(E, mask, uv_past: list) -> dict:
    """How far the patch's rails run past the face: the face's s-range in the patch, the rails' lengths
    before and after it (model units), and uv_past (the fractions of the rails' parameter past the face)."""
    s_lo = min(float(st[:, 0].min()) for st in mask.edges)
    s_hi = max(float(st[:, 0].max()) for st in mask.edges)
    run = {}
    for name, (a, b) in (("before", (0.0, s_lo)), ("after", (s_hi, 1.0))):
        x = np.linspace(a, b, 65)
        run[name] = max(float(np.linalg.norm(np.diff(E(x, np.full(x.size, t)), axis=0), axis=1).sum())
                        for t in (0.0, 1.0))
    return {"s_range": [s_lo, s_hi], "past_start": run["before"], "past_end": run["after"], "uv_past": uv_past}


def _trimmed_open(region: Region) -> bool:
    """The face is a trimmed region of an open surface (not its rectangle, no seam, nothing periodic)."""
    S = region.surface
    return not (region.is_rectangle() or any(region.closed) or any(region.seams) or S.periodic_u or S.periodic_v)


def own_patch(region: Region, size: float) -> Optional[FacePatch]:
    """The face's own surface, whole, as the patch, when it is exactly ruled along its iso lines (one
    span of degree 1 across them: a plane, a cylinder's or a cone's face, a bilinear patch) and the face is
    a trimmed region of it: the fit recovers the surface, and the result is it trimmed by the face's own
    edges (no four-sided map of the face is needed).  Oriented so that the rulings run along v, on the
    unit square; None otherwise (or where the face runs past the surface's domain)."""
    S = region.surface
    if not _trimmed_open(region):
        return None
    if S.degree_v == 1 and S.poles.shape[1] == 2:
        return box_patch(region, size, False, True)
    if S.degree_u == 1 and S.poles.shape[0] == 2:
        return box_patch(region, size, True, True)
    return None


def box_patches(region: Region, size: float) -> list:
    """The face's own surface, whole, as the patch, its rulings along v and along u (any surface): where
    the face has no four-sided map, its rails are the iso lines bounding its surface, and the result is
    trimmed by its edges.  [] where the face is not a trimmed region of an open surface."""
    if not _trimmed_open(region):
        return []
    return [p for p in (box_patch(region, size, swap, False) for swap in (False, True)) if p is not None]


def box_patch(region: Region, size: float, swap: bool, own: bool) -> Optional[FacePatch]:
    """The face's own surface on the unit square, transposed (swap) so that the rulings run along v, with
    the face's mask and its own curves mapped affinely (own: the surface is exactly ruled that way); None
    where the face runs past the surface's domain by more than the mask's band."""
    from ruled.fit.face.extend import BAND, PER_EDGE, FaceMask, masked
    S = region.surface
    u0, u1, v0, v1 = S.domain
    lo, span = np.array([u0, v0]), np.array([u1 - u0, v1 - v0])
    E = Surface(S.poles, (S.knots_u - u0) / span[0], (S.knots_v - v0) / span[1], S.degree_u, S.degree_v, S.weights)
    if swap:
        E = E.transposed()

    def st_of(curves):
        out = []
        for c in curves:
            st = (c(np.linspace(c.domain[0], c.domain[1], PER_EDGE)) - lo) / span
            out.append(st[:, ::-1] if swap else st)
        return out
    outer = st_of(region.loop)
    holes = [st_of(h) for h in region.holes]
    allst = np.concatenate(outer + [p for h in holes for p in h])
    over = max(0.0, float(-allst.min()), float(allst.max() - 1.0))
    if over > BAND:
        return None
    outer = tuple(np.clip(st, 0.0, 1.0) for st in outer)
    holes = [tuple(np.clip(st, 0.0, 1.0) for st in h) for h in holes]
    def curve_of(c):            # the pcurve in the patch's (s, t): its poles moved (and swapped) affinely
        P = (c.poles - lo) / span
        return Curve(P[:, ::-1] if swap else P, c.knots, c.degree, c.weights)
    curves, snap = None, 0.0
    if over <= 1e-12:
        loops = [_closed_loop([curve_of(c) for c in lp]) for lp in [region.loop] + list(region.holes)]
        curves = tuple(lp for lp, _ in loops)
        snap = max(d for _, d in loops)
    mask = FaceMask((np.concatenate(outer),) + tuple(np.concatenate(h) for h in holes), outer, tuple(holes), over,
                    curves)
    E = masked(E, mask)
    b = E.derivative_bounds()
    gap = EDGE_MARGIN * off_face(region) + over * max(float(b["Su"].max()), float(b["Sv"].max()))
    gap += snap * (float(b["Su"].max()) + float(b["Sv"].max()))
    s_lo = min(float(st[:, 0].min()) for st in outer)
    s_hi = max(float(st[:, 0].max()) for st in outer)
    return FacePatch(region, E, gap, False, None, "v", (0, 0), size, (), gap, 0.0, mask=mask,
                     extension=_extension(E, mask, [s_lo, 1.0 - s_hi]), own=own, box=True)


def _closed_loop(curves: list) -> tuple:
    """(curves, d): a loop of clamped 2D curves whose consecutive ends meet exactly, each corner the mean of
    its two curves' ends (a file's pcurves meet only within its edges' tolerance, which a rebuilt face's
    tighter vertices do not cover), d the largest end moved (a clamped curve's end pole is its end point, and
    moving a pole by d moves the curve by at most d).  Curves not clamped are left as they are."""
    def clamped(c):
        return np.all(c.knots[:c.degree + 1] == c.knots[0]) and \
            np.all(c.knots[-c.degree - 1:] == c.knots[-1])
    if not all(clamped(c) for c in curves):
        return tuple(curves), 0.0
    P = [c.poles.copy() for c in curves]
    moved = 0.0
    for k in range(len(P)):
        m = 0.5 * (P[k - 1][-1] + P[k][0])
        moved = max(moved, float(np.linalg.norm(P[k][0] - m)))
        P[k - 1][-1], P[k][0] = m, m
    return tuple(Curve(p, c.knots, c.degree, c.weights) for p, c in zip(P, curves)), moved


def fit_patch(patch: FacePatch, opts: FitOptions, progress: Progress = None) -> tuple:
    """(FitResult, None) of a masked patch (rails at t = 0 and 1), its candidates trimmed by the face's
    edges, or (None, why) where it cannot be fitted or no fit of it can be trimmed."""
    from ruled.fit.face.trim import with_trim
    try:
        res = with_iso(fit_surface(patch.surface, replace(opts, direction=Direction.V), progress), progress)
    except RuledError as exc:
        return None, f"the extended patch cannot be fitted ({exc})"
    cands = {}
    for d, c in res.candidates.items():
        cands[d] = c if isinstance(c, str) else (with_trim(c, patch.mask) or "its map folds over the face")
    ok = [c for c in cands.values() if not isinstance(c, str)]
    other = res.other if res.other is None or isinstance(res.other, str) else with_trim(res.other, patch.mask)
    if not ok:
        return None, "the fit's map folds over the face, so its image is not trimmed by the face's edges"
    top = min(ok, key=lambda c: c.error_bound)
    finer = _finer_trim(top, patch.mask, patch.deviation, progress)
    if finer is not top:
        cands = {d: finer if c is top else c for d, c in cands.items()}
        ok = [c for c in cands.values() if not isinstance(c, str)]
    if patch.own:
        cands = {d: c if isinstance(c, str) else _as_own(c, patch.surface) for d, c in cands.items()}
        ok = [c for c in cands.values() if not isinstance(c, str)]
    top = min(ok, key=lambda c: c.error_bound)
    return replace(with_deviation(replace(res, best=top, candidates=cands, other=other), patch.deviation),
                   patch=patch), None


# the trim's part of a bound above the certificate's own: the best candidate certified again on this grid
# (finer across the rulings: psi's kinks at the grid's lines, which the trim curves cut across, shrink
# with the cells' size squared)
GRID_TRIM = (240, 640)


def _finer_trim(c, mask, deviation: float = 0.0, progress: Progress = None):
    """The trimmed fit c certified on GRID_TRIM and trimmed again where the trim's part of its bound is
    the larger (an exact fit whose rulings cross the face's edges: the certificate's part is small; the
    patch's deviation from the face, added later, counted in), when that brings its bound down; else c."""
    from ruled.fit.certify.forward import certified_bound
    from ruled.fit.face.trim import with_trim
    if c.trim is None or c.trim.own or 2.0 * c.trim.added <= c.certificate.bound + deviation:
        return c
    if progress:
        progress("certifying the trimmed result on a finer grid", 0.0)
    t0 = time.perf_counter()
    # (a certificate at or above c's whole bound cannot bring it down, whatever the trim: its refinement stops there)
    cert = certified_bound(c.oriented, c.pairing, c.boundaries, c.surface, *GRID_TRIM, c.error_bound)
    finer = with_trim(replace(c, certificate=cert, trim=None), mask)
    if finer is None or finer.error_bound >= c.error_bound:
        return c
    timings = dict(c.timings)
    timings["certify"] = timings.get("certify", 0.0) + time.perf_counter() - t0
    return replace(finer, timings=timings)


def _as_own(c, E):
    """A trimmed fit of the face's own (ruled) surface E whose result has E's degrees, knots and weights:
    certified by its poles' largest distance from E's (both surfaces are the same convex combinations of
    their poles, so they are nowhere farther apart), where that is tighter than its certificate (a result
    that is E itself: 0, plus round-off and the trim's part).  Only where the trim is the face's own
    curves (psi the identity), so that the trimmed result is E over the face's own region."""
    R = c.surface
    if (not c.trim.own or R.poles.shape != E.poles.shape or (R.degree_u, R.degree_v) != (E.degree_u, E.degree_v)
            or not np.array_equal(R.knots_u, E.knots_u) or not np.array_equal(R.knots_v, E.knots_v)
            or (R.weights is None) != (E.weights is None)
            or (R.weights is not None and not np.array_equal(R.weights, E.weights))):
        return c
    d = float(np.linalg.norm(R.poles - E.poles, axis=2).max())
    cert = c.certificate
    bound = d + cert.rounding + c.trim.added
    if bound >= cert.bound:
        return c
    return replace(c, certificate=replace(cert, bound=bound, node_max=d, remainder=0.0,
                                          map_deviation=c.trim.added))


def fit_trimmed(region: Region, opts: FitOptions, progress: Progress = None, rails: Optional[tuple] = None,
                direction: Optional[str] = None, sides: Optional[Sides] = None) -> tuple:
    """(FitResult, None) of the face's extended patch, its candidates trimmed by the face's edges (the
    rails the pinned fit chose, by its direction, when known; else both pairs of opposite sides), or
    (None, why) where no extension covers the face or no fit of it can be trimmed."""
    size = region_size(region)
    if sides is None or rails is not None:
        try:
            sides = four_sides(region, rails)
        except RuledError as exc:
            return None, f"its sides cannot be found ({exc})"
    pairs = [sides, _rotated(sides)] if rails is None else [sides]
    if direction is not None and rails is None:
        pairs = [sides if direction == "v" else _rotated(sides)]
    best, why = None, "its rails cannot be run past the face without folding its map"
    for sd in pairs:
        patch = extended_patch(region, sd, size)
        if patch is None:
            continue
        r, w = fit_patch(patch, opts, progress)
        if r is None:
            why = w
            continue
        if best is None or r.error_bound < best.error_bound:
            best = r
    return (best, None) if best is not None else (None, why)


__all__ = ["extended_patch", "fit_patch", "fit_trimmed", "own_patch"]
