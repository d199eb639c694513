"""Independent error measure inside FreeCAD: the two-sided Hausdorff distance between two faces as
bounded by their edges: about n x n points of each inside its edges (Part's isPartOfDomain on a grid
of its parameter range) and n along every edge, each point's exact distance to the other bounded face
by OCCT's BRepExtrema (Part's distToShape).  The same points and faces as the command line's measure
(ruled.occ.measure), so both agree."""

from __future__ import annotations

import FreeCAD
import numpy as np
import Part

from ruled.core.hostform import Hausdorff, PolygonClassifier, grid_size


def face_bounds(face):
    """The face's parameter range, clipped to its surface's own range where not periodic."""
    u0, u1, v0, v1 = face.ParameterRange
    s = face.Surface
    a0, a1, b0, b1 = s.bounds()
    if not s.isUPeriodic():
        u0, u1 = max(u0, a0), min(u1, a1)
    if not s.isVPeriodic():
        v0, v1 = max(v0, b0), min(v1, b1)
    return u0, u1, v0, v1


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
    return PolygonClassifier(lambda: _polylines(face), face_bounds(face), face.isPartOfDomain)


def face_points(face, n: int) -> np.ndarray:
    """About n x n points of the face inside its edges (a grid of its parameter range as dense as it takes)
    and n points along every edge."""
    u0, u1, v0, v1 = face_bounds(face)
    s = face.Surface
    cls = classifier(face)
    frac = float(cls.grid(np.linspace(u0, u1, 24), np.linspace(v0, v1, 24)).mean())
    m = grid_size(n, frac)
    us, vs = np.linspace(u0, u1, m), np.linspace(v0, v1, m)
    keep = np.ones((m, m), bool) if m == n else cls.grid(us, vs)
    pts = [tuple(s.value(float(us[i]), float(vs[j]))) for i, j in zip(*np.nonzero(keep))]
    for e in face.Edges:
        if not e.Degenerated:
            a, b = e.ParameterRange
            pts += [tuple(e.valueAt(float(t))) for t in np.linspace(a, b, n)]
    return np.array(pts)


def distances(points: np.ndarray, face, progress=None) -> np.ndarray:
    out = np.empty(len(points))
    for i, p in enumerate(points):
        out[i] = face.distToShape(Part.Vertex(FreeCAD.Vector(*map(float, p))))[0]
        if progress is not None and i % 64 == 0:
            progress(i / len(points))
    return out


def hausdorff(results: list, design, n: int = 24, progress=None) -> Hausdorff:
    """Several result faces (strips, sides, patches) against the face they replace together: each
    result's n x n grid to the bounded design face (kept per face, in order, for colouring), and the
    design face's points to the nearest result (one compound, so the distance is to their union)."""
    total = len(results) * n * n
    dab, done = [], 0
    for f in results:
        dab.append(distances(grid(f, n), design, None if progress is None else
                             (lambda x, d=done: progress(0.5 * (d + x * n * n) / total))))
        done += n * n
    dab = np.concatenate(dab) if dab else np.zeros(0)
    pb = face_points(design, n)
    dba = distances(pb, Part.Compound(results), None if progress is None else (lambda x: progress(0.5 + 0.5 * x)))
    alld = np.concatenate([dab, dba])
    return Hausdorff(float(alld.max()), float(alld.mean()), float(dab.max()), float(dba.max()), int(alld.size),
                     tuple(dab))
