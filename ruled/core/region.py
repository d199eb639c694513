"""The face as bounded by its edges, and its four sides.

A :class:`Region` is a surface with the face's outer wire as 2D curves in the surface's (u, v) (the
edges' pcurves, in wire order, each running along the loop) and its inner wires (holes).  The outer
loop is grouped into four sides at its corners (:func:`four_sides`): a joint where the image of the
loop on the surface turns by more than ``CORNER_DEG`` is a corner; edges that continue smoothly merge
into one side; with more than four corners, or three (then one side is a point, so that the rulings
fan out of it), the candidate groupings are listed (:func:`side_candidates`) for the caller to score; a
face with fewer corners is divided at arc-length points.  Sides 0 and 2 are one pair of opposite sides (the rails
of rulings along t), sides 1 and 3 the other (rulings along s).

The face's own parametrization, a Coons map of the unit square onto the region, is in ruled.fit.face.coons.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np

from ruled.core.basis import bspline_basis_matrix
from ruled.core.errors import BadInputError
from ruled.core.nurbs import Curve, Surface

CORNER_DEG = 15.0          # a joint where the loop's image turns more than this is a corner
_TABLE = 96                # arc-length table points per edge piece


@dataclass(frozen=True)
class Region:
    """A surface and the face's boundary on it, as plain arrays.

    loop: the outer wire's pcurves (2D Curves in the surface's (u, v)), in wire order, each running
    along the loop; seams / degenerate: per loop edge, whether it is the surface's closing line (a
    seam, listed twice) or has no 3D length; holes: inner wires, each a tuple of 2D Curves."""

    surface: Surface
    loop: tuple
    seams: tuple = ()
    degenerate: tuple = ()
    holes: tuple = ()
    edges3d: tuple = ()     # the edges' own 3D curves (on the pcurves' parameters), when they are known
    closed: tuple = (False, False)   # the surface closes on itself across its u (v) domain: wrap, not clip
    tolerances: tuple = ()  # per loop edge, the model's tolerance of the edge (3D), when it is known
    hole_edges3d: tuple = ()     # per hole, its edges' 3D curves (as edges3d), when they are known
    hole_tolerances: tuple = ()  # per hole, its edges' tolerances

    def __post_init__(self):
        if not isinstance(self.surface, Surface):
            raise BadInputError(f"a region's surface must be a Surface, not {type(self.surface).__name__}")
        if len(self.loop) == 0:
            raise BadInputError("the face has no edges; pick a face bounded by a wire (see 'ruled faces')")
        for c in list(self.loop) + [c for h in self.holes for c in h]:
            if not isinstance(c, Curve) or c.poles.shape[1] != 2:
                raise BadInputError("the face's boundary must be given as 2D (u, v) curves")
        for c in self.edges3d:
            if c is not None and (not isinstance(c, Curve) or c.poles.shape[1] != 3):
                raise BadInputError("the face's 3D edges must be given as 3D curves (or None where unknown)")
        n = len(self.loop)
        object.__setattr__(self, "seams", tuple(bool(x) for x in self.seams) or (False,) * n)
        object.__setattr__(self, "degenerate", tuple(bool(x) for x in self.degenerate) or (False,) * n)
        object.__setattr__(self, "holes", tuple(tuple(h) for h in self.holes))
        if self.edges3d and len(self.edges3d) != n:
            raise BadInputError("the face's 3D edges do not match its boundary curves")
        if self.tolerances and (len(self.tolerances) != n or not all(np.isfinite(t) and t >= 0
                                                                      for t in self.tolerances)):
            raise BadInputError("the face's edge tolerances must be one finite, non-negative distance per edge")
        object.__setattr__(self, "tolerances", tuple(float(t) for t in self.tolerances))

    @property
    def size(self) -> int:
        return len(self.loop)

    def rect_sides(self) -> Optional[list]:
        """When every loop edge runs along a side of the surface's (u, v) rectangle within 1e-6 of its
        range, or within the edge's own tolerance in space (the model's: an exporter's sloppy edge), the
        loop, closed, goes round the rectangle: per edge, (side, offset) with side one of 'u0', 'u1' (the
        edge lies on u = u0 or u1), 'v0', 'v1', and its largest offset from that line; else None."""
        u0, u1, v0, v1 = self.surface.domain
        speed = None
        out = []
        for k, c in enumerate(self.loop):
            P = c(np.linspace(c.domain[0], c.domain[1], 33))
            best = None
            for ax, names, (a, b) in ((0, ("u0", "u1"), (u0, u1)), (1, ("v0", "v1"), (v0, v1))):
                for name, x in zip(names, (a, b)):
                    d = float(np.abs(P[:, ax] - x).max())
                    ok = d <= 1e-6 * (b - a)
                    if not ok and self.tolerances and d <= 1e-2 * (b - a):
                        if speed is None:        # the largest |S_u|, |S_v|: how far an offset reaches in space
                            bd = self.surface.derivative_bounds()
                            speed = (float(bd["Su"].max()), float(bd["Sv"].max()))
                        ok = d * speed[ax] <= self.tolerances[k]
                    if ok and (best is None or d < best[1]):
                        best = (name, d)
            if best is None:
                return None
            out.append(best)
        return out

    def rect_offset(self, sides: Optional[list] = None) -> Optional[tuple]:
        """The largest offsets (du, dv) of the loop from the rectangle (see rect_sides; given or found),
        or None."""
        sides = self.rect_sides() if sides is None else sides
        if sides is None:
            return None
        return (max([d for n, d in sides if n[0] == "u"], default=0.0),
                max([d for n, d in sides if n[0] == "v"], default=0.0))

    def is_rectangle(self) -> bool:
        """True when there are no holes and the loop runs round the surface's (u, v) rectangle (within
        1e-6 of its range; rect_offset): the face is its whole surface."""
        return not self.holes and self.rect_offset() is not None

    def rect_slack(self, gaps: bool = True) -> float:
        """An upper bound of the distance between a rectangle face and its surface's rectangle: the
        loop's offsets times the largest |S_u|, |S_v| (0 when the loop is the rectangle exactly), plus
        (gaps) the distance from the surface of the edges taken as sides within their tolerance."""
        sides = self.rect_sides()
        off = self.rect_offset(sides)
        if not off or off == (0.0, 0.0):
            return 0.0
        b = self.surface.derivative_bounds()
        slack = float(off[0] * b["Su"].max() + off[1] * b["Sv"].max())
        # an edge taken as a side within its tolerance: its own 3D curve may lie that far off the surface
        u0, u1, v0, v1 = self.surface.domain
        loose = [k for k, (name, d) in enumerate(sides)
                 if gaps and d > 1e-6 * ((u1 - u0) if name[0] == "u" else (v1 - v0))]
        return slack + max((self.edge_gap(k) for k in loose), default=0.0)

    def uv(self, k: int, t) -> np.ndarray:
        """Points (N, 2) of loop edge k, in the surface's domain (see inside)."""
        return self.inside(self.loop[k](np.clip(t, *self.loop[k].domain)))

    def inside(self, uv: np.ndarray) -> np.ndarray:
        """(u, v) points brought into the surface's domain: wrapped round a closed direction (a loop on a
        closed surface may run over its seam), clipped otherwise."""
        u0, u1, v0, v1 = self.surface.domain
        out = np.empty_like(uv)
        for ax, (a, b) in enumerate(((u0, u1), (v0, v1))):
            x = uv[:, ax]
            if self.closed[ax]:
                eps = 1e-12 * (b - a)
                x = np.where((x < a - eps) | (x > b + eps), a + np.mod(x - a, b - a), x)
            out[:, ax] = np.clip(x, a, b)
        return out

    def gap(self, k: int, t) -> np.ndarray:
        """(N, 3) from the surface at edge k's pcurve to the edge's 3D curve (zero when no 3D curve is
        known): a smooth least-squares cubic through the offsets to the nearest points of the 3D curve
        (a CAD kernel's pcurve and 3D curve share their parameter only within the edge's tolerance)."""
        t = np.asarray(t, float).ravel()
        g = self._gaps(k)
        if g is None:
            return np.zeros((t.size, 3))
        return g[0](np.clip(t, *g[0].domain))

    def edge_gap(self, k: int) -> float:
        """The two-sided largest distance between edge k's 3D curve and the surface at its pcurve."""
        g = self._gaps(k)
        return 0.0 if g is None else g[1]

    def outer_gap(self) -> float:
        """The largest distance between an outer edge's 3D curve and the surface at its pcurve (both ways)."""
        return max(self.edge_gap(k) for k in range(self.size)) if self.edges3d else 0.0

    def max_gap(self) -> float:
        """The largest distance between an edge's 3D curve and the surface at its pcurve (both ways), the
        holes' edges included."""
        return max(self.outer_gap(), self.hole_gap())

    def hole_gap(self) -> float:
        """max_gap over the holes' edges (computed once)."""
        if "_hole_gap_cache" not in self.__dict__:
            from ruled.core.edgegap import gap_of
            tols = self.hole_tolerances or [()] * len(self.holes)
            self.__dict__["_hole_gap_cache"] = max(
                [gap_of(lambda x, c=c: self.surface(*c(x).T), np.linspace(c.domain[0], c.domain[1], 2001), c3,
                        tol)[0]
                 for h, h3, ht in zip(self.holes, self.hole_edges3d, tols)
                 for c, c3, tol in zip(h, h3, ht or [0.0] * len(h)) if c3 is not None], default=0.0)
        return self.__dict__["_hole_gap_cache"]

    def _gaps(self, k: int):
        cache = self.__dict__.setdefault("_gap_cache", {})
        if k in cache:
            return cache[k]
        c3 = self.edges3d[k] if self.edges3d else None
        if c3 is None or self.degenerate[k]:
            cache[k] = None
            return None
        from ruled.core.edgegap import gap_of
        t = np.linspace(self.loop[k].domain[0], self.loop[k].domain[1], 2001)
        gap, agree, near = gap_of(lambda x: self.surface(*self.uv(k, x).T), t, c3,
                                  self.tolerances[k] if self.tolerances else 0.0)
        if agree:
            # the parameters agree: the 3D curve itself, tabulated densely (the patch's sampling asks
            # for it many times; linear interpolation of so small and smooth a difference errs by
            # h^2/8 of its second derivative, h a 8192th of the edge)
            G: object = _Tabled(_Difference(c3, self, k), 8193)
        else:
            spans = 64
            knots = np.concatenate([[t[0]] * 3, np.linspace(t[0], t[-1], spans + 1), [t[-1]] * 3])
            G = Curve(np.linalg.lstsq(bspline_basis_matrix(knots, 3, t), near, rcond=None)[0], knots, 3)
        cache[k] = (G, gap)
        return cache[k]

    def polygon(self, per_edge: int = 200) -> list:
        """The outer loop and every hole as closed (u, v) polylines (dense samples of each pcurve)."""
        def poly(curves):
            return np.concatenate([c(np.linspace(c.domain[0], c.domain[1], per_edge)) for c in curves])
        return [poly(self.loop)] + [poly(h) for h in self.holes]

    def contains(self, uv: np.ndarray, per_edge: int = 200) -> np.ndarray:
        """(N,) whether each (u, v) point lies inside the face (even-odd rule over the loop and the holes'
        polylines; points within a hair of the boundary count as inside)."""
        uv = np.atleast_2d(np.asarray(uv, float))
        inside = np.zeros(len(uv), bool)
        near = np.zeros(len(uv), bool)
        u0, u1, v0, v1 = self.surface.domain
        eps = 1e-7 * max(u1 - u0, v1 - v0, 1e-300)
        for P in self.polygon(per_edge):
            a, d = P, np.roll(P, -1, axis=0) - P
            inside ^= crossings_odd(P, uv)
            tt = np.clip(((uv[:, None, :] - a[None]) * d[None]).sum(-1) / np.maximum((d * d).sum(-1), 1e-300), 0, 1)
            dist = np.linalg.norm(uv[:, None, :] - (a[None] + tt[..., None] * d[None]), axis=-1).min(axis=1)
            near |= dist <= eps
        return inside | near

    def hole_span(self, n: int = 48, per_edge: int = 400) -> float:
        """How far a point of the surface over a hole can be from the face (0 without holes): a fit over
        the outer boundary spans the holes, and a point of it there is at most its distance to the surface
        plus this from the face.  Per hole, an n x n (u, v) grid over the hole's box: the largest distance
        from the surface at the grid points of every cell with a corner inside the hole to dense samples of
        the hole's edges (points of the face: each distance at least the true one), plus the largest
        diagonal of such a cell in space (a point of the cell is that near one of its corners)."""
        from scipy.spatial import cKDTree
        S = self.surface
        worst = 0.0
        for h in self.holes:
            poly = self.inside(np.concatenate([c(np.linspace(c.domain[0], c.domain[1], per_edge)) for c in h]))
            edge = cKDTree(S(poly[:, 0], poly[:, 1]))
            lo, hi = poly.min(axis=0), poly.max(axis=0)
            uu, vv = np.meshgrid(np.linspace(lo[0], hi[0], n), np.linspace(lo[1], hi[1], n), indexing="ij")
            ins = crossings_odd(poly, np.stack([uu.ravel(), vv.ravel()], axis=1)).reshape(n, n)
            cells = ins[:-1, :-1] | ins[1:, :-1] | ins[:-1, 1:] | ins[1:, 1:]
            if not cells.any():
                continue
            X = S(uu.ravel(), vv.ravel()).reshape(n, n, 3)
            d = edge.query(X.reshape(-1, 3))[0].reshape(n, n)
            corner = np.maximum.reduce([d[:-1, :-1], d[1:, :-1], d[:-1, 1:], d[1:, 1:]])
            diag = np.maximum(np.linalg.norm(X[1:, 1:] - X[:-1, :-1], axis=2),
                              np.linalg.norm(X[1:, :-1] - X[:-1, 1:], axis=2))
            worst = max(worst, float((corner + diag)[cells].max()))
        return worst

    def tangent3d(self, k: int, t: float) -> np.ndarray:
        """The image's tangent S_u u' + S_v v' of loop edge k at t (one point, (3,))."""
        c = self.loop[k]
        p, d = c.evaluate(np.array([float(np.clip(t, *c.domain))]), 1)
        uv = self.uv(k, np.array([t]))
        D = self.surface.evaluate(uv[:, 0], uv[:, 1], 1)
        return (D.Su * d[:, :1] + D.Sv * d[:, 1:2])[0]

    def joint_angles(self) -> np.ndarray:
        """(n,) the turn of the loop's image at the joint after each edge, degrees (180 where a tangent
        vanishes, and on both sides of a degenerate edge, a point of the surface: a corner, such as a cone's
        apex, unless the edges before and after it run on in 3D within CORNER_DEG, as the two halves of a
        straight side through a pole of the surface do: then both joints turn by that much)."""
        n = self.size
        out = np.empty(n)
        for k in range(n):
            j = (k + 1) % n
            if self.degenerate[k] or self.degenerate[j]:
                out[k] = 180.0
                continue
            out[k] = self._turn(k, j)
        for k in range(n):
            if not self.degenerate[k]:
                continue
            p, q = (k - 1) % n, (k + 1) % n
            while self.degenerate[p] and p != k:
                p = (p - 1) % n
            while self.degenerate[q] and q != k:
                q = (q + 1) % n
            if p == k or q == k or p == q:
                continue
            turn = self._turn(p, q)
            if turn <= CORNER_DEG:
                out[(k - 1) % n] = out[k] = turn
        return out

    def _turn(self, k: int, j: int) -> float:
        """The angle (degrees) between edge k's tangent at its end and edge j's at its start, in 3D (one-sided
        tangents a hair inside each edge: a pcurve's end derivative may vanish); 180 where one vanishes."""
        a0, a1 = self.loop[k].domain
        b0, b1 = self.loop[j].domain
        ta = self.tangent3d(k, a1 - 1e-9 * (a1 - a0))
        tb = self.tangent3d(j, b0 + 1e-9 * (b1 - b0))
        na, nb = np.linalg.norm(ta), np.linalg.norm(tb)
        if na == 0 or nb == 0:
            return 180.0
        return float(np.degrees(np.arccos(np.clip(ta @ tb / (na * nb), -1.0, 1.0))))



