"""The face's own parametrization: the bilinearly blended Coons map of a region's four sides
(ruled.core.region), each side parametrized by the arc length of its image on the surface,

    Omega(s, t) = (1-t) c0(s) + t c2(1-s) + (1-s) c3(1-t) + s c1(t)
                  - [(1-s)(1-t) P00 + s(1-t) P10 + s t P11 + (1-s) t P01],

with c0 .. c3 the sides in loop order.  The Jacobian's sign is checked on a grid: a map that folds is
refused.  The face is then the four-sided patch S o Omega (ruled.split.strips.side_surface samples it into a
bicubic B-spline), its sides moved onto the edges' own 3D curves by the blended gaps (offset).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import Optional

import numpy as np

from ruled.core.errors import DegenerateFaceError
from ruled.core.nurbs import Surface
from ruled.core.region import Region, Sides, piece_table


class SideCurve:
    """One side as a map tau in [0, 1] -> (u, v): its pieces in turn, each over a share of [0, 1]
    proportional to the 3D length of its image (to its (u, v) length where the side's image has none;
    a constant for a point side), linear in the piece's own parameter so that the map is as smooth as
    the pcurves."""

    def __init__(self, region: Region, pieces: tuple, point: Optional[np.ndarray] = None):
        self.region = region
        self.pieces = pieces
        self.point = point
        self.length = 0.0
        if not pieces:
            self.cum = np.array([0.0, 1.0])
            return
        tabs = [piece_table(region, p, 33) for p in pieces]
        lens = np.array([tb[2][-1] for tb in tabs])
        self.length = float(lens.sum())
        if lens.sum() <= 1e-12 * max(region.surface.diagonal(), 1e-300):
            lens = np.array([np.linalg.norm(np.diff(uv, axis=0), axis=1).sum() for _, uv, _ in tabs])
        if not lens.sum() > 0:
            lens = np.ones(len(tabs))
        self.cum = np.concatenate([[0.0], np.cumsum(lens)]) / lens.sum()

    def breaks(self) -> np.ndarray:
        """The side's parameters where its pieces join and where their pcurves have knots (at most 16
        per piece: where the composition with the surface is least smooth)."""
        out = [self.cum[1:-1]]
        for i, (k, a, b) in enumerate(self.pieces):
            kk = np.unique(self.region.loop[k].knots)
            kk = kk[(kk > min(a, b)) & (kk < max(a, b))]
            if kk.size > 16:
                kk = kk[np.linspace(0, kk.size - 1, 16).astype(int)]
            out.append(self.cum[i] + (self.cum[i + 1] - self.cum[i]) * (kk - a) / (b - a))
        return np.concatenate(out)

    def _map(self, tau, f, dim: int) -> np.ndarray:
        tau = np.clip(np.asarray(tau, float).ravel(), 0.0, 1.0)
        out = np.empty((tau.size, dim))
        idx = np.clip(np.searchsorted(self.cum, tau, side="right") - 1, 0, len(self.pieces) - 1)
        for i, (k, a, b) in enumerate(self.pieces):
            m = idx == i
            if m.any():
                lo, hi = self.cum[i], self.cum[i + 1]
                out[m] = f(k, a + (b - a) * (tau[m] - lo) / max(hi - lo, 1e-300))
        return out

    def __call__(self, tau) -> np.ndarray:
        if not self.pieces:
            return np.repeat(self.point[None, :], np.asarray(tau, float).size, axis=0)
        return self._map(tau, self.region.uv, 2)

    def gap(self, tau) -> np.ndarray:
        """(N, 3) the side's 3D edge curves minus the surface at the side's points."""
        if not self.pieces or not self.region.edges3d:
            return np.zeros((np.asarray(tau, float).size, 3))
        return self._map(tau, self.region.gap, 3)


@dataclass
class CoonsMap:
    """The Coons map of a region's four sides (see the module doc): omega(S, s, t) -> (u, v) arrays of
    the shape of s and t; the interface of ruled.split.strips.Strip, so side_surface samples it."""

    region: Region
    sides: Sides
    curves: list = field(default_factory=list)
    flip: bool = False
    name: str = "face's own parametrization"

    @property
    def refine_hint(self) -> str:
        """Why the face's own parametrization may not follow the surface, in the user's terms."""
        S = self.region.surface
        cu, cv = S.creases(0), S.creases(1)
        if cu.size or cv.size:
            where = ", ".join([f"u = {x:.6g}" for x in cu[:3]] + [f"v = {x:.6g}" for x in cv[:3]])
            more = " ..." if cu.size > 3 or cv.size > 3 else ""
            return (f"the surface has creases (knots where it is only C0: {where}{more}) that cross the face's "
                    f"curved sides, and a smooth parametrization of the face cannot follow them; split the "
                    f"face along its creases, or pick rails that run along them («rails»)")
        return "the face's boundary is too wiggly to parametrize; pick other rails («rails»)"

    def __post_init__(self):
        pcs = self.sides.pieces
        self.curves = []
        for i in range(4):
            pt = None
            if not pcs[i]:
                # a point side: the corner where its neighbours meet
                prev = pcs[(i - 1) % 4][-1]
                pt = self.region.uv(prev[0], np.array([prev[2]]))[0]
            self.curves.append(SideCurve(self.region, pcs[i], pt))

    @property
    def whole(self) -> bool:
        return False

    def _corner_values(self, f) -> tuple:
        """f at the four corners (00, 10, 11, 01), each the sides' own ends averaged with their
        neighbours' (the pcurves meet within tolerance)."""
        c = self.curves
        return tuple(0.5 * (f(c[i], 0.0) + f(c[(i - 1) % 4], 1.0)) for i in range(4))

    @cached_property
    def _corners(self) -> tuple:
        return self._corner_values(lambda c, x: c(x)[0])

    @cached_property
    def _gap_corners(self) -> tuple:
        """The gaps at the corners: the sides' ends averaged; where a corner's two edges' ends do not meet (a
        file's edges meet within their tolerance), the one of the three (either end, their mean) whose patch
        boundary misses the face's edges least (the Coons blend then ramps the two sides to the other end: a
        straight side runs on along itself to an end that lies on its extension, as Part Ruled's does)."""
        c = self.curves
        chosen = list(self._corner_values(lambda cc, x: cc.gap(x)[0]))
        tol = 1e-6 * max(self.region.surface.diagonal(), 1e-300)     # (below: within what no machine holds)
        for i in range(4):
            a, b = c[i].gap(0.0)[0], c[(i - 1) % 4].gap(1.0)[0]
            if not np.linalg.norm(a - b) > tol:
                continue
            best = None
            for g in (chosen[i], a, b):
                trial = tuple(chosen[:i]) + (g,) + tuple(chosen[i + 1:])
                miss = self.boundary_miss(257, trial)
                if best is None or miss < best[0]:
                    best = (miss, g)
            chosen[i] = best[1]
        return tuple(chosen)

    def _raw(self, s, t):
        c0, c1, c2, c3 = self.curves
        P00, P10, P11, P01 = self._corners
        s, t = s[:, None], t[:, None]
        out = ((1 - t) * _on(c0, s[:, 0]) + t * _on(c2, 1 - s[:, 0]) + (1 - s) * _on(c3, 1 - t[:, 0])
               + s * _on(c1, t[:, 0])
               - ((1 - s) * (1 - t) * P00 + s * (1 - t) * P10 + s * t * P11 + (1 - s) * t * P01))
        return out

    def offset(self, s, t, corners: Optional[tuple] = None) -> Optional[np.ndarray]:
        """(N, 3) the Coons blend of the gaps between the sides' 3D edges and the surface, so that the
        patch's boundary is the face's edges themselves (None when no 3D edges are known); corners: the gaps
        at the corners (_gap_corners when not given)."""
        if not self.region.edges3d:
            return None
        s = np.asarray(s, float).ravel()
        t = np.asarray(t, float).ravel()
        if self.flip:
            s = 1.0 - s
        c0, c1, c2, c3 = self.curves
        G00, G10, G11, G01 = self._gap_corners if corners is None else corners
        s, t = s[:, None], t[:, None]
        return ((1 - t) * _on(c0.gap, s[:, 0]) + t * _on(c2.gap, 1 - s[:, 0]) + (1 - s) * _on(c3.gap, 1 - t[:, 0])
                + s * _on(c1.gap, t[:, 0]) - ((1 - s) * (1 - t) * G00 + s * (1 - t) * G10 + s * t * G11
                                              + (1 - s) * t * G01))

    def omega(self, S: Surface, s, t):
        s, t = np.broadcast_arrays(np.asarray(s, float), np.asarray(t, float))
        shape = s.shape
        ss = s.ravel()
        if self.flip:
            ss = 1.0 - ss
        uv = self._raw(ss, t.ravel())
        uv = self.region.inside(uv)
        return uv[:, 0].reshape(shape), uv[:, 1].reshape(shape)

    def breaks(self, S: Surface):
        """Initial break points in s and t for sampling S o Omega: the sides' piece joints and the
        surface's knot lines crossing the middle of the patch, plus uniform ones."""
        c0, c1, c2, c3 = self.curves
        bs = np.concatenate([[0.0, 1.0], c0.breaks(), 1.0 - c2.breaks(), np.linspace(0, 1, 9),
                             self._knot_crossings(c0), 1.0 - self._knot_crossings(c2)])
        bt = np.concatenate([[0.0, 1.0], c1.breaks(), 1.0 - c3.breaks(), np.linspace(0, 1, 5),
                             self._knot_crossings(c1), 1.0 - self._knot_crossings(c3)])
        if self.flip:
            bs = 1.0 - bs
        return _merge(bs), _merge(bt)

    def _knot_crossings(self, c: "SideCurve", n: int = 1025, most: int = 16) -> np.ndarray:
        """The side's parameters where it crosses the surface's interior knot lines (where S o Omega is
        least smooth; where the map's lines follow the side, they are the patch's own knot lines)."""
        S = self.region.surface
        tau = np.linspace(0.0, 1.0, n)
        uv = self.region.inside(c(tau))
        out = []
        for ax, d in ((0, "u"), (1, "v")):
            for k in S.interior_knots(d):
                f = uv[:, ax] - k
                i = np.nonzero(np.sign(f[:-1]) * np.sign(f[1:]) < 0)[0]
                out.extend(tau[i] + (tau[i + 1] - tau[i]) * f[i] / (f[i] - f[i + 1]))
        found = np.array(sorted(out))
        if found.size > most:
            found = found[np.linspace(0, found.size - 1, most).astype(int)]
        return found

    def boundary_miss(self, n: int = 2001, corners: Optional[tuple] = None) -> float:
        """How far the patch's boundary, S o Omega moved by the offset (its corners' gaps given, or chosen),
        lies from the face's outer edges' 3D curves, both ways (dense polylines of each, every point to the
        other's segments): the sides follow the edges within this (the gaps are tabulated or fitted, and at
        a corner where the edges' ends do not meet one side runs to the other's end)."""
        from scipy.spatial import cKDTree

        from ruled.core.nearest import to_polyline
        region = self.region
        curves = [c for c, bad in zip(region.edges3d, region.degenerate) if c is not None and not bad]
        if not curves:
            return 0.0
        x = np.linspace(0.0, 1.0, n)
        one, zero = np.ones(n), np.zeros(n)
        S = region.surface
        B = []
        for s, t in ((x, zero), (one, x), (1.0 - x, one), (zero, 1.0 - x)):
            u, v = self.omega(S, s, t)
            B.append(S(u, v) + self.offset(s, t, corners))
        E = [c(np.linspace(c.domain[0], c.domain[1], n)) for c in curves]
        # the sides in turn are one closed polyline (each ends where the next starts); the edges are kept apart
        # (a file's edges need not meet: no segment may bridge them)
        loop = np.concatenate(B)
        tl = cKDTree(loop)
        out = max(float(np.linalg.norm(to_polyline(X, loop, tl) - X, axis=1).max()) for X in E)
        near = np.min([np.linalg.norm(to_polyline(loop, X, cKDTree(X)) - loop, axis=1) for X in E], axis=0)
        return max(out, float(near.max()))

    def jacobian_signs(self, n: int = 48) -> np.ndarray:
        """det(d Omega / d(s, t)) at the centres of an n x n grid (scaled by the domain's size)."""
        x = (np.arange(n) + 0.5) / n
        sg, tg = np.meshgrid(x, x, indexing="ij")
        s, t = sg.ravel(), tg.ravel()
        h = 0.25 / n
        u0, u1, v0, v1 = self.region.surface.domain
        sc = np.array([max(u1 - u0, 1e-300), max(v1 - v0, 1e-300)])
        ds = (self._raw(s + h, t) - self._raw(s - h, t)) / sc
        dt = (self._raw(s, t + h) - self._raw(s, t - h)) / sc
        return (ds[:, 0] * dt[:, 1] - ds[:, 1] * dt[:, 0]).reshape(n, n)


