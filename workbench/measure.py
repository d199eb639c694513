"""Independent error measure inside FreeCAD: the two-sided Hausdorff distance between two faces as
bounded by their edges: about n x n points of each inside its edges (Part's isPartOfDomain on a grid
of its parameter range) and n along every edge, each point's exact distance to the other bounded face
by OCCT's BRepExtrema (Part's distToShape).  The same points and faces as the command line's measure
(ruled.occ.measure), so both agree."""

from __future__ import annotations

import FreeCAD
import numpy as np
import Part

from ruled.core.hostform import Hausdorff, PolygonClassifier, clipped_bounds, grid_size


def face_bounds(face):
    """The face's parameter range, clipped to its surface's own range where not periodic."""
    s = face.Surface
    return clipped_bounds(face.ParameterRange, s.bounds(), (s.isUPeriodic(), s.isVPeriodic()))


def grid(face, n: int) -> np.ndarray:
    """n x n points over the face's parameter range (the result's own grid, for colouring)."""
    u0, u1, v0, v1 = face_bounds(face)
    s = face.Surface
    return np.array([tuple(s.value(float(u), float(v))) for u in np.linspace(u0, u1, n)
                     for v in np.linspace(v0, v1, n)])


def _polylines(face, per_edge: int = 256):
    """The pcurves of the face's edges as polylines in its (u, v) (Part's evaluation), or None when an
    edge has none."""
    out = []
    for e in face.Edges:
        got = face.curveOnSurface(e)
        if not got:
            return None
        c2, a, b = got
        out.append(np.array([(q.x, q.y) for q in (c2.value(float(t)) for t in np.linspace(a, b, per_edge))]))
    return out


def classifier(face) -> PolygonClassifier:
    """Which (u, v) are inside the face: its pcurves' polylines, Part's isPartOfDomain near them."""
    S = face.Surface
    periods = (S.UPeriod() if S.isUPeriodic() else 0.0, S.VPeriod() if S.isVPeriodic() else 0.0)
    return PolygonClassifier(lambda: _polylines(face), face_bounds(face), face.isPartOfDomain, periods)


def _inside(face, n: int) -> tuple:
    """(m, keep, points): the m x m grid of the face's parameter range as dense as it takes for about n x n
    of its nodes to lie inside its edges, which do (m * m booleans, u outer, v inner, as ``grid``), and
    their points."""
    u0, u1, v0, v1 = face_bounds(face)
    s = face.Surface
    cls = classifier(face)
    frac = float(cls.grid(np.linspace(u0, u1, 24), np.linspace(v0, v1, 24)).mean())
    m = grid_size(n, frac)
    us, vs = np.linspace(u0, u1, m), np.linspace(v0, v1, m)
    keep = np.ones((m, m), bool) if m == n else cls.grid(us, vs)
    pts = [tuple(s.value(float(us[i]), float(vs[j]))) for i, j in zip(*np.nonzero(keep))]
    return m, keep.ravel(), np.array(pts).reshape(-1, 3)


def _edge_points(face, n: int) -> np.ndarray:
    pts = [tuple(e.valueAt(float(t))) for e in face.Edges if not e.Degenerated
           for t in np.linspace(*e.ParameterRange, n)]
    return np.array(pts).reshape(-1, 3)


def face_points(face, n: int) -> np.ndarray:
    """About n x n points of the face inside its edges (a grid of its parameter range as dense as it takes)
    and n points along every edge."""
    return np.concatenate([_inside(face, n)[2], _edge_points(face, n)])


def distances(points: np.ndarray, face, progress=None) -> np.ndarray:
    """Each point's distance to the bounded face: OCCT's (Part's distToShape), or where the point's
    projection onto the face's surface lies inside the face or on its boundary (the command line's
    classifier), that distance when smaller.  A point on the surface a hair past the pcurves, where a
    result trimmed by them ends, is that far from the face, not as far as the face's 3D edge there
    (which may lie off the surface within its tolerance)."""
    out = np.empty(len(points))
    faces = [(f.Surface, classifier(f), face_bounds(f)) for f in face.Faces]     # (a face, or a compound's)
    for i, p in enumerate(points):
        x = FreeCAD.Vector(*map(float, p))
        d = face.distToShape(Part.Vertex(x))[0]
        for s, cls, box in faces:
            try:
                u, v = s.parameter(x)
            except Exception:       # (no projection: Part raises its own exception types)
                continue
            if box[0] <= u <= box[1] and box[2] <= v <= box[3] and cls(u, v):
                d = min(d, float((s.value(u, v) - x).Length))
        out[i] = d
        if progress is not None and i % 16 == 0:
            progress(i / len(points))
    return out


SEEDS = 48      # a face's grid of seeds for the quick projections, per direction
EXACT_CAP = 400     # at most this many points measured exactly per call (the command line's measure's cap)


