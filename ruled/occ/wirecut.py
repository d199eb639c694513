"""The design faces, with OCCT, for the measure of what a wire cuts from its lines alone (ruled.machine.wirecut):
points of each face as bounded by its edges with their normals on the wire's side, and the feet of points on the
faces' surfaces (OCCT's local extremum search from the nearest of a grid of seeds over each face's (u, v) bounds,
Newton-polished), kept where the foot is orthogonal and inside its face (OCCT's classifier)."""

from __future__ import annotations

import math

import numpy as np
from OCP.BRep import BRep_Tool
from OCP.Extrema import Extrema_GenLocateExtPS
from OCP.GeomAdaptor import GeomAdaptor_Surface
from OCP.gp import gp_Pnt, gp_Vec
from OCP.ShapeAnalysis import ShapeAnalysis_Surface
from OCP.TopAbs import TopAbs_REVERSED

from ruled.occ.edgerows import face_bounds
from ruled.occ.measure import _classifier, face_points

SEEDS = 48              # a SEEDS x SEEDS grid of each face's (u, v) bounds seeds the feet's searches
ORTHOGONAL = 1e-3       # a foot is orthogonal when the point's offset along the surface is below this of its distance


class _Face:
    def __init__(self, face, sign: float):
        self.face = face
        self.surf = BRep_Tool.Surface_s(face)
        self.bounds = face_bounds(face)
        u0, u1, v0, v1 = self.bounds
        self.adaptor = GeomAdaptor_Surface(self.surf, u0, u1, v0, v1)
        self.locate = Extrema_GenLocateExtPS(self.adaptor, 1e-12, 1e-12)
        self.inside = _classifier(face)
        self.sas = ShapeAnalysis_Surface(self.surf)
        # +1 where the wire runs on the side the face's normal in its solid points to (off the material)
        self.sign = sign * (-1.0 if face.Orientation() == TopAbs_REVERSED else 1.0)

    def seeds(self) -> tuple[np.ndarray, np.ndarray]:
        u0, u1, v0, v1 = self.bounds
        uu, vv = np.meshgrid(np.linspace(u0, u1, SEEDS), np.linspace(v0, v1, SEEDS), indexing="ij")
        uv = np.stack([uu.ravel(), vv.ravel()], axis=1)
        return np.array([self.surf.Value(float(u), float(v)).Coord() for u, v in uv]), uv

    def frame(self, u: float, v: float) -> tuple:
        """(the point, its unit normal on the wire's side) at (u, v), as tuples (plain floats: called per point)."""
        p, du, dv = gp_Pnt(), gp_Vec(), gp_Vec()
        self.surf.D1(u, v, p, du, dv)
        a, b = du.Coord(), dv.Coord()
        n = (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
        k = self.sign / max(math.sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), 1e-300)
        return p.Coord(), (n[0] * k, n[1] * k, n[2] * k)


    def normal_near(self, u: float, v: float) -> tuple:
        """The unit normal on the wire's side at (u, v) clamped into the face's bounds, or, where the surface is
        singular there (a cone's apex, a fan's point: no normal), a hair towards the bounds' middle."""
        u0, u1, v0, v1 = self.bounds
        u, v = min(max(u, u0), u1), min(max(v, v0), v1)
        for _ in range(6):
            du, dv = gp_Vec(), gp_Vec()
            self.surf.D1(u, v, gp_Pnt(), du, dv)
            a, b = du.Magnitude(), dv.Magnitude()
            if du.Crossed(dv).Magnitude() > 1e-6 * a * b and a * b > 1e-18 * (u1 - u0 + v1 - v0) ** 2 + 1e-300:
                break
            u, v = u + 1e-4 * (0.5 * (u0 + u1) - u), v + 1e-4 * (0.5 * (v0 + v1) - v)
        return self.frame(u, v)[1]


class FacesTarget:
    """The faces a wire cuts (one face, or a wall's faces), the wire on the side `side` of each (+1: the side its
    normal in its solid points to, off the material; -1: in it): ruled.machine.wirecut's Target."""

    def __init__(self, faces, side: float = 1.0, against: str = "the face"):
        from scipy.spatial import cKDTree
        self.faces = [_Face(f, 1.0 if side >= 0 else -1.0) for f in faces]
        self.against = against
        self.seeds = []
        for f in self.faces:
            P, uv = f.seeds()
            G = P.reshape(SEEDS, SEEDS, 3)      # no point of the face is farther from its nearest seed than this
            reach = max(float(np.linalg.norm(np.diff(G, axis=0), axis=2).max()),
                        float(np.linalg.norm(np.diff(G, axis=1), axis=2).max()))
            self.seeds.append((cKDTree(P), uv, reach))
        allp = np.concatenate([t.data for t, _, _ in self.seeds])
        self.size = float(np.linalg.norm(np.ptp(allp, axis=0)))

    def design(self, n: int) -> tuple[np.ndarray, np.ndarray]:
        P, N = [], []
        for f in self.faces:
            X = face_points(f.face, n)
            for x in X.tolist():
                uv = f.sas.ValueOfUV(gp_Pnt(*x), 1e-10)
                N.append(f.normal_near(uv.X(), uv.Y()))
            P.append(X)
        return np.concatenate(P), np.array(N)

    def feet(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The nearest orthogonal foot inside a face of each point (from the nearest seeds of each face near it),
        kept unless a foot of another kind (on a face's bounds, or outside its edges) is nearer."""
        X = np.asarray(X, float).reshape(-1, 3)
        F, N = np.full(X.shape, np.nan), np.full(X.shape, np.nan)
        good = np.full(len(X), np.inf)
        any_d = np.full(len(X), np.inf)
        uv = np.full((len(X), 2), np.nan)
        face_of = np.full(len(X), -1)
        near = [tree.query(X) for tree, _, _ in self.seeds]         # each face's nearest seed to each point
        lower = np.stack([d - reach for (d, _), (_, _, reach) in zip(near, self.seeds)], axis=1)
        order = np.argsort(lower, axis=1)
        for i, x in enumerate(X.tolist()):
            P = gp_Pnt(*x)
            for fk in order[i].tolist():
                if lower[i, fk] >= min(good[i], any_d[i]):          # (no point of this face is nearer)
                    break
                f, s = self.faces[fk], int(near[fk][1][i])
                seed = self.seeds[fk][1][s]
                f.locate.Perform(P, float(seed[0]), float(seed[1]), False)
                if not f.locate.IsDone():
                    continue
                d = math.sqrt(f.locate.SquareDistance())
                any_d[i] = min(any_d[i], d)
                if d >= good[i]:
                    continue
                u, v = f.locate.Point().Parameter()
                q, n = f.frame(u, v)
                r = (x[0] - q[0], x[1] - q[1], x[2] - q[2])
                rn = r[0] * n[0] + r[1] * n[1] + r[2] * n[2]
                tang = math.sqrt(max(r[0] * r[0] + r[1] * r[1] + r[2] * r[2] - rn * rn, 0.0))
                if tang <= ORTHOGONAL * d + 1e-9 * self.size:
                    good[i], F[i], N[i], uv[i], face_of[i] = d, q, n, (u, v), fk
        # inside its face: each face's classifier on its points at once
        for fk, f in enumerate(self.faces):
            at = np.nonzero(face_of == fk)[0]
            if at.size:
                good[at[~f.inside.points(uv[at])]] = np.inf
        return F, N, np.isfinite(good) & (good <= any_d + 1e-6 * self.size)


__all__ = ["FacesTarget"]
