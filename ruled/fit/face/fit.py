"""Fitting the face the user selected: its region mapped onto the unit square, then fitted.

A face that is its surface's whole (u, v) rectangle is fitted as it is (the exact path). Any other face is
first turned into the four-sided patch S o Omega of its Coons map (ruled.core.region, ruled.fit.face.coons),
sampled into a bicubic B-spline within ``PATCH_TOL`` of the face's size (ruled.split.strips.side_surface);
the patch is fitted, and the deviation of the sampled patch from S o Omega is added to the certified bound,
which is then for the bounded face. The rails are two opposite sides of the face: the fit's direction 'v'
joins sides 0 and 2, 'u' sides 1 and 3.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Optional

import numpy as np

from ruled.core.blas import one_thread
from ruled.core.edgegap import off_face
from ruled.core.errors import BadInputError, DegenerateFaceError, RuledError
from ruled.core.progress import Progress
from ruled.core.region import Region, four_sides, side_candidates
from ruled.fit.face.coons import coons_map
from ruled.fit.face.patch import (  # noqa: F401 (FacePatch, region_size, with_deviation, with_iso: re-exported)
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
from ruled.fit.face.trimfit import _trimmed_open, box_patches, fit_patch, fit_trimmed, own_patch
from ruled.fit.fit2d import FitResult, ruling_figure
from ruled.fit.options import Direction, Ends, FitOptions, Method, Objective
from ruled.fit.surface import fit_surface


def _rect_direction(region: Region, rails) -> str:
    """The fit direction of a rectangle whose rails are the given loop edges."""
    a, b = (int(x) for x in rails)
    for k in (a, b):
        if not 0 <= k < region.size:
            raise BadInputError(f"«rails»: the face has no edge {k}; its outer wire has edges 0..{region.size - 1} "
                                f"(see «edges_listing»)")
    sides = region.rect_sides()
    na, nb = sides[a][0], sides[b][0]
    if na[0] != nb[0] or na == nb:
        raise BadInputError(f"«rails={a},{b}»: edges {a} and {b} are not opposite sides of the face; name two "
                            f"opposite edges (see «edges_listing»)")
    return na[0]


OFF_EDGES = 1e-6   # a rectangle's outer edges off its surface by more than this fraction of its size: its Coons patch


def face_patch(region: Region, rails: Optional[tuple] = None) -> FacePatch:
    """The face as a four-sided patch (see the module doc); rails: two loop edges to fix the rails."""
    warnings = []
    span = region.hole_span()
    if region.holes:
        n = len(region.holes)
        warnings.append(f"the face has {n} hole{'s' if n > 1 else ''}: the ruled surface spans "
                        f"{'them' if n > 1 else 'it'} (it is fitted over the outer boundary), and its bound "
                        f"includes {span:.4g}, how far the spanning part can be from the face")
    size = region_size(region)
    if region.is_rectangle():
        direction = None if rails is None else _rect_direction(region, rails)
        if off_face(region) > OFF_EDGES * size:
            # its outer edges lie off its surface: its sides moved onto them (its Coons patch), so that the
            # result reaches the face's own edges as a CAD system's ruled surface between them does
            try:
                sides = four_sides(region, rails)
                return sided_patch(region, sides, None, size, None if rails is None else "v", tuple(warnings), span)
            except RuledError:      # (a patch that cannot be sampled: the surface's own rectangle)
                pass
        # the face's edges (which the measure samples) may lie off the surface within their tolerance
        gap = EDGE_MARGIN * off_face(region)
        return FacePatch(region, region.surface, region.rect_slack(gaps=False) + gap, True, None, direction,
                         face_size=size, warnings=tuple(warnings), edge_gap=gap)
    sides, m = _choose_sides(region, rails, size)
    return sided_patch(region, sides, m, size, None if rails is None else "v", tuple(warnings), span)


def sided_patch(region: Region, sides, m=None, size: Optional[float] = None, direction: Optional[str] = None,
                warnings: tuple = (), span: float = 0.0) -> FacePatch:
    """The face as the four-sided patch S o Omega of the Coons map m of the given sides (ruled.core.region.Sides;
    m built when not given), sampled into a bicubic B-spline, with its deviation from the bounded face."""
    size = region_size(region) if size is None else size
    m = coons_map(region, sides) if m is None else m
    tol = PATCH_TOL * max(size, 1e-300)
    side = side_surface(region.surface, m, tol, PATCH_MAX_SPANS, PATCH_ACCEPT * size)
    x = np.linspace(0.0, 1.0, 41)
    ss, tt = np.meshgrid(x, x, indexing="ij")
    off = m.offset(ss.ravel(), tt.ravel())
    # the blended offsets (the patch's sides follow the outer edges' 3D curves, within how far the offsets
    # miss them), and the holes' edges' own distance to the surface, all sampled: EDGE_MARGIN for what the
    # samples miss.  Without offsets, the outer edges' distance to the surface.
    lift = off_face(region) if off is None else float(np.linalg.norm(off, axis=1).max()) + m.boundary_miss()
    gap = EDGE_MARGIN * (lift + region.hole_gap())
    return FacePatch(region, side.surface, float(side.deviation) + gap + span, False, sides,
                     direction, side.spans, size, warnings, gap, span)


def _choose_sides(region: Region, rails, size: float):
    """The sides (and their Coons map): the rails' when given; else, among the candidate groupings
    (ruled.core.region.side_candidates) whose map does not fold, the one whose quick fit (16 samples, no
    refinement, no rebuild: the largest distance of its rulings, ruled.fit.fit2d.ruling_figure) is best."""
    if rails is not None:
        sides = four_sides(region, rails)
        return sides, coons_map(region, sides)
    cands = side_candidates(region)
    maps, errors = [], []
    for sd in cands:
        try:
            maps.append((sd, coons_map(region, sd)))
        except DegenerateFaceError as exc:
            errors.append(exc)
    if not maps:
        raise errors[0]
    if len(maps) == 1:
        return maps[0]
    best, score = None, np.inf
    quick = FitOptions(samples=16, refine=False, objective=Objective.MAX)
    for sd, m in maps:
        try:
            side = side_surface(region.surface, m, 1e-4 * size, 32, 1e-2 * size)
            q = ruling_figure(side.surface, quick) + side.deviation
        except RuledError:
            continue
        if q < score:
            best, score = (sd, m), q
    if best is None:
        raise DegenerateFaceError("no grouping of the face's edges into four sides can be fitted; pick two "
                                  "opposite edges as rails («rails=A,B», see «edges_listing»)")
    return best


@one_thread
def fit_region(region: Region, options: FitOptions = FitOptions(), progress: Progress = None,
               rails: Optional[tuple] = None, patch: Optional[FacePatch] = None) -> FitResult:
    """The globally optimal ruled fit of the face as bounded by its edges: with the end rulings pinned
    to its corners (fit_pinned), and with the rails run past the face and the result trimmed by its
    edges (ruled.fit.face.extend, ruled.fit.face.trim); by default the one with the smaller certified bound
    (options.ends), its notes saying which and why.  Where the face is much straighter along a direction of
    its surface's domain that is not an iso direction (an exactly ruled surface whose rulings cross its iso
    lines), the fit across a parallelogram along it (ruled.fit.face.skew) is a candidate too, and a planar face's
    plane (ruled.fit.face.plane)."""
    opts = options.checked()
    if patch is not None or opts.ends == Ends.PINNED or opts.method != Method.D2:
        return fit_pinned(region, opts, progress, rails, patch)
    flat = skewed = theta = None
    size = region_size(region)
    if rails is None:
        from ruled.fit.face.plane import plane_fit
        flat = plane_fit(region, size, opts, progress)
        if flat is not None and flat.error_bound <= EXACT * size:
            return flat         # a plane is ruled: exact at once
    if rails is None and (not region.holes or opts.ends == Ends.TRIMMED):
        skewed, theta = fit_skewed(region, size, opts, progress)
        if skewed is not None and skewed.error_bound <= EXACT * size:
            # exact along the face's straightest direction: no four-sided map can do better than that
            return _skew_noted(skewed, theta, None)
    try:
        res, why = _fit_region(region, opts, progress, rails), None
    except BadInputError as exc:          # no map of the four-sided kinds: the skewed one may have one
        res, why = None, exc
    if skewed is not None and (res is None or skewed.error_bound + _lead(region, res) < res.error_bound):
        res = _skew_noted(skewed, theta, res)
    if flat is not None and (res is None or flat.error_bound + _lead(region, res) < res.error_bound):
        res = flat
    if res is not None and rails is None and res.error_bound > size:
        # a bound past the face's size (the own surface's rectangle trimmed round a sliver, say): the whole
        # rectangle, untrimmed, where it does better
        got = _fit_inscribed(region, size, opts, progress)
        if got is not None and got.error_bound < res.error_bound:
            return got
    if res is None and rails is None:
        # no map of any kind above: the parallelogram along the surface's own iso lines, run a little past the
        # face (its own rectangle's rails touch a face inscribed in it, where a map onto the result folds)
        for th in (0.5 * np.pi, 0.0):
            got, _ = fit_skewed(region, size, opts, progress, th)
            if got is not None and got.error_bound <= size and (res is None or got.error_bound < res.error_bound):
                res, theta = got, th            # (a bound past the face's size is no result)
        if res is not None:
            return _skew_noted(res, theta, None)
        got = _fit_inscribed(region, size, opts, progress)
        if got is not None:
            return got
        if _trimmed_open(region):
            raise DegenerateFaceError(f"{getattr(why, 'template', why)} (no fit across its own surface's rectangle, "
                                      f"nor across a parallelogram round it, keeps its orientation over the face "
                                      f"within its size, {size:.4g})")
    if res is None:
        raise why
    if rails is None and res.error_bound > EXACT * size:
        # a face closed in one direction: both its sides folded onto one ruled surface (ruled.fit.face.fold)
        from ruled.fit.face.fold import fit_folded
        folded = fit_folded(region, size, opts, progress, res.error_bound - _lead(region, res))
        if folded is not None:
            return folded
    return res


def _fit_inscribed(region: Region, size: float, opts: FitOptions, progress: Progress) -> Optional[FitResult]:
    """The fit of the surface's whole rectangle, untrimmed, for a face inscribed in it that no map puts rulings
    over (ruled.fit.face.inscribed), with a note saying so; None where its bound is past the face's size."""
    from ruled.fit.face.inscribed import inscribed_patch
    patch = inscribed_patch(region, size)
    got = None if patch is None else fit_pinned(region, opts, progress, None, patch)
    if got is None or not got.error_bound <= size:
        return None
    note = (f"no map puts rulings over the face itself: the result is the fit of its surface's whole rectangle, "
            f"untrimmed, which reaches {patch.deviation - patch.edge_gap:.4g} past the face (in its bound "
            f"{got.error_bound:.4g}, with {patch.edge_gap:.4g} for the face's edges lying off its surface)")
    return replace(got, notes=tuple(got.notes) + (note,))


