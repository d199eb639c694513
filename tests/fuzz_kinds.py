"""Issue 34's kinds of random faces for the property test (tests/fuzz_faces.py names them METHOD:SEED:kN): the
faces a CAD file holds that fuzz_faces.random_face does not make, built with OCCT alone."""

from __future__ import annotations

import numpy as np
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace
from OCP.Geom import Geom_BSplineSurface
from OCP.gp import gp_Pnt
from OCP.TColgp import TColgp_Array2OfPnt
from OCP.TColStd import TColStd_Array1OfInteger, TColStd_Array2OfReal
from trimmed_faces import bow_edges, curve2d, face_from_loops, graph2d

from ruled.occ.convert import occ_array


def _occ_surface(poles, weights, ku, mu, kv, mv, pu, pv, peru=False):
    P = TColgp_Array2OfPnt(1, poles.shape[0], 1, poles.shape[1])
    W = TColStd_Array2OfReal(1, poles.shape[0], 1, poles.shape[1])
    for i in range(poles.shape[0]):
        for j in range(poles.shape[1]):
            P.SetValue(i + 1, j + 1, gp_Pnt(*map(float, poles[i, j])))
            W.SetValue(i + 1, j + 1, float(weights[i, j]))
    ints = TColStd_Array1OfInteger
    return Geom_BSplineSurface(P, W, occ_array(ku), occ_array(kv), occ_array(mu, ints), occ_array(mv, ints), pu, pv,
                               peru, False)


def _wave(rng, level: float, amp: float):
    k, ph = int(rng.integers(1, 4)), rng.uniform(0, 2 * np.pi)
    return lambda x, k=k, ph=ph: level + amp * np.sin(2 * np.pi * k * x + ph)


def kind_face(rng):
    """One face of the kinds issue 34 added (faces a CAD file holds that random_face does not make), and a
    short description: a band that goes once round a periodic surface from a seam of its own (OCCT's seam
    edge, or four edges), a sheet with one or two holes, or a whole rectangle whose edges lie off their
    surface within their tolerance."""
    kind = ["band", "hole", "sloppy"][int(rng.integers(0, 3))]
    scale = 10.0 ** rng.uniform(-1, 2)
    rational = rng.random() < 0.5
    if kind == "band":
        n, pu = int(rng.integers(6, 13)), int(rng.integers(2, 5))
        nv = int(rng.integers(3, 6))
        pv = int(rng.integers(2, nv))          # degree 1 across the band makes a crease at every knot
        a = 2 * np.pi * np.arange(n) / n
        t = np.linspace(0, 1, nv)
        r = 1 + 0.3 * t[None, :] + rng.choice([0.0, 0.05, 0.2]) * rng.standard_normal((n, nv))
        poles = np.stack([np.cos(a)[:, None] * r, np.sin(a)[:, None] * r, np.broadcast_to(2 * t, (n, nv))], -1)
        poles = poles * scale
        w = rng.uniform(0.5, 2.0, (n, nv)) if rational else np.ones((n, nv))
        inner = nv - pv - 1
        S = _occ_surface(poles, w, list(np.arange(n + 1.0)), [1] * (n + 1), list(np.linspace(0, 1, inner + 2)),
                         [pv + 1] + [1] * inner + [pv + 1], pu, pv, True)
        a0 = float(rng.uniform(0, n))
        bot, top = _wave(rng, 0.2, 0.08), _wave(rng, 0.8, 0.08)

        def f(g, x, a0=a0, n=n):
            return g((x - a0) / n)
        b = graph2d(a0, a0 + n, lambda x: f(bot, x), spans=24)
        tp = graph2d(a0, a0 + n, lambda x: f(top, x), spans=24, reverse=True)
        seam = rng.random() < 0.5
        if seam:
            face = face_from_loops(S, [[b], [tp]])
        else:
            face = face_from_loops(S, [[b, curve2d([[a0 + n, f(bot, a0 + n)], [a0 + n, f(top, a0 + n)]]), tp,
                                        curve2d([[a0, f(top, a0)], [a0, f(bot, a0)]])]])
        desc = f"band round a period, {'seam edge' if seam else 'four edges'}, seam at u = {a0:.3g} of {n}"
    else:
        nu, nv = int(rng.integers(4, 8)), int(rng.integers(3, 6))
        pu, pv = int(rng.integers(2, min(3, nu - 1) + 1)), int(rng.integers(2, min(3, nv - 1) + 1))
        s, t = np.meshgrid(np.linspace(0, 1, nu), np.linspace(0, 1, nv), indexing="ij")
        noise = rng.choice([0.0, 0.02, 0.2]) * rng.standard_normal((nu, nv, 3))
        poles = (np.stack([2 * s, 2 * t, 0.3 * s * t], -1) + noise) * scale
        w = rng.uniform(0.5, 2.0, (nu, nv)) if rational else np.ones((nu, nv))

        def clamped(n, p):
            inner = n - p - 1
            return list(np.linspace(0, 1, inner + 2)), [p + 1] + [1] * inner + [p + 1]
        (ku, mu), (kv, mv) = clamped(nu, pu), clamped(nv, pv)
        S = _occ_surface(poles, w, ku, mu, kv, mv, pu, pv)
        if kind == "hole":
            holes = []
            centres = ([(0.3, 0.5), (0.7, 0.5)] if rng.random() < 0.4 else
                       [(rng.uniform(0.35, 0.65), rng.uniform(0.35, 0.65))])
            for cx, cy in centres:
                rad = rng.uniform(0.05, 0.15)
                ang = np.linspace(0, 2 * np.pi, 25)
                wob = 1 + 0.2 * np.sin(3 * ang + rng.uniform(0, 6))
                holes.append([curve2d(np.stack([cx + rad * wob * np.cos(-ang), cy + rad * wob * np.sin(-ang)], 1))])
            inset = rng.random() < 0.5
            lo, hi = (0.05, 0.95) if inset else (0.0, 1.0)
            outer = [curve2d([[lo, lo], [hi, lo]]), curve2d([[hi, lo], [hi, hi]]), curve2d([[hi, hi], [lo, hi]]),
                     curve2d([[lo, hi], [lo, lo]])]
            face = face_from_loops(S, [outer] + holes)
            desc = f"{len(holes)} hole{'s' if len(holes) > 1 else ''}, {'inset' if inset else 'whole'} outer loop"
        else:
            off = 10.0 ** rng.uniform(-4, -2) * scale
            face = bow_edges(BRepBuilderAPI_MakeFace(S, 1e-7).Face(), off, int(rng.integers(1, 3)))
            desc = f"whole rectangle, edges bowed {off:.2g} off the surface within their tolerance"
    desc = (f"{kind}: {desc}, deg {pu}x{pv}{' rational' if rational else ''} scale {scale:.2g}")
    return face, desc


def kind_faces(seed: int, count: int) -> list:
    rng = np.random.default_rng(seed)
    return [kind_face(rng) for _ in range(count)]
