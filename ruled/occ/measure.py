"""Independent error measure: two-sided Hausdorff distance between two faces by dense
sampling plus exact point projection with OCCT (no code of the engine is used).  Trim-aware: the
samples are points of each face as bounded by its edges, and distances are to the bounded face."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from OCP.BRep import BRep_Tool
from OCP.BRepAdaptor import BRepAdaptor_Curve
from OCP.BRepTools import BRepTools
from OCP.BRepTopAdaptor import BRepTopAdaptor_FClass2d
from OCP.Extrema import Extrema_GenLocateExtPS
from OCP.GeomAdaptor import GeomAdaptor_Surface
from OCP.GeomAPI import GeomAPI_ProjectPointOnSurf
from OCP.gp import gp_Pnt, gp_Pnt2d, gp_Vec
from OCP.ShapeAnalysis import ShapeAnalysis_Surface
from OCP.TopAbs import TopAbs_ShapeEnum, TopAbs_State
from OCP.TopExp import TopExp_Explorer
from OCP.TopoDS import TopoDS

from ruled.core.distance import _golden_min
from ruled.core.hostform import Hausdorff, PolygonClassifier, grid_size, screened
from ruled.occ.curve_measure import _p3, distance_to
from ruled.occ.edgerows import face_bounds
from ruled.occ.edgerows import face_edges as _face_edges

SEED_GRID = 60     # about SEED_GRID^2 seeds inside a face for the local projections
SEEDS = 8          # the exact distance also searches locally from this many nearest seeds
PIECES = 6         # ... and in this many nearest smooth pieces between creases, from their own seeds
EDGE_SEEDS = 8     # ... and along the edges near this many nearest edge samples
REACH_MARGIN = 1.1  # an edge's arc between two samples is at most this many times their chord (dense samples)


def face_points(face, n: int, cls=None) -> np.ndarray:
    """About n x n points of the face as bounded by its edges: a (u, v) grid of its bounds, as dense
    as it takes for about n * n of its points to fall inside, kept where they are inside; and n points
    along every edge (OCCT evaluation throughout).  cls: the face's classifier, when one exists."""
    return face_samples(face, n, cls)[0]


def face_samples(face, n: int, cls=None, resolution: bool = False):
    """(face_points(face, n, cls), how far a point of the face can be from the nearest of them, or None
    unless resolution): the largest diagonal of a grid cell with a corner inside the face, or chord
    between neighbouring edge samples.  The distance to anything changes by at most the move (it is
    1-Lipschitz), so a sampled maximum is at most this much below the true one."""
    surf, us, vs, keep = _grid_layout(face, n, cls)
    need = keep
    if resolution:
        cells = keep[:-1, :-1] | keep[1:, :-1] | keep[:-1, 1:] | keep[1:, 1:]
        need = keep.copy()
        for di in (0, 1):
            for dj in (0, 1):
                need[di:di + cells.shape[0], dj:dj + cells.shape[1]] |= cells
    P = _grid_points(surf, us, vs, need)
    edges = _edge_polylines(face, n)
    pts = np.concatenate([P[keep].reshape(-1, 3)] + edges)
    if not resolution:
        return pts, None
    d1 = np.linalg.norm(P[1:, 1:] - P[:-1, :-1], axis=2)
    d2 = np.linalg.norm(P[1:, :-1] - P[:-1, 1:], axis=2)
    worst = float(np.max(np.where(cells, np.maximum(d1, d2), 0.0), initial=0.0))
    for E in edges:
        worst = max(worst, float(np.linalg.norm(np.diff(E, axis=0), axis=1).max(initial=0.0)))
    return pts, worst


def _grid_layout(face, n: int, cls=None):
    """(surface, us, vs, inside (m, m)) of the (u, v) grid of the face's bounds that puts about n x n
    points inside the face (denser for a trimmed face); cls: the face's classifier."""
    u0, u1, v0, v1 = face_bounds(face)
    m0 = 24
    cls = _classifier(face) if cls is None else cls
    frac = float(cls.grid(np.linspace(u0, u1, m0), np.linspace(v0, v1, m0)).mean())
    m = grid_size(n, frac)
    us, vs = np.linspace(u0, u1, m), np.linspace(v0, v1, m)
    keep = np.ones((m, m), bool) if m == n else cls.grid(us, vs)
    return BRep_Tool.Surface_s(face), us, vs, keep


