"""What the measure says of a face's fit, once its result is built and measured: a result whose own figures
disagree (measured above its bound, or covering another area than the face's) is refused and the fit's next
candidate tried (first_consistent); the warnings a user reads (a face no ruled surface comes near, a loose
bound, a result that does not cover the face, a bound made mostly of the face's edges lying off its surface)."""

from __future__ import annotations

from dataclasses import replace
from typing import Optional

import numpy as np

from ruled.core.errors import Text
from ruled.fit.fit2d import FitResult

FAR = 0.1      # a best ruled surface farther than this fraction of the face's size is no use to a line cut
LOOSE = 100.0  # a bound more than this many times the measured distance is reported as loose
FLOOR = 1e-6   # ... unless it is below this fraction of the face's size (no machine holds less)


def far_from_ruled(measured: float, size: float, explained: float = 0.0) -> Optional[str]:
    """The warning for a face no ruled surface comes near, said from the measured distance of the best
    result (a certified bound may be loose: it never says so on its own), less what is ``explained``
    otherwise (the part spanning a hole can be that far from the face)."""
    if not (size > 0 and measured - explained >= FAR * size):
        return None
    return Text(f"no ruled surface comes near this face: the best found is {measured:.4g} from it by the measure, "
                f"{100 * measured / size:.0f} % of its size ({size:.4g}); a line cannot cut it as one face: split "
                f"it into strips («partition») or machine it another way")


def loose_bound(res: FitResult, bound: float, measured: float, size: float) -> Optional[str]:
    """The note for a certified bound more than LOOSE times the measured distance, naming the part of the
    certificate that makes it (the bound stays true; the measure is the closer figure)."""
    if not (measured > 0 and bound > LOOSE * measured and bound > FLOOR * size):
        return None
    cert = getattr(res.best, "certificate", None)
    why = ""
    if cert is not None:
        parts = {"the certificate's remainder term (the surface's or the result's derivatives are large over "
                 "its grid: a collapsed row, extreme weights or a crease)": cert.remainder,
                 "the deviation of the face's four-sided patch from its edges": cert.map_deviation,
                 "the distance at the certificate's grid nodes (the face's map onto the result strays from "
                 "its nearest points)": cert.node_max}
        worst = max(parts, key=lambda k: parts[k])
        why = f"; most of it is {worst}, {parts[worst]:.4g}"
    return Text(f"the certified bound {bound:.4g} is loose: {bound / measured:.3g} times the measured distance "
                f"{measured:.4g}{why}")


def area_ratio(res: FitResult, face_area: float, result_area: Optional[float] = None) -> Optional[float]:
    """The result's area over the face's (None for a face with holes, which its result spans, for one
    inscribed in the surface's rectangle its result is, ruled.fit.face.inscribed, and for a closed face folded
    onto one ruled surface, ruled.fit.face.fold, which its two sides share): both
    integrated span by span (ruled.fit.fit2d.span_area), the face's from its surface when it is its
    surface's whole rectangle, else face_area (the CAD kernel's, adaptive).  A trimmed result's area is
    result_area (the CAD kernel's, of the trimmed face), its holes left out like the face's."""
    from ruled.fit.fit2d import span_area
    p = res.patch
    if res.best.trim is not None:
        return result_area / face_area if result_area is not None and face_area > 0 else None
    if p is not None and (p.region.holes or p.inscribed or p.fold is not None):
        return None
    a = span_area(p.surface) if p is not None and p.identity else face_area
    return span_area(res.surface) / a if a > 0 else None


AREA_TOL = 5e-3   # a result this close to the face (CLOSE of its size) covers its area within this fraction
CLOSE = 1e-3


