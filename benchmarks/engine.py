"""The engine's figures, today's beside a named commit's, in one run (``benchmarks/run.py --suite engine
[--against COMMIT]``, issue 60): the 2D fit at n = 100 on Elber's ex1 and ex2 (refined and certified, both
directions; ex1 along v alone too, as issue 60 measured it; one process's CPU seconds, median of 3 after a
warm-up) and the 4D SSHB fit at n = 50 with 41 levels on ex2 (wall
and CPU seconds, median of 3), each with its bound.  The commit's code is taken out of git (``git archive``) into
a temporary folder and measured in its own processes, alternating with today's (a shared machine's load falls on
both alike); the figures' ratios printed with issue 60's targets (2D ex1 <= 0.08 CPU s, 4D <= 1.5 s).

Run alone: ``python benchmarks/engine.py --measure`` prints one process's figures as JSON (the code imported is
whichever ``ruled`` is first on sys.path)."""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import tarfile
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TARGETS = {"2d ex1 n=100": (0.08, "CPU"), "2d ex1 n=100 v": (0.08, "CPU"), "2d ex2 n=100": (0.2, "CPU"),
           "4d ex2 n=50/41": (1.5, "wall")}
ROUNDS = 3


def measure() -> dict:
    """This process's figures: {name: [CPU s, wall s, bound]} (the median run of 3 after a warm-up)."""
    from ruled import FitOptions, fit_surface
    from ruled.examples import EXAMPLES
    cases = [("2d ex1 n=100", "ex1", dict(samples=100)), ("2d ex1 n=100 v", "ex1", dict(samples=100, direction="v")),
             ("2d ex2 n=100", "ex2", dict(samples=100)),
             ("4d ex2 n=50/41", "ex2", dict(samples=50, method="4d", elevations=20, metric="sshb"))]
    out = {}
    for name, example, kw in cases:
        S = EXAMPLES[example]()
        fit_surface(S, FitOptions(**{**kw, "samples": 12}))          # (the kernels compiled or loaded)
        runs = []
        for _ in range(3):
            c0, w0 = time.process_time(), time.perf_counter()
            r = fit_surface(S, FitOptions(**kw))
            runs.append((time.process_time() - c0, time.perf_counter() - w0, float(r.error_bound)))
        out[name] = list(sorted(runs)[1])
    return out


def _process(root: str) -> dict:
    """measure() in a fresh process importing the ruled package of root."""
    env = {**os.environ, "PYTHONPATH": root}
    run = subprocess.run([sys.executable, os.path.abspath(__file__), "--measure"], capture_output=True, text=True,
                         env=env, cwd=root)
    if run.returncode != 0:
        raise SystemExit(f"the engine's measure failed in {root}: {run.stderr.strip().splitlines()[-1:]}")
    return json.loads(run.stdout.strip().splitlines()[-1])


def checkout(commit: str) -> str:
    """The commit's tree, extracted into a temporary folder (its path)."""
    folder = tempfile.mkdtemp(prefix=f"ruled-{commit[:8]}-")
    archive = subprocess.run(["git", "-C", ROOT, "archive", "--format=tar", commit], capture_output=True)
    if archive.returncode != 0:
        raise SystemExit(f"no commit {commit!r} in {ROOT}: {archive.stderr.decode().strip()}")
    with tempfile.TemporaryFile() as fh:
        fh.write(archive.stdout)
        fh.seek(0)
        with tarfile.open(fileobj=fh) as tar:
            tar.extractall(folder, filter="data")
    return folder


def _median(values: list) -> float:
    return sorted(values)[len(values) // 2]


def bench_engine(against: str | None = None) -> None:
    print("== the engine (one process's CPU seconds, median of 3 after a warm-up; 4D wall too)"
          + (f": today beside {against}" if against else ""))
    roots = {"today": ROOT}
    if against:
        roots[against] = checkout(against)
    got: dict = {k: [] for k in roots}
    for _ in range(ROUNDS):               # alternating: the machine's load on both alike
        for k, root in roots.items():
            got[k].append(_process(root))
    for name, (target, kind) in TARGETS.items():
        fig = {k: [_median([g[name][0] for g in runs]), _median([g[name][1] for g in runs]), runs[0][name][2]]
               for k, runs in got.items()}
        t = fig["today"]
        line = f"   {name:16s} today {t[0]:6.3f} CPU s ({t[1]:6.3f} wall), bound {t[2]:.10g}"
        if against:
            o = fig[against]
            rel = abs(o[2] - t[2]) / max(abs(o[2]), 1e-300)
            same = "the same bound" + (f" to {int(-math.log10(rel))} digits" if rel > 0 else " (every digit)")
            line += f"   |   {against[:10]} {o[0]:6.3f} CPU s ({o[1]:6.3f} wall), {same}; today / it {t[0] / o[0]:.2f}"
        print(line + f"   |   target {target:g} {kind} s: {t[0 if kind == 'CPU' else 1] / target:.2f}")


if __name__ == "__main__":
    if sys.argv[1:] == ["--measure"]:
        print(json.dumps(measure()))
    else:
        bench_engine(sys.argv[1] if len(sys.argv) > 1 else None)