# a fit across the face's parallelogram certified within this fraction of its size is the result at once
EXACT = 1e-5


def fit_skewed(region: Region, size: float, opts: FitOptions, progress: Progress,
               theta: Optional[float] = None) -> tuple:
    """(fit, theta): the fit across the face's parallelogram along its straightest direction theta
    (ruled.fit.face.skew), trimmed by its edges, where that direction is worth a try (straighter than both iso
    directions by WORTH: its rulings may still curve in the domain, as a hyperboloid's do, so the fit decides),
    or along the theta given; (None, None) otherwise, or where it cannot be fitted and trimmed."""
    from ruled.fit.face.skew import skew_patch, straightest, worth_trying
    if not _trimmed_open(region):
        return None, None
    if theta is None:
        theta, score, iso = straightest(region)
        if not worth_trying(theta, score, iso):
            return None, None
    patch = skew_patch(region, size, theta)
    if patch is None:
        return None, None
    return fit_patch(patch, opts, progress)[0], theta


def _skew_noted(got: FitResult, theta: float, res: Optional[FitResult]) -> FitResult:
    vs = "" if res is None else f" (otherwise {res.error_bound:.4g})"
    note = (f"the face is straightest along a direction {np.degrees(theta):.3g} degrees from its surface's u lines: "
            f"the rulings run across a parallelogram of the surface's domain along it, trimmed by the face's edges, "
            f"bound {got.error_bound:.4g}{vs}")
    return replace(got, notes=tuple(got.notes) + (note,))


