"""Every face of tests/data and ../shared/data through ``ruled batch`` (the defaults: 40 samples, the 2D fit,
--jobs 2), each fitted result re-measured by OCCT alone (tests/trimmed_faces.py extrema_measure: BRepExtrema
from a grid inside each face and points on its edges, both ways), run by ``benchmarks/run.py --suite data``.
Prints per file the faces fitted, refused and failed, and the largest measured / bound by the report's
measure and by OCCT alone; then every result above its bound, and every face whose report says its area is
off the face's by more than 0.5 % while it is within 0.1 % of its size (issue 34's acceptance)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tests"))


from sound_corpus import data_files  # noqa: E402 (the CAD files of tests/data and ../shared/data)


def bench_data(jobs: int = 2, n: int = 12) -> int:
    from trimmed_faces import extrema_measure

    from ruled.occ.io import read_faces
    out = tempfile.mkdtemp(prefix="ruled-data-")
    files = data_files()
    print(f"== every face of the data files ({len(files)} files; ruled batch --jobs {jobs}; results in {out})")
    t0 = time.perf_counter()
    r = subprocess.run([sys.executable, "-m", "ruled.cli", "batch", *files, "--jobs", str(jobs), "--no-plots",
                        "--quiet", "-o", out], cwd=ROOT, capture_output=True, text=True)
    print(f"   batch: exit {r.returncode} in {time.perf_counter() - t0:.0f} s")
    rows = json.load(open(os.path.join(out, "summary.json")))["rows"]
    bad, worst, worst_occ, measured = [], (0.0, None), (0.0, None), 0
    inputs = {}
    for row in rows:
        who = f"{row['file']} face {row['face']}"
        if row["status"] != "ok":
            continue
        ratio = row["hausdorff"] / max(row["error_bound"], 1e-300)
        worst = max(worst, (ratio, who), key=lambda x: x[0])
        folder = os.path.join(out, os.path.splitext(row["file"])[0])
        rep = json.load(open(os.path.join(folder, f"face_{row['face']}.json")))
        area = (rep.get("area") or {}).get("ratio")
        size = (rep.get("region") or {}).get("face_size") or 0.0
        if row["hausdorff"] > row["error_bound"]:
            bad.append(f"{who}: measured {row['hausdorff']:.6g} above its bound {row['error_bound']:.6g}")
        if area is not None and row["hausdorff"] < 1e-3 * size and abs(area - 1) > 5e-3:
            bad.append(f"{who}: area {area:.4g} x the face's while {row['hausdorff']:.3g} from it")
        path = next(p for p in files if os.path.basename(p) == row["file"])
        if path not in inputs:
            inputs[path] = read_faces(path)
        result = read_faces(os.path.join(folder, f"face_{row['face']}.step"))[0]
        a, b = extrema_measure(inputs[path][row["face"]], result, n)
        measured += 1
        worst_occ = max(worst_occ, (max(a, b) / max(row["error_bound"], 1e-300), who), key=lambda x: x[0])
        if max(a, b) > row["error_bound"]:
            bad.append(f"{who}: by OCCT alone {a:.6g} face to result, {b:.6g} result to face, above its bound "
                       f"{row['error_bound']:.6g}")
    for f in sorted({row["file"] for row in rows}):
        st = {s: sum(1 for row in rows if row["file"] == f and row["status"] == s) for s in ("ok", "refused", "failed")}
        print(f"   {f}: {st['ok']} fitted, {st['refused']} refused, {st['failed']} failed")
    print(f"   {len(rows)} faces, {sum(row['status'] == 'ok' for row in rows)} fitted; the largest measured / bound: "
          f"{worst[0]:.4f} ({worst[1]}) by the report, {worst_occ[0]:.4f} ({worst_occ[1]}) by OCCT alone over "
          f"{measured} results")
    for line in bad:
        print("   VIOLATION", line)
    print(f"   {len(bad)} violations")
    return len(bad)


if __name__ == "__main__":
    sys.exit(1 if bench_data() else 0)
