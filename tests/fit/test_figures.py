"""Issue 34: what the measure alone can say.  A face far from every ruled surface is said so from the
measured distance, never from a certified bound (which may be loose); a bound more than 100x the measure is
reported as loose, with the part of the certificate that makes it; a result whose measure is above its
bound is never returned; the measure finds a boundary that races past its edge samples."""
import os
import re

import pytest

pytest.importorskip("OCP")

from conftest import ruled_here  # noqa: E402


@pytest.fixture(scope="module")
def loose_face(tmp_path_factory):
    """The fuzz's face 2378750657:2 (rational, extreme weights, 0.044 across): its 2D bound was 78.9 against
    a measured 0.0027, and it was told that 'no ruled surface comes near' it.  Its bound is 0.0277 now
    (graded grids), still loose against what the measure at 12 samples finds (5e-11: its samples miss where
    the result runs past the face, 0.006 by OCCT alone; see the test after this one)."""
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


def _fuzz_face_fitted(name: str) -> tuple:
    """A fuzz face by name, its fit in Python at the fuzz's samples, and OCCT alone's measure of the result
    (face to result, result to face: points inside and on the edges of each)."""
    import fuzz_faces as fz
    from trimmed_faces import extrema_measure

    import ruled.cq as rcq
    face = fz.face_named(name).face
    fit = rcq.fit_face(face, samples=fz.SAMPLES, measure_samples=fz.SAMPLES)
    return (face, fit) + tuple(extrema_measure(face, fit.face.wrapped, 40))


@pytest.mark.slow
def test_extreme_weights_get_a_bound_near_their_distance_and_their_true_area():
    """The same face (weights from 0.007 to 290 over a 4 x 3 net): its parameter speed varies a
    million-fold, and a grid uniform in the parameter bounded its second derivatives at 1e8 (a bound of 69
    on a fit 0.006 away); and its area, integrated by a fixed rule (OCCT's adaptive one too), came out 0.0044
    instead of 0.0076, so that the best candidate (along u) was refused as covering 1.77 times the face.
    Now the area is OCCT's fine mesh's to 1e-3, the fit along u is returned, and OCCT alone (points inside
    and on the edges, both ways) finds it within a bound no more than 10x its distance."""
    import numpy as np
    from OCP.BRep import BRep_Tool
    from OCP.BRepMesh import BRepMesh_IncrementalMesh
    from OCP.TopLoc import TopLoc_Location

    from ruled.fit.fit2d import span_area
    from ruled.occ.convert import face_to_container
    face, fit, there, back = _fuzz_face_fitted("2d:2378750657:2")
    BRepMesh_IncrementalMesh(face, 2e-5, False, 0.05, True)
    tri = BRep_Tool.Triangulation_s(face, TopLoc_Location())
    P = np.array([tri.Node(i).Coord() for i in range(1, tri.NbNodes() + 1)])
    T = np.array([tri.Triangle(i).Get() for i in range(1, tri.NbTriangles() + 1)]) - 1
    mesh = 0.5 * np.linalg.norm(np.cross(P[T[:, 1]] - P[T[:, 0]], P[T[:, 2]] - P[T[:, 0]]), axis=1).sum()
    area = span_area(face_to_container(face))
    assert abs(area / mesh - 1.0) < 1e-3, (area, mesh)
    assert fit.result.best.direction == "u" and not any("another region" in n for n in fit.result.notes), \
        fit.result.notes
    assert max(there, back) <= fit.error_bound <= 10.0 * max(there, back), (there, back, fit.error_bound)


@pytest.mark.slow
def test_a_closed_result_with_a_corner_at_its_seam_is_within_its_bound():
    """The rotating fuzz's face 2d:1008149261:42: a degree-1 tube (three poles round, a polyline along it,
    0.00027 across at 1.1e5 from the origin) fitted closed by the iso surface between its end triangles,
    whose seam is a corner of the result.  The certificate left out the jump of the result's derivative
    there: 1.747e-5, while OCCT alone (and a brute force over 500 x 500 points of each face) finds points
    of the result 1.854e-5 from the face.  Now OCCT alone finds both faces within the bound."""
    _, fit, there, back = _fuzz_face_fitted("2d:1008149261:42")
    assert fit.result.best.closed, fit.result.notes
    assert back > 1.8e-5 and max(there, back) <= fit.error_bound, (there, back, fit.error_bound)


