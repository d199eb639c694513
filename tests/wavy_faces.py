"""Trimmed faces with wavy boundaries (issue 58): a random B-spline surface (degrees 2-5, some rational) over
the unit square, trimmed by a closed loop of wavy 2D curves round its middle (2-6 edges; one-edge loops left
out: OCCT's closed approximations of them self-intersect), with 0-2 wavy holes inside, built with OCCT alone
(its 3D edges from the pcurves): the kind of face a CAD user selects and the four-sided maps find hard.
`benchmarks/run.py --suite wavy` fits a set of them and counts the outcomes."""

from __future__ import annotations

import math

import numpy as np
from OCP.Geom import Geom_BSplineSurface
from OCP.gp import gp_Pnt
from OCP.TColgp import TColgp_Array2OfPnt
from OCP.TColStd import TColStd_Array1OfInteger, TColStd_Array2OfReal
from trimmed_faces import curve2d, face_from_loops

from ruled.occ.convert import occ_array


def _surface(rng) -> Geom_BSplineSurface:
    """Degrees 2-5 each way, degree + 1 to degree + 4 poles, uniform clamped knots on [0, 1] over a square of
    100, the poles' heights random with a spread of 0.5, 2.5 or 10 (from nearly ruled to far from it), weights
    0.5-2 on one surface in three."""
    degs = [int(rng.integers(2, 6)) for _ in range(2)]
    ns = [p + 1 + int(rng.integers(0, 4)) for p in degs]
    P = TColgp_Array2OfPnt(1, ns[0], 1, ns[1])
    size = 100.0
    h = rng.normal(0.0, float(rng.choice([0.5, 2.5, 10.0])), (ns[0], ns[1]))
    for i in range(ns[0]):
        for j in range(ns[1]):
            P.SetValue(i + 1, j + 1, gp_Pnt(size * i / (ns[0] - 1), size * j / (ns[1] - 1), float(h[i, j])))
    knots, mults = [], []
    for p, n in zip(degs, ns):
        inner = n - p - 1
        knots.append(np.linspace(0.0, 1.0, inner + 2))
        mults.append([p + 1] + [1] * inner + [p + 1])
    ka, kb = (occ_array(k) for k in knots)
    ma, mb = (occ_array(m, TColStd_Array1OfInteger) for m in mults)
    if rng.random() < 1.0 / 3.0:
        W = TColStd_Array2OfReal(1, ns[0], 1, ns[1])
        w = np.exp(rng.uniform(math.log(0.5), math.log(2.0), (ns[0], ns[1])))
        for i in range(ns[0]):
            for j in range(ns[1]):
                W.SetValue(i + 1, j + 1, float(w[i, j]))
        return Geom_BSplineSurface(P, W, ka, kb, ma, mb, degs[0], degs[1], False, False)
    return Geom_BSplineSurface(P, ka, kb, ma, mb, degs[0], degs[1], False, False)


def _wavy_loop(rng, centre, r0: float, waves: int, amp: float, edges: int, reverse: bool) -> list:
    """A closed wavy loop r(theta) = r0 (1 + amp sin(waves theta + phase)) round centre, in edges 2D curves
    (counter-clockwise; clockwise with reverse, as a hole runs)."""
    phase = rng.uniform(0.0, 2.0 * math.pi)
    start = rng.uniform(0.0, 2.0 * math.pi)
    step = 2.0 * math.pi / edges          # the edges' shares, jittered by up to a third
    bounds = start + step * (np.arange(edges + 1) + np.concatenate([[0.0], rng.uniform(-0.3, 0.3, edges - 1),
                                                                     [0.0]]))
    curves = []
    for a, b in zip(bounds[:-1], bounds[1:]):
        th = np.linspace(a, b, max(6, int(40 * (b - a) / (2 * math.pi)) + 4))
        r = r0 * (1.0 + amp * np.sin(waves * th + phase))
        pts = np.stack([centre[0] + r * np.cos(th), centre[1] + r * np.sin(th)], axis=1)
        curves.append(pts)
    if reverse:
        curves = [c[::-1] for c in curves[::-1]]
    # the ends shared exactly (each curve runs through its points, the ends included)
    return [curve2d(c) for c in curves]


def wavy_face(seed: int):
    """The face of this seed (an OCCT TopoDS_Face) and its description."""
    rng = np.random.default_rng(seed)
    surf = _surface(rng)
    edges = int(rng.integers(2, 7))
    waves, amp = int(rng.integers(2, 7)), float(rng.uniform(0.03, 0.15))
    loops = [_wavy_loop(rng, (0.5, 0.5), 0.36, waves, amp, edges, False)]
    holes = int(rng.choice([0, 0, 1, 2]))
    spots = [(0.42, 0.5), (0.6, 0.45)] if holes == 2 else [(0.5 + rng.uniform(-0.08, 0.08),
                                                            0.5 + rng.uniform(-0.08, 0.08))]
    for k in range(holes):
        loops.append(_wavy_loop(rng, spots[k], 0.05, int(rng.integers(2, 5)), 0.2, int(rng.integers(2, 4)), True))
    name = (f"wavy {seed}: degrees {surf.UDegree()}x{surf.VDegree()}{' rational' if surf.IsURational() else ''}, "
            f"{edges} edge{'s' if edges > 1 else ''}, {holes} hole{'s' if holes != 1 else ''}")
    return face_from_loops(surf, loops), name


__all__ = ["wavy_face"]