def _grid_points(surf, us, vs, mask) -> np.ndarray:
    """(m, m, 3): the surface at the grid nodes where mask holds (OCCT), NaN elsewhere."""
    P = np.full(mask.shape + (3,), np.nan)
    for i, j in zip(*np.nonzero(mask)):
        P[i, j] = _p3(surf.Value(float(us[i]), float(vs[j])))
    return P


def interior_grid(face, n: int, cls=None):
    """(points (N, 3), parameters (N, 2)) of a (u, v) grid of the face's bounds inside the face, about
    n x n of them (the grid is made denser for a trimmed face); cls: the face's classifier."""
    surf, us, vs, keep = _grid_layout(face, n, cls)
    iu, iv = np.nonzero(keep)
    return _grid_points(surf, us, vs, keep)[keep].reshape(-1, 3), np.stack([us[iu], vs[iv]], axis=1)


def _edge_polylines(face, n: int) -> list:
    """n points along each edge of the face (degenerate edges left out), one (n, 3) array per edge."""
    out = []
    for e in _face_edges(face):
        c = BRepAdaptor_Curve(e)
        out.append(np.array([_p3(c.Value(float(t))) for t in np.linspace(c.FirstParameter(), c.LastParameter(), n)])
                   .reshape(-1, 3))
    return out


def corner_points(face, n: int) -> np.ndarray:
    """n points along each ruling of the face's B-spline surface at its corners (ruled.core.edgerows.
    corner_rulings), inside its (u, v) bounds; none for another surface."""
    from OCP.GeomAbs import GeomAbs_BSplineSurface

    from ruled.core.edgerows import corner_rulings
    surf = BRep_Tool.Surface_s(face)
    ad = GeomAdaptor_Surface(surf)
    if ad.GetType() != GeomAbs_BSplineSurface:
        return np.zeros((0, 3))
    bs = ad.BSpline()

    def flat(knots, mults, count):
        return [knots(k) for k in range(1, count + 1) for _ in range(mults(k))]
    uv = corner_rulings(flat(bs.UKnot, bs.UMultiplicity, bs.NbUKnots()),
                        flat(bs.VKnot, bs.VMultiplicity, bs.NbVKnots()), bs.UDegree(), bs.VDegree(),
                        BRepTools.UVBounds_s(face), n)
    return np.array([_p3(surf.Value(float(u), float(v))) for u, v in uv]).reshape(-1, 3)


def _boundary_polygon(face, per_edge: int = 256):
    """The pcurves of every edge of the face as polylines in its (u, v) (seam edges once per side), or
    None when an edge has no pcurve."""
    out = []
    ex = TopExp_Explorer(face, TopAbs_ShapeEnum.TopAbs_EDGE)
    while ex.More():
        e = TopoDS.Edge_s(ex.Current())
        a, b = BRep_Tool.Range_s(e, face)
        c2 = BRep_Tool.CurveOnSurface_s(e, face, a, b)
        if c2 is None:
            return None
        out.append(np.array([(q.X(), q.Y()) for q in (c2.Value(float(t)) for t in np.linspace(a, b, per_edge))]))
        ex.Next()
    return out or None


def _classifier(face) -> PolygonClassifier:
    """The face's (u, v) classifier: its pcurves' polylines, OCCT's face classifier near them."""
    cls = BRepTopAdaptor_FClass2d(face, 1e-9)

    def exact(u, v) -> bool:
        return cls.Perform(gp_Pnt2d(u, v)) in (TopAbs_State.TopAbs_IN, TopAbs_State.TopAbs_ON)
    surf = BRep_Tool.Surface_s(face)
    periods = (surf.UPeriod() if surf.IsUPeriodic() else 0.0, surf.VPeriod() if surf.IsVPeriodic() else 0.0)
    return PolygonClassifier(lambda: _boundary_polygon(face), face_bounds(face), exact, periods)


def _crease_knots(surf, bounds) -> tuple:
    """The knots of the face's B-spline surface inside its bounds where it is only C0 (multiplicity >=
    degree), in u and in v; none for other surfaces."""
    from OCP.GeomAbs import GeomAbs_SurfaceType
    ad = GeomAdaptor_Surface(surf)
    if ad.GetType() != GeomAbs_SurfaceType.GeomAbs_BSplineSurface:
        return [], []
    bs = ad.BSpline()
    u0, u1, v0, v1 = bounds
    return ([bs.UKnot(i) for i in range(1, bs.NbUKnots() + 1) if bs.UMultiplicity(i) >= bs.UDegree()
             and u0 < bs.UKnot(i) < u1],
            [bs.VKnot(i) for i in range(1, bs.NbVKnots() + 1) if bs.VMultiplicity(i) >= bs.VDegree()
             and v0 < bs.VKnot(i) < v1])


