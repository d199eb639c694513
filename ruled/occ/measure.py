"""Independent error measure: two-sided Hausdorff distance between two faces by dense
sampling plus exact point projection with OCCT (no code of the engine is used)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from OCP.BRep import BRep_Tool
from OCP.BRepTools import BRepTools
from OCP.GeomAPI import GeomAPI_ProjectPointOnSurf
from OCP.ShapeAnalysis import ShapeAnalysis_Surface
from OCP.gp import gp_Pnt, gp_Vec


@dataclass(frozen=True)
class Hausdorff:
    max: float
    mean: float
    max_a_to_b: float
    max_b_to_a: float
    samples: int


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


def _grid(face, n: int):
    u0, u1, v0, v1 = face_bounds(face)
    surf = BRep_Tool.Surface_s(face)
    us = np.linspace(u0, u1, n)
    vs = np.linspace(v0, v1, n)
    pts = []
    for u in us:
        for v in vs:
            p = surf.Value(float(u), float(v))
            pts.append((p.X(), p.Y(), p.Z()))
    return np.array(pts)


class _Projector:
    def __init__(self, face):
        self.u0, self.u1, self.v0, self.v1 = face_bounds(face)
        self.surf = BRep_Tool.Surface_s(face)
        self.proj = GeomAPI_ProjectPointOnSurf()
        self.proj.Init(self.surf, self.u0, self.u1, self.v0, self.v1)
        self.sas = ShapeAnalysis_Surface(self.surf)
        # a coarse cloud for the boundary: closest points may lie on the edges
        n = 200
        us = np.linspace(self.u0, self.u1, n)
        vs = np.linspace(self.v0, self.v1, n)
        edge_uv = np.concatenate([np.stack([us, np.full(n, self.v0)], 1), np.stack([us, np.full(n, self.v1)], 1),
                                  np.stack([np.full(n, self.u0), vs], 1), np.stack([np.full(n, self.u1), vs], 1)])
        self.edge_uv = edge_uv
        self.edge_pts = np.array([self._value(u, v) for u, v in edge_uv])

    def _value(self, u, v):
        p = self.surf.Value(float(u), float(v))
        return (p.X(), p.Y(), p.Z())

    def _polish(self, x, u, v, iters: int = 6) -> float:
        """Newton steps on |S(u, v) - x|^2 with OCCT's D2, clamped to the bounds; the best distance seen."""
        best = np.inf
        for _ in range(iters):
            p, du, dv, duu, dvv, duv = gp_Pnt(), gp_Vec(), gp_Vec(), gp_Vec(), gp_Vec(), gp_Vec()
            self.surf.D2(float(u), float(v), p, du, dv, duu, dvv, duv)
            r = np.array(p.Coord()) - x
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
        p = self.surf.Value(float(u), float(v))
        return min(best, float(np.linalg.norm(np.array(p.Coord()) - x)))

    def distance(self, x) -> float:
        """Distance from x to the face: the best of OCCT's orthogonal projection, its analysis
        projection (which also finds boundary points), both polished by Newton steps, and the
        nearest boundary point (dense edge samples refined along their edge)."""
        P = gp_Pnt(*map(float, x))
        cands = []
        self.proj.Perform(P)
        if self.proj.IsDone() and self.proj.NbPoints() > 0:
            cands.append((self.proj.LowerDistance(), *self.proj.LowerDistanceParameters()))
        uv = self.sas.ValueOfUV(P, 1e-10)
        u = min(max(uv.X(), self.u0), self.u1)
        v = min(max(uv.Y(), self.v0), self.v1)
        cands.append((float(np.linalg.norm(np.array(self._value(u, v)) - x)), u, v))
        d0, u, v = min(cands)
        best = min(d0, self._polish(x, u, v, 4))
        de = np.linalg.norm(self.edge_pts - x, axis=1)
        k = int(np.argmin(de))
        if de[k] < 1.5 * best + 1e-12:  # the boundary may hold the closest point
            eu, ev = self.edge_uv[k]
            best = min(best, float(de[k]), self._edge_refine(x, eu, ev, k))
        return best

    def _edge_refine(self, x, eu, ev, k) -> float:
        n = 200
        side = k // n
        i = k % n
        along_u = side < 2
        col = 0 if along_u else 1
        lo, hi = self.edge_uv[max(i - 1, 0) + side * n][col], self.edge_uv[min(i + 1, n - 1) + side * n][col]

        def f(t):
            uv = (t, ev) if along_u else (eu, t)
            return np.linalg.norm(np.array(self._value(*uv)) - x)
        g = 0.5 * (np.sqrt(5) - 1)
        a, b = lo, hi
        c, d = b - g * (b - a), a + g * (b - a)
        fc, fd = f(c), f(d)
        for _ in range(40):
            if fc < fd:
                b, d, fd = d, c, fc
                c = b - g * (b - a)
                fc = f(c)
            else:
                a, c, fc = c, d, fd
                d = a + g * (b - a)
                fd = f(d)
        return float(min(fc, fd))


def hausdorff(face_a, face_b, n: int = 40) -> Hausdorff:
    """Two-sided Hausdorff distance between two faces (n x n samples of each, projected on the other)."""
    pa = _grid(face_a, n)
    pb = _grid(face_b, n)
    pr_b = _Projector(face_b)
    pr_a = _Projector(face_a)
    dab = np.array([pr_b.distance(x) for x in pa])
    dba = np.array([pr_a.distance(x) for x in pb])
    alld = np.concatenate([dab, dba])
    return Hausdorff(float(alld.max()), float(alld.mean()), float(dab.max()), float(dba.max()), int(alld.size))
