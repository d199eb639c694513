"""A result trimmed by the face's edges, machined: the rulings that cross the face.

The trimmed result is a ruled surface R (rulings along v, between its rails at t = 0 and 1) whose rails
run past the face, and a trim: the face's edges as 2D curves in R's (s, t).  What a wire or a flank tool
sweeps is R over the s-range the trim spans (every ruling there crosses the face, plane to plane), and
what it cuts of the face is where those rulings lie inside the trim.
"""

from __future__ import annotations

import numpy as np

from ruled.core.errors import BadInputError
from ruled.core.knots import clamp_segment
from ruled.core.nurbs import Curve, Surface
from ruled.core.region import crossings_odd
from ruled.fit.trim import loop_polylines

PER_CURVE = 129     # samples of each trim curve for its s-range and the inside test


def trim_polygons(trim) -> list:
    """The trim's loops as closed polylines (N, 2) in R's (s, t): the outer loop first, then the holes."""
    return loop_polylines((trim.outer,) + tuple(trim.holes), PER_CURVE)


def s_range(trim) -> tuple:
    """The s-range of R's rulings that meet the face (the outer loop's extent in s)."""
    P = trim_polygons(trim)[0]
    return float(P[:, 0].min()), float(P[:, 0].max())


def inside_trim(polygons: list, st: np.ndarray) -> np.ndarray:
    """Whether the points st (N, 2) of R's domain lie in the face (the even-odd rule over its loops)."""
    odd = np.zeros(st.shape[0], bool)
    for P in polygons:
        odd ^= crossings_odd(P, st)
    return odd


def ruling_span(R: Surface, a: float, b: float) -> Surface:
    """R (rulings along v: degree 1, two poles across) over s in [a, b], exactly (knot insertion on both
    rails): the rulings that cross the face."""
    if R.degree_v != 1 or R.poles.shape[1] != 2 or R.periodic_u:
        raise BadInputError("a trimmed result is machined along its rulings only when it is an open ruled surface "
                            "along v; fit with «ends=pinned»")
    u0, u1 = R.domain[:2]
    a, b = max(a, u0), min(b, u1)
    if not b > a:
        raise BadInputError("the trimmed result's rulings do not cross the face; fit with «ends=pinned»")
    rails = [clamp_segment(Curve(R.poles[:, j], R.knots_u, R.degree_u, None if R.weights is None else R.weights[:, j]),
                           a, b) for j in (0, 1)]
    w = None if R.weights is None else np.stack([c.weights for c in rails], axis=1)
    return Surface(np.stack([c.poles for c in rails], axis=1), rails[0].knots, R.knots_v, R.degree_u, 1, w)


__all__ = ["inside_trim", "ruling_span", "s_range", "trim_polygons"]