def measured_warnings(res: FitResult, bound: float, measured: Optional[float], size: float,
                      area_ratio: Optional[float] = None) -> tuple:
    """What only the measure can say, once the result is measured (None: not measured).  First the result is
    checked against its own figures: a measured distance above its certified bound (beyond round-off)
    means one of the two is wrong; a result within CLOSE of the face's size by the measure whose area
    (area_ratio: the result's over the face's; None for a face with holes, which a
    result spans) differs from the face's by more than AREA_TOL
    covers another region than the face.  Either is refused naming the figures (FiguresError).  Then the
    warnings: a face far from every ruled surface (beyond what spanning its holes explains), and a bound
    that is loose."""
    from ruled.core.errors import FiguresError
    if measured is None or not np.isfinite(measured):
        return ()
    if measured > bound * (1.0 + 1e-9) + 1e-12 * max(size, 1.0):
        raise FiguresError(f"the result's measured distance {measured:.6g} is above its certified bound "
                           f"{bound:.6g}: one of the two is wrong, so the result is not returned (please report "
                           f"the face); try the other «direction», or other «rails»")
    if area_ratio is not None and measured < CLOSE * size and abs(area_ratio - 1.0) > AREA_TOL:
        raise FiguresError(f"the result's area is {area_ratio:.4g} times the face's while it is {measured:.4g} "
                           f"from it by the measure ({100 * measured / size:.2g} % of its size): it covers another "
                           f"region than the face, so it is not returned (please report the face); try other "
                           f"«rails»")
    span = res.patch.hole_span if res.patch is not None else 0.0
    return tuple(w for w in (far_from_ruled(measured, size, span), uncovered(area_ratio),
                             loose_bound(res, bound, measured, size), edge_share(res, bound)) if w)


COVER = 2.0   # a result whose area is below 1 / COVER or above COVER times the face's is said not to cover it


def uncovered(ratio: Optional[float]) -> Optional[str]:
    """The warning for a result whose area is far from the face's (ratio: the result's over the face's): it
    is within its bound of the face, but does not cover it (a sliver of a face narrower than the result's
    distance from it, or rulings pinned at the corners of a face whose sides bulge far past them)."""
    if ratio is None or not np.isfinite(ratio) or 1.0 / COVER <= ratio <= COVER:
        return None
    return Text(f"the result's area is {ratio:.3g} times the face's: it lies within its bound of the face but does "
                f"not cover it; check it, or try other «rails» or «ends»")


def next_candidates(res: FitResult, why: str) -> list:
    """The fit with each of its other candidates as the result (the other direction, the iso surface, the 4D
    attempt or its 2D baseline), lowest bound first: what to return when the best one's own figures disagree
    (why: the refusal), each with a note saying so."""
    def key(c):
        return c.method, c.direction, float(c.error_bound)
    seen, out = {key(res.best)}, []
    for c in sorted((c for c in list(res.candidates.values()) + [res.other]
                     if c is not None and not isinstance(c, str)), key=lambda c: c.error_bound):
        if key(c) in seen:        # the same fit (the best is a copy of its direction's candidate)
            continue
        seen.add(key(c))
        note = (f"the fit with the lowest bound ({res.best.method} along {res.best.direction}) was not returned: "
                f"{why}; the next candidate ({c.method} along {c.direction}, bound {c.error_bound:.4g}) is the result")
        out.append(replace(res, best=c, notes=tuple(res.notes) + (note,)))
    return out


def first_consistent(res: FitResult, build) -> tuple:
    """(fit, *build(fit)) for the fit, or, where its own figures disagree (build raises FiguresError: a front
    door builds and measures the result), for the next of its candidates whose figures agree
    (next_candidates); the first refusal when none do."""
    from ruled.core.errors import FiguresError
    try:
        return (res,) + tuple(build(res))
    except FiguresError as exc:
        first = exc
    for cand in next_candidates(res, first.problem):
        try:
            return (cand,) + tuple(build(cand))
        except FiguresError:
            continue
    raise first


def edge_share(res: FitResult, bound: float) -> Optional[str]:
    """The note for a bound of which a tenth or more is the face's edges lying off its surface (within
    their own tolerance in the file): the measure samples those edges, so the bound covers them.  Not for a
    bound below FLOOR of the face's size (no machine holds less)."""
    p = res.patch
    if p is None or not (p.edge_gap > 0.1 * bound > 0 and bound > FLOOR * p.face_size):
        return None
    tol = max(p.region.tolerances, default=0.0)
    # (the bound itself is not repeated: the report's line beside this one gives it, to its own digits)
    return Text(f"{p.edge_gap:.3g} of the bound is how far the face's edges lie off its surface"
                + (f" (their tolerance in the file is up to {tol:.3g})" if tol > 0 else ""))


__all__ = ["area_ratio", "first_consistent", "measured_warnings", "next_candidates"]