def upper_distances(points: np.ndarray, face) -> np.ndarray:
    """Each point's distance to a point of the bounded face, at least the distance to the face and, where the
    point's foot lies inside it, equal to it: the engine's projection onto each face's B-spline surface (from
    the nearest of a grid of seeds) where the foot is inside the face (its classifier), else the nearest of the
    face's edge samples (points of the face too).  Part's surfaces evaluate the points kept."""
    from scipy.spatial import cKDTree

    from ruled.core.distance import project_points

    from .arrays import surface_to_arrays
    X = np.asarray(points, float).reshape(-1, 3)
    best = np.full(len(X), np.inf)
    edge = _edge_points(face, 64)
    if len(edge):
        best = np.minimum(best, cKDTree(edge).query(X)[0])
    for f in face.Faces:
        if not isinstance(f.Surface, Part.BSplineSurface):
            try:                # (a plane, a cylinder: its B-spline form, points of the same face)
                f = f.toNurbs().Faces[0]
            except Exception:   # (Part raises its own types; the exact pass measures such a face)
                continue
        s = f.Surface
        S = surface_to_arrays(s)
        u0, u1, v0, v1 = face_bounds(f)
        us, vs = np.linspace(u0, u1, SEEDS), np.linspace(v0, v1, SEEDS)
        UU, VV = np.meshgrid(us, vs, indexing="ij")
        seeds = np.stack([UU.ravel(), VV.ravel()], axis=1)
        k = cKDTree(S(seeds[:, 0], seeds[:, 1])).query(X)[1]
        uv, _ = project_points(S, X, seeds[k], 8)
        inside = (uv[:, 0] >= u0) & (uv[:, 0] <= u1) & (uv[:, 1] >= v0) & (uv[:, 1] <= v1)
        inside[inside] = classifier(f).points(uv[inside])
        for i in np.nonzero(inside)[0]:         # (Part's point, not the engine's: a point of the face)
            p = s.value(float(uv[i, 0]), float(uv[i, 1]))
            best[i] = min(best[i], float(np.linalg.norm(np.array((p.x, p.y, p.z)) - X[i])))
    return best


def screened_distances(points: np.ndarray, face, progress=None) -> np.ndarray:
    """Each point's distance to the bounded face (distances' figure wherever a point can hold the largest):
    upper_distances for every point, distances in decreasing order of them while one can exceed the largest
    exact distance found (ruled.core.hostform.screened, the command line's measure's screen; at most EXACT_CAP)."""
    from types import SimpleNamespace

    from ruled.core.hostform import screened
    proj = SimpleNamespace(upper=lambda X: upper_distances(X, face),
                           distance=lambda x: float(distances(x.reshape(1, 3), face)[0]))
    return screened(proj, points, EXACT_CAP, progress)


def edge_views(face) -> list:
    """The face's edges with a pcurve, as the measures' EdgeViews (ruled.core.edgerows; Part's evaluation, as
    the command line's OCCT one)."""
    from ruled.core.edgerows import EdgeView
    s, box = face.Surface, face_bounds(face)

    def surface(u, v):
        return tuple(s.value(float(u), float(v)))
    out = []
    for e in face.Edges:
        got = None if e.Degenerated else face.curveOnSurface(e)
        if not got:
            continue
        c2, a, b = got

        def pcurve(t, c2=c2):
            q = c2.value(float(t))
            return (q.x, q.y)

        def curve(t, e=e):
            return tuple(e.valueAt(float(t)))
        out.append(EdgeView(surface, pcurve, a, b, curve, *e.ParameterRange, box))
    return out


def _extra(face, n: int, offset: float) -> np.ndarray:
    """The face's extra samples where edges lie off their surface (ruled.core.edgerows): its own such edges,
    densely, and rows inward of its edges at fractions of the other side's edges' offset."""
    from ruled.core.edgerows import edge_offsets, edge_rows, off_edge_points
    views = edge_views(face)
    return np.concatenate([edge_rows(views, n, offset, classifier(face).points),
                           off_edge_points(views, edge_offsets(views), n)])


def _offset(faces) -> float:
    """How far the faces' edges lie off their surfaces, at most (ruled.core.edgerows.edge_offsets)."""
    from ruled.core.edgerows import edge_offsets
    return max([g for f in faces for g in edge_offsets(edge_views(f))], default=0.0)


def trimmed(face) -> bool:
    """The face is trimmed inside its surface's rectangle (a result trimmed by the design face's edges)."""
    u0, u1, v0, v1 = face_bounds(face)
    return bool(face.Area < (1.0 - 1e-3) * face.Surface.toShape(u0, u1, v0, v1).Area)


def _filled(d: np.ndarray, inside: np.ndarray, m: int) -> np.ndarray:
    """Grid values outside a trimmed face taken from the nearest node inside (for colouring only)."""
    from scipy.ndimage import distance_transform_edt
    if not inside.any():
        return d
    _, (i, j) = distance_transform_edt(~inside.reshape(m, m), return_indices=True)
    return d.reshape(m, m)[i, j].ravel()