def _crease_runs(surf, bounds, inside, n: int = 200) -> list:
    """The face's creases: iso-curves of its B-spline surface at knots of full multiplicity (where the
    surface is only C0), as (curve, parameters, points, (u, v), the direction across) runs of n samples
    inside the face.  A closest
    point can lie on a crease without being an extremum of either side, so the local projections miss it."""
    from OCP.GeomAdaptor import GeomAdaptor_Curve
    ku, kv = _crease_knots(surf, bounds)
    u0, u1, v0, v1 = bounds
    runs = []
    for along_u, ks, iso in ((False, ku, surf.UIso), (True, kv, surf.VIso)):
        a, b = (u0, u1) if along_u else (v0, v1)
        for k in ks:
            c = GeomAdaptor_Curve(iso(k), a, b)
            t = np.linspace(a, b, n)
            uv = np.stack([t, np.full(n, k)] if along_u else [np.full(n, k), t], axis=1)
            ok = inside.points(uv)
            # contiguous runs inside the face
            edges = np.flatnonzero(np.diff(np.concatenate([[0], ok.astype(int), [0]])))
            for s0, s1 in zip(edges[::2], edges[1::2]):
                tt = t[s0:s1]
                runs.append((c, tt, np.array([_p3(c.Value(float(x))) for x in tt]), uv[s0:s1],
                             1 if along_u else 0))         # the parameter that crosses the crease
    return runs