def crossings_odd(P: np.ndarray, uv: np.ndarray) -> np.ndarray:
    """(N,) whether a ray from each (u, v) point towards +u crosses the closed polyline P an odd number of
    times (the even-odd rule: inside one loop)."""
    a, b = P, np.roll(P, -1, axis=0)
    d = b - a
    x, y = uv[:, :1], uv[:, 1:]
    cross = (a[None, :, 1] > y) != (b[None, :, 1] > y)
    with np.errstate(divide="ignore", invalid="ignore"):
        xi = a[None, :, 0] + (y - a[None, :, 1]) * (d[None, :, 0] / d[None, :, 1])
    return (np.sum(cross & (x < xi), axis=1) % 2).astype(bool)


class _Difference:
    """t -> c3(t) - S(pcurve(t)), with the domain of the pcurve."""

    def __init__(self, c3: Curve, region: "Region", k: int):
        self.c3, self.region, self.k = c3, region, k
        self.domain = region.loop[k].domain

    def __call__(self, t) -> np.ndarray:
        uv = self.region.uv(self.k, t)
        return self.c3(np.clip(t, *self.c3.domain)) - self.region.surface(uv[:, 0], uv[:, 1])


class _Tabled:
    """A vector function of t sampled once at m parameters of its domain, linearly interpolated."""

    def __init__(self, f, m: int):
        self.domain = f.domain
        self.t = np.linspace(f.domain[0], f.domain[1], m)
        self.y = f(self.t)

    def __call__(self, t) -> np.ndarray:
        t = np.asarray(t, float).ravel()
        return np.stack([np.interp(t, self.t, self.y[:, c]) for c in range(self.y.shape[1])], axis=1)


