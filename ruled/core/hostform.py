"""The B-spline form CAD kernels exchange (OCCT's, which FreeCAD's Part module wraps too): distinct
knots with multiplicities, and periodic surfaces stored with their unique poles over one period.
Both host adapters (ruled/occ and FreeCAD's workbench) convert through these plain-array functions,
so the two agree exactly.  No CAD host is imported here.

The engine's containers (ruled.core.nurbs.Surface) keep full knot vectors; a periodic container is
stored unwrapped (the first p poles repeated at the end) with its flag set, or clamped as a kernel's
own non-periodic form of a periodic surface delivers it (then it is evaluated as it is).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np

from ruled.core.nurbs import Curve, Surface


def full_knots(knots, mults) -> np.ndarray:
    return np.repeat(np.asarray(knots, float), np.asarray(mults, int))


def compress(full: np.ndarray):
    """Distinct knots (the exact value of each first occurrence) and their multiplicities."""
    full = np.asarray(full, float)
    _, m = np.unique(np.round(full, 15), return_counts=True)
    vals = []
    i = 0
    for c in m:
        vals.append(full[i])
        i += c
    return np.array(vals), m


def is_unwrapped_periodic(knots: np.ndarray, p: int) -> bool:
    """Clamped containers (read from a kernel) are evaluated as they are."""
    return not (np.all(knots[: p + 1] == knots[0]) and np.all(knots[-p - 1:] == knots[-1]))


def wraps(poles, weights, p, axis) -> bool:
    """Our unwrapped periodic storage repeats the first p poles at the end.  A kernel's own
    non-periodic form of a periodic surface (also unclamped) does not: it is kept as it is."""
    n = poles.shape[axis]
    if p == 0 or n <= p:
        return False
    head, tail = np.take(poles, np.arange(p), axis=axis), np.take(poles, np.arange(n - p, n), axis=axis)
    if weights is not None:
        hw, tw = np.take(weights, np.arange(p), axis=axis), np.take(weights, np.arange(n - p, n), axis=axis)
        if not np.array_equal(hw, tw):
            return False
    return bool(np.array_equal(head, tail))


def to_kernel_periodic(poles, weights, knots, p, axis):
    """Unwrapped periodic storage -> the kernel's periodic form (unique poles, one period of knots)."""
    n = poles.shape[axis] - p  # unique poles
    a, b = knots[p], knots[n + p]
    inner = knots[p: n + p + 1]
    kk, mm = compress(inner)
    mm = mm.copy()
    mm[-1] = mm[0]
    uniq = np.take(poles, np.arange(n), axis=axis)
    w = None if weights is None else np.take(weights, np.arange(n), axis=axis)
    # the kernel's pole 1 is our pole (m0 - 1), m0 the multiplicity of the first knot (checked in tests)
    uniq = np.roll(uniq, -(int(mm[0]) - 1), axis=axis)
    if w is not None:
        w = np.roll(w, -(int(mm[0]) - 1), axis=axis)
    assert abs(kk[0] - a) < 1e-15 * max(1, abs(a)) + 1e-300 and abs(kk[-1] - b) <= 1e-12 * max(1, abs(b))
    return uniq, w, kk, mm


def kernel_form(s: Surface) -> dict:
    """The arrays a kernel builds a B-spline surface from: poles (nu, nv, 3), weights (nu, nv) or None,
    distinct knots and multiplicities in u and v, degrees, periodic flags."""
    poles, weights = s.poles, s.weights
    pu, pv = s.degree_u, s.degree_v
    ku, mu = compress(s.knots_u)
    kv, mv = compress(s.knots_v)
    per_u = bool(s.periodic_u and is_unwrapped_periodic(s.knots_u, pu) and wraps(poles, weights, pu, 0))
    per_v = bool(s.periodic_v and is_unwrapped_periodic(s.knots_v, pv) and wraps(poles, weights, pv, 1))
    if per_u:
        poles, weights, ku, mu = to_kernel_periodic(poles, weights, s.knots_u, pu, axis=0)
    if per_v:
        poles, weights, kv, mv = to_kernel_periodic(poles, weights, s.knots_v, pv, axis=1)
    return {"poles": poles, "weights": weights, "uknots": ku, "umults": mu, "vknots": kv, "vmults": mv,
            "udegree": pu, "vdegree": pv, "uperiodic": per_u, "vperiodic": per_v}


