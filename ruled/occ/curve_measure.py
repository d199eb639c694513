"""The independent measure of a curve on a surface (OCCT): its distance to the exact image of the (u, v)
curve, and the angles at its joints, against OCCT's own evaluation and projection."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from OCP.Adaptor3d import Adaptor3d_CurveOnSurface
from OCP.Extrema import Extrema_ExtPC
from OCP.Geom2dAdaptor import Geom2dAdaptor_Curve
from OCP.GeomAdaptor import GeomAdaptor_Surface
from OCP.GeomAPI import GeomAPI_ProjectPointOnCurve, GeomAPI_ProjectPointOnSurf
from OCP.gp import gp_Pnt, gp_Vec

from ruled.core.distance import _golden_min


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


def distance_to(curve, x):
    """f(t): the distance from the point x to the curve (anything with D0(t, P): an adaptor, a Geom curve) at t,
    by OCCT into one reused point (the searches call it a million times per batch of faces: numpy's per-call cost
    was most of theirs)."""
    P, Q = gp_Pnt(*(float(c) for c in x)), gp_Pnt()

    def f(t):
        curve.D0(float(t), Q)
        return Q.Distance(P)
    return f


def _seeded(curve, ts, pts, x, iters: int = 60) -> float:
    """Distance from x to a curve (anything with D0(t, P)): golden-section search around the
    nearest of the dense samples pts (at parameters ts)."""
    k = int(np.argmin(np.linalg.norm(pts - x, axis=1)))
    a, b = ts[max(k - 1, 0)], ts[min(k + 1, ts.size - 1)]
    return min(_golden_min(distance_to(curve, x), a, b, iters), float(np.linalg.norm(pts[k] - x)))


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
