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

from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from ruled.core.basis import bspline_basis_matrix
from ruled.core.errors import BadInputError
from ruled.core.nurbs import Curve, Surface

DEGREE = 3
# split edges follow the smooth split curves within this fraction of the surface's size
EDGE_TOL = 2e-5


def _clamped(breaks: np.ndarray, p: int) -> np.ndarray:
    return np.concatenate([[breaks[0]] * p, breaks, [breaks[-1]] * p])


def _greville(knots: np.ndarray, p: int) -> np.ndarray:
    n = knots.size - p - 1
    return np.array([knots[i + 1:i + p + 1].mean() for i in range(n)])


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
        bs = np.array(sorted(bs))
        if bs.size < 9:
            bs = np.unique(np.concatenate([bs, np.linspace(0.0, 1.0, 9)]))
        return bs, np.linspace(0.0, 1.0, 5)

    def cut(self, S: Surface, c: Curve) -> tuple["Strip", "Strip"]:
        return Strip(self.lo, c), Strip(c, self.hi)

    def curve_at(self, S: Surface, t_of_s, samples: int = 64) -> Curve:
        """The domain curve v = lo(u) + t(s) (hi(u) - lo(u)) for a function t of s (or a constant), as a
        graph curve; for a constant t on the whole face, the exact iso-line."""
        u0, u1, v0, v1 = S.domain
        if np.isscalar(t_of_s) and self.whole:
            return iso_curve(u0, u1, v0 + float(t_of_s) * (v1 - v0))

        def v_of(u):
            s = (u - u0) / (u1 - u0)
            t = np.full(s.shape, float(t_of_s)) if np.isscalar(t_of_s) else t_of_s(s)
            return self.omega(S, s, t)[1]
        return graph_curve(np.linspace(u0, u1, samples), v_of)


@dataclass
class SideSurface:
    """S o Omega of a strip as a bicubic B-spline, with its measured deviation from S o Omega."""

    surface: Surface
    deviation: float
    spans: tuple = field(default=(0, 0))


def _collocate(knots: np.ndarray, sites: np.ndarray, F: np.ndarray) -> np.ndarray:
    """The coefficients of the spline interpolating F at the sites (a sparse LU of the banded matrix)."""
    from scipy.sparse import csc_matrix
    from scipy.sparse.linalg import splu
    try:
        lu = splu(csc_matrix(bspline_basis_matrix(knots, DEGREE, sites)))
    except RuntimeError:        # SuperLU: "Factor is exactly singular"
        raise BadInputError("the face's own parametrization could not be interpolated (its collocation is "
                            "singular: an edge almost a point, or sides that meet almost tangentially); pick "
                            "other rails («rails»)") from None
    return lu.solve(np.ascontiguousarray(F))


def _target(S: Surface, strip, ss: np.ndarray, tt: np.ndarray) -> np.ndarray:
    """The points (N, 3) the side surface interpolates: S o Omega, plus the map's own offset (the
    blended gaps between a face's edges and its surface) when it has one."""
    u, v = strip.omega(S, ss, tt)
    P = S(u.ravel(), v.ravel())
    off = strip.offset(ss.ravel(), tt.ravel())
    return P if off is None else P + off


def _solve_grid(S: Surface, strip: Strip, ks: np.ndarray, kt: np.ndarray) -> Surface:
    gs, gt = _greville(ks, DEGREE), _greville(kt, DEGREE)
    ss, tt = np.meshgrid(gs, gt, indexing="ij")
    F = _target(S, strip, ss, tt).reshape(gs.size, gt.size, 3)
    X = _collocate(ks, gs, F.reshape(gs.size, -1)).reshape(gs.size, gt.size, 3)
    X = _collocate(kt, gt, np.transpose(X, (1, 0, 2)).reshape(gt.size, -1)).reshape(gt.size, gs.size, 3)
    return Surface(np.transpose(X, (1, 0, 2)), ks, kt, DEGREE, DEGREE)


def side_surface(S: Surface, strip, tol: Optional[float] = None, max_spans: int = 1024,
                 accept: Optional[float] = None) -> SideSurface:
    """The strip's surface S o Omega over the unit square, interpolated by a bicubic B-spline and
    refined (span by span, in s and t) until its deviation at the span midpoints is below tol
    (default 1e-6 of the surface's size).  The whole face is S itself (deviation 0).

    strip: a :class:`Strip`, or any map of the unit square into S's domain with the same interface
    (``omega(S, s, t)``, ``offset(s, t)``, ``whole``, ``breaks(S)``, ``name``, ``refine_hint``), such as
    the Coons map of a trimmed face (ruled.fit.coons.CoonsMap).  When the spans run out, a deviation up
    to ``accept`` (default tol) is kept (the caller adds it to its bound), a larger one refused."""
    if strip.whole:
        return SideSurface(S, 0.0)
    tol = 1e-6 * S.diagonal() if tol is None else tol
    bs, bt = strip.breaks(S)

    def mids(br):
        return np.concatenate([a + (b - a) * np.array([0.25, 0.5, 0.75]) for a, b in zip(br[:-1], br[1:])])

    def dev(side, ss, tt):
        return np.linalg.norm(_target(S, strip, ss, tt) - side(ss.ravel(), tt.ravel()), axis=1).reshape(ss.shape)

    while True:
        ks, kt = _clamped(bs, DEGREE), _clamped(bt, DEGREE)
        side = _solve_grid(S, strip, ks, kt)
        fs, ft = mids(bs), mids(bt)
        # each direction's error where the other is interpolated (at its sites), then both between sites
        es = dev(side, *np.meshgrid(fs, _greville(kt, DEGREE), indexing="ij")).max(axis=1)
        et = dev(side, *np.meshgrid(_greville(ks, DEGREE), ft, indexing="ij")).max(axis=0)
        bad_s = es.reshape(-1, 3).max(axis=1) > 0.5 * tol
        bad_t = et.reshape(-1, 3).max(axis=1) > 0.5 * tol
        refine = bad_s.any() or bad_t.any()

        def deviation():   # both directions between the sites: needed only to accept (or to give up)
            both = float(dev(side, *np.meshgrid(fs, ft, indexing="ij")).max())
            return max(both, float(es.max()), float(et.max()))
        d = None if refine else deviation()
        if not refine and d <= tol:
            return SideSurface(side, d, (bs.size - 1, bt.size - 1))
        if not refine:
            bad_s[:] = True
            bad_t[:] = True
        if max(bs.size - 1 + bad_s.sum(), bt.size - 1 + bad_t.sum()) > max_spans:
            d = deviation() if d is None else d
            if d <= max(tol, accept or 0.0):
                return SideSurface(side, d, (bs.size - 1, bt.size - 1))
            raise BadInputError(f"the {strip.name} could not be interpolated within {tol:.3g} with "
                                f"{max_spans} spans (deviation {d:.3g}); {strip.refine_hint}")
        if bad_s.any():
            bs = np.unique(np.concatenate([bs, 0.5 * (bs[:-1] + bs[1:])[bad_s]]))
        if bad_t.any():
            bt = np.unique(np.concatenate([bt, 0.5 * (bt[:-1] + bt[1:])[bad_t]]))