def from_kernel_form(poles, weights, uknots, umults, vknots, vmults, udegree, vdegree, rational: bool,
                     uperiodic: bool = False, vperiodic: bool = False) -> Surface:
    """A container from a kernel's non-periodic form (the caller unrolls periodic surfaces with the
    kernel's own SetNotPeriodic first and passes the flags it had)."""
    return Surface(np.asarray(poles, float), full_knots(uknots, umults), full_knots(vknots, vmults), int(udegree),
                   int(vdegree), np.asarray(weights, float) if rational else None, bool(uperiodic), bool(vperiodic))


def curve_from_kernel_form(poles, weights, knots, mults, degree: int, reversed_: bool = False,
                           onto=None) -> Curve:
    """A (2D or 3D) curve container from a kernel's non-periodic form (distinct knots, multiplicities),
    reversed when the edge runs against its curve in its wire, and, with onto = (a, b), its parameter
    mapped affinely onto [a, b] (an edge's 3D curve onto its pcurve's range)."""
    poles = np.asarray(poles, float)
    w = None if weights is None else np.asarray(weights, float)
    full = full_knots(knots, mults)
    if reversed_:
        poles = poles[::-1].copy()
        w = None if w is None else w[::-1].copy()
        full = (full[0] + full[-1]) - full[::-1]
    if onto is not None:
        k0, k1 = full[degree], full[-degree - 1]
        full = onto[0] + (full - k0) * (onto[1] - onto[0]) / (k1 - k0)
    if w is not None and np.all(w == w[0]):
        w = None
    return Curve(poles, full, int(degree), w)


def bounds_slack(S: Surface, face_bounds) -> float:
    """Upper bound of the distance from the container to the face, where the face's UV bounds
    (u0, u1, v0, v1) lie inside the container's domain by less than the segmentation tolerance (a
    round-off strip): the strip width times the largest |S_u| or |S_v| there."""
    fu0, fu1, fv0, fv1 = face_bounds
    u0, u1, v0, v1 = S.domain
    if S.periodic_u:
        fu0, fu1 = u0, u1
    if S.periodic_v:
        fv0, fv1 = v0, v1
    du = max(0.0, fu0 - u0) + max(0.0, u1 - fu1)
    dv = max(0.0, fv0 - v0) + max(0.0, v1 - fv1)
    if du == 0.0 and dv == 0.0:
        return 0.0
    b = S.derivative_bounds()
    return float(du * b["Su"].max() + dv * b["Sv"].max())


@dataclass(frozen=True)
class Hausdorff:
    """Both hosts' independent measure between two faces: the largest and mean sampled distance, each
    side's largest, the sample count, and the distance of each sample of the first face."""

    max: float
    mean: float
    max_a_to_b: float
    max_b_to_a: float
    samples: int
    a_to_b: tuple = ()
    resolution: Optional[float] = None   # the largest gap between neighbouring samples: the true distance
                                         # is at most max + resolution (None where not worked out)


