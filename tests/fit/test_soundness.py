"""Issue 72's soundness corpus, a slice that rotates with the commit (tests/fuzz_seed.commit_seed, as the fuzz run
rotates): a face of tests/data, two trimmed faces with wavy boundaries and an exactly ruled face across its iso
lines (tests/wavy_faces.py), each through the whole ``ruled fit`` job and its result measured again by OCCT at
80 x 80 of each face as bounded by its edges, both ways: never above the certified bound, and no refusal for
"measured above the bound" (each a certificate's bug).  The whole corpus: benchmarks/run.py --suite soundness."""

from __future__ import annotations

import os
import sys

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