@pytest.mark.slow
def test_the_measure_finds_the_boundary_where_an_edge_races_past_its_samples(tmp_path):
    """kj66 face 2 at the defaults: the report printed a measured 0.0275 against a bound of 0.0066.  A
    point of the result lies on the face's edge 6 near its corner with edge 0, where edge 6 moves fast in
    its parameter: the nearest edge sample was the corner, refined along edge 0 only.  Now the report's
    maximum is no more than a brute force over a dense cloud of the face (each of whose distances is at
    least the true one), and within the bound."""
    from conftest import data_file
    from scipy.spatial import cKDTree

    from ruled.jobs.face import run_fit
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


FOLD = """
import sys
sys.path.insert(0, {tests!r})
import provoke, ruled.fit.face.fit
provoke.fold_results(ruled.fit.face.fit)
"""


@pytest.mark.slow
def test_a_result_that_covers_another_region_than_the_face_is_never_returned(tmp_path, monkeypatch):
    """Issue 34: a close fit that covers a different region is wrong.  A face ruled exactly (its fit within
    1e-5 of it) whose result is folded back over itself (tests/provoke.py: the same points, so the same
    measured distance and a true bound, twice the area): the command line refuses in one line naming the area
    and the distance and leaves no STEP, Python raises, the batch records the face as refused.  Unfolded, the
    same face is returned, its area within 0.5 % of the face's."""
    import json

    import provoke
    from conftest import ruled_process
    from trimmed_faces import ruled_sheet_face

    import ruled.cq as rcq
    import ruled.fit.face.fit as ff
    from ruled.core.errors import FiguresError
    from ruled.occ.io import write_step
    path, out, rep = str(tmp_path / "sheet.step"), str(tmp_path / "o.step"), str(tmp_path / "r.json")
    face = ruled_sheet_face()
    write_step(face, path)
    # along v, the face's rulings: the only candidate (across them, the fit is 1.47 away and may cover more)
    args = ("fit", path, "--face", "0", "--samples", "16", "--measure-samples", "16", "--direction", "v", "-o", out,
            "--quiet")
    good = ruled_here(*args, "--report", rep)
    assert good.returncode == 0, good.stderr
    r = json.load(open(rep))
    assert abs(r["area"]["ratio"] - 1) < 5e-3 and r["hausdorff"]["max"] < 1e-3 * r["region"]["face_size"], r
    os.unlink(out)
    monkeypatch.setattr(ff, "fit_region", provoke.folding(ff.fit_region))
    run = ruled_here(*args)
    assert run.returncode == 2 and run.stderr.count("\n") == 1, run.stderr
    assert re.search(r"area is 2(\.00\d*)? times the face's", run.stderr), run.stderr
    assert "covers another region" in run.stderr, run.stderr
    assert not os.path.exists(out)
    with pytest.raises(FiguresError, match="covers another region"):
        rcq.fit_face(face, samples=16, measure_samples=16, direction="v")
    (tmp_path / "site").mkdir()
    (tmp_path / "site" / "sitecustomize.py").write_text(FOLD.format(tests=os.path.dirname(os.path.dirname(__file__))))
    b = ruled_process("batch", path, "--jobs", "1", "--samples", "16", "--measure-samples", "16", "--direction", "v",
                      "--no-plots",
                      "--quiet", "-o", str(tmp_path / "b"), timeout=300,
                      env={"PYTHONPATH": str(tmp_path / "site")})
    assert b.returncode == 0, b.stderr
    row = json.load(open(tmp_path / "b" / "summary.json"))["rows"][0]
    assert row["status"] == "refused" and "covers another region" in row["reason"], row


@pytest.mark.parametrize("kind", [pytest.param("seam", marks=pytest.mark.slow),
                                  pytest.param("four", marks=pytest.mark.slow), "crease",
                                  pytest.param("hub", marks=pytest.mark.slow)])
