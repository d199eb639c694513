"""The face fitted over a longer span: its rails run past the face (ruled.fit.extend), and each candidate
is trimmed by the face's edges (ruled.fit.trim).  ruled.fit.facefit.fit_region compares it with the fit
pinned to the face's corners."""

from __future__ import annotations

from dataclasses import replace
from typing import Optional

import numpy as np

from ruled.core.errors import RuledError
from ruled.core.progress import Progress
from ruled.core.region import Region, Sides, four_sides
from ruled.fit.facepatch import (
    EDGE_MARGIN,
    PATCH_ACCEPT,
    PATCH_MAX_SPANS,
    PATCH_TOL,
    FacePatch,
    region_size,
    with_deviation,
    with_iso,
)
from ruled.fit.options import Direction, FitOptions
from ruled.fit.surface import fit_surface
from ruled.split.strips import side_surface


def _rotated(sides: Sides) -> Sides:
    """The same sides with sides 1 and 3 as the rails."""
    p = sides.pieces
    return replace(sides, pieces=(p[1], p[2], p[3], p[0]))


def extended_patch(region: Region, sides: Sides, size: float) -> Optional[FacePatch]:
    """The face's extended patch with rails on sides 0 and 2 (ruled.fit.extend), sampled like the pinned
    patch, or None where no extension covers the face."""
    from ruled.fit.extend import extended_map, masked
    got = extended_map(region, sides)
    if got is None:
        return None
    m, mask = got
    try:
        # (a rational surface's natural extension can reach a zero weight: no extension there)
        with np.errstate(divide="raise", over="raise", invalid="raise"):
            side = side_surface(region.surface, m, PATCH_TOL * max(size, 1e-300), PATCH_MAX_SPANS,
                                PATCH_ACCEPT * size)
    except (RuledError, ArithmeticError):
        return None
    if not np.all(np.isfinite(side.surface.poles)):
        return None
    E = masked(side.surface, mask)
    gap = EDGE_MARGIN * region.max_gap()
    # the loop's points a hair past the rails were clipped onto them: the face runs past the patch by so much
    gap += mask.overshoot * float(E.derivative_bounds()["Sv"].max())
    s_lo = min(float(st[:, 0].min()) for st in mask.edges)
    s_hi = max(float(st[:, 0].max()) for st in mask.edges)
    run = {}
    for name, (a, b) in (("before", (0.0, s_lo)), ("after", (s_hi, 1.0))):
        x = np.linspace(a, b, 65)
        run[name] = max(float(np.linalg.norm(np.diff(E(x, np.full(x.size, t)), axis=0), axis=1).sum())
                        for t in (0.0, 1.0))
    ext = {"s_range": [s_lo, s_hi], "past_start": run["before"], "past_end": run["after"],
           "uv_past": [float(m.A.a), float(1.0 - m.A.b)]}
    return FacePatch(region, E, float(side.deviation) + gap, False, sides, "v", side.spans, size, (), gap, 0.0,
                     mask=mask, extension=ext)


def fit_trimmed(region: Region, opts: FitOptions, progress: Progress = None, rails: Optional[tuple] = None,
                direction: Optional[str] = None, sides: Optional[Sides] = None) -> tuple:
    """(FitResult, None) of the face's extended patch, its candidates trimmed by the face's edges (the
    rails the pinned fit chose, by its direction, when known; else both pairs of opposite sides), or
    (None, why) where no extension covers the face or no fit of it can be trimmed."""
    from ruled.fit.trim import with_trim
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
        try:
            res = with_iso(fit_surface(patch.surface, replace(opts, direction=Direction.V), progress), progress)
        except RuledError as exc:
            why = f"the extended patch cannot be fitted ({exc})"
            continue
        cands = {}
        for d, c in res.candidates.items():
            cands[d] = c if isinstance(c, str) else (with_trim(c, patch.mask) or "its map folds over the face")
        ok = [c for c in cands.values() if not isinstance(c, str)]
        other = res.other if res.other is None or isinstance(res.other, str) else with_trim(res.other, patch.mask)
        if not ok:
            why = "the fit's map folds over the face, so its image is not trimmed by the face's edges"
            continue
        top = min(ok, key=lambda c: c.error_bound)
        r = replace(with_deviation(replace(res, best=top, candidates=cands, other=other), patch.deviation),
                    patch=patch)
        if best is None or r.error_bound < best.error_bound:
            best = r
    return (best, None) if best is not None else (None, why)


__all__ = ["extended_patch", "fit_trimmed"]
