"""The fixed fuzz runs (issues 19 and 22), run by ``benchmarks/run.py --suite fuzz``: 300 random faces
fitted in 2D (seed 2202) and 50 in 4D (seed 2204) through ``ruled batch --jobs 2``, every check of
tests/fuzz_faces.py applied (what CI's rotating run checks on 60 and 10 faces); then issue 34's kinds (60 in 2D,
seed 3402; 10 in 4D, seed 3404), re-measured by OCCT alone too; prints the counts, the
wall time, the tightest measure / bound ratios and the 4D / 2D bound ratios, and every violation.
Larger runs: ``python tests/fuzz_faces.py --seed N`` with ROTATING raised, or --face for single faces."""

from __future__ import annotations

import os
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "tests"))


def bench_fuzz(jobs: int = 2) -> int:
    from fuzz_faces import FIXED, FIXED_KINDS, check, check_independent, faces_of, run_batch, summary
    folder = tempfile.mkdtemp(prefix="ruled-fuzz-fixed-")
    print(f"== the fixed fuzz runs (ruled batch --jobs {jobs}; results in {folder})")
    bad = 0
    for name, fixed, family in (("", FIXED, ""), ("kinds", FIXED_KINDS, "k")):
        for method, (seed, count) in fixed.items():
            b = run_batch(os.path.join(folder, name), method, faces_of(method, seed, count, family), jobs)
            print("   " + (f"issue 34's kinds, seed {seed}: " if family else "") + summary(b)
                  + f"; {b.seconds / len(b.faces):.2f} s a face")
            if family:
                _, worst, n = check_independent(b)
                print(f"   by OCCT alone: {n} faces, the largest measured / bound {worst:.4f}")
            for line in check(b):
                bad += 1
                print("   VIOLATION", line)
    print(f"   {bad} violations")
    return bad


if __name__ == "__main__":
    sys.exit(1 if bench_fuzz() else 0)
