"""Independent error measure: two-sided Hausdorff distance between two faces by dense
sampling plus exact point projection with OCCT (no code of the engine is used).  Trim-aware: the
samples are points of each face as bounded by its edges, and distances are to the bounded face."""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from OCP.BRep import BRep_Tool
from OCP.BRepTools import BRepTools
from OCP.Adaptor3d import Adaptor3d_CurveOnSurface
from OCP.Extrema import Extrema_ExtPC, Extrema_GenLocateExtPS
from OCP.Geom2dAdaptor import Geom2dAdaptor_Curve
from OCP.GeomAdaptor import GeomAdaptor_Surface
from OCP.GeomAPI import GeomAPI_ProjectPointOnCurve, GeomAPI_ProjectPointOnSurf
from OCP.ShapeAnalysis import ShapeAnalysis_Surface
from OCP.BRepAdaptor import BRepAdaptor_Curve
from OCP.BRepTopAdaptor import BRepTopAdaptor_FClass2d
from OCP.TopAbs import TopAbs_ShapeEnum, TopAbs_State
from OCP.TopExp import TopExp_Explorer
from OCP.TopoDS import TopoDS
from OCP.gp import gp_Pnt, gp_Pnt2d, gp_Vec

from ..hostform import Hausdorff, PolygonClassifier, grid_size

SEED_GRID = 60     # about SEED_GRID^2 seeds inside a face for the local projections
SEEDS = 8          # the exact distance also searches locally from this many nearest seeds
PIECES = 6         # ... and in this many nearest smooth pieces between creases, from their own seeds


def face_bounds(face):
    """The face's UV bounds, clipped to its surface's own range (faces may overhang it by round-off)."""
    u0, u1, v0, v1 = BRepTools.UVBounds_s(face)
    surf = BRep_Tool.Surface_s(face)
    a0, a1, b0, b1 = surf.Bounds()
    if not surf.IsUPeriodic():
        u0, u1 = max(u0, a0), min(u1, a1)
    if not surf.IsVPeriodic():
        v0, v1 = max(v0, b0), min(v1, b1)
    return u0, u1, v0, v1


def _face_edges(face):
    """The face's edges with a 3D curve (every wire, degenerate edges left out)."""
    out = []
    ex = TopExp_Explorer(face, TopAbs_ShapeEnum.TopAbs_EDGE)
    while ex.More():
        e = TopoDS.Edge_s(ex.Current())
        if not BRep_Tool.Degenerated_s(e):
            out.append(e)
        ex.Next()
    return out


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
    return PolygonClassifier(lambda: _boundary_polygon(face), face_bounds(face), exact)


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
            adaptor = GeomAdaptor_Surface(self.surf, self.u0, self.u1, self.v0, self.v1)
            self._local = (adaptor, Extrema_GenLocateExtPS(adaptor, 1e-10, 1e-10),
                           cKDTree(pts) if len(pts) else None, uv,
                           cKDTree(self.edge_pts) if len(self.edge_pts) else None)
        return self._local

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
                        ad = GeomAdaptor_Surface(self.surf, a, b, c, d)
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
            for i, (x, kk) in enumerate(zip(X, k)):
                loc.Perform(gp_Pnt(*map(float, x)), float(uv[kk, 0]), float(uv[kk, 1]), False)
                if loc.IsDone():
                    feet[i] = loc.Point().Parameter()
                    dist[i] = np.sqrt(loc.SquareDistance())
            ok = np.isfinite(dist)
            ok[ok] = self.inside.points(feet[ok])
            ub[ok] = np.minimum(ub[ok], dist[ok])
        if etree is not None:
            de, ke = etree.query(X)
            ub = np.minimum(ub, de)
            for i in np.nonzero(de < 1.5 * ub + 1e-12)[0]:
                ub[i] = min(ub[i], self._edge_refine(X[i], ke[i]))
        return ub

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
            de = np.linalg.norm(self.edge_pts - x, axis=1)
            k = int(np.argmin(de))
            if de[k] < 1.5 * best + 1e-12:  # the boundary may hold the closest point
                best = min(best, float(de[k]), self._edge_refine(x, k))
        return best

    def _edge_refine(self, x, k) -> float:
        c = self.curves[self.edge_id[k]]
        same = self.edge_id == self.edge_id[k]
        lo = self.edge_t[k - 1] if k > 0 and same[k - 1] else self.edge_t[k]
        hi = self.edge_t[k + 1] if k + 1 < self.edge_t.size and same[k + 1] else self.edge_t[k]

        def f(t):
            return np.linalg.norm(_p3(c.Value(float(t))) - x)
        return _golden_min(f, lo, hi, 40)


