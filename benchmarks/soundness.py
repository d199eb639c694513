"""The soundness corpus (issue 72), run by ``benchmarks/run.py --suite soundness [--count N]`` (not in all: an hour
on 2 cores): every B-spline face of tests/data and ../shared/data, N trimmed faces with wavy boundaries and N
exactly ruled faces across their iso lines (tests/wavy_faces.py), and the fixed fuzz runs' faces of issue 34's
kinds (tests/fuzz_faces.py, seed 3402), each through the whole ``ruled fit`` job on a pool of 2 and its result
measured again by OCCT at 80 x 80 of each face as bounded by its edges, both ways (tests/sound_corpus.py).

Prints per source the faces fitted, refused and failed; every face whose dense measure exceeds its bound and every
refusal for "measured above the bound" (each a certificate's bug: acceptance wants 0 of both); the largest dense
measure / bound; the bounds above 10x the dense measure where it is below 1 % of the size (loose); the slowest."""

from __future__ import annotations

import collections
import os
import sys
import tempfile
import time
from multiprocessing import Pool

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tests"))


def corpus(count: int) -> list:
    """(source, key) of every face of the corpus."""
    from fuzz_faces import FIXED_KINDS
    from sound_corpus import data_faces
    seed, n = FIXED_KINDS["2d"]
    return (data_faces() + [("wavy", s) for s in range(count)] + [("ruled", s) for s in range(count)]
            + [("fuzz", f"2d:{seed}:k{k}") for k in range(n)])


def bench_soundness(count: int = 40, jobs: int = 2) -> int:
    from sound_corpus import DENSE, above, refused_above, sound_row
    todo = corpus(count)
    print(f"== the soundness corpus: {len(todo)} faces through the ruled fit job, each result measured by OCCT at "
          f"{DENSE} x {DENSE}, both ways, against its bound")
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory() as d, Pool(jobs, maxtasksperchild=10) as pool:
        rows = pool.map(sound_row, [(s, k, d, DENSE) for s, k in todo], chunksize=1)
    print(f"   ({time.perf_counter() - t0:.0f} s wall, {sum(r.get('cpu', 0.0) for r in rows):.0f} CPU s in the fits)")
    for source in ("data", "wavy", "ruled", "fuzz"):
        by = collections.Counter(r["status"] for r in rows if r["source"] == source)
        print(f"   {source}: fitted {by['fitted']}, refused {by['refused']}, failed {by['failed']}, invalid input "
              f"{by['invalid input']}")
    fitted = [r for r in rows if r["status"] == "fitted"]
    bad, caught = [r for r in rows if above(r)], [r for r in rows if refused_above(r)]
    print(f"   dense measure above the bound: {len(bad)}")
    for r in bad:
        print(f"      {r['name']}: dense {r['dense']:.6g} (face to result {r['face_to_result']:.4g}, result to face "
              f"{r['result_to_face']:.4g}), bound {r['bound']:.6g}, the job's measure {r['measured']:.4g}")
    print(f"   refused, measured above the bound: {len(caught)}")
    for r in caught:
        print(f"      {r['name']}: {r['reason'][:160]}")
    for r in sorted(fitted, key=lambda r: -r["dense"] / max(r["bound"], 1e-300))[:5]:
        print(f"   tightest: {r['name']}: dense / bound {r['dense'] / max(r['bound'], 1e-300):.4f} (bound "
              f"{r['bound']:.4g})")
    close = [r for r in fitted if r["dense"] < 0.01 * r["size"]]
    loose = [r for r in close if r["bound"] > 10.0 * max(r["dense"], 1e-9 * r["size"])]
    print(f"   bounds above 10x the dense measure (of {len(close)} within 1 % of the size): {len(loose)}")
    for r in sorted(loose, key=lambda r: -r["bound"] / max(r["dense"], 1e-9 * r["size"]))[:8]:
        print(f"      {r['name']}: bound {r['bound']:.4g}, dense {r['dense']:.4g}, size {r['size']:.4g}")
    slow = sorted(rows, key=lambda r: -r.get("cpu", 0.0))[:10]
    print("   slowest (fit CPU s): " + ", ".join(f"{r['name']} {r.get('cpu', 0.0):.1f}" for r in slow))
    return len(bad) + len(caught)


if __name__ == "__main__":
    sys.exit(1 if bench_soundness(int(sys.argv[1]) if len(sys.argv) > 1 else 40) else 0)