# a piece of a side: (loop edge index, start parameter, end parameter)
Piece = tuple


def piece_table(region: Region, piece: Piece, m: int = _TABLE):
    """Parameters, (u, v) points and cumulative 3D chord length along a piece."""
    k, a, b = piece
    t = np.linspace(a, b, m)
    uv = region.uv(k, t)
    P = region.surface(uv[:, 0], uv[:, 1])
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(P, axis=0), axis=1))])
    return t, uv, s


@dataclass(frozen=True)
class Sides:
    """The four sides of a region in loop order, each a tuple of pieces (empty: a degenerate side, a
    point at the corner between its neighbours), and the loop edges of each side."""

    pieces: tuple
    corner_angles: tuple = ()
    how: str = "corners"

    def edges(self, i: int) -> tuple:
        return tuple(dict.fromkeys(p[0] for p in self.pieces[i]))

    def rails(self, direction: str) -> tuple:
        """The loop edges of the two rails of rulings along 'v' (sides 0 and 2) or 'u' (sides 1 and 3)."""
        a, b = (0, 2) if direction == "v" else (1, 3)
        return self.edges(a), self.edges(b)


def _whole(region: Region, k: int) -> Piece:
    a, b = region.loop[k].domain
    return (k, a, b)


def _runs(region: Region, corners: list) -> list:
    """The loop cut at the given joints (joint k: after edge k): runs of whole edges."""
    n = region.size
    cs = sorted(corners)
    out = []
    for i, c in enumerate(cs):
        nxt = cs[(i + 1) % len(cs)]
        run, k = [], (c + 1) % n
        while True:
            run.append(_whole(region, k))
            if k == nxt:
                break
            k = (k + 1) % n
        out.append(tuple(run))
    return out