def _fit_region(region: Region, opts: FitOptions, progress: Progress, rails: Optional[tuple]) -> FitResult:
    """fit_region's four-sided and own-surface candidates (pinned, trimmed, the surface's own box)."""
    lazy = why = None
    if opts.ends == Ends.AUTO:
        try:
            lazy = _Pinned(region, opts, progress, rails)
        except BadInputError as exc:        # (no four-sided patch: raised again if nothing else fits)
            why = exc
    # the pinned fit's figures before its rails are compacted (a lower bound of its final bound: compacting
    # only raises it) decide where they can; its final, compacted fit is made where it is the result or the
    # decision needs its final bound
    pinned = None if lazy is None else lazy.lower
    own = own_patch(region, region_size(region)) if rails is None else None
    if own is not None:
        got, _ = fit_patch(own, opts, progress)
        # within the file's own edge tolerance both are as exact as the file allows: the own surface needs no map
        file_tol = max(region.tolerances, default=0.0)
        if got is not None and lazy is not None and got.error_bound > max(pinned.error_bound, file_tol):
            pinned = lazy.final()
        if got is not None and (pinned is None or got.error_bound <= max(pinned.error_bound, file_tol)):
            vs = "" if pinned is None else f" (pinned {pinned.error_bound:.4g})"
            note = (f"the face's own surface is ruled along its iso lines: the result is that surface trimmed by "
                    f"the face's edges, bound {got.error_bound:.4g}{vs}")
            return replace(got, notes=tuple(got.notes) + (note,))
    if opts.ends == Ends.AUTO and region.holes and lazy is not None:
        # a trimmed result with holes built an invalid face on a fuzz face (issue 35): asked for only
        pinned = lazy.final()
        return replace(pinned, notes=tuple(pinned.notes) + (
            "the rulings are pinned to the face's corners: a face with holes is trimmed only when asked "
            "(«ends=trimmed»)",))
    if any(region.seams) or (pinned is not None and pinned.best.closed):
        return lazy.final() if lazy is not None else fit_pinned(region, opts, progress, rails)  # closed: no ends
    # both pairs of opposite sides as rails: the pinned fit's choice is made by the curved end edges'
    # sagitta, which the trimmed result no longer has
    trimmed, reason = fit_trimmed(region, opts, progress, rails, None,
                                  None if pinned is None else pinned.patch.sides)
    if trimmed is None:
        if pinned is None and rails is None:
            boxed = fit_box(region, opts, progress, why or reason)
            if boxed is not None:
                return boxed
        if lazy is None:
            if why is not None:
                raise why
            pinned = fit_pinned(region, opts, progress, rails)
        else:
            pinned = lazy.final()
        note = f"the rulings are pinned to the face's corners: {reason}"
        return replace(pinned, notes=tuple(pinned.notes) + (note,))
    if lazy is None:
        return trimmed
    tb = trimmed.error_bound
    if not tb < pinned.error_bound:         # (below the lower bound, the trimmed fit wins whatever the final)
        pinned = lazy.final()
    pb = pinned.error_bound
    # where the face's edges lie off its surface, the pinned patch's sides lie on them and its result reaches
    # them (as a CAD system's ruled surface between them does), while the trimmed result stops at the surface:
    # within its bound, it is up to the whole gap from them, the pinned one about half of it (the strip beyond
    # the surface's end it covers is half the gap from both): the trimmed result must win by that half
    lead = _lead(region, pinned)
    won, how = (trimmed, "the rails run past the face, trimmed by its edges") if tb + lead < pb else \
        (pinned, "the rulings are pinned to the face's corners" + (
            ", its sides on the face's own edges (they lie off its surface)" if lead else ""))
    note = f"{how}: bound {won.error_bound:.4g} (trimmed {tb:.4g}, pinned {pb:.4g})"
    return replace(won, notes=tuple(won.notes) + (note,))


