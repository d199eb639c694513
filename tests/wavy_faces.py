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


def _bezier(f, p: int, q: int, rng_box=(0.0, 1.0)) -> Geom_BSplineSurface:
    """The Bezier surface of degrees p x q over the unit square equal to the polynomial map f(u, v) -> (N, 3) of
    those degrees: its poles solved from (p + 1) x (q + 1) values (exact to round-off)."""
    from math import comb
    x, y = np.linspace(0.0, 1.0, p + 1), np.linspace(0.0, 1.0, q + 1)

    def bern(n, t):
        return np.array([[comb(n, k) * tt ** k * (1 - tt) ** (n - k) for k in range(n + 1)] for tt in t])
    U, V = np.meshgrid(x, y, indexing="ij")
    F = f(U.ravel(), V.ravel()).reshape(p + 1, q + 1, 3)
    Bu, Bv = np.linalg.inv(bern(p, x)), np.linalg.inv(bern(q, y))
    Pl = np.einsum("ia,abk,jb->ijk", Bu, F, Bv)
    P = TColgp_Array2OfPnt(1, p + 1, 1, q + 1)
    for i in range(p + 1):
        for j in range(q + 1):
            P.SetValue(i + 1, j + 1, gp_Pnt(*map(float, Pl[i, j])))
    ka, kb = occ_array([0.0, 1.0]), occ_array([0.0, 1.0])
    ma, mb = occ_array([p + 1, p + 1], TColStd_Array1OfInteger), occ_array([q + 1, q + 1], TColStd_Array1OfInteger)
    return Geom_BSplineSurface(P, ka, kb, ma, mb, p, q, False, False)


def _poly_curve(rng, n: int, scale: float):
    """A random polynomial space curve of degree n on [0, 1] (coefficients), scale its extent."""
    c = rng.normal(0.0, 0.25 * scale, (n + 1, 3))
    c[1] += scale * np.array([1.0, 0.0, 0.0])
    return c


def _poly(c, s):
    return sum(c[k][None, :] * s[:, None] ** k for k in range(c.shape[0]))


def _hyperboloid() -> object:
    """A one-sheet hyperboloid x^2 + y^2 - z^2 / 4 = 1 (r = 10): a hyperbola's arc revolved by 120 degrees,
    OCCT's exact rational B-spline of it (its iso lines circles and hyperbolas, its rulings neither)."""
    from OCP.GC import GC_MakeArcOfHyperbola
    from OCP.Geom import Geom_SurfaceOfRevolution
    from OCP.GeomConvert import GeomConvert
    from OCP.gp import gp_Ax1, gp_Ax2, gp_Dir, gp_Hypr
    h = gp_Hypr(gp_Ax2(gp_Pnt(0, 0, 0), gp_Dir(0, 1, 0), gp_Dir(1, 0, 0)), 10.0, 20.0)
    arc = GC_MakeArcOfHyperbola(h, -1.0, 1.0, True).Value()
    rev = Geom_SurfaceOfRevolution(arc, gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)))
    from OCP.Geom import Geom_RectangularTrimmedSurface
    return GeomConvert.SurfaceToBSplineSurface_s(Geom_RectangularTrimmedSurface(rev, 0.0, 2.0 * math.pi / 3.0,
                                                                                -1.0, 1.0))