def _split_run(region: Region, run: tuple, parts: int) -> list:
    """A run of pieces cut into parts of equal 3D arc length (pieces cut inside edges where needed)."""
    tabs = [piece_table(region, p) for p in run]
    lens = np.array([tb[2][-1] for tb in tabs])
    cum = np.concatenate([[0.0], np.cumsum(lens)])
    cuts = list(cum[-1] * np.arange(1, parts) / parts)
    out, cur = [], []
    for (k, a, b), (t, _, s), c0, ln in zip(run, tabs, cum[:-1], lens):
        start = a
        while cuts and cuts[0] < c0 + ln and ln > 0:
            x = float(np.interp(cuts.pop(0) - c0, s, t))
            cur.append((k, start, x))
            out.append(tuple(cur))
            cur, start = [], x
        cur.append((k, start, b))
    out.append(tuple(cur))
    while len(out) < parts:      # a run without length: its last piece halved until there are enough
        k, a, b = out[-1][-1]
        out[-1] = out[-1][:-1] + ((k, a, 0.5 * (a + b)),)
        out.append(((k, 0.5 * (a + b), b),))
    return out


def four_sides(region: Region, rails: Optional[tuple] = None, corner_deg: float = CORNER_DEG) -> Sides:
    """Group the loop into four sides (see the module doc).  rails: two loop edge indices to be the
    rails (sides 0 and 2): they must be opposite, i.e. not neighbours."""
    n = region.size
    ang = region.joint_angles()
    if rails is not None:
        a, b = (int(x) for x in rails)
        for x in (a, b):
            if not 0 <= x < n:
                raise BadInputError(f"«rails»: the face has no edge {x}; its outer wire has edges 0..{n - 1} "
                                    f"(see «edges_listing»)")
        if a == b:
            raise BadInputError(f"«rails={a},{b}» names one edge twice; name two opposite edges")
        if (a + 1) % n == b or (b + 1) % n == a:
            raise BadInputError(f"«rails={a},{b}»: edges {a} and {b} are neighbours, not opposite; name two edges "
                                f"with other edges between them on both sides")
        runs = _runs(region, [(a - 1) % n, a, (b - 1) % n, b])
        # the runs start after joint a-1 (edge a), after a, after b-1 (edge b) and after b, in sorted order
        byfirst = {r[0][0]: r for r in runs}
        ra, rb = byfirst[a], byfirst[b]
        r1 = byfirst[(a + 1) % n]
        r3 = byfirst[(b + 1) % n]
        return Sides((ra, r1, rb, r3), tuple(ang), "rails")
    return side_candidates(region, corner_deg)[0]


