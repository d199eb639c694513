"""Random B-spline faces for the fuzz and property tests, built with OCCT alone (issues 19 and 22).

Rational and periodic surfaces of degrees 1-5 with 2-12 poles per direction (at least degree + 1), knots
of every multiplicity (creases across and along the rulings included), weights 0.2-5 and, on some, over a
ratio of up to 1e5, tiny closed faces (1e-3.5 to 1e-2 across), scales 1e-4-1e4, offsets up to 1e5, collapsed
rows of poles (a boundary shrunk to a point), and faces trimmed to a part of their surface (a smaller
rectangle, or a side that waves): the kinds of input a CAD file can hold."""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Optional

import numpy as np
from fuzz_kinds import kind_faces
from fuzz_seed import ROOT, commit_seed  # noqa: F401 (commit_seed: the seed of CI's run)
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


# The fixed runs of issues 19 and 22 (``benchmarks/run.py --suite fuzz``): seed and faces per method.
FIXED = {"2d": (2202, 300), "4d": (2204, 50)}
# The fixed runs of issue 34's kinds (kind_faces): seed and faces per method.
FIXED_KINDS = {"2d": (3402, 60), "4d": (3404, 10)}
# CI's run (tests/batch/test_fuzz.py): faces per method, drawn from a seed that changes with every commit (2D: 32
# since stop 79, 40 since stop 66, 60 before: CI's 25 minutes; a face with no four-sided map costs up to 20 s at
# times, its trim certified again on the finer grid; the fixed runs above and the soundness corpus,
# benchmarks/run.py --suite soundness, hold the counts of record).
ROTATING = {"2d": 32, "4d": 10}
ROTATING_KINDS = {"2d": 8, "4d": 3}
# Faces that once failed a check, or came within 0.2 % of failing one, as (method, seed, index): face
# `index` of random_faces(seed, ...), or of kind_faces when it reads "kN".  CI runs them every time, beside
# the rotating faces.  A face that fails goes here, with what it found.
REGRESSIONS = [
    # no face of a fixed or rotating run has failed since the fixed runs were made sound (stop 31); these
    # are the fixed runs' tightest, measured / bound at stop 31 in the comment
    ("2d", 2202, 7, "0.9998"), ("2d", 2202, 85, "0.9975"), ("2d", 2202, 26, "0.9974"),
    ("4d", 2204, 21, "0.9864"), ("4d", 2204, 5, "0.9735"),
    # found by the rotating run of 8dc8dac: 2D bound 78.9 against a measured 0.0027, its 4D attempt 2612
    # (33x the 2D bound); issue 34's bounds that blow up (extreme weights: graded grids and an adaptive area
    # since, 2D bound 0.0277 for 0.006 by OCCT alone, 4D within 0.1x the 2D bound)
    ("4d", 2378750657, 2, "issue 34"),
    # found by the rotating run of 0ba438b: a rational face with a collapsed row, 2D bound 0.0219 against a
    # measured 0.0144; its 4D surface measures 0.0128 but is certified at 0.739 (33.7x the 2D bound): a
    # loose 4D certificate at a collapsed row, the 2D result returned with a note saying why (xfail, named)
    ("4d", 195311794, 6, "loose 4D certificate"),
    # found by the rotating run of 7b44d42: a sheet with a hole, read back from STEP, where OCCT's ray
    # classifier (and BRepExtrema with it) puts a wedge of the face outside it: the oracle measured 22.7
    # against the bound 6.01, the product 1.45; trimmed_faces.classifier settles such disagreements
    ("2d", 2068108334, "k0", "oracle"),
    # found by the rotating run of 3c17230: a degree-1 tube (periodic, a corner at its seam) fitted closed by
    # the iso surface, certified at 1.747e-5 while points of the result lie 1.854e-5 from it: the forward
    # certificate left out the jump of R_s at the closed result's seam (now 1.998e-5)
    ("2d", 1008149261, 42, "seam kink"),
    # found by the rotating run of 54a5a4f: a rational face whose natural extension past the face (issue 35's
    # trimmed fit) reaches a zero weight: the fit crashed dividing by it; no extension there now
    ("2d", 1420141814, 19, "zero weight past the face"),
    # found by the rotating run of f06e6dd: a face with a hole and an inset outer loop, whose result trimmed by
    # its edges built an invalid face (measured 0.0118 against its bound 0.00124; the product refused it): by
    # default a face with holes is now pinned, and an invalid trimmed face is refused
    ("2d", 4033768917, "k1", "trimmed face with a hole"),
    # found by the rotating run of 3b84171: a tiny closed degree-1 x 4 face (size 5e-4, 1.2e5 from the origin)
    # whose 4D surface itself measures 5.9e-5 against the 2D bound 4.3e-6 (13.9x): a far 4D rebuild (issue
    # 36's), the 2D result returned (measured 3.2e-7); named in FAR_4D (xfail) until the rebuild holds it
    ("4d", 998512410, 9, "far 4D rebuild"),
    # found by the rotating run of 247c6cf: a rational face with extreme weights whose rails, run past the face
    # (issue 35), leave the surface's finite numbers: the fit crashed building the map's inverse; no extension
    # there now (the fit pinned at the face's corners, with a note)
    ("2d", 612134142, 10, "non-finite extension"),
    # found by the rotating run of 6ceec07 (and there at 1fbbd46 already): a rational degree-1 x 3 face, periodic
    # in v, extreme weights, whose 4D result is certified at 1.519 (its remainder: 1.519, nodes 0.411) while the
    # 32 x 32 measure finds 3.897 (12 x 12: 1.484): a 4D certificate that misses part of its result; named in
    # KNOWN_DENSE (xfail) until the certificate holds it
    ("4d", 1827586172, 4, "4D certificate below the dense measure"),
]
# Faces whose result a denser measure finds beyond its bound, known and reported (the check xfails naming them)
KNOWN_DENSE = {"4d:1827586172:4": "its 4D result certified at 1.519, measured 3.897 at 32 x 32 (a rational "
                                  "periodic face with extreme weights: the 4D certificate misses part of the result)"}
