"""Every B-spline face of tests/data and ../shared/data fitted as ``ruled fit`` fits it (12 samples, on a
pool of 2), run by ``benchmarks/run.py --suite census`` (``--ends pinned`` for the corner-pinned fit that
was the only one before issue 35).  Prints the faces fitted and refused (per reason), and every fitted face
whose result's area (OCCT's, of the result as built) is off the face's by more than 0.5 %, with its bound:
issue 35's counts of refusals and of results that do not cover their face."""

from __future__ import annotations

import collections
import math
import os
import sys
import time
from multiprocessing import Pool

from data import data_files

AREA_TOL = 5e-3


def _fit(job: tuple) -> dict:
    path, k, ends = job
    from ruled.core.errors import RuledError
    from ruled.fit.options import FitOptions
    from ruled.occ.io import face_area, read_faces
    from ruled.occ.region import fit_face
    from ruled.occ.trimmed import result_face
    face = read_faces(path)[k]
    row = {"file": os.path.basename(path), "face": k}
    t0 = time.process_time()
    try:
        res, slack = fit_face(face, FitOptions(samples=12, ends=ends).checked())
        a0 = face_area(face, 1e-6)
        row.update(status="fitted", bound=res.error_bound + slack, trimmed=res.best.trim is not None,
                   area=face_area(result_face(res), 1e-6) / a0 if a0 > 0 else math.nan)
    except RuledError as exc:
        row.update(status="refused", reason=str(exc))
    row["cpu"] = time.process_time() - t0
    return row


def _kind(reason: str) -> str:
    for key, name in (("Coons map", "no four-sided map (its Coons map folds)"),
                      ("too wiggly", "its own parametrization cannot be interpolated"),
                      ("map folds", "the fit's map folds over the face")):
        if key in reason:
            return name
    return reason.split(";")[0][:80]


def bench_census(ends: str = "auto", jobs: int = 2) -> None:
    from ruled.occ.convert import face_surface_type
    from ruled.occ.io import read_faces
    todo = [(p, k, ends) for p in data_files() for k, f in enumerate(read_faces(p))
            if face_surface_type(f) == "bspline"]
    print(f"== every B-spline face of the data files ({len(todo)}), ruled fit --samples 12 --ends {ends}")
    t0 = time.perf_counter()
    with Pool(jobs, maxtasksperchild=20) as pool:
        rows = sorted(pool.map(_fit, todo, chunksize=1), key=lambda r: (r["file"], r["face"]))
    fitted = [r for r in rows if r["status"] == "fitted"]
    refused = [r for r in rows if r["status"] == "refused"]
    print(f"   fitted {len(fitted)}, refused {len(refused)} ({time.perf_counter() - t0:.0f} s wall, "
          f"{sum(r['cpu'] for r in rows):.0f} CPU s in the workers)")
    for kind, n in collections.Counter(_kind(r["reason"]) for r in refused).most_common():
        faces = ", ".join(f"{r['file'].split('.')[0]} {r['face']}" for r in refused if _kind(r["reason"]) == kind)
        print(f"   refused, {kind}: {n} ({faces})")
    off = [r for r in fitted if not abs(r["area"] - 1.0) <= AREA_TOL]
    print(f"   results whose area is off the face's by more than {100 * AREA_TOL:g} %: {len(off)}")
    for r in off:
        print(f"      {r['file']} face {r['face']}: area {r['area']:.4f} of the face's, bound {r['bound']:.4g}, "
              f"{'trimmed by its edges' if r['trimmed'] else 'pinned at its corners'}")


if __name__ == "__main__":
    bench_census(sys.argv[1] if len(sys.argv) > 1 else "auto")
