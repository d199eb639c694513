"""Issue 72's soundness corpus, a slice that rotates with the commit (tests/fuzz_seed.commit_seed, as the fuzz run
rotates): a face of tests/data, two trimmed faces with wavy boundaries and an exactly ruled face across its iso
lines (tests/wavy_faces.py), each through the whole ``ruled fit`` job and its result measured again by OCCT at
80 x 80 of each face as bounded by its edges, both ways: never above the certified bound, and no refusal for
"measured above the bound" (each a certificate's bug).  The whole corpus: benchmarks/run.py --suite soundness."""

from __future__ import annotations

import os
import sys

import numpy as np
import pytest

sys.path.insert(0, os.path.dirname(os.path.dirname(__file__)))
pytest.importorskip("OCP")

from fuzz_seed import ROOT, commit_seed  # noqa: E402
from sound_corpus import DENSE, above, data_faces, refused_above, sound_row  # noqa: E402


def _slice(seed: int) -> list:
    import glob
    own = data_faces(sorted(glob.glob(os.path.join(ROOT, "tests", "data", "*.st*p"))))
    return [own[seed % len(own)], ("wavy", 1000 + seed % 997), ("wavy", 2000 + seed % 991),
            ("ruled", 3000 + seed % 983)]


@pytest.mark.slow
@pytest.mark.parametrize("which", range(4))
def test_the_rotating_slice_is_measured_within_its_bounds(tmp_path, which):
    seed = commit_seed()
    source, key = _slice(seed)[which]
    row = sound_row((source, key, str(tmp_path), DENSE))
    print(f"soundness slice (seed {seed}): {row}")
    assert not refused_above(row), row
    assert not above(row), row
    if row["status"] == "fitted":
        assert row["measured"] <= row["bound"] and row["dense"] > 0.0, row


@pytest.mark.slow
def test_the_two_bands_round_a_period_measured_above_their_bounds_no_more():
    """The corpus's first run (stop 77) measured two bands round a period above their bounds: one (k8) by the
    measure (a local search held at the face's seam, a foot just across it refused as outside), one (k55) by
    the sampled patch's deviation (three points a span missed 17 % of it).  Both fitted and measured again."""
    import tempfile
    for key in ("2d:3402:k8", "2d:3402:k55"):
        with tempfile.TemporaryDirectory() as tmp:
            row = sound_row(("fuzz", key, tmp, DENSE))
        assert row["status"] == "fitted" and not above(row), row


def test_the_measure_finds_the_foot_across_a_bands_seam():
    """Points a known distance off a band that goes once round a periodic surface from a seam of its own (u in
    [a0, a0 + period)): OCCT's distance to the bounded face is that distance, also for points whose foot lies
    just across the seam (the screen's upper values were the seeds' distances there, above the truth)."""
    from fuzz_faces import face_named
    from OCP.BRep import BRep_Tool
    from OCP.BRepAdaptor import BRepAdaptor_Surface
    from OCP.BRepLProp import BRepLProp_SLProps

    from ruled.occ.measure import _Projector, face_bounds
    face = face_named("2d:3402:k8").face
    u0, u1, v0, v1 = face_bounds(face)
    assert BRep_Tool.Surface_s(face).IsUPeriodic() and u0 > 0.5
    ad = BRepAdaptor_Surface(face)
    pts = []
    for u in list(u0 + (u1 - u0) * np.array([1e-4, 3e-3, 0.01])) + list(u1 - (u1 - u0) * np.array([1e-4, 3e-3, 0.01])):
        for v in np.linspace(0.45, 0.55, 3):
            pr = BRepLProp_SLProps(ad, float(u), float(v), 1, 1e-9)
            p, n = pr.Value(), pr.Normal()
            pts.append([p.X() + 1e-3 * n.X(), p.Y() + 1e-3 * n.Y(), p.Z() + 1e-3 * n.Z()])
    P = np.array(pts)
    up = _Projector(face).upper(P)
    assert np.all(np.abs(up - 1e-3) < 1e-7), up
