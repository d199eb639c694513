"""Trimmed faces with wavy boundaries (issue 58), run by ``benchmarks/run.py --suite wavy [--count N]``: N faces of
tests/wavy_faces.py (random B-spline surfaces of degrees 2-5, some rational, trimmed by wavy loops of 2-6
edges with 0-2 holes), each through the whole ``ruled fit`` job (fit, build, OCCT's measure both ways) on a
pool of 2.  Prints the faces fitted, refused (per reason) and failed, the violations (measured above the
certified bound), the results within 1 % of the face's size that cover less than 99.5 % of it, the bounds
beyond 10x the measure where the measure is below 1 % of the size, and the slowest face: issue 58's counts.
Then 36 exactly ruled faces whose rulings cross their iso lines (ruled_face), counted within 1e-5 of their size."""

from __future__ import annotations

import collections
import os
import sys
import tempfile
import time
from multiprocessing import Pool

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def _kind(reason: str) -> str:
    for key, name in (("could not be interpolated", "the face's own parametrization could not be interpolated"),
                      ("no grouping", "no grouping of the edges into four sides can be fitted"),
                      ("Coons map", "the Coons map folds"), ("a single point", "two sides a single point"),
                      ("above its certified bound", "measured above the bound (withheld)")):
        if key in reason:
            return name
    return reason.split(";")[0][:90]


def bench_wavy(count: int = 80, jobs: int = 2, ruled: int = 36) -> int:
    print(f"== {count} trimmed faces with wavy boundaries (tests/wavy_faces.py), the whole ruled fit job")
    t0 = time.perf_counter()
    sys.path.insert(0, os.path.join(ROOT, "tests"))
    from wavy_faces import fit_row
    with tempfile.TemporaryDirectory() as d, Pool(jobs, maxtasksperchild=10) as pool:
        rows = sorted(pool.map(fit_row, [("wavy", s, d, 20, False) for s in range(count)], chunksize=1),
                      key=lambda r: r["seed"])
    by = collections.Counter(r["status"] for r in rows)
    print(f"   fitted {by['fitted']}, refused {by['refused']}, failed {by['failed']}, invalid input "
          f"{by['invalid input']} ({time.perf_counter() - t0:.0f} s wall)")
    for kind, n in collections.Counter(_kind(r["reason"]) for r in rows if r["status"] in ("refused", "failed")
                                       ).most_common():
        print(f"      {n:3d}  {kind}")
    fitted = [r for r in rows if r["status"] == "fitted"]
    bad = [r for r in fitted if r["measured"] > r["bound"] * (1 + 1e-9) + 1e-12]
    size = {r["seed"]: r.get("size") or 0.0 for r in fitted}
    close = [r for r in fitted if size[r["seed"]] and r["measured"] <= 0.01 * size[r["seed"]]]
    short = [r for r in close if r.get("ratio") is not None and r["ratio"] < 0.995]
    loose = [r for r in close if r["bound"] > 10.0 * max(r["measured"], 1e-9 * size[r["seed"]])]
    print(f"   violations (measured above the bound): {len(bad)}")
    print(f"   within 1 % of the size: {len(close)}; covering less than 99.5 %: {len(short)}; bound above 10x the "
          f"measure: {len(loose)}")
    slow = max(rows, key=lambda r: r.get("cpu", 0.0))
    print(f"   slowest: {slow['name']}, {slow.get('cpu', 0.0):.1f} CPU s ({slow['status']})")
    return len(bad) + bench_ruled(ruled, jobs) if ruled else len(bad)


def bench_ruled(count: int = 36, jobs: int = 2) -> int:
    """Exactly ruled faces whose rulings cross their iso lines (tests/wavy_faces.py ruled_face: skewed lofts,
    hyperbolic paraboloids, hyperboloid pieces, trimmed by wavy loops): how many are measured and certified
    within 1e-5 of their size, per kind, and the slowest."""
    print(f"== {count} exactly ruled faces across their iso lines (tests/wavy_faces.py ruled_face), the whole job")
    t0 = time.perf_counter()
    from wavy_faces import fit_row
    with tempfile.TemporaryDirectory() as d, Pool(jobs, maxtasksperchild=10) as pool:
        rows = pool.map(fit_row, [("ruled", s, d, 20, False) for s in range(count)], chunksize=1)
    kinds = collections.defaultdict(list)
    for r in rows:
        kinds[r["name"].split(": ")[1].split(",")[0]].append(r)
    bad = 0
    for kind, rs in kinds.items():
        ok = [r for r in rs if r["status"] == "fitted" and max(r["measured"], r["bound"]) <= 1e-5 * r["size"]]
        worst = max((r["bound"] / r["size"] for r in rs if r["status"] == "fitted"), default=float("nan"))
        print(f"   {kind}: {len(ok)} of {len(rs)} measured and certified within 1e-5 of the size (the largest "
              f"bound {worst:.3g} of it)")
        bad += len(rs) - len(ok)
    print(f"   ({time.perf_counter() - t0:.0f} s wall; slowest {max(r.get('cpu', 0.0) for r in rows):.1f} CPU s)")
    return bad


if __name__ == "__main__":
    bench_wavy(int(sys.argv[1]) if len(sys.argv) > 1 else 80)