class PolygonClassifier:
    """Which (u, v) points are inside a face or on its boundary, for the hosts' independent measures.
    The even-odd rule on the face's edges' pcurves as polylines (in the host's own evaluation) decides
    for points clear of them; the host's face classifier ``exact(u, v) -> bool`` decides near them, on
    rows that graze a vertex or cross them an odd number of times, and everywhere when the polylines
    do not bound the face (a band round a periodic surface without a seam edge: checked once, on a
    12 x 12 grid of the bounds, against the host).  polylines: a function giving them (or None), called
    on the first question about more than a few points."""

    def __init__(self, polylines, bounds, exact, periods=(0.0, 0.0)):
        self.exact, self.bounds, self._polylines = exact, bounds, polylines
        self.periods = tuple(float(p or 0.0) for p in periods)
        u0, u1, v0, v1 = bounds
        self.scale = np.array([max(u1 - u0, 1e-300), max(v1 - v0, 1e-300)])
        self._built = False
        self.P = None

    def _build(self) -> None:
        if self._built:
            return
        self._built = True
        polylines = self._polylines()
        if not polylines:
            return
        from scipy.spatial import cKDTree
        P = np.concatenate([r[:-1] for r in polylines])
        Q = np.concatenate([r[1:] for r in polylines])
        self.lo, self.hi = np.minimum(P[:, 1], Q[:, 1]), np.maximum(P[:, 1], Q[:, 1])
        self.vert = np.sort(np.concatenate([P[:, 1], Q[:, 1]]))
        self.tree = cKDTree(np.concatenate(polylines) / self.scale)
        self.seg = float(np.linalg.norm((Q - P) / self.scale, axis=1).max())
        self.P, self.Q = P, Q
        u0, u1, v0, v1 = self.bounds
        us, vs = np.linspace(u0, u1, 12), np.linspace(v0, v1, 12)
        if (self._poly_grid(us, vs) != self._exact_grid(us, vs)).any():
            self.P = None

    def _into(self, x, ax: int):
        """x (a float or an array) moved by whole periods into the face's bounds along ax where it lies outside
        them and the direction is periodic."""
        per = self.periods[ax]
        lo, hi = self.bounds[2 * ax], self.bounds[2 * ax + 1]
        out = (x < lo - 1e-12 * per) | (x > hi + 1e-12 * per)
        return np.where(out, lo + np.mod(x - lo, per), x) if per > 0.0 else x

    def wrap(self, uv: np.ndarray) -> np.ndarray:
        """uv (N, 2) with each coordinate of a periodic direction that lies outside the face's bounds moved by
        whole periods into them: a local search on a periodic surface returns its foot in any period (a band
        round the seam, its bounds [a0, a0 + period), has points inside it at u < a0)."""
        uv = np.array(uv, float).reshape(-1, 2)
        return np.stack([self._into(uv[:, 0], 0), self._into(uv[:, 1], 1)], axis=1)

    def __call__(self, u, v) -> bool:
        if self.periods != (0.0, 0.0):
            u, v = self._into(float(u), 0), self._into(float(v), 1)
        return bool(self.exact(float(u), float(v)))

    def _exact_grid(self, us, vs) -> np.ndarray:
        return np.array([[self(u, v) for v in vs] for u in us], bool).reshape(us.size, vs.size)

    def _grazing(self, v: np.ndarray) -> np.ndarray:
        """Rows v within round-off of a polyline vertex (an edge along the row)."""
        k = np.searchsorted(self.vert, v)
        near = np.full(v.shape, np.inf)
        for i in (k - 1, k):
            ok = (i >= 0) & (i < self.vert.size)
            near[ok] = np.minimum(near[ok], np.abs(self.vert[i[ok]] - v[ok]))
        return near <= 1e-6 * self.scale[1]

    def _near(self, uv: np.ndarray) -> np.ndarray:
        d, _ = self.tree.query(uv / self.scale)
        return d <= 2.0 * self.seg + 1e-12

    def _poly_grid(self, us, vs) -> np.ndarray:
        P, Q = self.P, self.Q
        out = np.zeros((us.size, vs.size), bool)
        graze = self._grazing(vs)
        for j, v in enumerate(vs):
            hit = (self.lo <= v) & (v < self.hi)       # half-open in v: a vertex counts once
            if hit.sum() % 2 or graze[j]:
                out[:, j] = [self(u, v) for u in us]
                continue
            if not hit.any():
                continue
            p, q = P[hit], Q[hit]
            x = np.sort(p[:, 0] + (v - p[:, 1]) * (q[:, 0] - p[:, 0]) / (q[:, 1] - p[:, 1]))
            out[:, j] = np.searchsorted(x, us, side="right") % 2 == 1
        UU, VV = np.meshgrid(us, vs, indexing="ij")
        for k in np.nonzero(self._near(np.stack([UU.ravel(), VV.ravel()], axis=1)))[0]:
            i, j = divmod(int(k), vs.size)
            out[i, j] = self(us[i], vs[j])
        return out

    def grid(self, us: np.ndarray, vs: np.ndarray) -> np.ndarray:
        """(us.size, vs.size) booleans for the grid us x vs (row by row: a row's crossings serve all its
        points, many times faster than ``points`` on a dense grid).  A small grid is asked of the host point by
        point unless the polylines are built already (a measure's many small grids of a creased face's pieces)."""
        if us.size * vs.size > 144:
            self._build()
        if self.P is None:          # (not built, or the polylines do not bound the face)
            return self._exact_grid(us, vs)
        return self._poly_grid(us, vs)

    def points(self, uv: np.ndarray) -> np.ndarray:
        """Booleans for scattered points uv (N, 2)."""
        uv = self.wrap(uv) if self.periods != (0.0, 0.0) else np.asarray(uv, float).reshape(-1, 2)
        if len(uv) > 64:
            self._build()
        if self.P is None or len(uv) <= 64:
            return np.array([self(u, v) for u, v in uv], bool)
        P, Q = self.P, self.Q
        dv = np.where(self.hi > self.lo, Q[:, 1] - P[:, 1], 1.0)
        out = np.zeros(len(uv), bool)
        odd = np.zeros(len(uv), bool)       # a row crossing the polylines an odd number of times
        for i0 in range(0, len(uv), 256):
            u, v = uv[i0:i0 + 256, :1], uv[i0:i0 + 256, 1:]
            hit = (self.lo <= v) & (v < self.hi)
            x = P[:, 0] + (v - P[:, 1]) * (Q[:, 0] - P[:, 0]) / dv
            out[i0:i0 + 256] = (hit & (x > u)).sum(axis=1) % 2 == 1
            odd[i0:i0 + 256] = hit.sum(axis=1) % 2 == 1
        for k in np.nonzero(odd | self._near(uv) | self._grazing(uv[:, 1]))[0]:
            out[k] = self(*uv[k])
        return out


