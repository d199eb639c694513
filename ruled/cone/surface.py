"""The cone spline of a ruled surface (the entry point): its two boundaries, the spline within a
tolerance, and, when the tolerance is refused, a search for the nearest tolerances that work."""

from __future__ import annotations

import time

import numpy as np

from ruled.cone.conespline import ConeSpline, cone_spline_of_curves, ruled_boundaries
from ruled.core.errors import ToleranceError
from ruled.core.nurbs import Surface
from ruled.core.progress import Progress

SEARCH_FACTOR = 3.0          # the tolerances tried after a refusal: tol / 3, tol x 3, x 9, ... up to the face's size


SEARCH_HALVINGS = 3          # a larger one that works is narrowed down (geometric bisection) this many times,


SEARCH_SECONDS = 15.0        # while the search has taken less than this


def cone_spline_of_surface(S: Surface, tol: float, step: float = 0.1, *, direction: str = "auto",
                           progress: Progress = None, search: bool = True, **kw) -> ConeSpline:
    """Cone spline of a ruled B-spline surface (linear in u or v; k + 1 rows of poles: k strips).

    Refused within tol (ToleranceError), it says what would work: tol / 3 (the arcs then fall
    differently: a refusal is not always cured by a larger tolerance), then tol x 3, x 9, ... up to the
    surface's size; a larger tolerance that works is narrowed down.  The refusal names the tolerance
    found (every one named was tried), or says that none up to the face's size works and to split the
    face.  search=False: only tol."""
    try:
        return _cone_spline_of_surface(S, tol, step, direction, progress, **kw)
    except ToleranceError as exc:
        if not search:
            raise
        why = exc.template
        creases = ", or «keep_creases»" if exc.creases_help else ""

    def works(t: float) -> bool:
        if progress is not None:
            progress(f"refused within {tol:.3g}: trying {t:.3g}", 0.0)
        try:
            _cone_spline_of_surface(S, t, step, direction, None, **kw)
            return True
        except ToleranceError:
            return False

    def rounded(t: float) -> float:      # the value the message prints is the value tried
        return float(f"{t:.3g}")

    t_search = time.perf_counter()
    tighter = rounded(tol / SEARCH_FACTOR)
    if works(tighter):
        raise ToleranceError(f"{why}; a tighter tolerance works (the patches then fall differently): "
                             f"«tol={tighter:g}»{creases}")
    size = S.diagonal()
    lo, hi, t = tol, None, tol
    while hi is None and t < size:
        t = rounded(min(t * SEARCH_FACTOR, size))
        if works(t):
            hi = t
        else:
            lo = t
    if hi is None:
        raise ToleranceError(f"{why}; no tolerance up to the face's size ({size:.3g}) gives a cone spline: split "
                             f"the face where the surface twists (ruled split){creases}")
    for _ in range(SEARCH_HALVINGS):
        if time.perf_counter() - t_search > SEARCH_SECONDS:     # narrowing down is a nicety: not minutes of it
            break
        mid = rounded(float(np.sqrt(lo * hi)))
        if not lo < mid < hi:
            break
        if works(mid):
            hi = mid
        else:
            lo = mid
    raise ToleranceError(f"{why}; the smallest tolerance above it that works is about {hi:g} (tried: «tol={hi:g}»)"
                         f"{creases}")


def _cone_spline_of_surface(S: Surface, tol: float, step: float, direction: str, progress: Progress,
                            **kw) -> ConeSpline:
    name, strips = ruled_boundaries(S, direction)
    out = None
    for i, (C0, C1) in enumerate(strips):
        prog = None if progress is None else \
            (lambda stage, frac, i=i: progress(stage, (i + frac) / len(strips)))
        res = cone_spline_of_curves(C0, C1, tol, step, progress=prog, **kw)
        if out is None:
            out = res
            continue
        base = len(out.pieces)
        for p in res.patches:
            p.piece += base
        out.patches += res.patches
        out.pieces += res.pieces
        out.notes += res.notes
        out.bound = max(out.bound, res.bound)
        out.max_g1_deg = max(out.max_g1_deg, res.max_g1_deg)
        out.max_crease_deg = max(out.max_crease_deg, res.max_crease_deg)
        out.timings["fit"] += res.timings["fit"]
    if len(strips) > 1:
        out.notes.append(f"the face is {len(strips)} ruled strips (degree 1 with {len(strips) + 1} rows of poles "
                         f"along {name}); each has its own cone spline")
    return out
