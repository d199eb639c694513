"""The whole-part batch: every B-spline face of kj66 (48 faces, the defaults) with --jobs 1 and
--jobs 2, wall time of the user's whole command (start-up, read, fits, measures, writes, summary).
Target: --jobs 2 within 0.6 x the sequential wall time, and (issue 60) within 60 s.

With a commit (``benchmarks/run.py --suite batch --against COMMIT``): --jobs 2 today and at the commit (its
tree out of git, its kernels compiled by a warm run first), alternating, and the summaries' figures: the sum of
the faces' seconds and the median error bound of each."""

from __future__ import annotations

import csv
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TARGET = 0.6


def _data() -> str:
    for d in (os.path.join(ROOT, "tests", "data"), os.path.join(ROOT, "..", "shared", "data")):
        p = os.path.join(d, "kj66_impeller.step")
        if os.path.exists(p):
            return p
    raise SystemExit("kj66_impeller.step not found")


def _env(root: str) -> dict:
    """A user's environment (Python's bytecode cache on: job.USER_ENV), running root's ruled."""
    from job import USER_ENV
    return USER_ENV if root == ROOT else {**USER_ENV, "PYTHONPATH": root}


def _run(step: str, jobs: int, root: str = ROOT, rows: list | None = None) -> float:
    """The batch's wall seconds (its summary's rows appended to rows, when given), run with root's ruled."""
    out = tempfile.mkdtemp(prefix="ruled-batch-")
    try:
        t0 = time.perf_counter()
        r = subprocess.run([sys.executable, "-m", "ruled.cli", "batch", step, "--faces", "bspline", "--jobs",
                            str(jobs), "-o", out, "--quiet"], capture_output=True, text=True, cwd=root, env=_env(root))
        if r.returncode != 0:
            raise SystemExit(r.stderr)
        wall = time.perf_counter() - t0
        if rows is not None:
            with open(os.path.join(out, "summary.csv")) as fh:
                rows.extend(csv.DictReader(fh))
        return wall
    finally:
        shutil.rmtree(out, ignore_errors=True)


def bench_batch_against(commit: str) -> None:
    """--jobs 2 today and at commit, alternating (twice each after a warm run of each): wall seconds, the sum of
    the faces' own seconds, the median bound."""
    from engine import checkout
    step = _data()
    roots = {"today": ROOT, commit: checkout(commit)}
    with tempfile.TemporaryDirectory() as d:
        for root in roots.values():                      # the commit's kernels compiled, both caches warm
            subprocess.run([sys.executable, "-m", "ruled.cli", "fit", step, "--face", "6", "-o",
                            os.path.join(d, "f.step"), "--quiet"], cwd=root, env=_env(root), capture_output=True)
    got: dict = {k: [] for k in roots}
    for _ in range(2):
        for k, root in roots.items():
            rows: list = []
            got[k].append((_run(step, 2, root, rows), sum(float(r["seconds"] or 0.0) for r in rows),
                           statistics.median(float(r["error_bound"]) for r in rows if r["status"] == "ok"),
                           sum(r["status"] == "ok" for r in rows), len(rows)))
    print(f"== the batch, kj66 --faces bspline --jobs 2: today beside {commit}")
    for k, runs in got.items():
        w, s, b, ok, n = min(runs)
        print(f"   {k[:10]:10s} {w:6.1f} s wall (best of 2), faces' own seconds {s:6.1f}, {ok}/{n} fitted, median "
              f"bound {b:.4g}")
    t, o = min(got["today"])[0], min(got[commit])[0]
    print(f"   today / {commit[:10]} {t / o:.2f}; target 60 s wall: {t / 60.0:.2f}")


def bench_batch() -> None:
    step = _data()
    t1 = _run(step, 1)
    t2 = _run(step, 2)
    print(f"batch kj66 --faces bspline (48 faces): --jobs 1 {t1:.1f} s wall, --jobs 2 {t2:.1f} s wall, ratio "
          f"{t2 / t1:.2f} (target <= {TARGET}: {'met' if t2 / t1 <= TARGET else 'NOT met'}; {os.cpu_count()} cores)")


if __name__ == "__main__":
    bench_batch_against(sys.argv[1]) if len(sys.argv) > 1 else bench_batch()
