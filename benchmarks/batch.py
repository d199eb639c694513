"""The whole-part batch: every B-spline face of kj66 (48 faces, the defaults) with --jobs 1 and
--jobs 2, wall time of the user's whole command (start-up, read, fits, measures, writes, summary).
Target: --jobs 2 within 0.6 x the sequential wall time."""

from __future__ import annotations

import os
import shutil
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


def _run(step: str, jobs: int) -> float:
    out = tempfile.mkdtemp(prefix="ruled-batch-")
    try:
        t0 = time.perf_counter()
        r = subprocess.run([sys.executable, "-m", "ruled.cli", "batch", step, "--faces", "bspline", "--jobs",
                            str(jobs), "-o", out, "--quiet"], capture_output=True, text=True, cwd=ROOT)
        if r.returncode != 0:
            raise SystemExit(r.stderr)
        return time.perf_counter() - t0
    finally:
        shutil.rmtree(out, ignore_errors=True)


def bench_batch() -> None:
    step = _data()
    t1 = _run(step, 1)
    t2 = _run(step, 2)
    print(f"batch kj66 --faces bspline (48 faces): --jobs 1 {t1:.1f} s wall, --jobs 2 {t2:.1f} s wall, ratio "
          f"{t2 / t1:.2f} (target <= {TARGET}: {'met' if t2 / t1 <= TARGET else 'NOT met'}; {os.cpu_count()} cores)")


if __name__ == "__main__":
    bench_batch()
