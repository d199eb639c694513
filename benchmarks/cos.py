"""Curves-on-surfaces benchmark (Yang et al. 2008), run by ``benchmarks/run.py --suite cos``.

Targets: the paper's first example at 1e-3 / 10 degrees in <= 5 ms; a 20-segment cubic domain
curve on a 19 x 19 bicubic surface at 1e-3 / 1 degree in <= 100 ms.  Times are the engine's
``approximate`` (pieces, subdivision, composition into one B-spline and its pcurve), warm, the
best of several repeats (the VM is noisy).  Also printed: the segment counts against the paper's,
the fewest chords that can reach the tolerance on the first example (greedy, measured), and the
tolerance sweep of the paper's Table 1 (measured / tolerance).
"""

from __future__ import annotations

import os
import subprocess
import sys
import time

import numpy as np

from ruled.core.nurbs import Curve, Surface
from ruled.curves.curve_on_surface import approximate, sampled_error
from ruled.examples import yang_curve, yang_surface


def ear_like_surface(n: int = 19) -> Surface:
    """A smooth bicubic height-field B-spline with n x n poles (uniform knots), in the unit square."""
    k = np.concatenate([np.zeros(4), np.linspace(0, 1, n - 2)[1:-1], np.ones(4)])
    g = np.linspace(0, 1, n)
    X, Y = np.meshgrid(g, g, indexing="ij")
    Z = 0.3 * np.sin(3 * X) * np.cos(4 * Y) + 0.2 * np.exp(-((X - .5) ** 2 + (Y - .4) ** 2) * 8)
    return Surface(np.stack([X, Y, Z], axis=2), k, k, 3, 3)


def star_curve(segments: int = 20) -> Curve:
    """A closed-looking cubic B-spline with the given number of polynomial segments."""
    m = segments + 3
    k = np.concatenate([np.zeros(4), np.linspace(0, 1, m - 2)[1:-1], np.ones(4)])
    t = np.linspace(0, 1, m)
    r = 0.4 * (0.6 + 0.4 * np.sin(6 * np.pi * t))
    return Curve(np.stack([0.5 + r * np.cos(2 * np.pi * t), 0.5 + r * np.sin(2 * np.pi * t)], axis=1), k, 3)


def _best_time(fn, repeat: int) -> float:
    fn()
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def _chord_error(S, D, a, b, n=300):
    """Measured Hausdorff distance between S(chord of D over [a, b]) and S(D) over [a, b] (dense)."""
    from scipy.spatial import cKDTree
    t = np.linspace(a, b, n)
    E = S(*D(t).T)
    P, Q = D(np.array([a, b]))
    s = np.linspace(0, 1, n)[:, None]
    C = S(*(P + s * (Q - P)).T)
    return max(cKDTree(E).query(C)[0].max(), cKDTree(C).query(E)[0].max())


def fewest_chords(S, D, tol) -> int:
    """Greedy cover of the domain curve by chords whose measured error is within tol (each chord as
    long as it can be): the fewest chords of any polyline through points of D reaching tol."""
    lo, hi = D.domain
    a, count = lo, 0
    while a < hi:
        if _chord_error(S, D, a, hi) <= tol:
            return count + 1
        x, y = a, hi
        for _ in range(40):
            m = 0.5 * (x + y)
            x, y = (m, y) if _chord_error(S, D, a, m) <= tol else (x, m)
        a, count = x, count + 1
    return count


def bench_cos(repeat: int = 7) -> None:
    S, D = yang_surface(), yang_curve()
    print("curves on surfaces (Yang et al. 2008), the engine's approximate(), warm, best of", repeat)
    print("first example: quadratic domain curve on the biquadratic patch, tolerance 1e-3")
    print(f"  {'angle':>6} {'rule':>6} {'segments':>8} {'after distance':>14} {'bound':>10} {'measured':>10} "
          f"{'joint deg':>9} {'time ms':>8} {'ratio to 5 ms':>13}")
    for ang in (10.0, 1.0):
        for rule in ("local", "span"):
            r = approximate(S, D, 1e-3, ang, bound=rule)
            t = _best_time(lambda: approximate(S, D, 1e-3, ang, bound=rule), repeat)
            h = sampled_error(S, D, r)["hausdorff"]
            print(f"  {ang:6g} {rule:>6} {r.segments:8d} {r.distance_segments:14d} {r.error_bound:10.3g} {h:10.3g} "
                  f"{r.max_joint_angle_deg:9.3g} {1e3 * t:8.2f} {t / 5e-3:13.2f}")
    n8 = _chord_error_uniform(S, D, 8)
    print(f"  the paper reports 8 segments; 8 equal chords measure {n8:.3g} (33x the tolerance); the fewest "
          f"chords reaching 1e-3 (greedy, measured): {fewest_chords(S, D, 1e-3)}")
    print("tolerance sweep (the paper's Table 1), angle 10 degrees:")
    for tol in (1.0, 0.5, 0.3, 0.1, 0.01, 1e-3, 1e-4):
        r = approximate(S, D, tol, 10.0)
        h = sampled_error(S, D, r)["hausdorff"]
        print(f"  tol {tol:8g}: {r.segments:4d} segments, bound {r.error_bound:9.3g}, measured {h:9.3g}, "
              f"measured/tol {h / tol:5.2f}")
    E, C = ear_like_surface(), star_curve()
    print("20-segment cubic domain curve on a 19x19 bicubic surface, tolerance 1e-3:")
    for ang in (10.0, 1.0):
        r = approximate(E, C, 1e-3, ang)
        t = _best_time(lambda: approximate(E, C, 1e-3, ang), max(2, repeat // 2))
        h = sampled_error(E, C, r)["hausdorff"]
        print(f"  angle {ang:4g}: {r.segments:5d} segments ({r.control_points} control points), bound "
              f"{r.error_bound:.3g}, measured {h:.3g}, {1e3 * t:7.1f} ms, ratio to 100 ms {t / 0.1:5.2f}")
    here = os.path.dirname(os.path.abspath(__file__))
    code = (f"import sys; sys.path[:0] = [{here!r}, {os.path.dirname(here)!r}]; "
            f"from cos import numpy_times; numpy_times()")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         env={**os.environ, "RULED_NO_NUMBA": "1"})
    print(out.stdout.rstrip() or out.stderr[-500:])


def numpy_times(repeat: int = 5) -> None:
    """The two timing targets on the NumPy path alone (run with RULED_NO_NUMBA=1, as FreeCAD's Python)."""
    S, D = yang_surface(), yang_curve()
    E, C = ear_like_surface(), star_curve()
    t1 = _best_time(lambda: approximate(S, D, 1e-3, 10.0), repeat)
    t2 = _best_time(lambda: approximate(E, C, 1e-3, 1.0), max(2, repeat // 2))
    print(f"  NumPy only (no numba): first example {1e3 * t1:.2f} ms, 19x19 at 1 degree {1e3 * t2:.1f} ms")


def _chord_error_uniform(S, D, k: int) -> float:
    t = np.linspace(*D.domain, k + 1)
    return max(_chord_error(S, D, a, b) for a, b in zip(t[:-1], t[1:]))
