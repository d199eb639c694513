"""A map of the unit square into a surface's domain (a strip of a split, ruled.split.strips.Strip; the Coons
map of a face, ruled.fit.face.coons.CoonsMap) sampled point by point into a bicubic B-spline, refined span by span
until its deviation from S o Omega, measured at the spans' midpoints, is below a tolerance: the surface a face
or a strip is fitted on, its deviation added to the bound (Wang & Elber's virtual subdivision, §4)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from ruled.core.basis import bspline_basis_matrix
from ruled.core.errors import BadInputError
from ruled.core.nurbs import Surface

DEGREE = 3


def _clamped(breaks: np.ndarray, p: int) -> np.ndarray:
    return np.concatenate([[breaks[0]] * p, breaks, [breaks[-1]] * p])


def _greville(knots: np.ndarray, p: int) -> np.ndarray:
    n = knots.size - p - 1
    return np.array([knots[i + 1:i + p + 1].mean() for i in range(n)])


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


def _solve_grid(S: Surface, strip, ks: np.ndarray, kt: np.ndarray) -> Surface:
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
    the Coons map of a trimmed face (ruled.fit.face.coons.CoonsMap).  When the spans run out, a deviation up
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
            # accepted at three points a span: the deviation taken again at DENSE points a span, kept as it is
            # (a kink of the map between the sites can hold twice what they show: a band round a period,
            # 5.26e-5 at three points, 9.7e-5 at eight; no refinement follows it, which would raise the patch's
            # derivative bounds, the certificate's remainders, by more than the deviation gains)
            return SideSurface(side, max(d, dense_deviation(S, strip, side, bs, bt)), (bs.size - 1, bt.size - 1))
        if not refine:
            bad_s[:] = True
            bad_t[:] = True
        if max(bs.size - 1 + bad_s.sum(), bt.size - 1 + bad_t.sum()) > max_spans:
            d = max(deviation() if d is None else d, dense_deviation(S, strip, side, bs, bt))
            if d <= max(tol, accept or 0.0):
                return SideSurface(side, d, (bs.size - 1, bt.size - 1))
            raise BadInputError(f"the {strip.name} could not be interpolated within {tol:.3g} with "
                                f"{max_spans} spans (deviation {d:.3g}); {strip.refine_hint}")
        if bad_s.any():
            bs = np.unique(np.concatenate([bs, 0.5 * (bs[:-1] + bs[1:])[bad_s]]))
        if bad_t.any():
            bt = np.unique(np.concatenate([bt, 0.5 * (bt[:-1] + bt[1:])[bad_t]]))


DENSE = 8       # the deviation taken again at this many points across each span of the sampled surface


def span_grid(breaks: np.ndarray, per_span: int) -> np.ndarray:
    """per_span cells across each span between the breaks (spans of zero length left out)."""
    br = np.unique(breaks)
    return np.concatenate([np.linspace(a, b, per_span + 1)[:-1] for a, b in zip(br[:-1], br[1:])] + [br[-1:]])


def dense_deviation(S: Surface, strip, P: Surface, bs: np.ndarray, bt: np.ndarray, per_span: int = DENSE) -> float:
    """The largest distance between the sampled surface P and its target S o Omega (+ the map's offset) on a
    grid of per_span points across each of P's spans (breaks bs, bt), its sides included: a measure, denser
    than the sampling's own three points a span, not a proof (a proof's remainder, from second differences,
    counts the patch's slip along the surface at a kink of the map, and made exact faces' bounds 10-40 times
    their measure)."""
    ss, tt = np.meshgrid(span_grid(bs, per_span), span_grid(bt, per_span), indexing="ij")
    return float(np.linalg.norm(_target(S, strip, ss, tt) - P(ss.ravel(), tt.ravel()), axis=1).max())


__all__ = ["DEGREE", "SideSurface", "side_surface", "dense_deviation", "span_grid"]