def _result_side(f, design, n: int, progress) -> tuple:
    """(the distances to the design face of the result's grid, for colouring: n x n over its parameters,
    or for a trimmed result m x m, about n x n inside its edges, and values outside from the nearest inside;
    the distances measured: inside its edges and along them for a trimmed result)."""
    if not trimmed(f):
        d = screened_distances(grid(f, n), design, progress)
        return d, d
    m, keep, pts = _inside(f, n)
    d = screened_distances(np.concatenate([pts, _edge_points(f, n)]), design, progress)
    full = np.zeros(m * m)
    full[keep] = d[:len(pts)]
    return _filled(full, keep, m), d


def corner_points(face, n: int) -> np.ndarray:
    """n points along each ruling of the face's B-spline surface at its corners (ruled.core.edgerows.
    corner_rulings, as the OCCT measure takes them), inside its parameter range; none for another surface."""
    from ruled.core.edgerows import corner_rulings
    s = face.Surface
    if not isinstance(s, Part.BSplineSurface):
        return np.zeros((0, 3))

    def flat(knots, mults):
        return [k for k, m in zip(knots, mults) for _ in range(m)]
    uv = corner_rulings(flat(s.getUKnots(), s.getUMultiplicities()), flat(s.getVKnots(), s.getVMultiplicities()),
                        s.UDegree, s.VDegree, face.ParameterRange, n)
    return np.array([tuple(s.value(float(u), float(v))) for u, v in uv], float).reshape(-1, 3)


def _wall_points(results: list, design, n: int) -> tuple:
    """A wall's extra samples (ruled.occ.wall.measure_wall's): CORNERS x n points along the result's corner
    rulings, and along every edge of the wall's faces."""
    from ruled.core.edgerows import CORNERS
    ra = np.concatenate([corner_points(f, CORNERS * n) for f in results]) if results else np.zeros((0, 3))
    pb = [np.array([tuple(p) for p in e.discretize(Number=CORNERS * n)], float).reshape(-1, 3)
          for f in design.Faces for e in f.Edges if not e.Degenerated]
    return ra, np.concatenate(pb) if pb else np.zeros((0, 3))


def hausdorff(results: list, design, n: int = 24, progress=None, parts=None, wall: bool = False) -> Hausdorff:
    """Several result faces (strips, sides, patches) against the face they replace together (or a wall's
    faces, a compound of them, against its closed result): each
    result's n x n grid to the bounded design face (kept per face, in order, for colouring; a result
    trimmed by the design's edges measured inside its edges and along them), and the design face's points
    to the nearest result (one compound, so the distance is to their union; of parts, the results' smooth
    parts, where given: OCCT's distance search does not cross a crease); a wall's: its extra samples too
    (_wall_points)."""
    total = len(results) * n * n
    g_design, g_results = _offset(design.Faces), _offset(results)
    colours, dab, done = [], [], 0
    for f in results:
        c, d = _result_side(f, design, n, None if progress is None else
                            (lambda x, d=done: progress(0.5 * (d + x * n * n) / total)))
        colours.append(c)
        dab.append(d)
        rows = _extra(f, n, g_design)
        if len(rows):
            dab.append(screened_distances(rows, design))
        done += n * n
    ra, rb = _wall_points(results, design, n) if wall else (np.zeros((0, 3)), np.zeros((0, 3)))
    if len(ra):
        dab.append(screened_distances(ra, design))
    dab = np.concatenate(dab) if dab else np.zeros(0)
    pb = np.concatenate([np.concatenate([face_points(f, n), _extra(f, n, g_results)])
                         for f in design.Faces] + [rb])      # (a face, or a wall's faces)
    dba = screened_distances(pb, Part.Compound(parts or results),
                    None if progress is None else (lambda x: progress(0.5 + 0.5 * x)))
    alld = np.concatenate([dab, dba])
    return Hausdorff(float(alld.max()), float(alld.mean()), float(dab.max()), float(dba.max()), int(alld.size),
                     tuple(np.concatenate(colours)) if colours else ())


def measure_into(obj, results: list, design, progress=None, parts=None, wall: bool = False) -> None:
    """Measure the result faces against the design face into obj.Hausdorff and obj.Deviation (skipped,
    0 and empty, when obj.MeasureSamples < 2); parts: the results' smooth parts (faces) to measure the
    design's points against, where a result has creases."""
    n = int(obj.MeasureSamples)
    if n < 2 or not results:
        obj.Hausdorff, obj.Deviation = 0.0, []
        return
    h = hausdorff(results, design, n, progress, parts, wall)
    obj.Hausdorff, obj.Deviation = h.max, list(h.a_to_b)
