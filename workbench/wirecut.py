"""The design faces, in FreeCAD, for the measure of what a wire cuts from its lines alone (ruled.machine.wirecut,
the command line's measure and ``ruled replay``'s): the same points of each face as bounded by its edges as the
command line's (workbench.measure.face_points), with their normals on the wire's side, and the feet of points on
the faces' surfaces (the face's B-spline as arrays, a Newton projection from the nearest of a grid of seeds over
its parameter range), kept where the foot is orthogonal and inside its face (its pcurves' classifier)."""

from __future__ import annotations

import numpy as np
import Part

from .measure import SEEDS, classifier, face_bounds, face_points

ORTHOGONAL = 1e-3       # a foot is orthogonal when the point's offset along the surface is below this of its distance


class _Face:
    def __init__(self, face, side: float):
        from scipy.spatial import cKDTree

        from .arrays import surface_to_arrays
        self.face = face
        nurbs = face if isinstance(face.Surface, Part.BSplineSurface) else face.toNurbs().Faces[0]
        self.S = surface_to_arrays(nurbs.Surface)
        self.bounds = face_bounds(nurbs)
        self.inside = classifier(nurbs)
        u0, u1, v0, v1 = self.bounds
        uu, vv = np.meshgrid(np.linspace(u0, u1, SEEDS), np.linspace(v0, v1, SEEDS), indexing="ij")
        self.seeds = np.stack([uu.ravel(), vv.ravel()], axis=1)
        P = self.S(self.seeds[:, 0], self.seeds[:, 1])
        self.tree = cKDTree(P)
        G = P.reshape(SEEDS, SEEDS, 3)          # no point of the face is farther from its nearest seed than this
        self.reach = max(float(np.linalg.norm(np.diff(G, axis=0), axis=2).max()),
                         float(np.linalg.norm(np.diff(G, axis=1), axis=2).max()))
        # +1 where the wire runs on the side the face's normal in its solid points to (off the material)
        self.sign = side * (-1.0 if face.Orientation == "Reversed" else 1.0)

    def frames(self, uv: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(points, unit normals on the wire's side) at the parameters uv (N, 2)."""
        D = self.S.evaluate(uv[:, 0], uv[:, 1], 1)
        n = np.cross(D.Su, D.Sv)
        return D.P, self.sign * n / np.maximum(np.linalg.norm(n, axis=1), 1e-300)[:, None]

    def normals_near(self, uv: np.ndarray) -> np.ndarray:
        """Unit normals on the wire's side at uv clamped into the face's range, a hair towards its middle where the
        surface has none (a cone's apex)."""
        u0, u1, v0, v1 = self.bounds
        uv = np.column_stack([np.clip(uv[:, 0], u0, u1), np.clip(uv[:, 1], v0, v1)])
        mid = np.array([0.5 * (u0 + u1), 0.5 * (v0 + v1)])
        for _ in range(6):
            D = self.S.evaluate(uv[:, 0], uv[:, 1], 1)
            a, b = np.linalg.norm(D.Su, axis=1), np.linalg.norm(D.Sv, axis=1)
            bad = np.linalg.norm(np.cross(D.Su, D.Sv), axis=1) <= 1e-6 * a * b + 1e-300
            if not bad.any():
                break
            uv[bad] += 1e-4 * (mid - uv[bad])
        return self.frames(uv)[1]


class FreeCADFaces:
    """The faces a wire cuts (one face, or a wall's faces), the wire on the side `side` of each (+1: the side its
    normal in its solid points to, off the material; -1: in it): ruled.machine.wirecut's Target."""

    def __init__(self, faces, side: float = 1.0, against: str = "the face"):
        self.faces = [_Face(f, 1.0 if side >= 0 else -1.0) for f in faces]
        self.against = against
        P = np.concatenate([f.tree.data for f in self.faces])
        self.size = float(np.linalg.norm(np.ptp(P, axis=0)))

    def design(self, n: int) -> tuple[np.ndarray, np.ndarray]:
        from ruled.core.distance import project_points
        P, N = [], []
        for f in self.faces:
            X = face_points(f.face, n)
            uv, _ = project_points(f.S, X, f.seeds[f.tree.query(X)[1]], 8)
            P.append(X)
            N.append(f.normals_near(uv))
        return np.concatenate(P), np.concatenate(N)

    def feet(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        from ruled.core.distance import project_points
        X = np.asarray(X, float).reshape(-1, 3)
        F, N = np.full(X.shape, np.nan), np.full(X.shape, np.nan)
        good = np.full(len(X), np.inf)
        any_d = np.full(len(X), np.inf)
        for f in self.faces:
            d0, k = f.tree.query(X)
            near = d0 - f.reach < np.minimum(good, any_d)        # (no point of this face is nearer for the rest)
            if not near.any():
                continue
            idx = np.nonzero(near)[0]
            uv, _ = project_points(f.S, X[idx], f.seeds[k[idx]], 8)
            q, n = f.frames(uv)
            r = X[idx] - q
            d = np.linalg.norm(r, axis=1)
            any_d[idx] = np.minimum(any_d[idx], d)
            rn = np.einsum("ij,ij->i", r, n)
            tang = np.sqrt(np.maximum(d * d - rn * rn, 0.0))
            u0, u1, v0, v1 = f.bounds
            ok = (tang <= ORTHOGONAL * d + 1e-9 * self.size) & (d < good[idx]) & \
                (uv[:, 0] >= u0) & (uv[:, 0] <= u1) & (uv[:, 1] >= v0) & (uv[:, 1] <= v1)
            ok[ok] = f.inside.points(uv[ok])
            j = idx[ok]
            good[j], F[j], N[j] = d[ok], q[ok], n[ok]
        return F, N, np.isfinite(good) & (good <= any_d + 1e-6 * self.size)


__all__ = ["FreeCADFaces"]