def clipped_bounds(face_range, surface_range, periodic: tuple) -> tuple:
    """A face's (u0, u1, v0, v1) clipped to its surface's own range where the surface is not periodic (faces may
    overhang it by round-off): both hosts' measures sample the same rectangle."""
    u0, u1, v0, v1 = face_range
    a0, a1, b0, b1 = surface_range
    if not periodic[0]:
        u0, u1 = max(u0, a0), min(u1, a1)
    if not periodic[1]:
        v0, v1 = max(v0, b0), min(v1, b1)
    return u0, u1, v0, v1


def grid_size(n: int, frac: float) -> int:
    """The side of a (u, v) grid of a face's bounds that puts about n x n points inside a face covering
    the share frac of its bounds (n when it covers nearly all of them; at most 8 n)."""
    return n if frac > 0.97 else int(min(8 * n, np.ceil(n / np.sqrt(max(frac, 1.0 / (64 * n * n))))))


def screened(proj, X: np.ndarray, cap: int = 400, progress=None) -> np.ndarray:
    """Distances from the points X to what proj measures (an object with a vectorized ``upper`` and an
    exact, slower ``distance``).  Every value is the distance to an actual point of the face, so at
    least the true one.  The exact search runs on the points in decreasing order of their upper value
    while that exceeds the largest exact distance found so far: the maximum is then the exact
    search's own maximum over all points, found with a few hundred exact projections instead of one
    per point (at most ``cap``; beyond, the upper values stand, which can only raise the maximum)."""
    X = np.asarray(X, float).reshape(-1, 3)
    d = proj.upper(X)
    if progress is not None:      # (the exact searches' share of cap, at most)
        progress(0.0)
    top = 0.0
    order = np.argsort(-d, kind="stable")
    for n, i in enumerate(order[:cap]):
        if d[i] <= top:
            break
        d[i] = min(d[i], proj.distance(X[i]))
        top = max(top, d[i])
        if progress is not None and n % 16 == 0:
            progress(n / cap)
    return d