def hausdorff(face_a, face_b, n: int = 40) -> Hausdorff:
    """Two-sided Hausdorff distance between two faces as bounded by their edges (about n x n samples
    of each plus n along every edge, projected on the other)."""
    to_a, to_b = _Projector(face_a), _Projector(face_b)
    pa, ra = face_samples(face_a, n, to_a.inside, resolution=True)
    pb, rb = face_samples(face_b, n, to_b.inside, resolution=True)
    return replace(two_sided(pa, pb, to_a, to_b), resolution=max(ra, rb))


def screened(proj, X: np.ndarray, cap: int = 400) -> np.ndarray:
    """Distances from the points X to what proj measures (an object with a vectorized ``upper`` and an
    exact, slower ``distance``).  Every value is the distance to an actual point of the face, so at
    least the true one.  The exact search runs on the points in decreasing order of their upper value
    while that exceeds the largest exact distance found so far: the maximum is then the exact
    search's own maximum over all points, found with a few hundred exact projections instead of one
    per point (at most ``cap``; beyond, the upper values stand, which can only raise the maximum)."""
    X = np.asarray(X, float).reshape(-1, 3)
    d = proj.upper(X)
    top = 0.0
    order = np.argsort(-d, kind="stable")
    for i in order[:cap]:
        if d[i] <= top:
            break
        d[i] = min(d[i], proj.distance(X[i]))
        top = max(top, d[i])
    return d


def two_sided(pa: np.ndarray, pb: np.ndarray, to_a, to_b) -> Hausdorff:
    """The Hausdorff measure from the samples pa of A and pb of B and the projectors onto each."""
    dab = to_b.distances(pa)
    dba = to_a.distances(pb)
    alld = np.concatenate([dab, dba])
    return Hausdorff(float(alld.max()), float(alld.mean()), float(dab.max()), float(dba.max()), int(alld.size))


@dataclass(frozen=True)
class CurveMeasure:
    hausdorff: float          # two-sided, result <-> exact image
    result_to_exact: float
    exact_to_result: float
    on_surface: float         # largest distance of a result sample to the surface (projection)
    joints: list              # [(t, angle between the result's one-sided tangents, the exact image's)]
    samples: int

    def max_joint_angle_deg(self, corner_deg: float = 180.0) -> float:
        """The largest joint angle where the exact image itself turns by less than corner_deg."""
        a = [r for _, r, e in self.joints if not e >= corner_deg]
        return max(a) if a else 0.0

    def corners(self, corner_deg: float) -> list:
        return [(t, r, e) for t, r, e in self.joints if e >= corner_deg]


def _p3(p) -> np.ndarray:
    return np.array((p.X(), p.Y(), p.Z()))


def _seeded(curve, ts, pts, x, iters: int = 60) -> float:
    """Distance from x to a curve (anything with Value(t)): golden-section search around the
    nearest of the dense samples pts (at parameters ts)."""
    k = int(np.argmin(np.linalg.norm(pts - x, axis=1)))
    a, b = ts[max(k - 1, 0)], ts[min(k + 1, ts.size - 1)]

    def f(t):
        return float(np.linalg.norm(_p3(curve.Value(float(t))) - x))
    return min(_golden_min(f, a, b, iters), float(np.linalg.norm(pts[k] - x)))


def _golden_min(f, a, b, iters: int):
    """The smallest value golden-section search finds for f on [a, b]; elementwise when a, b are arrays
    (f then maps arrays of parameters to arrays of values)."""
    g = 0.5 * (np.sqrt(5) - 1)
    a, b = np.asarray(a, float), np.asarray(b, float)
    c, d = b - g * (b - a), a + g * (b - a)
    fc, fd = np.asarray(f(c), float), np.asarray(f(d), float)
    for _ in range(iters):
        left = fc < fd
        a, b = np.where(left, a, c), np.where(left, d, b)
        c, d = np.where(left, b - g * (b - a), d), np.where(left, c, a + g * (b - a))
        fn = np.asarray(f(np.where(left, c, d)), float)
        fc, fd = np.where(left, fn, fd), np.where(left, fc, fn)
    m = np.minimum(fc, fd)
    return float(m) if m.ndim == 0 else m


def _angle(a: gp_Vec, b: gp_Vec) -> float:
    if a.Magnitude() == 0 or b.Magnitude() == 0:
        return float("nan")
    return float(np.degrees(a.Angle(b)))


def _result_angle(result, ta, ia, ja, tb, ib, jb) -> float:
    p, q = gp_Pnt(), gp_Pnt()
    va, vb = gp_Vec(), gp_Vec()
    result.LocalD1(ta, ia, ja, p, va)
    result.LocalD1(tb, ib, jb, q, vb)
    return _angle(va, vb)