def test_a_band_round_a_whole_period_is_fitted_closed_within_its_bound(kind):
    """Issue 34: a face that goes once round its surface's periodic direction was fitted as a four-sided patch
    over half of itself (area ratio 0.50, measured 13.97 against a bound of 0.332).  Bands round a wavy
    cylinder-like surface, their seam where the surface's is not (tests/trimmed_faces.py band_face): with OCCT's
    seam edge, with four edges, and on a clamped surface whose ends meet at a crease (whose certificate missed
    the crease at the seam: 0.313 against a measured 0.340); and a blade root wrapping an exact rational hub
    (trimmed_faces.hub_surface), between a lobed footprint and a wavy top.  Each is fitted closed, covers the
    face's area,
    and OCCT alone (BRepExtrema from points inside and on the edges of each face) finds both faces within the
    bound."""
    from trimmed_faces import band_face, extrema_measure

    import ruled.cq as rcq
    from ruled.occ.io import face_area
    face = band_face(kind)
    fit = rcq.fit_face(face, samples=16, measure_samples=16)
    assert fit.result.best.closed, kind
    a, b = extrema_measure(face, fit.face.wrapped, 16)
    assert max(a, b) <= fit.error_bound, (kind, a, b, fit.error_bound)
    assert fit.hausdorff.max <= fit.error_bound < 1.1 * max(a, b), (kind, fit.hausdorff.max, fit.error_bound, a, b)
    assert abs(face_area(fit.face.wrapped) / face_area(face) - 1) < 0.01, kind


def test_a_face_with_a_hole_gets_a_bound_that_covers_the_spanning_part():
    """Issue 34: faces with a hole were certified for the face as bounded while their result, spanning the
    hole, broke the bound there (8 of 20 such faces of a generator).  A sheet ruled exactly, with a round hole:
    its bound includes how far the spanning part can be from the face, and is said so; OCCT alone finds the
    result within it, over the hole too (the face within 1e-5 of the result, the result 2.07 from the face);
    nothing says that no ruled surface comes near the face."""
    from trimmed_faces import extrema_measure, ruled_sheet_face

    import ruled.cq as rcq
    face = ruled_sheet_face(hole=0.1)
    fit = rcq.fit_face(face, samples=16, measure_samples=16, ends="pinned")
    span = fit.result.patch.hole_span
    a, b = extrema_measure(face, fit.face.wrapped, 16)
    assert a < 1e-4 and 1.0 < b <= fit.error_bound, (a, b, fit.error_bound)
    assert span <= fit.error_bound < span + 1e-3 and span < 1.6 * b, (span, fit.error_bound, b)
    assert any(f"its bound includes {span:.4g}, how far the spanning part" in w for w in fit.warnings), fit.warnings
    assert not any("comes near" in w for w in fit.warnings), fit.warnings


@pytest.mark.slow
def test_a_face_with_a_hole_comes_back_with_the_hole_when_trimmed():
    """Issue 35: trimmed by the face's edges, the result has the face's hole: OCCT finds it within its bound
    both ways (no spanning part), its area the face's, and no warning about spanning the hole."""
    from trimmed_faces import extrema_measure, ruled_sheet_face

    import ruled.cq as rcq
    from ruled.occ.io import face_area
    face = ruled_sheet_face(hole=0.1)
    fit = rcq.fit_face(face, samples=16, measure_samples=16, ends="trimmed")
    assert fit.result.best.trim is not None and len(fit.result.best.trim.holes) == 1
    a, b = extrema_measure(face, fit.face.wrapped, 16)
    assert max(a, b) <= fit.error_bound < 0.1, (a, b, fit.error_bound)
    assert abs(face_area(fit.face.wrapped) / face_area(face) - 1) < 5e-3
    assert not any("spans" in w for w in fit.warnings), fit.warnings


@pytest.mark.parametrize("name", ["2d:2202:69", pytest.param("2d:2202:54", marks=pytest.mark.slow),
                                  pytest.param("2d:2202:56", marks=pytest.mark.slow)])
