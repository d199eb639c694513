"""Issue 34: what the measure alone can say.  A face far from every ruled surface is said so from the
measured distance, never from a certified bound (which may be loose); a bound more than 100x the measure is
reported as loose, with the part of the certificate that makes it; a result whose measure is above its
bound is never returned; the measure finds a boundary that races past its edge samples."""
import os

import pytest

pytest.importorskip("OCP")

from conftest import ruled_here  # noqa: E402


@pytest.fixture(scope="module")
def loose_face(tmp_path_factory):
    """The fuzz's face 2378750657:2 (rational, extreme weights, 0.044 across): its 2D bound was 78.9 against
    a measured 0.0027, and it was told that 'no ruled surface comes near' it."""
    import fuzz_faces as fz

    from ruled.occ.io import write_step
    path = str(tmp_path_factory.mktemp("loose") / "loose.step")
    write_step(fz.face_named("2d:2378750657:2").face, path)
    return path


@pytest.mark.slow
def test_a_loose_bound_is_said_loose_and_never_far(loose_face, tmp_path):
    """The command line (its report and its stderr) and Python say the same: the bound is loose, and which
    part of the certificate makes it; nothing says the face is far from ruled."""
    import json

    import ruled.cq as rcq
    from ruled.occ.io import get_face
    run = ruled_here("fit", loose_face, "--face", "0", "--samples", "12", "--measure-samples", "12", "-o",
                     str(tmp_path / "o.step"), "--report", str(tmp_path / "r.json"), "--quiet")
    assert run.returncode == 0, run.stderr
    rep = json.load(open(tmp_path / "r.json"))
    bound, measured = rep["error_bound"], rep["hausdorff"]["max"]
    assert measured <= bound, (measured, bound)
    assert bound > 100 * measured, (bound, measured)             # the case: a loose certificate
    loose = [w for w in rep["warnings"] if w.startswith(f"the certified bound {bound:.4g} is loose: ")]
    assert len(loose) == 1 and "most of it is the " in loose[0], rep["warnings"]
    assert not any("comes near" in w for w in rep["warnings"]), rep["warnings"]
    assert f"ruled: warning: face 0: {loose[0]}" in run.stderr.splitlines(), run.stderr
    fit = rcq.fit_face(get_face(loose_face, 0), samples=12, measure_samples=12)
    assert [w for w in fit.warnings if "is loose" in w] == loose


def test_the_measure_finds_the_boundary_where_an_edge_races_past_its_samples(tmp_path):
    """kj66 face 2 at the defaults: the report printed a measured 0.0275 against a bound of 0.0066.  A
    point of the result lies on the face's edge 6 near its corner with edge 0, where edge 6 moves fast in
    its parameter: the nearest edge sample was the corner, refined along edge 0 only.  Now the report's
    maximum is no more than a brute force over a dense cloud of the face (each of whose distances is at
    least the true one), and within the bound."""
    from conftest import data_file
    from scipy.spatial import cKDTree

    from ruled.cli.fit import run_fit
    from ruled.occ.io import get_face
    from ruled.occ.measure import face_points
    path = data_file("kj66_impeller.step")
    out = str(tmp_path / "k2.step")
    rep = run_fit(path, 2, out, quiet=True, say=False)
    h = rep["hausdorff"]
    assert h["max"] <= rep["error_bound"], (h, rep["error_bound"])
    face, result = get_face(path, 2), get_face(out, 0)
    dense = cKDTree(face_points(face, 300))
    brute = float(dense.query(face_points(result, 40))[0].max())
    assert h["result_to_input"] <= brute + 1e-9, (h["result_to_input"], brute)


def test_a_result_whose_measure_is_above_its_bound_is_never_returned(tmp_path, monkeypatch):
    """Issue 34: a result printed with 'error bound 0.332' and 'measured Hausdorff 13.97', exit 0.  The bound
    of a face whose measure is within 0.02 % of it (the fuzz's face 2202:7) broken to 0.9x itself: the
    command line refuses in one line naming both figures and leaves no STEP; Python raises; the batch
    records the face as refused (tests/fuzz_faces.py counts such a refusal as a violation)."""
    import fuzz_faces as fz

    import ruled.cq as rcq
    import ruled.fit.fit2d as f
    from ruled.core.errors import FiguresError
    from ruled.occ.io import get_face, write_step
    path, out = str(tmp_path / "tight.step"), str(tmp_path / "o.step")
    write_step(fz.face_named("2d:2202:7").face, path)
    args = ("fit", path, "--face", "0", "--samples", str(fz.SAMPLES), "--measure-samples", str(fz.SAMPLES),
            "-o", out, "--quiet")
    monkeypatch.setattr(f.DirectionFit, "error_bound", property(lambda self: 0.9 * self.certificate.bound))
    run = ruled_here(*args)
    assert run.returncode == 2 and run.stderr.count("\n") == 1, run.stderr
    assert "is above its certified bound" in run.stderr and "not returned" in run.stderr, run.stderr
    assert not os.path.exists(out)
    with pytest.raises(FiguresError, match="is above its certified bound"):
        rcq.fit_face(get_face(path, 0), samples=fz.SAMPLES, measure_samples=fz.SAMPLES)
    monkeypatch.undo()
    good = ruled_here(*args)              # the true bound: the same face is returned
    assert good.returncode == 0 and os.path.exists(out), good.stderr