FACE_LIMIT = 120       # seconds: a face that takes longer hangs (they take about 3 s)
SAMPLES = 12           # the DP's and the measure's samples: small faces of every kind, not fine fits


@dataclass(frozen=True)
class FuzzFace:
    """One random face and where it comes from: face `index` of random_faces(seed, ...), or of
    kind_faces(seed, ...) when family is "k"."""

    method: str
    seed: int
    index: int
    face: object
    desc: str
    family: str = ""

    @property
    def name(self) -> str:
        """How to run this face alone: python tests/fuzz_faces.py --face NAME"""
        return f"{self.method}:{self.seed}:{self.family}{self.index}"


def faces_of(method: str, seed: int, count: int, family: str = "") -> list:
    made = kind_faces(seed, count) if family == "k" else random_faces(seed, count)
    return [FuzzFace(method, seed, k, f, d, family) for k, (f, d) in enumerate(made)]


def face_named(name: str) -> FuzzFace:
    method, seed, index = name.split(":")
    family = "k" if index.startswith("k") else ""
    k = int(index[len(family):])
    face, desc = (kind_faces if family else random_faces)(int(seed), k + 1)[-1]
    return FuzzFace(method, int(seed), k, face, desc, family)


def rotating_faces(seed: int, method: str) -> list:
    """CI's faces of one method: ROTATING[method] faces of the commit's seed (the 4D faces from seed + 1),
    ROTATING_KINDS[method] faces of issue 34's kinds (from seed + 2, and + 3 in 4D), then the regressions."""
    return (faces_of(method, seed + (method == "4d"), ROTATING[method])
            + faces_of(method, seed + 2 + (method == "4d"), ROTATING_KINDS[method], "k")
            + [face_named(f"{m}:{s}:{k}") for m, s, k, _ in REGRESSIONS if m == method])


