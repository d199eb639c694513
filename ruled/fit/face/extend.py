"""The face over a longer span: its two rails run past the face, and the result is trimmed by its edges.

The rails are two opposite sides of the face (ruled.core.region.Sides: sides 0 and 2), each extended past
both of its ends along its end tangent in the surface's (u, v) (the surface itself past the face, and its
natural extension, the polynomial of its end span, where its domain ends).  The map of the unit square

    Omega(s, t) = (1 - t) A(s) + t B(s),     A = side 0 extended, B = side 2 reversed and extended,

covers the face and more: the end sides 1 and 3 lie inside it, so the rulings a fit chooses may cross them.
The face is then a region of the patch S o Omega, given by its boundary in the patch's (s, t)
(:class:`FaceMask`): a certificate counts only the cells of its grid that meet the face, and the result is
the ruled surface trimmed by the face's edges mapped onto it (ruled.fit.face.trim).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Optional

import numpy as np

from ruled.core.errors import DegenerateFaceError
from ruled.core.nurbs import Surface
from ruled.core.region import Region, Sides
from ruled.fit.face.coons import SideCurve, _merge, _on

# the rails run past each end by this many times the length (in (u, v)) of the end side there; tried in
# turn, the first that covers the face without folding the map is kept
REACH = (1.5, 1.0, 0.6, 3.0)
FD = 1e-4          # the step of a side's end tangent (a fraction of its parameter)
PER_EDGE = 257     # samples of each loop edge for the face's boundary in the patch
BAND = 1e-3        # the face's loop may leave the band between the rails by this much of it (round-off, clipping)
RASTER = (1025, 257)  # the face's raster in the patch's (s, t), for the rulings' costs over the face
# ... grown by this fraction of the patch each way: a ruling that crosses an end edge is measured a little
# past it, where the face's own surface goes on, so that its pairing is held by more than the few samples
# it has over the face (a ruling near a corner could otherwise turn freely)
GROW = 0.02


class Rail:
    """A side of the region as a map of [0, 1] into (u, v), extended past both ends along its end
    tangents: the side itself over [a, b], straight lines over [0, a] and [b, 1]."""

    def __init__(self, side: SideCurve, before: float, after: float):
        self.side = side
        f = self._side
        h = np.array([0.0, FD, 2 * FD])
        f0, f1 = f(h), f(1.0 - h)
        # second-order one-sided differences: the end tangents
        d0 = (-3 * f0[0] + 4 * f0[1] - f0[2]) / (2 * FD)
        d1 = (3 * f1[0] - 4 * f1[1] + f1[2]) / (2 * FD)
        # extension lengths in (u, v) turned into the side's own parameter (its end speeds)
        e0 = before / max(float(np.linalg.norm(d0)), 1e-300)
        e1 = after / max(float(np.linalg.norm(d1)), 1e-300)
        total = 1.0 + e0 + e1
        self.a, self.b = e0 / total, (1.0 + e0) / total
        self.d0, self.d1 = d0, d1
        self.p0, self.p1 = f0[0], f1[0]

    def _side(self, tau) -> np.ndarray:
        """The side at tau in [0, 1] from its pcurves as they are (not clipped to the surface's domain: a
        pcurve a hair past it runs on the surface's natural extension)."""
        reg = self.side.region
        if not self.side.pieces:
            return np.repeat(self.side.point[None, :], np.asarray(tau).size, axis=0)
        return self.side._map(np.asarray(tau, float), lambda k, t: reg.loop[k](np.clip(t, *reg.loop[k].domain)), 2)

    def sigma(self, s) -> np.ndarray:
        """The side's own parameter at s (below 0 and above 1 on the extensions)."""
        return (np.asarray(s, float) - self.a) / (self.b - self.a)

    def __call__(self, s) -> np.ndarray:
        sg = self.sigma(np.asarray(s, float).ravel())
        out = self._side(np.clip(sg, 0.0, 1.0))
        lo, hi = sg < 0.0, sg > 1.0
        out[lo] = self.p0 + sg[lo, None] * self.d0
        out[hi] = self.p1 + (sg[hi, None] - 1.0) * self.d1
        return out


@dataclass
class ExtendedMap:
    """Omega of the module doc: the interface of ruled.split.strips.Strip (side_surface samples it)."""

    region: Region
    sides: Sides
    A: Rail
    B: Rail
    flip: bool = False
    name: str = "face's extended patch"

    @property
    def whole(self) -> bool:
        return False

    @property
    def refine_hint(self) -> str:
        return "the surface past the face is too wiggly to extend the rails; the rulings are pinned to the corners"

    def raw(self, s, t) -> np.ndarray:
        s = np.asarray(s, float).ravel()
        t = np.asarray(t, float).ravel()
        if self.flip:
            s = 1.0 - s
        return (1.0 - t)[:, None] * _on(self.A, s) + t[:, None] * _on(self.B, s)

    def omega(self, S: Surface, s, t):
        s, t = np.broadcast_arrays(np.asarray(s, float), np.asarray(t, float))
        uv = self.raw(s.ravel(), t.ravel())
        uv = _wrapped(self.region, uv)
        return uv[:, 0].reshape(s.shape), uv[:, 1].reshape(s.shape)

    def offset(self, s, t):
        return None

    def breaks(self, S: Surface):
        """Breaks in s: where the rails' extensions join the sides and the sides' own breaks; uniform in t."""
        bs = [np.array([0.0, 1.0, self.A.a, self.A.b, self.B.a, self.B.b]), np.linspace(0, 1, 9)]
        for R in (self.A, self.B):
            bs.append(R.a + (R.b - R.a) * R.side.breaks())
        b = np.concatenate(bs)
        if self.flip:
            b = 1.0 - b
        return _merge(b), np.linspace(0.0, 1.0, 5)

    def jacobian(self, n: int = 64, m: int = 16) -> np.ndarray:
        """det(d Omega / d(s, t)) at the centres of an n x m grid, in units of the surface's domain."""
        gs, gt = np.meshgrid((np.arange(n) + 0.5) / n, (np.arange(m) + 0.5) / m, indexing="ij")
        s, t = gs.ravel(), gt.ravel()
        h = 0.25 / n
        u0, u1, v0, v1 = self.region.surface.domain
        sc = np.array([max(u1 - u0, 1e-300), max(v1 - v0, 1e-300)])
        ds = (self.raw(s + h, t) - self.raw(s - h, t)) / sc
        dt = (self.raw(s, t + 1e-3) - self.raw(s, t - 1e-3)) / sc
        return (ds[:, 0] * dt[:, 1] - ds[:, 1] * dt[:, 0]).reshape(n, m)

    def invert(self, uv: np.ndarray, iters: int = 30) -> tuple:
        """(s, t) with Omega(s, t) = uv (N, 2) by Newton's method from the nearest node of a grid, and
        the residual (N,) in units of the surface's domain."""
        from scipy.spatial import cKDTree
        u0, u1, v0, v1 = self.region.surface.domain
        sc = np.array([max(u1 - u0, 1e-300), max(v1 - v0, 1e-300)])
        gs, gt = np.meshgrid(np.linspace(0, 1, 257), np.linspace(0, 1, 65), indexing="ij")
        G = self.raw(gs.ravel(), gt.ravel()) / sc
        uvs = uv / sc
        if not np.all(np.isfinite(G)):          # a rail's extension leaves the surface's numbers: no inverse
            return np.zeros((len(uv), 2)), np.full(len(uv), np.inf)
        _, near = cKDTree(G).query(uvs)
        st = np.stack([gs.ravel()[near], gt.ravel()[near]], axis=1)
        h = 1e-7
        for _ in range(iters):
            F = self.raw(st[:, 0], st[:, 1]) / sc - uvs
            Js = (self.raw(st[:, 0] + h, st[:, 1]) / sc - uvs - F) / h
            Jt = (self.raw(st[:, 0], st[:, 1] + h) / sc - uvs - F) / h
            det = Js[:, 0] * Jt[:, 1] - Js[:, 1] * Jt[:, 0]
            det = np.where(np.abs(det) > 1e-300, det, 1e-300)
            ds = (F[:, 0] * Jt[:, 1] - F[:, 1] * Jt[:, 0]) / det
            dt = (Js[:, 0] * F[:, 1] - Js[:, 1] * F[:, 0]) / det
            step = np.stack([ds, dt], axis=1)
            n = np.linalg.norm(step, axis=1)
            step *= np.minimum(1.0, 0.25 / np.maximum(n, 1e-300))[:, None]
            st = st - step
            if n.max() < 1e-13:
                break
        res = np.linalg.norm(self.raw(st[:, 0], st[:, 1]) / sc - uvs, axis=1)
        return st, res


def _wrapped(region: Region, uv: np.ndarray) -> np.ndarray:
    """(u, v) wrapped round a closed direction of the surface; not clipped (past the domain: its natural
    extension)."""
    out = uv.copy()
    u0, u1, v0, v1 = region.surface.domain
    for ax, (a, b) in enumerate(((u0, u1), (v0, v1))):
        if region.closed[ax]:
            out[:, ax] = a + np.mod(out[:, ax] - a, b - a)
    return out


@dataclass(frozen=True)
class FaceMask:
    """The face in the patch's (s, t): its outer loop and holes as closed polylines, and per loop edge the
    (s, t) of its samples (PER_EDGE each, along the loop)."""

    polygons: tuple           # closed (N, 2) polylines: the outer loop first, then the holes
    edges: tuple              # per outer loop edge: (PER_EDGE, 2) (s, t) samples
    hole_edges: tuple = ()    # per hole: per edge (PER_EDGE, 2)
    overshoot: float = 0.0    # how far (in t) the loop ran past the rails before it was clipped onto them
    curves: Optional[tuple] = None   # the loops as 2D curves in (s, t) (outer first), where known exactly
    grow: tuple = (GROW, GROW)   # the raster of the rulings' costs grown by these fractions of the patch in s, t

    @cached_property
    def _points(self) -> np.ndarray:
        return np.concatenate(self.polygons)

    @cached_property
    def _cells(self) -> dict:
        return {}

    @cached_property
    def _raster(self) -> tuple:
        """(us, vs, inside): the face on a fine grid of the unit square, its nodes next to the boundary's
        samples counted in, grown by GROW."""
        us, vs = np.linspace(0.0, 1.0, RASTER[0]), np.linspace(0.0, 1.0, RASTER[1])
        g = inside_grid(self.polygons, us, vs)
        X = self._points
        iu = np.clip(np.round(X[:, 0] * (us.size - 1)).astype(np.int64), 0, us.size - 1)
        iv = np.clip(np.round(X[:, 1] * (vs.size - 1)).astype(np.int64), 0, vs.size - 1)
        g[iu, iv] = True
        if max(self.grow) > 0:
            # dilated by a rectangle: a running maximum along each axis in turn (separable, linear time)
            from scipy.ndimage import maximum_filter1d
            g8 = g.view(np.uint8)
            for axis, (f, n) in enumerate(zip(self.grow, (us.size, vs.size))):
                if int(f * n) > 0:
                    g8 = maximum_filter1d(g8, 2 * int(f * n) + 1, axis=axis, mode="constant")
            g = g8.astype(bool)
        g.flags.writeable = False
        return us, vs, g

    def inside(self, st: np.ndarray) -> np.ndarray:
        """(N,) whether the points st (N, 2) of the patch's (s, t) lie in the face grown by .grow (to the
        raster's node spacing): the DP's and the refinement's costs count a ruling's points there only
        (ruled.fit.dp.pairing.ruling_cost); the certificate counts the cells that meet the face."""
        us, vs, g = self._raster
        st = np.asarray(st, float).reshape(-1, 2)
        iu = np.clip(np.round(st[:, 0] * (us.size - 1)), 0, us.size - 1).astype(np.int64)
        iv = np.clip(np.round(st[:, 1] * (vs.size - 1)), 0, vs.size - 1).astype(np.int64)
        return g[iu, iv]

    def cells(self, us: np.ndarray, vs: np.ndarray) -> np.ndarray:
        """(nu - 1, nv - 1) whether each cell of the grid us x vs meets the face (its nodes inside, or the
        boundary passing through it), and the cells next to those (conservative: the boundary's samples
        are dense, not continuous).  Kept per grid (every candidate of a fit is certified on the same one);
        read only."""
        key = (np.asarray(us, float).tobytes(), np.asarray(vs, float).tobytes())
        got = self._cells.get(key)
        if got is None:
            got = self._cells[key] = self._cells_of(us, vs)
            got.flags.writeable = False
        return got

    def _cells_of(self, us: np.ndarray, vs: np.ndarray) -> np.ndarray:
        nu, nv = us.size, vs.size
        g = inside_grid(self.polygons, us, vs)
        cell = g[:-1, :-1] | g[1:, :-1] | g[:-1, 1:] | g[1:, 1:]
        X = self._points
        iu = np.clip(np.searchsorted(us, X[:, 0], side="right") - 1, 0, nu - 2)
        iv = np.clip(np.searchsorted(vs, X[:, 1], side="right") - 1, 0, nv - 2)
        cell[iu, iv] = True
        grown = cell.copy()
        grown[1:] |= cell[:-1]
        grown[:-1] |= cell[1:]
        g2 = grown.copy()
        g2[:, 1:] |= grown[:, :-1]
        g2[:, :-1] |= grown[:, 1:]
        return g2


def inside_grid(polygons, us: np.ndarray, vs: np.ndarray) -> np.ndarray:
    """(nu, nv) whether each node of the grid us x vs lies inside the closed polylines (even-odd rule; the
    ray from a node runs towards -v): per polyline segment, the columns us in [lo, hi) of its s-range
    crossed at its t there, counted at every node above the crossing."""
    nu, nv = us.size, vs.size
    count = np.zeros((nu, nv + 1), np.int64)
    for P in polygons:
        a, b = P, np.roll(P, -1, axis=0)
        lo, hi = np.minimum(a[:, 0], b[:, 0]), np.maximum(a[:, 0], b[:, 0])
        i0, i1 = np.searchsorted(us, lo, side="left"), np.searchsorted(us, hi, side="left")
        n = np.maximum(i1 - i0, 0)
        if not n.sum():
            continue
        seg = np.repeat(np.arange(a.shape[0]), n)
        col = i0[seg] + (np.arange(n.sum()) - np.repeat(np.cumsum(n) - n, n))
        ds = b[seg, 0] - a[seg, 0]
        t = a[seg, 1] + (us[col] - a[seg, 0]) * (b[seg, 1] - a[seg, 1]) / ds
        j = np.searchsorted(vs, t, side="right")      # the nodes above the crossing: vs > t
        np.add.at(count, (col, j), 1)
    return (np.cumsum(count, axis=1)[:, :nv] % 2).astype(bool)


def _samples(region: Region, curves) -> list:
    return [c(np.linspace(c.domain[0], c.domain[1], PER_EDGE)) for c in curves]


def extended_map(region: Region, sides: Sides) -> Optional[tuple]:
    """(ExtendedMap, FaceMask) for rails on sides 0 and 2, or None when no reach of REACH covers the face
    without folding (the rails are points, the face's loop leaves the band between the rails, or the map
    folds): the fit is then pinned to the corners."""
    if not sides.pieces[0] or not sides.pieces[2]:
        return None
    c0 = SideCurve(region, sides.pieces[0])
    c2 = SideCurve(region, tuple((k, b, a) for k, a, b in reversed(sides.pieces[2])))

    def uv_length(pieces) -> float:
        if not pieces:
            return 0.0
        c = SideCurve(region, pieces)
        P = c(np.linspace(0, 1, 129))
        return float(np.linalg.norm(np.diff(P, axis=0), axis=1).sum())
    rail_len = max(uv_length(sides.pieces[0]), uv_length(sides.pieces[2]), 1e-300)
    end_before = max(uv_length(sides.pieces[3]), 0.02 * rail_len)   # side 3 joins the rails' starts
    end_after = max(uv_length(sides.pieces[1]), 0.02 * rail_len)
    loops = _samples(region, region.loop)
    holes = [_samples(region, h) for h in region.holes]
    for reach in REACH:
        A = Rail(c0, reach * end_before, reach * end_after)
        B = Rail(c2, reach * end_before, reach * end_after)
        m = ExtendedMap(region, sides, A, B)
        J = m.jacobian()
        if not np.all(np.isfinite(J)):          # (extreme weights: the extension reaches no finite point)
            continue
        small = 1e-2 * float(np.median(np.abs(J)))
        pos, neg = int((J > small).sum()), int((J < -small).sum())
        if pos and neg:
            continue
        m.flip = neg > pos
        st_edges, ok, over = [], True, 0.0
        for P in loops + [p for h in holes for p in h]:
            st, res = m.invert(P)
            # the rails' own points come back within round-off of t = 0 and 1 (their pcurves may run a hair
            # past the surface's domain, where the sides are clipped)
            if (res.max() > 1e-8 or st[:, 1].min() < -BAND or st[:, 1].max() > 1.0 + BAND
                    or st[:, 0].min() < 1e-4 or st[:, 0].max() > 1 - 1e-4):
                ok = False
                break
            over = max(over, float(-st[:, 1].min()), float(st[:, 1].max() - 1.0))
            st_edges.append(np.clip(st, 0.0, 1.0))
        if not ok:
            continue
        n = len(loops)
        outer = tuple(st_edges[:n])
        hl, k = [], n
        for h in holes:
            hl.append(tuple(st_edges[k:k + len(h)]))
            k += len(h)
        polys = (np.concatenate(outer),) + tuple(np.concatenate(h) for h in hl)
        return m, FaceMask(polys, outer, tuple(hl), over)
    return None


def masked(E: Surface, mask: FaceMask) -> Surface:
    """The patch E carrying the face's mask: its certificates count only the cells that meet the face."""
    E.__dict__["face_mask"] = mask
    return E


def face_mask(S: Surface) -> Optional[FaceMask]:
    """The face's mask a patch carries (masked), or None."""
    return S.__dict__.get("face_mask")


__all__ = ["ExtendedMap", "FaceMask", "Rail", "extended_map", "masked", "face_mask", "DegenerateFaceError"]
