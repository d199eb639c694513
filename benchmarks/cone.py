"""Cone-spline benchmark (Yang & Yang 2006), run by ``benchmarks/run.py --suite cone``.

Target: each of the paper's examples (1, 2, 3a, 3b) in <= 0.2 s: the fat conic spline fitting of
the extended fat curve (parallel steps, tangents, triangles, weights, eq. 9 per candidate arc, the
longest-step search and the balancing passes), warm, the best of five repeats (the VM is noisy).
Also printed: the patch counts beside the paper's, the paper's own step search (shrink by 0.9 only)
for comparison, the whole space pipeline (frame, extension, fit, trim, patches) on the original
surfaces, and the NumPy-only times (RULED_NO_NUMBA=1, as in FreeCAD's Python).
"""

from __future__ import annotations

import os
import subprocess
import sys
import time

import numpy as np

from ruled.cone.conespline import cone_spline
from ruled.cone.fatarc import fit_fat_conic
from ruled.examples import cone_examples

TARGET_S = 0.2


def _best(fn, repeat: int = 5) -> float:
    fn()
    ts = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        ts.append(time.perf_counter() - t)
    return min(ts)


def _lift(b, db, z):
    return (lambda v: np.column_stack([b(v), np.full(len(np.atleast_1d(v)), z)]),
            lambda v: np.column_stack([db(v), np.zeros(len(np.atleast_1d(v)))]))


def _space(case):
    _, b0, db0, b1, db1, tol, step, h, _ = case
    c0, dc0 = _lift(lambda v: 0.8 * b0(v) + 0.2 * b1(v), lambda v: 0.8 * db0(v) + 0.2 * db1(v), 0.2 * h)
    c1, dc1 = _lift(lambda v: 0.2 * b0(v) + 0.8 * b1(v), lambda v: 0.2 * db0(v) + 0.8 * db1(v), 0.8 * h)
    return cone_spline(c0, dc0, c1, dc1, tol, step)


def numpy_times() -> list:
    code = ("import sys; sys.path.insert(0, %r); from cone import _best, cone_examples, fit_fat_conic\n"
            "for c in cone_examples():\n"
            "    print(c[0], _best(lambda: fit_fat_conic(*c[1:7], h1=c[7]), 3))" % os.path.dirname(__file__))
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         env={**os.environ, "RULED_NO_NUMBA": "1"})
    return [(ln.split()[0], float(ln.split()[1])) for ln in out.stdout.splitlines() if ln.strip()]


def bench_cone() -> None:
    print("== cone splines (Yang & Yang 2006): the paper's examples, fat conic fitting of the extended fat curve")
    print(f"{'example':>8} {'patches':>8} {'paper':>6} {'paper loop':>11} {'bound':>9} {'tol':>6} "
          f"{'time':>8} {'target':>7} {'ratio':>6} {'in space':>9}")
    for case in cone_examples():
        name, b0, db0, b1, db1, tol, step, h, paper = case
        arcs = fit_fat_conic(b0, db0, b1, db1, tol, step, h1=h)
        plain = fit_fat_conic(b0, db0, b1, db1, tol, step, h1=h, search="paper", balance=False)
        t = _best(lambda: fit_fat_conic(b0, db0, b1, db1, tol, step, h1=h))
        ts = _best(lambda: _space(case), 3)
        print(f"{name:>8} {len(arcs):>8} {paper:>6} {len(plain):>11} {max(a.err for a in arcs):>9.4g} {tol:>6g} "
              f"{t:>7.3f}s {TARGET_S:>6.1f}s {t / TARGET_S:>6.2f} {ts:>8.3f}s")
    for name, t in numpy_times():
        print(f"   NumPy only (RULED_NO_NUMBA=1), example {name}: {t:.3f} s")