@dataclass
class Batch:
    """A fuzz batch: its faces, the STEP file they were written to, the batch's folder of results and its
    summary rows (row["face"] indexes faces)."""

    method: str
    faces: list
    src: str
    folder: str
    rows: list
    seconds: float


def run_batch(folder: str, method: str, faces: list, jobs: int = 1, env: Optional[dict] = None) -> Batch:
    """The faces written to one STEP file in folder and fitted by ``ruled batch`` (a per-face limit, no
    plots).  Raises with the batch's log when it exits non-zero."""
    import json
    import subprocess
    import sys
    import time

    from ruled.occ.io import write_step
    os.makedirs(folder, exist_ok=True)
    src = os.path.join(folder, f"fuzz{method}.step")
    write_step([f.face for f in faces], src)
    out = os.path.join(folder, f"out{method}")
    t0 = time.perf_counter()
    r = subprocess.run([sys.executable, "-m", "ruled.cli", "batch", src, "--method", method, "--samples", str(SAMPLES),
                        "--measure-samples", str(SAMPLES), "--jobs", str(jobs), "--face-timeout", str(FACE_LIMIT),
                        "--no-plots", "--quiet", "-o", out], cwd=ROOT, capture_output=True, text=True,
                       env={**os.environ, **(env or {})})
    seconds = time.perf_counter() - t0
    if r.returncode != 0:
        raise RuntimeError(f"ruled batch exited {r.returncode}: {(r.stdout + r.stderr)[-3000:]}")
    with open(os.path.join(out, "summary.json")) as fh:
        rows = json.load(fh)["rows"]
    return Batch(method, faces, src, os.path.join(out, f"fuzz{method}"), rows, seconds)


def _who(b: Batch, r: dict) -> str:
    f = b.faces[r["face"]]
    return f"face {f.name} ({f.desc})"


def check_outcomes(b: Batch) -> list:
    """No crash or hang, refusals in one line, most faces fitted, the report's measure within its bound,
    a valid result face.  Returns the violations, one line each."""
    from OCP.BRepCheck import BRepCheck_Analyzer

    from ruled.occ.io import read_faces
    bad = []
    if len(b.rows) != len(b.faces):
        bad.append(f"{len(b.rows)} rows for {len(b.faces)} faces")
    for r in b.rows:
        if r["status"] == "failed":
            bad.append(f"{_who(b, r)}: failed: {r['reason']}")
        elif r["status"] == "refused" and "is above its certified bound" in r["reason"]:
            # the product caught a false certificate of its own (issue 34): the user is safe, the bound is not
            bad.append(f"{_who(b, r)}: refused by its own check: {r['reason']}")
        elif r["status"] == "refused" and (not r["reason"] or "\n" in r["reason"] or "Traceback" in r["reason"]):
            bad.append(f"{_who(b, r)}: a refusal not in one line: {r['reason']!r}")
        elif r["status"] == "ok":
            if r["hausdorff"] > r["error_bound"]:
                bad.append(f"{_who(b, r)}: measured {r['hausdorff']:.6g} above the bound {r['error_bound']:.6g}")
            out = read_faces(os.path.join(b.folder, f"face_{r['face']}.step"))
            if len(out) != 1 or not BRepCheck_Analyzer(out[0]).IsValid():
                bad.append(f"{_who(b, r)}: the result is not one valid face")
    # a generator whose faces are all refused would test nothing: 90 % fitted (the fixed runs: 97 % in 2D,
    # 98 % in 4D); 75 % of a batch under 30 faces, where one refusal more is 8 % (binomial noise, not a fault)
    ok = sum(r["status"] == "ok" for r in b.rows)
    if ok < (0.9 if len(b.rows) >= 30 else 0.75) * len(b.rows):
        bad.append(f"only {ok} of {len(b.rows)} faces fitted")
    return bad