def _follows_edges(region: Region, fit: FitResult) -> bool:
    """Whether the fit's patch has its sides moved onto the face's outer edges, which lie off its surface."""
    return fit.patch is not None and fit.patch.sides is not None and fit.patch.mask is None and \
        off_face(region) > OFF_EDGES * region_size(region)


def _lead(region: Region, fit: FitResult) -> float:
    """How much lower another candidate's bound must be to win over fit, a fit whose sides lie on the face's
    edges where they leave its surface (see _fit_region's last comparison): half the edges' distance off it."""
    return 0.5 * EDGE_MARGIN * off_face(region) if _follows_edges(region, fit) else 0.0


def fit_box(region: Region, opts: FitOptions, progress: Progress, why) -> Optional[FitResult]:
    """The face with no four-sided map (why: the refusal, or why its rails cannot run past it) fitted over
    its own surface's rectangle, the rulings along v and along u, trimmed by its edges: the lower bound, a
    note saying so; None where neither can be fitted and trimmed."""
    best = None
    for patch in box_patches(region, region_size(region)):
        got, _ = fit_patch(patch, opts, progress)
        if got is not None and (best is None or got.error_bound < best.error_bound):
            best = got
    if best is None:
        return None
    note = (f"the face has no four-sided map ({why}): the rulings run between the iso lines bounding its own "
            f"surface, trimmed by its edges, bound {best.error_bound:.4g}")
    return replace(best, notes=tuple(best.notes) + (note,))


