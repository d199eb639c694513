"""Random faces through the whole job (issue 19, point 5; issue 22's property test; issue 33's rotation):
32 faces fitted in 2D and 10 in 4D by ``ruled batch`` with a per-face time limit, drawn from a seed that
changes with every commit (its first eight hex digits; RULED_FUZZ_SEED overrides), plus the faces of
tests/fuzz_faces.py's REGRESSIONS, each result measured by OCCT against the face as bounded by its edges.
Asserted on every face: no crash and no hang (a refusal is a one-line RuledError), the certified bound at
least the measured distance (and, for the tightest six, at least a denser measure), a valid result face;
in 4D, the 4D attempt's bound within 10x the 2D bound.  The faces (tests/fuzz_faces.py) are rational and
periodic, of degrees 1-5 with 2-12 poles, knots of every multiplicity (creases across and along the
rulings), weights 0.2-5 and over ratios up to 1e5, tiny closed faces, scales 1e-4-1e4, offsets up to 1e5,
collapsed rows and trimmed sides; and issue 34's kinds (8 in 2D, 3 in 4D): bands round a whole period,
faces with holes, edges off their surface within their tolerance, re-measured by OCCT alone.  A certificate
broken to 0.9x itself is caught by the same checks.

A failing face prints its name; ``python tests/fuzz_faces.py --face NAME`` runs it alone, and
``python tests/fuzz_faces.py --seed N`` the whole rotating run of seed N.  The fixed runs of 300 and 50
faces: ``benchmarks/run.py --suite fuzz``."""

from __future__ import annotations

import os

import pytest

pytest.importorskip("OCP")

import fuzz_faces as fz  # noqa: E402


@pytest.fixture(scope="module")
def seed():
    return fz.commit_seed()          # printed in the session's header (conftest.py)


@pytest.fixture(scope="module", params=list(fz.ROTATING))
def batch(request, seed, tmp_path_factory):
    method = request.param
    return fz.run_batch(str(tmp_path_factory.mktemp(f"fuzz{method}")), method, fz.rotating_faces(seed, method))


@pytest.mark.slow
def test_random_faces_are_fitted_soundly_or_refused_in_one_line(batch, seed):
    bad = fz.check_outcomes(batch)
    assert not bad, f"seed {seed}: " + "\n".join(bad)


@pytest.mark.slow
def test_the_tightest_bounds_hold_against_a_denser_measure(batch, seed):
    bad = fz.check_dense(batch)
    known = [x for x in bad if any(f"face {name} " in x for name in fz.KNOWN_DENSE)]
    unknown = [x for x in bad if x not in known]
    assert not unknown, f"seed {seed}: " + "\n".join(unknown)
    if known:       # reported, not hidden: the faces are named, and the test passes again once they hold
        pytest.xfail(f"known certificates below a denser measure, seed {seed}: " + "; ".join(known))


@pytest.mark.slow
def test_the_kinds_of_issue_34_hold_their_bounds_by_occt_alone(batch, seed):
    """Issue 34's kinds (tests/fuzz_faces.py kind_face: bands round a whole period from a seam of their own,
    sheets with holes, whole rectangles whose edges lie off their surface within their tolerance), each
    fitted result re-measured by OCCT alone (BRepExtrema from points inside and on the edges of each face,
    both ways): within its bound.  Prints the largest measured / bound."""
    bad, worst, count = fz.check_independent(batch)
    print(f"\n{batch.method}: {count} faces of issue 34's kinds measured by OCCT alone; the largest measured / "
          f"bound {worst:.4f}")
    assert count >= 0.5 * fz.ROTATING_KINDS[batch.method], count
    assert not bad, f"seed {seed}: " + "\n".join(bad)


@pytest.mark.slow
def test_a_4d_attempt_stays_within_ten_times_the_2d_bound(batch, seed):
    """Issue 22: the 4D rebuild once made knot spans so small (or lifted ends so torn at creases and
    focal points) that its bound reached 30,890 against 0.506 in 2D.  Whether or not the 4D result wins,
    its own certified bound stays within 10x the 2D bound of the same face.  Where its surface is within
    that by its own measure and only a certificate is loose (a 4D fit at a collapsed row; the product
    returns the 2D result and says why), the face is named as an expected failure."""
    if batch.method != "4d":
        pytest.skip("the 4D batch compares its 4D attempt with its 2D baseline")
    bad = fz.check_4d(batch)
    known = fz.known_blowups(batch)
    unknown = [x for x in bad if x not in known]
    assert not unknown, f"seed {seed}: " + "\n".join(unknown)
    if known:       # reported, not hidden: the faces are named, and the test passes again once they are tight
        pytest.xfail(f"loose 4D certificates (the 2D result returned), seed {seed}: "
                     + "; ".join(f"{x} ({why})" for x, why in known.items()))


BROKEN = """
import ruled.fit.fit2d as f
f.DirectionFit.error_bound = property(lambda self: 0.9 * self.certificate.bound)
"""


@pytest.mark.slow
def test_a_certificate_broken_to_nine_tenths_of_itself_is_caught(batch, tmp_path):
    """The checks above are sharp enough: the bound of every fit monkeypatched to 0.9x itself (in every
    process of the batch, through a sitecustomize module), the four faces of this run whose measure came
    closest to their bound are fitted again, and the same checks find a violation."""
    if batch.method != "2d":
        pytest.skip("the 2D batch: its faces are fitted in seconds")
    (tmp_path / "sitecustomize.py").write_text(BROKEN)
    faces = [batch.faces[r["face"]] for r in fz.tightest(batch, 4)]
    path = os.pathsep.join([str(tmp_path)] + ([os.environ["PYTHONPATH"]] if os.environ.get("PYTHONPATH") else []))
    broken = fz.run_batch(str(tmp_path / "broken"), "2d", faces, env={"PYTHONPATH": path})
    # the patch took: the same faces, bounds at 0.9x (within what the 0.9x choices between candidates change)
    assert len(broken.rows) == len(faces)
    bad = fz.check_outcomes(broken) or fz.check_dense(broken)     # the denser measure only if needed
    assert bad, "a certificate at 0.9x itself passed every check"
    print(f"\nthe broken certificate: {len(bad)} violations found in {len(faces)} faces, e.g. {bad[0]}")


def test_a_face_named_by_a_failure_is_the_face_that_failed():
    """The name a failure prints (method:seed:index) rebuilds the very face of the run: the same surface
    (poles, weights, knots, read back from OCCT) and the same bounds, so that ``python tests/fuzz_faces.py
    --face NAME`` reruns it."""
    import numpy as np
    from OCP.BRepTools import BRepTools

    from ruled.occ.convert import face_to_container

    def key(f):
        S = face_to_container(f.face)
        return [S.poles, S.weights, S.knots_u, S.knots_v], BRepTools.UVBounds_s(f.face)
    run = fz.faces_of("2d", 12345, 8)
    again = fz.face_named(run[5].name)
    assert run[5].name == "2d:12345:5" and again.desc == run[5].desc
    (a, ba), (b, bb), (c, _) = key(run[5]), key(again), key(run[4])
    assert ba == bb and all(np.array_equal(x, y) for x, y in zip(a, b))
    assert not all(x.shape == y.shape and np.array_equal(x, y) for x, y in zip(a, c))
    kinds = fz.faces_of("2d", 12345, 3, "k")
    again = fz.face_named(kinds[2].name)
    assert kinds[2].name == "2d:12345:k2" and again.desc == kinds[2].desc and again.family == "k"
    assert BRepTools.UVBounds_s(again.face) == BRepTools.UVBounds_s(kinds[2].face)