def ruled_face(seed: int):
    """An exactly ruled face whose rulings are not its surface's iso lines, trimmed by a wavy loop (2-5 edges)
    round the middle of its domain, and its description: a skewed ruled loft ((1 - t) a(s) + t b(s) of random
    cubics, written in (u, v) with s = u + c v: a Bezier of degrees 3 x 4 whose rulings run across the iso
    lines), a hyperbolic paraboloid (z = x y over x = u + v, y = u - v, scaled and turned: degrees 2 x 2), or
    a piece of a one-sheet hyperboloid (OCCT's rational B-spline of a revolved hyperbola)."""
    rng = np.random.default_rng(10_000 + seed)
    kind = ("skewed loft", "hyperbolic paraboloid", "hyperboloid")[seed % 3]
    if kind == "skewed loft":
        a, b = _poly_curve(rng, 3, 100.0), _poly_curve(rng, 3, 100.0)
        b[0] += np.array([0.0, 40.0, 10.0]) + rng.normal(0.0, 5.0, 3)
        c = float(rng.uniform(0.2, 0.6)) * rng.choice([-1.0, 1.0])

        def f(u, v):
            s = u + c * v
            return (1.0 - v)[:, None] * _poly(a, s) + v[:, None] * _poly(b, s)
        surf = _bezier(f, 3, 4)
    elif kind == "hyperbolic paraboloid":
        k = float(rng.uniform(0.3, 1.5))
        th = float(rng.uniform(0.0, math.pi))

        def f(u, v):
            x, y = 60.0 * (u + v - 1.0), 60.0 * (u - v)
            z = k * x * y / 60.0
            return np.stack([math.cos(th) * x - math.sin(th) * y, math.sin(th) * x + math.cos(th) * y, z], axis=1)
        surf = _bezier(f, 2, 2)
    else:
        surf = _hyperboloid()
    u0, u1, v0, v1 = surf.Bounds()
    edges = int(rng.integers(2, 6))
    waves, amp = int(rng.integers(2, 6)), float(rng.uniform(0.03, 0.12))
    loop = _wavy_loop(rng, (0.5, 0.5), 0.36, waves, amp, edges, False)
    if (u0, u1, v0, v1) != (0.0, 1.0, 0.0, 1.0):      # the loop moved into the surface's own domain
        loop = [_scaled(c, u0, u1, v0, v1) for c in loop]
    name = f"ruled {seed}: {kind}, {edges} edges"
    return face_from_loops(surf, [loop]), name


def _scaled(c, u0, u1, v0, v1):
    """A 2D B-spline curve of the unit square moved affinely onto [u0, u1] x [v0, v1]."""
    from OCP.gp import gp_Pnt2d
    c = c.Copy()
    for i in range(1, c.NbPoles() + 1):
        p = c.Pole(i)
        c.SetPole(i, gp_Pnt2d(u0 + (u1 - u0) * p.X(), v0 + (v1 - v0) * p.Y()))
    return c


def fit_row(job: tuple) -> dict:
    """One face through the whole ``ruled fit`` job (defaults; its own measure at `samples`), a row of what came
    of it: job = (kind "wavy" or "ruled", seed, folder, samples, independent).  With independent, the result's
    area and the face's are taken from OCCT's BRepGProp, and (independent True) the result measured again by
    OCCT alone (trimmed_faces.extrema_measure, both ways, 12 x 12).  Run in a pool (benchmarks/wavy.py,
    tests/fit/test_wavy.py)."""
    import os
    import time

    from OCP.BRepCheck import BRepCheck_Analyzer

    from ruled.core.errors import RuledError
    from ruled.jobs.face import run_fit
    from ruled.occ.io import face_area, read_faces, write_step
    kind, seed, folder, samples, independent = job
    face, name = (wavy_face if kind == "wavy" else ruled_face)(seed)
    row = {"kind": kind, "seed": seed, "name": name}
    if not BRepCheck_Analyzer(face).IsValid():
        return {**row, "status": "invalid input"}
    path, out = os.path.join(folder, f"{kind}{seed}.step"), os.path.join(folder, f"{kind}{seed}_result.step")
    write_step(face, path)
    t0 = time.process_time()
    try:
        rep = run_fit(path, 0, out, quiet=True, say=False, measure_samples=samples, face_timeout=300.0)
        row.update(status="fitted", bound=rep["error_bound"], measured=rep["hausdorff"]["max"],
                   size=(rep.get("region") or {}).get("face_size"), ratio=(rep.get("area") or {}).get("ratio"),
                   notes=rep.get("notes", []))
    except RuledError as exc:
        row.update(status="refused", reason=str(exc))
    except Exception as exc:  # a crash is a row too: the count says so
        row.update(status="failed", reason=f"{type(exc).__name__}: {exc}")
    row["cpu"] = time.process_time() - t0
    if independent and row["status"] == "fitted":
        inp, res = read_faces(path)[0], read_faces(out)[0]
        row["occt_area"] = face_area(res, 1e-6) / face_area(inp, 1e-6)
        if independent is True:
            from trimmed_faces import extrema_measure
            row["occt"] = max(extrema_measure(inp, res, 12))
    return row


__all__ = ["wavy_face", "ruled_face", "fit_row"]
