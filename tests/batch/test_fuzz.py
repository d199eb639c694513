"""Random faces through the whole job (issue 19, point 5; issue 22's property test): 300 faces fitted in
2D and 50 in 4D by ``ruled batch`` with a per-face time limit, each result measured by OCCT against the
face as bounded by its edges (with local refinement around the worst samples).  Asserted on every face:
no crash and no hang (a refusal is a one-line RuledError), the certified bound at least the measured
distance, a valid result face; in 4D, the 4D attempt's bound within 10x the 2D bound.  The faces
(tests/fuzz_faces.py) are rational and periodic, of degrees 1-5 with 2-12 poles, knots of every
multiplicity (creases across and along the rulings), weights 0.2-5 and over ratios up to 1e5, tiny
closed faces, scales 1e-4-1e4, offsets up to 1e5, collapsed rows and trimmed sides.  The batches start
in the background after the batch tests (conftest.py), and their checks run last."""

from __future__ import annotations

import json
import os

import pytest

pytest.importorskip("OCP")

from conftest import FUZZ  # noqa: E402
from fuzz_faces import COUNTS, random_faces  # noqa: E402


@pytest.fixture(scope="module")
def batches():
    proc = FUZZ.get("proc")
    assert proc is not None, "the fuzz batches start with the first test past tests/batch/test_batch.py (conftest.py)"
    assert proc.wait(timeout=3000) == 0, [open(os.path.join(FUZZ["dir"], f)).read()[-3000:]
                                          for f in os.listdir(FUZZ["dir"]) if f.endswith(".log")]
    return FUZZ["dir"]


@pytest.fixture(scope="module", params=list(COUNTS))
def fuzz(request, batches):
    method = request.param
    with open(os.path.join(batches, f"out{method}", "summary.json")) as fh:
        rows = json.load(fh)["rows"]
    seed, count = COUNTS[method]
    return (method, random_faces(seed, count), os.path.join(batches, f"fuzz{method}.step"),
            os.path.join(batches, f"out{method}", f"fuzz{method}"), rows)


@pytest.mark.slow
def test_random_faces_are_fitted_soundly_or_refused_in_one_line(fuzz):
    from OCP.BRepCheck import BRepCheck_Analyzer

    from ruled.occ.io import read_faces
    method, faces, _, folder, rows = fuzz
    seed, count = COUNTS[method]
    assert len(rows) == count
    by_status = {s: [r for r in rows if r["status"] == s] for s in ("ok", "refused", "failed")}
    print(f"{method}: {len(by_status['ok'])} fitted, {len(by_status['refused'])} refused, "
          f"{len(by_status['failed'])} failed")
    assert not by_status["failed"], [(r["face"], r["reason"], faces[r["face"]][1]) for r in by_status["failed"]]
    for r in by_status["refused"]:
        assert r["reason"] and "\n" not in r["reason"] and "Traceback" not in r["reason"], r
    # most faces fit: a generator whose faces are all refused would test nothing
    assert len(by_status["ok"]) >= 0.9 * count
    for r in by_status["ok"]:
        assert r["hausdorff"] <= r["error_bound"], (r["face"], r["hausdorff"], r["error_bound"], faces[r["face"]][1])
        out = read_faces(os.path.join(folder, f"face_{r['face']}.step"))
        assert len(out) == 1 and BRepCheck_Analyzer(out[0]).IsValid(), (r["face"], faces[r["face"]][1])


@pytest.mark.slow
def test_the_tightest_bounds_hold_against_a_denser_measure(fuzz):
    """The faces whose measure came closest to their bound, measured again more densely (32 x 32 points
    of each face plus its edges, projected by OCCT onto the other)."""
    from trimmed_faces import measure

    from ruled.occ.io import read_faces
    method, faces, src, folder, rows = fuzz
    inputs = read_faces(src)                  # the faces as the batch read them
    ok = [r for r in rows if r["status"] == "ok" and r["error_bound"] > 0]
    tight = sorted(ok, key=lambda r: r["hausdorff"] / r["error_bound"], reverse=True)[:6]
    for r in tight:
        face = inputs[r["face"]]
        out = read_faces(os.path.join(folder, f"face_{r['face']}.step"))[0]
        h = measure(face, out, 32)
        assert h <= r["error_bound"], (r["face"], h, r["error_bound"], faces[r["face"]][1])


@pytest.mark.slow
def test_a_4d_attempt_stays_within_ten_times_the_2d_bound(fuzz):
    """Issue 22: the 4D rebuild once made knot spans so small (or lifted ends so torn at creases and
    focal points) that its bound reached 30,890 against 0.506 in 2D.  Whether or not the 4D result wins,
    its own certified bound stays within 10x the 2D bound of the same face."""
    method, faces, _, folder, rows = fuzz
    if method != "4d":
        pytest.skip("the 4D batch compares its 4D attempt with its 2D baseline")
    ratios = []
    for r in rows:
        if r["status"] != "ok":
            continue
        with open(os.path.join(folder, f"face_{r['face']}.json")) as fh:
            c = json.load(fh).get("comparison", {})
        if "2d" in c and "4d" in c and c["2d"]["error_bound"] > 0:
            ratios.append((c["4d"]["error_bound"] / c["2d"]["error_bound"], r["face"]))
    print("4D / 2D bound: the largest", sorted(ratios, reverse=True)[:5])
    assert len(ratios) >= 0.5 * len(rows)          # most faces get a 4D attempt: the check is not empty
    assert max(ratios)[0] <= 10.0, [(x, f, faces[f][1]) for x, f in ratios if x > 10.0]