def side_candidates(region: Region, corner_deg: float = CORNER_DEG, most: int = 15) -> list:
    """The ways of grouping the loop into four sides worth trying, the likeliest first: one side per edge
    for a face of four edges; else four of the (at most six) sharpest corners, every choice; for three
    corners, the point side at each corner in turn, and the three corners with each tangent joint as a
    fourth corner; for fewer, the loop halved or quartered by arc length."""
    from itertools import combinations
    n = region.size
    ang = region.joint_angles()
    corners = [k for k in range(n) if ang[k] > corner_deg]
    if n == 4 and not any(region.degenerate):
        return [Sides(tuple((_whole(region, k),) for k in range(4)), tuple(ang), "four edges, one side each")]
    out = []
    if len(corners) >= 4:
        top = sorted(corners, key=lambda k: -ang[k])[:6]
        for keep in sorted(combinations(top, 4), key=lambda c: -sum(ang[k] for k in c)):
            out.append(Sides(tuple(_runs(region, sorted(keep))), tuple(ang),
                             f"corners after edges {','.join(map(str, sorted(keep)))}"))
        return out[:most]
    if len(corners) == 3:
        runs = _runs(region, corners)
        cs = sorted(corners)
        for j in sorted(range(3), key=lambda j: -ang[cs[j]]):    # joint cs[j] ends run j-1 and starts run j
            order = [runs[(j + i) % 3] for i in range(3)]
            out.append(Sides((order[0], order[1], order[2], ()), tuple(ang),
                             f"three corners: the rulings fan out of the corner after edge {cs[j]}"))
        for k in range(n):
            if k not in corners:
                out.append(Sides(tuple(_runs(region, sorted(corners + [k]))), tuple(ang),
                                 f"three corners and the tangent joint after edge {k}"))
        return out[:most]
    if len(corners) == 2:
        r = _runs(region, corners)
        s0, s1 = _split_run(region, r[0], 2), _split_run(region, r[1], 2)
        return [Sides((r[0], (), r[1], ()), tuple(ang), "two corners: rulings from one side to the other"),
                Sides((s0[0], s0[1], s1[0], s1[1]), tuple(ang), "two corners: each side halved")]
    start = corners[0] if corners else n - 1
    whole = _runs(region, [start])[0] if n > 1 or corners else (_whole(region, 0),)
    what = f"{len(corners)} corner{'s' if len(corners) != 1 else ''}"
    halves = _split_run(region, whole, 2)
    return [Sides((halves[0], (), halves[1], ()), tuple(ang),
                  f"{what}: the loop halved by arc length, rulings from one half to the other"),
            Sides(tuple(_split_run(region, whole, 4)), tuple(ang), f"{what}: the loop quartered by arc length")]


__all__ = ["Region", "Sides", "four_sides", "side_candidates", "CORNER_DEG"]