def test_a_whole_face_is_ruled_at_least_as_closely_as_the_iso_surface_between_its_rails(name):
    """Issue 34: Ruled returned 0.434 where FreeCAD's Part Ruled between the same two edges reaches 0.052.
    Three whole-rectangle faces of the fuzz on which the DP's pairing loses to the iso-parametric one (its
    certified bound 2.0x, 1.2x and 1.2x the iso surface's): the result is no farther from the face, measured,
    than OCCT's ruled surface between the result's rails (BRepFill, as Part Ruled builds it, the better of its
    two orientations), and the fit says why it is the iso surface."""
    import fuzz_faces as fz
    from trimmed_faces import measure, part_ruled

    import ruled.cq as rcq
    face = fz.face_named(name).face
    fit = rcq.fit_face(face, samples=fz.SAMPLES, measure_samples=fz.SAMPLES)
    ra, rb = fit.result.patch.rails(fit.result.direction)
    part = min(measure(face, s, fz.SAMPLES) for s in part_ruled(face, ra, rb))
    assert fit.hausdorff.max <= part * (1 + 1e-6), (fit.hausdorff.max, part)
    assert fit.result.best.method == "iso" and any("iso-parametric" in n for n in fit.result.notes), fit.result.notes


def test_edges_off_their_surface_within_their_tolerance_are_in_the_bound_and_said_so():
    """Issue 34: a dozen flat faces certified at 3.5e-10 measured 5.5e-4 from their results on their edges,
    which lie off the surface within their own tolerance.  A flat face, its surface's whole rectangle, with
    one edge's 3D curve bowed 5e-4 off it (tolerance 1e-3): the measure samples that edge, and the bound
    covers it, by OCCT alone too; the report says how much of the bound is the edges."""
    from trimmed_faces import extrema_measure, sloppy_face

    import ruled.cq as rcq
    face = sloppy_face(5e-4)
    fit = rcq.fit_face(face, samples=12, measure_samples=12)
    a, b = extrema_measure(face, fit.face.wrapped, 12)
    assert 4.9e-4 < max(a, b) <= fit.error_bound < 6e-4, (a, b, fit.error_bound)
    # (the edge bowed off the plane: the patch's side is moved onto it, and that is in the bound)
    assert not fit.result.patch.identity and fit.result.patch.edge_gap >= 5e-4, fit.result.patch
    assert any("is how far the face's edges lie off its surface (their tolerance in the file is up to 0.001)" in w
               for w in fit.warnings), fit.warnings


@pytest.mark.slow
def test_a_best_fit_whose_figures_disagree_gives_way_to_the_next_candidate(tmp_path, monkeypatch):
    """Issue 34: a result whose measure is above its bound is not a result; the next candidate is tried before
    refusing.  The fuzz's face 2202:7 (its fit along u measured within 0.9 % of its bound of 1.29) with only
    the u direction's bounds broken to 0.9x themselves: the command line and Python return the fit along v
    (bound 5.44, its measure within it), saying why; the batch records the face as fitted."""
    import json

    import fuzz_faces as fz

    import ruled.cq as rcq
    import ruled.fit.fit2d as f
    from ruled.occ.io import write_step
    path, out, rep = str(tmp_path / "tight.step"), str(tmp_path / "o.step"), str(tmp_path / "r.json")
    face = fz.face_named("2d:2202:7").face
    write_step(face, path)
    monkeypatch.setattr(f.DirectionFit, "error_bound", property(
        lambda self: (0.9 if self.direction == "u" else 1.0) * self.certificate.bound))
    run = ruled_here("fit", path, "--face", "0", "--samples", str(fz.SAMPLES), "--measure-samples",
                     str(fz.SAMPLES), "-o", out, "--report", rep, "--quiet")
    assert run.returncode == 0 and os.path.exists(out), run.stderr
    r = json.load(open(rep))
    assert r["direction"] == "v" and r["hausdorff"]["max"] <= r["error_bound"], r
    assert "the fit with the lowest bound (2d along u) was not returned: the result's measured distance" \
        in run.stderr and "the next candidate (2d along v" in run.stderr, run.stderr
    fit = rcq.fit_face(face, samples=fz.SAMPLES, measure_samples=fz.SAMPLES)
    assert fit.result.direction == "v" and fit.hausdorff.max <= fit.error_bound
    assert any("the next candidate (2d along v" in n for n in fit.result.notes), fit.result.notes
