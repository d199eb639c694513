"""Benchmarks: the full 2D fit, and the 4D-DP engine; per-stage times, peak memory, ratios to targets.

    .venv/bin/python benchmarks/run.py [--suite all|2d|4d|cos|cone|split|machine|trimmed|job|batch|fuzz|data|wall|wavy
                                                |engine|census [--ends auto|pinned]|soundness [--count N]]
                                       [--against COMMIT (engine, job, batch)]
                                       [--n 50 100 200] [--surface ex2] [--no-numpy]

2D target: n = 100 end to end (both directions tried, refined, rebuilt, certified) in <= 0.5 s.
4D targets (the 4D-DP end to end: elevated samples, closest-point nodes, cost tables, DP sweep and
back-tracking): SSHB n = 50 with 41 levels <= 1.5 s and n = 100 with 21 levels <= 2.5 s, peak
memory <= 400 MB for both; LSAD n = 50 with 49 levels <= 0.6 s.  Curves on surfaces: see
benchmarks/cos.py; cone splines: benchmarks/cone.py; the split DP: benchmarks/split.py; machine
outputs: benchmarks/machine.py; trimmed faces: benchmarks/trimmed.py; the user's whole job (processes'
CPU seconds, the engine at n = 100): benchmarks/job.py; the engine's figures beside a named commit's, in one
run: benchmarks/engine.py; the whole-part batch (--jobs 1 against
--jobs 2): benchmarks/batch.py; the fixed fuzz runs (300 faces in 2D, 50 in 4D): benchmarks/fuzz.py; every
face of the data files, re-measured by OCCT alone: benchmarks/data.py; every B-spline face fitted, its
refusals and results that do not cover it counted (--suite census, not in all): benchmarks/census.py; a part's
wall fitted closed: benchmarks/wall.py; trimmed faces with wavy boundaries counted (--suite wavy, not in
all): benchmarks/wavy.py; the soundness corpus, every source's faces measured at 80 x 80 against their bounds
(--suite soundness, not in all): benchmarks/soundness.py.
The NumPy-only times (no numba, as in FreeCAD's Python) are printed too, from a subprocess with
RULED_NO_NUMBA=1.

The machine has 2 cores.  The first call compiles the numba kernels (cached afterwards); the
figures are from warm runs, median of three.  Peak memory is the traced Python/NumPy allocation
peak (numba kernels allocate nothing large).
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
import tracemalloc

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from ruled import FitOptions, fit_surface  # noqa: E402
from ruled.core import jit
from ruled.examples import EXAMPLES  # noqa: E402

TARGET_N, TARGET_S = 100, 0.5


CASES_4D = [("sshb", 50, 20, 1.5), ("sshb", 100, 10, 2.5), ("lsad", 50, 24, 0.6)]
TARGET_MB = 400


def main(argv=None) -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--suite", choices=["all", "2d", "4d", "cos", "cone", "split", "machine", "trimmed", "job",
                                        "engine", "batch", "fuzz", "data", "census", "wall", "wavy", "soundness"],
                    default="all")
    ap.add_argument("--slow", action="store_true", help="with --suite job: the closed 4D fit at n = 100 too")
    ap.add_argument("--against", metavar="COMMIT", help="with --suite engine, job or batch: a commit's figures beside "
                    "today's, in one run")
    ap.add_argument("--ends", choices=["auto", "pinned", "trimmed"], default="auto",
                    help="with --suite census: the fit's ends (pinned: the fit before issue 35)")
    ap.add_argument("--count", type=int, default=40, help="with --suite soundness: the wavy and ruled faces each")
    ap.add_argument("--n", type=int, nargs="+", default=[50, 100, 200])
    ap.add_argument("--surface", choices=sorted(EXAMPLES), default="ex2")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--no-numpy", action="store_true", help="skip the NumPy-only 4D times")
    ap.add_argument("--numpy-child", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    S = EXAMPLES[args.surface]()
    if args.numpy_child:
        for metric, n, m, _ in CASES_4D:
            t, st, _ = _engine_4d(S, n, m, metric)
            print(f"numpy {metric} {n} {2 * m + 1} {t:.3f} " + " ".join(f"{k}={v:.3f}" for k, v in st.items()))
        return 0
    if args.suite in ("all", "2d"):
        _bench_2d(S, args)
    if args.suite in ("all", "4d"):
        _bench_4d(S, args)
    if args.suite in ("all", "cos"):
        from cos import bench_cos
        bench_cos()
    if args.suite in ("all", "cone"):
        from cone import bench_cone
        bench_cone()
    if args.suite in ("all", "split"):
        from split import bench_split
        bench_split()
    if args.suite in ("all", "machine"):
        from machine import bench_machine
        bench_machine()
    if args.suite in ("all", "trimmed"):
        from trimmed import bench_trimmed
        bench_trimmed()
    if args.suite in ("all", "job"):
        from job import bench_job
        bench_job(args.slow, args.against)
    if args.suite in ("all", "engine"):
        from engine import bench_engine
        bench_engine(args.against)
    if args.suite in ("all", "batch"):
        from batch import bench_batch, bench_batch_against
        bench_batch_against(args.against) if args.against else bench_batch()
    if args.suite in ("all", "wall"):
        from wall import bench_wall
        bench_wall()
    if args.suite == "wavy":         # (not in all: minutes)
        from wavy import bench_wavy
        bench_wavy()
    bad = 0
    if args.suite in ("all", "fuzz"):
        from fuzz import bench_fuzz
        bad += bench_fuzz()
    if args.suite in ("all", "data"):
        from data import bench_data
        bad += bench_data()
    if args.suite == "census":
        from census import bench_census
        bench_census(args.ends)
    if args.suite == "soundness":    # (not in all: an hour)
        from soundness import bench_soundness
        bad += bench_soundness(args.count)
    return 1 if bad else 0


def _engine_4d(S, n: int, m: int, metric: str):
    """The 4D-DP end to end on the oriented surface S: (seconds, stages, DP result)."""
    from ruled.core import sampling
    from ruled.fit.dp import dp4d, metrics4d
    st = {}
    t0 = time.perf_counter()
    smp = sampling.elevated_samples(S, n, m, 0.05 * S.diagonal() / max(m, 1), False)
    if metric == "sshb":
        feet = metrics4d.ruling_feet(S, smp, 16)
        terms = metrics4d.patch_terms(S, smp, feet)
        st["nodes"] = time.perf_counter() - t0
        t1 = time.perf_counter()
        T = dp4d.Tables(True, n, 2 * m + 1, None, metrics4d.sshb_ruling_tables(smp, feet), terms)
    else:
        feet = metrics4d.ruling_feet(S, smp, 9, edges=False)
        st["nodes"] = time.perf_counter() - t0
        t1 = time.perf_counter()
        T = dp4d.Tables(False, n, 2 * m + 1, metrics4d.lsad_tables(smp, feet))
    st["tables"] = time.perf_counter() - t1
    t1 = time.perf_counter()
    res = dp4d.solve(T, False, "sum")
    st["dp"] = time.perf_counter() - t1
    return time.perf_counter() - t0, st, res


def _bench_4d(S, args) -> None:
    import resource
    import subprocess
    _engine_4d(S, 8, 2, "sshb")
    _engine_4d(S, 8, 2, "lsad")
    print(f"\n4D-DP engine on {args.surface} (numba {'on' if jit.enabled() else 'off'}), median of "
          f"{args.repeat}:")
    print(f"{'metric':>6} {'n':>4} {'levels':>6} {'total s':>8} {'nodes':>7} {'tables':>7} {'dp':>7} "
          f"{'peak MiB':>9} {'target s':>8} {'ratio':>6}")
    for metric, n, m, target in CASES_4D:
        runs = [_engine_4d(S, n, m, metric) for _ in range(args.repeat)]
        runs.sort(key=lambda r: r[0])
        t, st, _ = runs[len(runs) // 2]
        tracemalloc.start()
        _engine_4d(S, n, m, metric)
        peak = tracemalloc.get_traced_memory()[1] / 2**20
        tracemalloc.stop()
        print(f"{metric:>6} {n:4d} {2 * m + 1:6d} {t:8.3f} {st['nodes']:7.3f} {st['tables']:7.3f} {st['dp']:7.3f} "
              f"{peak:9.1f} {target:8.1f} {t / target:6.2f}" + ("" if metric == "lsad" else
                                                                 f"   memory ratio {peak / TARGET_MB:.2f}"))
    print(f"process peak RSS so far: {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.0f} MiB")
    if not args.no_numpy:
        run = subprocess.run([sys.executable, os.path.abspath(__file__), "--surface", args.surface, "--numpy-child"],
                             capture_output=True, text=True, env={**os.environ, "RULED_NO_NUMBA": "1"})
        print("NumPy only (RULED_NO_NUMBA=1, one run each):")
        for line in run.stdout.splitlines():
            if line.startswith("numpy"):
                _, metric, n, lv, t, *rest = line.split()
                print(f"{metric:>6} {int(n):4d} {int(lv):6d} {float(t):8.3f}   " + " ".join(rest))
        if run.returncode:
            print(run.stderr[-2000:])
    # the whole 4D fit (2D baseline, 4D-DP, refinement, rebuild, certificates, measures), and the
    # independent OCCT measure of both results when OCP is installed
    from ruled.examples import elber_ex1, elber_ex2
    try:
        from ruled.occ.convert import container_to_face
        from ruled.occ.measure import hausdorff
    except ImportError:
        hausdorff = None
    for name, make in (("ex1", elber_ex1), ("ex2", elber_ex2)):
        for metric in ("lsad", "sshb"):
            S = make()
            t = time.perf_counter()
            r = fit_surface(S, FitOptions(samples=40, method="4d", elevations=10, metric=metric))
            t = time.perf_counter() - t
            line = f"full 4D fit {name} (40 samples, 21 levels, {metric}): {t:.2f} s, bound {r.error_bound:.4g}"
            if hausdorff is not None and r.other is not None:
                face = container_to_face(S)
                h4 = hausdorff(face, container_to_face(r.surface), 40).max
                h2 = hausdorff(face, container_to_face(r.other.surface), 40).max
                line += (f"; OCCT Hausdorff {h4:.4g} vs 2D {h2:.4g} ({100 * (1 - h4 / h2):.1f}% lower), "
                         f"bound/measure {r.error_bound / h4:.3f}")
            print(line)


def _bench_2d(S, args) -> None:
    t = time.perf_counter()
    fit_surface(S, FitOptions(samples=10))
    print(f"warm-up (numba {'on' if jit.enabled() else 'off'}, includes any compile): "
          f"{time.perf_counter() - t:.2f} s")
    print(f"{'n':>5} {'total s':>8} {'cost':>7} {'dp':>7} {'refine':>7} {'rebuild':>7} {'certify':>7} "
          f"{'peak MiB':>9}")
    for n in args.n:
        totals, stages = [], []
        for _ in range(args.repeat):
            t = time.perf_counter()
            r = fit_surface(S, FitOptions(samples=n))
            totals.append(time.perf_counter() - t)
            st = {}
            for c in r.candidates.values():
                if isinstance(c, str):
                    continue
                for k, v in c.timings.items():
                    st[k] = st.get(k, 0.0) + v
            stages.append(st)
        tracemalloc.start()
        fit_surface(S, FitOptions(samples=n))
        peak = tracemalloc.get_traced_memory()[1] / 2**20
        tracemalloc.stop()
        k = totals.index(statistics.median(totals))
        st = stages[k]
        print(f"{n:5d} {totals[k]:8.3f} {st.get('cost_table', 0):7.3f} {st.get('dp', 0):7.3f} "
              f"{st.get('refine', 0):7.3f} {st.get('rebuild', 0):7.3f} {st.get('certify', 0):7.3f} {peak:9.1f}")
        if n == TARGET_N:
            print(f"      target n={TARGET_N}: {TARGET_S} s -> ratio measured/target = {totals[k] / TARGET_S:.2f}")
    _with_occt(S, TARGET_N)


def _with_occt(S, n: int) -> None:
    """The same job through STEP files, as the command line runs it, and the independent measure."""
    try:
        from ruled.occ.convert import container_to_face, face_to_container
        from ruled.occ.io import get_face, write_step
        from ruled.occ.measure import hausdorff
    except ImportError:
        print("(OCP not installed: no STEP round trip)")
        return
    import tempfile
    with tempfile.TemporaryDirectory() as d:
        src = os.path.join(d, "in.step")
        write_step(container_to_face(S), src)
        t0 = time.perf_counter()
        face = get_face(src, 0)
        res = fit_surface(face_to_container(face), FitOptions(samples=n))
        out = container_to_face(res.surface)
        write_step(out, os.path.join(d, "out.step"))
        t1 = time.perf_counter()
        h = hausdorff(face, out, 40)
        t2 = time.perf_counter()
    print(f"n={n} through STEP (read, fit, build, write): {t1 - t0:.3f} s; "
          f"independent OCCT measure (40x40 samples per face): {t2 - t1:.2f} s, Hausdorff {h.max:.4g}")


if __name__ == "__main__":
    sys.exit(main())