def tightest(b: Batch, count: int = 6) -> list:
    """The rows of the faces whose measure came closest to their bound."""
    ok = [r for r in b.rows if r["status"] == "ok" and r["error_bound"] > 0]
    return sorted(ok, key=lambda r: r["hausdorff"] / r["error_bound"], reverse=True)[:count]


def check_dense(b: Batch, count: int = 6, n: int = 32) -> list:
    """The faces whose measure came closest to their bound, measured again more densely (n x n points of
    each face plus its edges, projected by OCCT onto the other): within their bounds."""
    from trimmed_faces import measure

    from ruled.occ.io import read_faces
    inputs = read_faces(b.src)                  # the faces as the batch read them
    bad = []
    for r in tightest(b, count):
        out = read_faces(os.path.join(b.folder, f"face_{r['face']}.step"))[0]
        h = measure(inputs[r["face"]], out, n)
        if h > r["error_bound"]:
            bad.append(f"{_who(b, r)}: measured {h:.6g} at {n} x {n} above the bound {r['error_bound']:.6g}")
    return bad


def check_independent(b: Batch, n: int = 12) -> tuple:
    """The fitted faces of issue 34's kinds (family "k") re-measured by OCCT alone, both ways, with points
    inside each face and on its edges (trimmed_faces.extrema_measure): (violations, the largest measured /
    bound, the faces measured)."""
    from trimmed_faces import extrema_measure

    from ruled.occ.io import read_faces
    inputs = read_faces(b.src)
    bad, worst, count = [], 0.0, 0
    for r in b.rows:
        if r["status"] != "ok" or b.faces[r["face"]].family != "k":
            continue
        out = read_faces(os.path.join(b.folder, f"face_{r['face']}.step"))[0]
        a, c = extrema_measure(inputs[r["face"]], out, n)
        count += 1
        worst = max(worst, max(a, c) / max(r["error_bound"], 1e-300))
        if max(a, c) > r["error_bound"]:
            bad.append(f"{_who(b, r)}: by OCCT alone {a:.6g} face to result, {c:.6g} result to face, above the "
                       f"bound {r['error_bound']:.6g}")
    return bad, worst, count


def four_d_ratios(b: Batch) -> list:
    """(4D bound / 2D bound, row, the report's comparison: the two attempts' bounds and sampled measures) of
    every fitted face whose report compares the two."""
    import json
    ratios = []
    for r in b.rows:
        if r["status"] != "ok":
            continue
        with open(os.path.join(b.folder, f"face_{r['face']}.json")) as fh:
            c = json.load(fh).get("comparison", {})
        if "2d" in c and "4d" in c and c["2d"]["error_bound"] > 0:
            x = c["4d"]["error_bound"] / c["2d"]["error_bound"]
            ratios.append((x, r, c))
    return ratios


def check_4d(b: Batch) -> list:
    """Issue 22: the 4D attempt's own bound within 10x the 2D bound of the same face, on most faces."""
    ratios = four_d_ratios(b)
    bad = [_too_far(b, x, r) for x, r, _ in ratios if x > 10.0]
    if len(ratios) < 0.5 * len(b.rows):
        bad.append(f"only {len(ratios)} of {len(b.rows)} faces got a 4D attempt")
    return bad


FAR_4D = {"4d:998512410:9": "its 4D surface measured 5.9e-5 against the 2D bound 4.3e-6 (issue 36's rebuild)"}


