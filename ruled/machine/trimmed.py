"""A result trimmed by the face's edges, machined: the rulings that cross the face.

The trimmed result is a ruled surface R (rulings along v, between its rails at t = 0 and 1) whose rails
run past the face, and a trim: the face's edges as 2D curves in R's (s, t).  What a wire or a flank tool
sweeps is R over the s-range the trim spans (every ruling there crosses the face, plane to plane), and
what it cuts of the face is where those rulings lie inside the trim.
"""

from __future__ import annotations

import numpy as np

from ruled.core.errors import BadInputError, Text
from ruled.core.knots import clamp_segment
from ruled.core.nurbs import Curve, Surface
from ruled.core.region import crossings_odd
from ruled.fit.face.trim import loop_polylines

PER_CURVE = 129     # samples of each trim curve for its s-range and the inside test


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


def trimmed_lines(R: Surface, loops) -> tuple:
    """What a machine sweeps of a result trimmed by the face's edges, for every host: (R over the s-range of
    the rulings that cross the face, keep), keep(s, f) -> bool (N,): whether the points at the ruling s and
    the fraction f (0 to 1) between R's rails lie in the face.  loops: the face's boundary on R, in R's
    (s, t), as loops of 2D curves (the outer loop first, then the holes: a Trim's outer and holes, or a host
    face's pcurves on R)."""
    polygons = loop_polylines(tuple(loops), PER_CURVE)
    span = ruling_span(R, *s_extent(tuple(loops)[0]))
    t0, t1 = R.domain[2:]

    def keep(s, f):
        return inside_trim(polygons, np.stack([s, t0 + np.asarray(f) * (t1 - t0)], axis=1))
    return span, keep


def s_extent(loop) -> tuple:
    """The smallest and largest s of a loop of 2D curves (s, t): each curve sampled, its extreme samples refined
    by golden-section searches between their neighbours, so that the same curves however parametrized (a
    host's pcurves read back from its face) give the same range to round-off."""
    from ruled.core.nearest import golden
    lo, hi = np.inf, -np.inf
    for c in loop:
        a, b = c.domain
        x = np.linspace(a, b, PER_CURVE)
        s = c(x)[:, 0]
        for sign, k in ((1.0, int(np.argmin(s))), (-1.0, int(np.argmax(s)))):
            left, right = x[max(k - 1, 0)], x[min(k + 1, len(x) - 1)]
            _, f = golden(lambda y, sign=sign: sign * c(np.clip(y, a, b))[:, 0], np.array([left]), np.array([right]),
                          60)
            v = min(sign * float(f[0]), float(s[k])) if sign > 0 else max(sign * float(f[0]), float(s[k]))
            lo, hi = (min(lo, v), hi) if sign > 0 else (lo, max(hi, v))
    return float(lo), float(hi)


def along_tool(path, keep):
    """keep (trimmed_lines) as the flank tool's envelope measure asks it: (s, f), f the fraction along the tool
    from its tip (at the second rail where the path says so)."""
    if not path.stats.get("tip_at_t1"):
        return keep

    def from_tip(s, f):
        return keep(s, 1.0 - np.asarray(f))
    return from_tip


def figure(bound: float, measured=None) -> str:
    """A fit's figures in a few words, for a warning that compares two fits."""
    return f"bound {bound:.4g}" + ("" if measured is None else f", measured {measured:.4g}")


def fallback_warning(mode: str, pinned: str, why, trimmed: str) -> Text:
    """The warning of every host when a result trimmed by the face's edges cannot be machined and the path
    follows the fit pinned to the face's corners instead: both fits' figures (see figure) and why."""
    what = "wire" if mode == "xyuv" else "tool"
    return Text(f"the {what} follows the corner-pinned fit ({pinned}), not the fit shown: the trimmed fit's rulings "
                f"cannot be machined ({getattr(why, 'template', why)}); the trimmed fit is {trimmed}")


def swapped(c: Curve) -> Curve:
    """A 2D curve with its coordinates swapped: a pcurve in (u, v) as one in (v, u)."""
    return Curve(c.poles[:, ::-1].copy(), c.knots, c.degree, c.weights)


__all__ = ["along_tool", "fallback_warning", "figure", "inside_trim", "ruling_span", "s_extent", "swapped",
           "trimmed_lines"]
