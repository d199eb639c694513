"""Virtual subdivision (Wang & Elber §4) and strips of a face.

A strip is the part of the (oriented) surface S between two domain curves that run from the u = u0
side to the u = u1 side as graphs v = lo(u) < v = hi(u); the face itself is the strip between
v = v0 and v = v1.  Its Coons map (the boundaries u = u0 and u = u1 are straight, and the curves are
parametrized by u, so the bilinearly blended Coons patch reduces to)

    Omega(s, t) = (u0 + s (u1 - u0), lo(u) + t (hi(u) - lo(u))),   s, t in [0, 1],

takes the unit square onto the strip.  The side surface S o Omega is sampled point by point, as the
paper does, and interpolated by a bicubic B-spline whose deviation from S o Omega is measured at the
midpoints of every span and refined until it is below a tolerance; the ruled fit of a strip is the fit
of that surface, and its bound adds the deviation.  The split faces themselves are built on S (the
occ layer), bounded by the images of the same domain curves.

Domain curves are 2D B-splines D(x) = (x, v(x)) over [u0, u1] (their first coordinate is the
parameter itself), so that v = lo(u) is D(u)[1] and the curves can be mapped onto S exactly by the
curves-on-surfaces module.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np

from ruled.core.basis import bspline_basis_matrix
from ruled.core.nurbs import Curve, Surface
from ruled.fit.face.sampled import DEGREE, SideSurface, _clamped, _greville, side_surface  # noqa: F401 (re-exported)

# split edges follow the smooth split curves within this fraction of the surface's size
EDGE_TOL = 2e-5


def graph_curve(u: np.ndarray, v, spans: Optional[int] = None) -> Curve:
    """A cubic domain curve (x, v(x)) over [u[0], u[-1]] with uniform spans: for a function v, its
    interpolant at the Greville abscissae (len(u) - 3 spans unless given); for values v at the
    increasing u, their least-squares fit with the given number of spans.  Its first coordinate
    reproduces the parameter exactly (the poles sit at the Greville abscissae)."""
    u = np.asarray(u, float)
    spans = max(1, u.size - DEGREE) if spans is None else max(1, int(spans))
    knots = _clamped(np.linspace(u[0], u[-1], spans + 1), DEGREE)
    g = _greville(knots, DEGREE)
    if callable(v):
        cv = np.linalg.solve(bspline_basis_matrix(knots, DEGREE, g), v(g))
    else:
        cv = np.linalg.lstsq(bspline_basis_matrix(knots, DEGREE, u), np.asarray(v, float), rcond=None)[0]
    return Curve(np.stack([g, cv], axis=1), knots, DEGREE)


def iso_curve(u0: float, u1: float, v: float) -> Curve:
    """The straight domain curve v = const (degree 1): its image on S is the exact iso-curve."""
    return Curve(np.array([[u0, v], [u1, v]]), np.array([u0, u0, u1, u1]), 1)


def input_curve(c: Curve, transposed: bool) -> Curve:
    """A domain curve of the oriented surface in the input surface's (u, v) (exchanged when transposed)."""
    return Curve(c.poles[:, ::-1].copy(), c.knots, c.degree, c.weights) if transposed else c


def curve_v(c: Curve, u: np.ndarray) -> np.ndarray:
    return c(np.clip(u, *c.domain))[:, 1]


@dataclass
class Strip:
    """The part of S between the domain curves lo and hi (None: the surface's own v0 / v1 side)."""

    lo: Optional[Curve] = None
    hi: Optional[Curve] = None

    def bounds(self, S: Surface, u: np.ndarray):
        _, _, v0, v1 = S.domain
        lo = np.full(u.shape, v0) if self.lo is None else curve_v(self.lo, u)
        hi = np.full(u.shape, v1) if self.hi is None else curve_v(self.hi, u)
        return lo, hi

    def omega(self, S: Surface, s, t):
        """The Coons map of the strip: (s, t) in the unit square to (u, v) on S."""
        u0, u1, _, _ = S.domain
        s, t = np.broadcast_arrays(np.asarray(s, float), np.asarray(t, float))
        u = u0 + s * (u1 - u0)
        lo, hi = self.bounds(S, u.ravel())
        return u, (lo + t.ravel() * (hi - lo)).reshape(u.shape)

    name = "strip's surface"
    refine_hint = "the split curve is too wiggly: use fewer interior rows («interior»)"

    @property
    def whole(self) -> bool:
        return self.lo is None and self.hi is None

    def offset(self, s, t):
        """None: a strip's side surface is S o Omega itself."""
        return None

    def breaks(self, S: Surface):
        """Initial break points in s and t for sampling S o Omega: the surface's and the curves' knots."""
        u0, u1, _, _ = S.domain
        bs = {0.0, 1.0}
        for x in S.interior_knots("u"):
            bs.add(float((x - u0) / (u1 - u0)))
        for c in (self.lo, self.hi):
            if c is not None:
                kk = np.unique(c.knots)
                bs.update(float((x - u0) / (u1 - u0)) for x in kk[(kk > u0) & (kk < u1)])
        out = np.array(sorted(bs))
        if out.size < 9:
            out = np.unique(np.concatenate([out, np.linspace(0.0, 1.0, 9)]))
        return out, np.linspace(0.0, 1.0, 5)

    def cut(self, S: Surface, c: Curve) -> tuple["Strip", "Strip"]:
        return Strip(self.lo, c), Strip(c, self.hi)

    def curve_at(self, S: Surface, t_of_s, samples: int = 64) -> Curve:
        """The domain curve v = lo(u) + t(s) (hi(u) - lo(u)) for a function t of s (or a constant), as a
        graph curve; for a constant t on the whole face, the exact iso-line."""
        u0, u1, v0, v1 = S.domain
        if np.isscalar(t_of_s) and self.whole:
            return iso_curve(u0, u1, v0 + float(t_of_s) * (v1 - v0))  # type: ignore[arg-type]

        def v_of(u):
            s = (u - u0) / (u1 - u0)
            t = np.full(s.shape, float(t_of_s)) if np.isscalar(t_of_s) else t_of_s(s)
            return self.omega(S, s, t)[1]
        return graph_curve(np.linspace(u0, u1, samples), v_of)


