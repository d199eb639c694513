"""Random B-spline faces for the fuzz and property tests, built with OCCT alone (issues 19 and 22).

Rational and periodic surfaces of degrees 1-5 with 2-12 poles per direction (at least degree + 1), knots
of every multiplicity (creases across and along the rulings included), weights 0.2-5 and, on some, over a
ratio of up to 1e5, tiny closed faces (1e-3.5 to 1e-2 across), scales 1e-4-1e4, offsets up to 1e5, collapsed
rows of poles (a boundary shrunk to a point), and faces trimmed to a part of their surface (a smaller
rectangle, or a side that waves): the kinds of input a CAD file can hold."""

from __future__ import annotations

import numpy as np
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace
from OCP.Geom import Geom_BSplineSurface
from OCP.gp import gp_Pnt
from OCP.TColgp import TColgp_Array2OfPnt
from OCP.TColStd import TColStd_Array1OfInteger, TColStd_Array2OfReal
from trimmed_faces import curve2d, face_from_loops, graph2d

from ruled.occ.convert import occ_array


def _knots(rng, n: int, p: int, periodic: bool):
    """Distinct knots and multiplicities for n poles of degree p: interior multiplicities 1..p."""
    if periodic:
        total = n              # sum of the multiplicities but the last (= the first)
        mults = []
        while sum(mults) < total:
            mults.append(int(min(rng.integers(1, p + 1), total - sum(mults))))
        mults.append(mults[0])
    else:
        inner = n - p - 1      # interior knots, counted with multiplicity
        mults = [p + 1]
        while sum(mults) - (p + 1) < inner:
            mults.append(int(min(rng.integers(1, p + 1), inner - (sum(mults) - (p + 1)))))
        mults.append(p + 1)
    gaps = rng.uniform(0.2, 1.0, len(mults) - 1)
    knots = np.concatenate([[0.0], np.cumsum(gaps)])
    return list(knots * rng.choice([1.0, 10.0, 0.01])), mults


def _direction(rng, periodic_ok: bool):
    p = int(rng.integers(1, 6))
    periodic = periodic_ok and rng.random() < 0.3
    n = int(rng.integers(max(p + 1, 2 if not periodic else p + 1), 13))
    if periodic and n < p + 1:
        periodic = False
    return p, n, periodic