def known_blowups(b: Batch) -> dict:
    """The violations of check_4d where the 4D surface itself is within 10x the 2D bound by its own sampled
    measure, and only a certificate is loose (the 4D attempt's, or the 2D one it inherits, at least 10x its
    measured distance): a loose certificate, where the 2D result is returned with a note (the one known is a
    4D fit at a collapsed row, 4d:195311794:6).  A 4D surface that is itself far (issue 22's rebuild) is not
    among them, unless named in FAR_4D with the 2D result returned.  {violation: what the measure says}."""
    out = {}
    for x, r, c in four_d_ratios(b):
        b2, b4, m4 = c["2d"]["error_bound"], c["4d"]["error_bound"], c["4d"].get("measured_sampled")
        loose = (r["error_bound"] >= 10.0 * max(r["hausdorff"], 1e-300)
                 or (m4 is not None and b4 >= 10.0 * max(m4, 1e-300)))
        if x > 10.0 and m4 is not None and m4 <= 10.0 * b2 and loose:
            out[_too_far(b, x, r)] = f"the 4D surface measured {m4:.4g}: a loose certificate"
        # a far 4D rebuild, known by name, where the product returned the 2D result (its bound the 2D one)
        elif x > 10.0 and b.faces[r["face"]].name in FAR_4D and r["error_bound"] <= b2:
            out[_too_far(b, x, r)] = FAR_4D[b.faces[r["face"]].name]
    return out


def _too_far(b: Batch, x: float, r: dict) -> str:
    return f"{_who(b, r)}: 4D bound {x:.4g} x the 2D bound"


def check(b: Batch, dense: int = 6) -> list:
    """Every check of a batch."""
    return (check_outcomes(b) + check_dense(b, dense) + check_independent(b)[0]
            + (check_4d(b) if b.method == "4d" else []))


def main(argv=None) -> int:
    """python tests/fuzz_faces.py [--seed N | --fixed | --face M:SEED:INDEX ...] [--jobs J] [-o FOLDER]:
    the rotating run of a seed (CI's, RULED_FUZZ_SEED or the commit's when no option), the fixed runs, or
    the faces named, through ``ruled batch``; prints the figures and every violation; exit 1 on any."""
    import argparse
    import tempfile
    ap = argparse.ArgumentParser(description=main.__doc__)
    ap.add_argument("--seed", type=int)
    ap.add_argument("--fixed", action="store_true", help="the fixed runs (2D seed 2202: 300 faces, 4D 2204: 50)")
    ap.add_argument("--face", nargs="+", default=[], help="faces by name, as a failing check prints them")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("-o", "--out", help="the folder of the batches (default: a new temporary one)")
    a = ap.parse_args(argv)
    folder = a.out or tempfile.mkdtemp(prefix="ruled-fuzz-")
    if a.face:
        named = [face_named(n) for n in a.face]
        runs = {m: [f for f in named if f.method == m] for m in ("2d", "4d")}
    elif a.fixed:
        runs = {m: faces_of(m, s, c) + faces_of(m, *FIXED_KINDS[m], "k") for m, (s, c) in FIXED.items()}
    else:
        seed = commit_seed() if a.seed is None else a.seed
        print(f"fuzz seed {seed}")
        runs = {m: rotating_faces(seed, m) for m in ROTATING}
    failed = 0
    for method, faces in runs.items():
        if not faces:
            continue
        b = run_batch(folder, method, faces, a.jobs)
        print(summary(b))
        bad = check(b)
        failed += len(bad)
        for line in bad:
            print("  VIOLATION", line)
    print(f"results in {folder}")
    return 1 if failed else 0


def summary(b: Batch) -> str:
    """One line of a batch's figures."""
    st = {s: sum(r["status"] == s for r in b.rows) for s in ("ok", "refused", "failed")}
    top = [r["hausdorff"] / r["error_bound"] for r in tightest(b, 3)]
    line = (f"{b.method}: {len(b.rows)} faces, {st['ok']} fitted, {st['refused']} refused, {st['failed']} failed "
            f"in {b.seconds:.0f} s wall; measured / bound, the largest: {', '.join(f'{x:.4f}' for x in top)}")
    if b.method == "4d":
        ratios = sorted(four_d_ratios(b), key=lambda xr: xr[0], reverse=True)
        line += f"; 4D / 2D bound, the largest: {', '.join(f'{x:.3g}' for x, _, _ in ratios[:3])}"
    return line


if __name__ == "__main__":
    import sys
    sys.exit(main())