def _exact_angle(surface, domain, ta, tb) -> float:
    """Angle between the exact image's tangent arriving at domain(ta) and leaving from domain(tb)
    (one-sided at the domain curve's knots)."""
    from OCP.gp import gp_Pnt2d, gp_Vec2d

    def tangent(t, left):
        k = [domain.Knot(i) for i in range(1, domain.NbKnots() + 1)]
        j = int(np.searchsorted(k, t, side="left" if left else "right"))
        j = min(max(j, 1), len(k) - 1)       # the span [k[j-1], k[j]] (1-based knots j, j + 1)
        p2, d2 = gp_Pnt2d(), gp_Vec2d()
        domain.LocalD1(t, j, j + 1, p2, d2)
        p, su, sv = gp_Pnt(), gp_Vec(), gp_Vec()
        surface.D1(p2.X(), p2.Y(), p, su, sv)
        return su.Multiplied(d2.X()).Added(sv.Multiplied(d2.Y()))
    return _angle(tangent(ta, True), tangent(tb, False))


def curve_on_surface_measure(surface, domain, result, n: int = 2000, pcurve=None) -> CurveMeasure:
    """Measure a curve meant to lie on a surface against the exact image of a domain curve, with
    OCCT only: surface a Geom_Surface, domain a Geom2d_Curve in its (u, v), result a
    Geom_BSplineCurve.  The exact image is OCCT's curve on surface; n samples of each curve (plus
    every knot of the result) are projected exactly onto the other (Extrema / GeomAPI), ends
    included.  The distance to the surface is GeomAPI_ProjectPointOnSurf's or, when the result's
    pcurve (a Geom2d_Curve on the same parameters) is given and closer, |result(t) - surface(pcurve(t))|
    (the projection can miss the foot on a folded surface)."""
    exact = Adaptor3d_CurveOnSurface(Geom2dAdaptor_Curve(domain), GeomAdaptor_Surface(surface))
    e0, e1 = domain.FirstParameter(), domain.LastParameter()
    r0, r1 = result.FirstParameter(), result.LastParameter()
    dk = [e0] + [domain.Knot(i) for i in range(1, domain.NbKnots() + 1) if e0 < domain.Knot(i) < e1] + [e1]
    rk = [result.Knot(i) for i in range(1, result.NbKnots() + 1)]
    # the curves' knot points: the closest point may sit at a corner, where no extremum exists
    kp_exact = np.array([_p3(exact.Value(float(t))) for t in dk])
    kp_res = np.array([_p3(result.Value(float(t))) for t in rk])
    tr = np.unique(np.concatenate([np.linspace(r0, r1, n), rk]))
    te = np.unique(np.concatenate([np.linspace(e0, e1, n), dk]))
    pr = np.array([_p3(result.Value(float(t))) for t in tr])
    pe = np.array([_p3(exact.Value(float(t))) for t in te])
    # result -> exact image: extrema on every knot span of the domain curve, the knot points (the
    # closest point may sit at a corner, where no extremum exists) and a golden-section search
    # seeded at the nearest dense sample (OCCT's extrema can miss a minimum near a span's end)
    d_re = 0.0
    d_surf = 0.0
    ps = GeomAPI_ProjectPointOnSurf()
    u0, u1, v0, v1 = surface.Bounds()
    ps.Init(surface, u0, u1, v0, v1)
    for t, x in zip(tr, pr):
        p = gp_Pnt(*map(float, x))
        best = min(float(np.linalg.norm(kp_exact - x, axis=1).min()), _seeded(exact, te, pe, x))
        for a, b in zip(dk[:-1], dk[1:]):
            ext = Extrema_ExtPC(p, exact, a, b, 1e-10)
            if ext.IsDone():
                for k in range(1, ext.NbExt() + 1):
                    best = min(best, float(np.sqrt(ext.SquareDistance(k))))
        d_re = max(d_re, best)
        ds = np.inf
        ps.Perform(p)
        if ps.IsDone() and ps.NbPoints() > 0:
            ds = float(ps.LowerDistance())
        if pcurve is not None:
            q = pcurve.Value(float(t))
            ds = min(ds, float(surface.Value(q.X(), q.Y()).Distance(p)))
        d_surf = max(d_surf, ds)
    # exact image -> result
    d_er = 0.0
    pc = GeomAPI_ProjectPointOnCurve()
    for t, x in zip(te, pe):
        best = min(float(np.linalg.norm(kp_res - x, axis=1).min()), _seeded(result, tr, pr, x))
        pc.Init(gp_Pnt(*map(float, x)), result)
        if pc.NbPoints() > 0:
            best = min(best, float(pc.LowerDistance()))
        d_er = max(d_er, best)
    # joints: the result's one-sided tangents at its interior knots (and at the closing point of a
    # closed curve), beside the exact image's own one-sided tangents there (a corner of the domain
    # curve or a polyline vertex is a corner of the exact image too)
    joints = []
    nk = result.NbKnots()
    for i in range(2, nk):
        t = result.Knot(i)
        joints.append((t, _result_angle(result, t, i - 1, i, t, i, i + 1),
                       _exact_angle(surface, domain, t, t)))
    if result.IsClosed() and nk > 2:
        joints.append((r1, _result_angle(result, r1, nk - 1, nk, r0, 1, 2), _exact_angle(surface, domain, e1, e0)))
    return CurveMeasure(max(d_re, d_er), d_re, d_er, d_surf, joints, int(tr.size + te.size))