def random_face(rng):
    """One random face and a short description of it."""
    tiny_closed = rng.random() < 0.1                      # a closed face a few thousandths across
    pu, nu, peru = _direction(rng, True)
    if tiny_closed:
        pu, peru = min(pu, 4), True
        nu = max(nu, pu + 1)
    pv, nv, perv = _direction(rng, not peru)
    ku, mu = _knots(rng, nu, pu, peru)
    kv, mv = _knots(rng, nv, pv, perv)
    scale = 10.0 ** rng.uniform(-3.5, -2) if tiny_closed else 10.0 ** rng.uniform(-4, 4)
    offset = rng.choice([0.0, 1e3, 1e5]) * rng.standard_normal(3) / np.sqrt(3)
    # a gently curved sheet with noise, so that faces range from nearly ruled to far from it
    s, t = np.meshgrid(np.linspace(0, 1, nu), np.linspace(0, 1, nv), indexing="ij")
    if peru:
        a = 2 * np.pi * np.arange(nu) / nu
        base = np.stack([np.cos(a)[:, None] * (1 + 0.3 * t), np.sin(a)[:, None] * (1 + 0.3 * t), 2 * t], -1)
    elif perv:
        a = 2 * np.pi * np.arange(nv) / nv
        base = np.stack([np.cos(a)[None, :] * (1 + 0.3 * s), np.sin(a)[None, :] * (1 + 0.3 * s), 2 * s], -1)
    else:
        base = np.stack([2 * s, 2 * t, np.zeros_like(s)], -1)
    poles = base + rng.choice([0.0, 0.02, 0.2, 0.6]) * rng.standard_normal(base.shape)
    what = []
    if not (peru or perv) and rng.random() < 0.15:        # a boundary row collapsed to a point
        if rng.random() < 0.5:
            poles[0, :] = poles[0, :].mean(axis=0)
            what.append("collapsed u-min")
        else:
            poles[:, -1] = poles[:, -1].mean(axis=0)
            what.append("collapsed v-max")
    poles = poles * scale + offset
    rational = rng.random() < 0.5
    extreme = rational and rng.random() < 0.3             # weights over a ratio of up to 1e5
    weights = (10.0 ** rng.uniform(-2.5, 2.5, (nu, nv)) if extreme else rng.uniform(0.2, 5.0, (nu, nv))) \
        if rational else np.ones((nu, nv))
    what += ["extreme weights"] if extreme else []
    what += ["tiny closed"] if tiny_closed else []
    P = TColgp_Array2OfPnt(1, nu, 1, nv)
    W = TColStd_Array2OfReal(1, nu, 1, nv)
    for i in range(nu):
        for j in range(nv):
            P.SetValue(i + 1, j + 1, gp_Pnt(*map(float, poles[i, j])))
            W.SetValue(i + 1, j + 1, float(weights[i, j]))
    ints = TColStd_Array1OfInteger
    bs = Geom_BSplineSurface(P, W, occ_array(ku), occ_array(kv), occ_array(mu, ints), occ_array(mv, ints), pu, pv,
                             peru, perv)
    u0, u1, v0, v1 = bs.Bounds()
    trim = rng.random()
    if trim < 0.15 and not (peru or perv):                  # a smaller rectangle of the surface
        a, b = sorted(rng.uniform(0, 1, 2))
        c, d = sorted(rng.uniform(0, 1, 2))
        a, b = u0 + (u1 - u0) * a * 0.4, u0 + (u1 - u0) * (0.6 + 0.4 * b)
        c, d = v0 + (v1 - v0) * c * 0.4, v0 + (v1 - v0) * (0.6 + 0.4 * d)
        face = BRepBuilderAPI_MakeFace(bs, a, b, c, d, 1e-7).Face()
        what.append("sub-rectangle")
    elif trim < 0.3 and not (peru or perv):                 # a side that waves
        du, dv = u1 - u0, v1 - v0
        a, b, c, d = u0 + 0.1 * du, u1 - 0.1 * du, v0 + 0.1 * dv, v1 - 0.25 * dv
        amp = 0.1 * dv * rng.uniform(0.2, 1.0)

        def top(x, a=a, b=b, d=d, amp=amp):
            return d + amp * np.sin(np.pi * (x - a) / (b - a)) ** 2
        face = face_from_loops(bs, [[curve2d([[a, c], [b, c]]), curve2d([[b, c], [b, top(b)]]),
                                     graph2d(a, b, top, reverse=True), curve2d([[a, top(a)], [a, c]])]])
        what.append("wavy side")
    else:
        face = BRepBuilderAPI_MakeFace(bs, 1e-7).Face()
    desc = (f"deg {pu}x{pv} poles {nu}x{nv} mults {mu}/{mv} {'rational ' if rational else ''}"
            f"{'periodic u ' if peru else ''}{'periodic v ' if perv else ''}scale {scale:.2g} "
            f"offset {np.linalg.norm(offset):.2g} {' '.join(what)}")
    return face, desc


def random_faces(seed: int, count: int) -> list:
    rng = np.random.default_rng(seed)
    return [random_face(rng) for _ in range(count)]


# the fuzz batches: seed and number of faces per method
COUNTS = {"2d": (2202, 300), "4d": (2204, 50)}
FACE_LIMIT = 120       # seconds: a face that takes longer hangs (they take about 1 s)


def run(folder: str, jobs: int = 1) -> int:
    """Write the random faces of each method to a STEP file in folder and fit them with ``ruled batch``
    (a per-face limit, no plots); the summaries land in folder/out<method>.  Returns the exit code."""
    import os
    import subprocess
    import sys

    from ruled.occ.io import write_step
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    for method, (seed, count) in COUNTS.items():
        src = os.path.join(folder, f"fuzz{method}.step")
        write_step([f for f, _ in random_faces(seed, count)], src)
        r = subprocess.run([sys.executable, "-m", "ruled.cli", "batch", src, "--method", method, "--samples", "12",
                            "--measure-samples", "12", "--jobs", str(jobs), "--face-timeout", str(FACE_LIMIT),
                            "--no-plots", "--quiet", "-o", os.path.join(folder, f"out{method}")],
                           cwd=root, capture_output=True, text=True)
        with open(os.path.join(folder, f"batch{method}.log"), "w") as fh:
            fh.write(r.stdout + r.stderr)
        if r.returncode != 0:
            return r.returncode
    return 0


if __name__ == "__main__":       # python tests/fuzz_faces.py FOLDER [JOBS]
    import sys
    sys.exit(run(sys.argv[1], int(sys.argv[2]) if len(sys.argv) > 2 else 1))