class _Projector:
    """Distances to a face as bounded by its edges (OCCT only)."""

    def __init__(self, face):
        self.u0, self.u1, self.v0, self.v1 = face_bounds(face)
        self.surf = BRep_Tool.Surface_s(face)
        self.proj = GeomAPI_ProjectPointOnSurf()
        self.proj.Init(self.surf, self.u0, self.u1, self.v0, self.v1)
        self.sas = ShapeAnalysis_Surface(self.surf)
        self.inside = _classifier(face)
        # a dense cloud of every edge and crease: closest points may lie on the boundary, or on a crease
        self.curves, pts, ids, ts = [], [], [], []
        for e in _face_edges(face):
            c = BRepAdaptor_Curve(e)
            t = np.linspace(c.FirstParameter(), c.LastParameter(), 200)
            pts.append(np.array([_p3(c.Value(float(x))) for x in t]))
            ids.append(np.full(t.size, len(self.curves)))
            ts.append(t)
            self.curves.append(c)
        crease_pts, crease_uv, crease_dir = [], [], []
        for c, t, p, uv, across in _crease_runs(self.surf, (self.u0, self.u1, self.v0, self.v1), self.inside):
            pts.append(p)
            ids.append(np.full(t.size, len(self.curves)))
            ts.append(t)
            self.curves.append(c)
            crease_pts.append(p)
            crease_uv.append(uv)
            crease_dir.append(np.full(t.size, across))
        # seeds on either side of every crease: a local search does not cross one
        self.crease = None
        if crease_pts:
            from scipy.spatial import cKDTree
            self.crease = (cKDTree(np.concatenate(crease_pts)), np.concatenate(crease_uv), np.concatenate(crease_dir))
        self.edge_pts = np.concatenate(pts) if pts else np.zeros((0, 3))
        self.edge_id = np.concatenate(ids) if ids else np.zeros(0, int)
        # per sample, how far along its edge the next samples lie (a margin over their chords): no point of
        # the edge between them is nearer to a point than its distance to the sample less this
        self.edge_reach = np.zeros(len(self.edge_pts))
        if len(self.edge_pts) > 1:
            chord = np.linalg.norm(np.diff(self.edge_pts, axis=0), axis=1)
            chord[self.edge_id[1:] != self.edge_id[:-1]] = 0.0
            self.edge_reach = REACH_MARGIN * np.maximum(np.concatenate([[0.0], chord]), np.concatenate([chord, [0.0]]))
        self.edge_t = np.concatenate(ts) if ts else np.zeros(0)
        self.face = face
        self._local = None
        self._piece_cache = None

    def _local_search(self):
        """The seeds of the local projection (a grid inside the face, KD-tree) and OCCT's local
        extremum search from a seed (built on first use; the adaptor is kept: the search refers to it)."""
        if self._local is None:
            from scipy.spatial import cKDTree
            pts, uv = interior_grid(self.face, SEED_GRID, self.inside)
            adaptor = GeomAdaptor_Surface(self.surf, *self._search_bounds(self.u0, self.u1, self.v0, self.v1))
            self._local = (adaptor, Extrema_GenLocateExtPS(adaptor, 1e-10, 1e-10),
                           cKDTree(pts) if len(pts) else None, uv,
                           cKDTree(self.edge_pts) if len(self.edge_pts) else None)
        return self._local

    def _search_bounds(self, a, b, c, d) -> tuple:
        """A local search's (u, v) bounds: (a, b, c, d), reaching half a period past the face's own bounds in a
        periodic direction (a search held at the face's seam stops there short of a foot just across it; its
        foot is brought back by the classifier's wrap)."""
        per = self.inside.periods
        half = (0.5 * per[0], 0.5 * per[1])
        a = a - half[0] if a <= self.u0 else a
        b = b + half[0] if b >= self.u1 else b
        c = c - half[1] if c <= self.v0 else c
        d = d + half[1] if d >= self.v1 else d
        return a, b, c, d

    def _pieces(self) -> list:
        """The face's smooth pieces between its creases (none without creases): for each, OCCT's local
        extremum search bounded to it and a grid of seeds inside the face (built on first use).  A local
        search does not cross a crease, and where the surface folds there the nearest seeds of the whole
        face can all lie on the other sheet."""
        if self._piece_cache is None:
            from scipy.spatial import cKDTree
            ku, kv = _crease_knots(self.surf, (self.u0, self.u1, self.v0, self.v1))
            self._piece_cache = []
            if ku or kv:
                ub, vb = [self.u0, *ku, self.u1], [self.v0, *kv, self.v1]
                m = max(6, int(SEED_GRID / np.sqrt((len(ub) - 1) * (len(vb) - 1))))
                for a, b in zip(ub[:-1], ub[1:]):
                    for c, d in zip(vb[:-1], vb[1:]):
                        us, vs = np.linspace(a, b, m), np.linspace(c, d, m)
                        iu, iv = np.nonzero(self.inside.grid(us, vs))
                        if iu.size == 0:
                            continue
                        uv = np.stack([us[iu], vs[iv]], axis=1)
                        pts = np.array([_p3(self.surf.Value(float(u), float(v))) for u, v in uv])
                        ad = GeomAdaptor_Surface(self.surf, *self._search_bounds(a, b, c, d))
                        self._piece_cache.append((Extrema_GenLocateExtPS(ad, 1e-10, 1e-10), cKDTree(pts), uv, ad))
        return [(loc, tree, uv) for loc, tree, uv, _ in self._piece_cache]

    def upper(self, X: np.ndarray) -> np.ndarray:
        """Distances from the points X (N, 3) to points of the face (each at least the distance to the
        bounded face, and equal to it unless a local search misses the global minimum): the nearest
        seed, OCCT's local extremum from it where its foot is inside the face, and the nearest edge
        point refined along its edge where the boundary may be nearer."""
        X = np.asarray(X, float).reshape(-1, 3)
        _, loc, tree, uv, etree = self._local_search()
        ub = np.full(len(X), np.inf)
        if tree is not None:
            d0, k = tree.query(X)
            ub = d0.copy()
            feet, dist = np.zeros((len(X), 2)), np.full(len(X), np.inf)
            for i, (x, s) in enumerate(zip(X.tolist(), uv[k].tolist())):     # (plain floats: a loop of 8000)
                loc.Perform(gp_Pnt(*x), s[0], s[1], False)
                if loc.IsDone():
                    feet[i] = loc.Point().Parameter()
                    dist[i] = np.sqrt(loc.SquareDistance())
            ok = np.isfinite(dist)
            ok[ok] = self.inside.points(feet[ok])
            ub[ok] = np.minimum(ub[ok], dist[ok])
            self._piece_upper(X, ub)
        if etree is not None:
            de, ke = etree.query(X)
            ub = np.minimum(ub, de)
            for j in np.nonzero(de - self.edge_reach[ke] < ub)[0]:
                ub[j] = min(ub[j], self._edge_refine(X[j], ke[j]))
        return ub

    def _piece_upper(self, X: np.ndarray, ub: np.ndarray) -> None:
        """ub lowered by local searches in the two smooth pieces (between creases) whose seeds are nearest each
        point, from their nearest seed: a search from the whole face's seeds does not cross a crease, and on a
        surface of many narrow pieces (a wall's faces joined) the nearest seed is often on the wrong one."""
        pieces = self._pieces()
        if len(pieces) < 2:
            return
        q = [tree.query(X) for _, tree, _ in pieces]
        dist = np.stack([d for d, _ in q])
        near = np.argsort(dist, axis=0)[:2]
        for i, x in enumerate(X):
            P = gp_Pnt(*map(float, x))
            for j in near[:, i]:
                loc, _, uv = pieces[j]
                s = uv[q[j][1][i]]
                loc.Perform(P, float(s[0]), float(s[1]), False)
                if loc.IsDone():
                    d = float(np.sqrt(loc.SquareDistance()))
                    if d < ub[i] and self.inside(*loc.Point().Parameter()):
                        ub[i] = d

    def distances(self, X: np.ndarray) -> np.ndarray:
        """Distances from the points X to the bounded face: exact (``distance``) wherever a point can
        hold the largest, the local search's elsewhere (see ``screened``)."""
        return screened(self, X)

    def _value(self, u, v):
        p = self.surf.Value(float(u), float(v))
        return (p.X(), p.Y(), p.Z())

    def _polish(self, x, u, v, iters: int = 6) -> float:
        """Newton steps on |S(u, v) - x|^2 with OCCT's D2, clamped to the bounds; the best distance seen
        at a point inside the face."""
        best = np.inf
        for _ in range(iters):
            p, du, dv, duu, dvv, duv = gp_Pnt(), gp_Vec(), gp_Vec(), gp_Vec(), gp_Vec(), gp_Vec()
            self.surf.D2(float(u), float(v), p, du, dv, duu, dvv, duv)
            r = np.array(p.Coord()) - x
            if self.inside(u, v):
                best = min(best, float(np.linalg.norm(r)))
            Su, Sv = np.array(du.Coord()), np.array(dv.Coord())
            Suu, Svv, Suv = np.array(duu.Coord()), np.array(dvv.Coord()), np.array(duv.Coord())
            g = np.array([Su @ r, Sv @ r])
            H = np.array([[Su @ Su + Suu @ r, Su @ Sv + Suv @ r], [Su @ Sv + Suv @ r, Sv @ Sv + Svv @ r]])
            try:
                step = np.linalg.solve(H, -g)
            except np.linalg.LinAlgError:
                break
            if not np.all(np.isfinite(step)):
                break
            u = min(max(u + step[0], self.u0), self.u1)
            v = min(max(v + step[1], self.v0), self.v1)
        if self.inside(u, v):
            best = min(best, float(np.linalg.norm(np.array(self._value(u, v)) - x)))
        return best

    def distance(self, x) -> float:
        """Distance from x to the face: the nearest of OCCT's extrema on the surface whose foot lies
        inside the face, its analysis projection when inside, both polished by Newton steps, and the
        nearest boundary point (dense edge samples refined along their edge): the closest point of a
        bounded face is an interior extremum or lies on its boundary."""
        P = gp_Pnt(*map(float, x))
        best, seed = np.inf, None
        self.proj.Perform(P)
        if self.proj.IsDone():
            ext = []
            for i in range(1, self.proj.NbPoints() + 1):
                uv = self.proj.Parameters(i)
                ext.append((float(self.proj.Distance(i)), *uv))
            for d, u, v in sorted(ext):
                if self.inside(u, v):
                    best, seed = d, (u, v)
                    break
        uv = self.sas.ValueOfUV(P, 1e-10)
        u = min(max(uv.X(), self.u0), self.u1)
        v = min(max(uv.Y(), self.v0), self.v1)
        if self.inside(u, v):
            d = float(np.linalg.norm(np.array(self._value(u, v)) - x))
            if d < best:
                best, seed = d, (u, v)
        # OCCT's extrema can miss the nearest point where the surface folds back over itself at a crease:
        # local searches from the nearest seeds of the face's grid, on either sheet
        _, loc, tree, uvs, _ = self._local_search()
        starts = []
        if tree is not None and self.crease is not None:
            _, ks = tree.query(x, k=min(SEEDS, tree.n))
            starts += [uvs[kk] for kk in np.atleast_1d(ks)]
        if self.crease is not None:
            ctree, cuv, cdir = self.crease
            _, ks = ctree.query(x, k=min(SEEDS // 2, ctree.n))
            span = (self.u1 - self.u0, self.v1 - self.v0)
            for kk in np.atleast_1d(ks):
                for side in (-1e-7, 1e-7):
                    st = cuv[kk].copy()
                    st[cdir[kk]] += side * span[cdir[kk]]
                    starts.append(st)
        searches = [(loc, u, v) for u, v in starts]
        near = []
        for ploc, ptree, puv in self._pieces():     # the nearest smooth pieces, each from its own seeds
            ds, ks = ptree.query(x, k=min(2, ptree.n))
            near.append((float(np.min(ds)), ploc, puv[np.atleast_1d(ks)]))
        for _, ploc, puv in sorted(near, key=lambda t: t[0])[:PIECES]:
            searches += [(ploc, u, v) for u, v in puv]
        for lc, u, v in searches:
            lc.Perform(P, float(u), float(v), False)
            if lc.IsDone():
                u, v = lc.Point().Parameter()
                d = float(np.sqrt(lc.SquareDistance()))
                if d < best and self.inside(u, v):
                    best, seed = d, (u, v)
        if seed is not None:
            best = min(best, self._polish(x, *seed, 4))
        if self.edge_pts.size:
            # the boundary may hold the closest point: refined along each edge near one of the nearest
            # samples (a corner's sample is on both its edges, and an edge that moves fast in its
            # parameter can pass far nearer than its samples between two of them)
            de = np.linalg.norm(self.edge_pts - x, axis=1)
            lower = de - self.edge_reach        # no point of the edge near sample k is nearer than this
            for k in np.argsort(lower)[:EDGE_SEEDS]:
                if lower[k] >= best:
                    break
                best = min(best, float(de[k]), self._edge_refine(x, int(k)))
        return best

    def _edge_refine(self, x, k) -> float:
        c = self.curves[self.edge_id[k]]
        same = self.edge_id == self.edge_id[k]
        lo = self.edge_t[k - 1] if k > 0 and same[k - 1] else self.edge_t[k]
        hi = self.edge_t[k + 1] if k + 1 < self.edge_t.size and same[k + 1] else self.edge_t[k]
        return _golden_min(distance_to(c, x), lo, hi, 40)


def hausdorff(face_a, face_b, n: int = 40) -> Hausdorff:
    """Two-sided Hausdorff distance between two faces as bounded by their edges (about n x n samples
    of each plus n along every edge, and rows inward of its edges where the other's lie off their surface
    (ruled.core.edgerows), projected on the other)."""
    from ruled.core.edgerows import edge_offsets, edge_rows, off_edge_points
    from ruled.occ.edgerows import edge_views
    to_a, to_b = _Projector(face_a), _Projector(face_b)
    pa, ra = face_samples(face_a, n, to_a.inside, resolution=True)
    pb, rb = face_samples(face_b, n, to_b.inside, resolution=True)
    # where one face's edges lie off its surface: they are sampled densely (they may leave it at spots), and the
    # other face may cover the strip between them and the surface: rows inward of its edges
    va, vb = edge_views(face_a), edge_views(face_b)
    oa, ob = edge_offsets(va), edge_offsets(vb)
    pa = np.concatenate([pa, edge_rows(va, n, max(ob, default=0.0), to_a.inside.points), off_edge_points(va, oa, n)])
    pb = np.concatenate([pb, edge_rows(vb, n, max(oa, default=0.0), to_b.inside.points), off_edge_points(vb, ob, n)])
    return replace(two_sided(pa, pb, to_a, to_b), resolution=max(ra, rb))


def two_sided(pa: np.ndarray, pb: np.ndarray, to_a, to_b) -> Hausdorff:
    """The Hausdorff measure from the samples pa of A and pb of B and the projectors onto each."""
    dab = to_b.distances(pa)
    dba = to_a.distances(pb)
    alld = np.concatenate([dab, dba])
    return Hausdorff(float(alld.max()), float(alld.mean()), float(dab.max()), float(dba.max()), int(alld.size))