def _on(f, x: np.ndarray) -> np.ndarray:
    """f at x, evaluated once per distinct value (the map is sampled on grids: a side's parameter takes
    one value per row or column)."""
    u, inv = np.unique(x, return_inverse=True)
    if u.size * 2 > x.size:
        return f(x)
    return f(u)[inv.ravel()]


def _merge(b: np.ndarray) -> np.ndarray:
    b = np.unique(np.clip(b, 0.0, 1.0))
    keep = np.concatenate([[True], np.diff(b) > 1e-3])
    b = b[keep]
    b[-1] = 1.0
    return b


def coons_map(region: Region, sides: Sides) -> CoonsMap:
    """The Coons map of the sides, oriented so that the patch's normal is the surface's (s runs so
    that det > 0); refused with a one-line reason when it folds."""
    m = CoonsMap(region, sides)
    J = m.jacobian_signs()
    # a few cells of the other sign with a vanishing Jacobian at a sharp corner are round-off, not a fold
    small = 1e-2 * float(np.median(np.abs(J)))
    pos, neg = int((J > small).sum()), int((J < -small).sum())
    if pos and neg:
        bad = np.argwhere(J < -small if pos >= neg else J > small)[0]
        x = (bad + 0.5) / J.shape[0]
        uv = m._raw(np.array([x[0]]), np.array([x[1]]))[0]
        edges = "; ".join(f"side {i}: edges {','.join(map(str, sides.edges(i))) or 'a point'}" for i in range(4))
        what = ("pick two other opposite edges as rails («rails=A,B», see «edges_listing»)"
                if region.size > 4 else "cut the face into simpler four-sided faces in your CAD system")
        raise DegenerateFaceError(f"the face's four sides ({edges}) do not bound a region that a Coons map "
                                  f"parametrizes without folding (it folds near (u, v) = ({uv[0]:.4g}, {uv[1]:.4g})); "
                                  f"{what}")
    if pos == 0 and neg == 0:
        raise DegenerateFaceError("the face's boundary encloses no area in its surface's (u, v); repair the face")
    m.flip = neg > pos
    return m


__all__ = ["SideCurve", "CoonsMap", "coons_map"]