# ------------------------------------------------------------------------------ several faces
class FaceSet:
    """Distances from points to the nearest of several faces: each face's projector, tried on the faces
    that can be the nearest one by their coarse sample clouds."""

    def __init__(self, faces, n: int = 24):
        from scipy.spatial import cKDTree

        self.proj = [_Projector(f) for f in faces]
        samples = [face_samples(f, n, resolution=True) for f in faces]
        self.trees = [cKDTree(c) for c, _ in samples]
        # per face, how far a point of it can be from its cloud: the face can be this much nearer to a
        # point than its cloud is
        self.slack = np.array([r for _, r in samples])

    def _candidates(self, X: np.ndarray, chunk: int = 4096) -> np.ndarray:
        """(N, faces) booleans: the faces that can be the nearest to each point.  A face's cloud lies on
        it, so the nearest face is at most the nearest cloud's distance away; a face whose cloud is
        farther than that by more than its slack cannot be the nearest."""
        out = np.zeros((len(X), len(self.proj)), bool)
        for lo in range(0, len(X), chunk):
            D = np.column_stack([t.query(X[lo:lo + chunk])[0] for t in self.trees])
            out[lo:lo + chunk] = D - self.slack[None, :] <= D.min(axis=1, keepdims=True)
        return out

    def distance(self, x) -> float:
        cand = np.nonzero(self._candidates(np.asarray(x, float).reshape(1, 3))[0])[0]
        return min(self.proj[i].distance(x) for i in cand)

    def upper(self, X: np.ndarray) -> np.ndarray:
        X = np.asarray(X, float).reshape(-1, 3)
        cand = self._candidates(X)
        ub = np.full(len(X), np.inf)
        for i, p in enumerate(self.proj):
            m = cand[:, i]
            if m.any():
                ub[m] = np.minimum(ub[m], p.upper(X[m]))
        return ub

    def distances(self, X: np.ndarray) -> np.ndarray:
        return screened(self, X)


def sample_faces(faces, n: int) -> np.ndarray:
    """About n x n samples of each face as bounded by its edges (OCCT evaluation), stacked."""
    return np.concatenate([face_points(f, n) for f in faces])


def to_lines(points: np.ndarray, ends, m: int = 2049, iters: int = 40) -> np.ndarray:
    """Distances from points to the ruled surface swept by the segments ends(v) = (A(v), B(v)), v in
    [0, 1] (each (N, 3)): the nearest of m segments, then a golden-section search over v between its
    neighbours, exact segment distances throughout."""
    def seg(X, A, B):
        D = B - A
        s = np.clip(((X - A) * D).sum(axis=-1) / np.maximum((D * D).sum(axis=-1), 1e-300), 0, 1)
        return np.linalg.norm(X - (A + s[..., None] * D), axis=-1)
    vs = np.linspace(0.0, 1.0, m)
    A, B = ends(vs)
    size = float(np.ptp(np.vstack([A, B]), axis=0).max())
    closed = max(np.linalg.norm(A[0] - A[-1]), np.linalg.norm(B[0] - B[-1])) <= 1e-12 * max(size, 1e-300)
    out = np.empty(len(points))
    for i in range(0, len(points), 256):
        X = points[i:i + 256]
        d = seg(X[:, None, :], A[None], B[None])
        k = np.argmin(d, axis=1)

        def f(v, X=X):
            a, b = ends(v)
            return seg(X, a, b)
        best = np.minimum(d[np.arange(len(X)), k],
                          _golden_min(f, vs[np.maximum(k - 1, 0)], vs[np.minimum(k + 1, m - 1)], iters))
        if closed:            # v = 0 and v = 1 are one ruling: search the other side of the seam too
            k2 = np.where(k == 0, m - 1, np.where(k == m - 1, 0, k))
            best = np.minimum(best, _golden_min(f, vs[np.maximum(k2 - 1, 0)], vs[np.minimum(k2 + 1, m - 1)], iters))
        out[i:i + 256] = best
    return out