def fit_pinned(region: Region, opts: FitOptions, progress: Progress = None, rails: Optional[tuple] = None,
               patch: Optional[FacePatch] = None) -> FitResult:
    """The fit with its end rulings pinned to the face's corners: fit_surface on the face's patch (its own
    surface when it is its whole (u, v) rectangle, else its Coons patch); the result's ``patch`` tells
    the rails, and its bound includes the patch's deviation."""
    return _Pinned(region, opts, progress, rails, patch, compact=True).lower


class _Pinned:
    """The pinned fit made once, finished twice at most: .lower, from the 2D fit before its rails are compacted
    (its bounds a lower bound of the final's: compacting raises a bound, by COMPACT of it at most), and
    .final(), the fit fit_pinned returns (compacted, as fit_surface compacts it), made when asked."""

    def __init__(self, region: Region, opts: FitOptions, progress: Progress = None, rails: Optional[tuple] = None,
                 patch: Optional[FacePatch] = None, compact: bool = False):
        if progress is not None:
            progress("the face's own parametrization", 0.0)
        self.patch = face_patch(region, rails) if patch is None else patch
        if progress is not None:
            progress("the face's own parametrization", 1.0)
        if self.patch.direction is not None:
            opts = replace(opts, direction=Direction(self.patch.direction))
        self.progress = progress
        self.raw = fit_surface(self.patch.surface, opts, progress, compact=compact)
        self.lower = self._finished(self.raw)
        self._final = self.lower if compact or opts.method != Method.D2 else None

    def _finished(self, raw: FitResult) -> FitResult:
        res = with_iso(raw, self.progress)
        if not self.patch.identity:          # an untrimmed face keeps today's exact path
            res = _area_checked(res, self.patch)
        return replace(with_deviation(res, self.patch.deviation), patch=self.patch)

    def final(self) -> FitResult:
        if self._final is None:
            from ruled.fit.fit2d import compacted
            self._final = self._finished(compacted(self.raw))
        return self._final


def _area_checked(res: FitResult, patch: FacePatch) -> FitResult:
    """Drop candidates whose surface's area is far from the face's (rails that nearly meet, a
    collapsed map): a result that does not cover the face is refused, never returned."""
    from ruled.fit.fit2d import surface_area
    a = surface_area(patch.surface)
    cands, reasons = {}, []
    for d, c in res.candidates.items():
        if isinstance(c, str):
            cands[d] = c
            continue
        r = surface_area(c.surface) / a if a > 0 else 1.0
        if 0.5 <= r <= 2.0:
            cands[d] = c
        else:
            ra, rb = patch.rails(d)
            why = (f"the fit between edges {','.join(map(str, ra)) or 'a point'} and "
                   f"{','.join(map(str, rb)) or 'a point'} covers {100 * r:.3g}% of the face's area")
            cands[d] = why
            reasons.append(why)
    ok: list = [c for c in cands.values() if not isinstance(c, str)]
    if not ok:
        raise DegenerateFaceError("; ".join(reasons) + "; the face's edges do not bound a four-sided region "
                                  "a ruled surface can span (check the face in a CAD viewer, or name other rails "
                                  "with «rails=A,B»)")
    best = min(ok, key=lambda c: c.error_bound)
    return res if best is res.best else replace(res, best=best, candidates=cands)


__all__ = ["FacePatch", "face_patch", "fit_region", "region_size", "with_deviation", "PATCH_TOL"]
