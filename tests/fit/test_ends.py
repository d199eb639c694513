"""Rulings that cross the face's end edges (issue 35, ``ends="trimmed"``): the rails run past the face and
the result is trimmed by the face's own edges.

Measured with OCCT alone (ruled.occ.measure: points inside each face's edges and along them, projected
onto the other bounded face), areas by BRepGProp, validity by BRepCheck, and FreeCAD's Part "Ruled
Surface" (BRepFill) between the face's rails as the reference a user has today.
"""

from __future__ import annotations

import pytest

pytest.importorskip("OCP")

from conftest import data_file  # noqa: E402
from trimmed_faces import diamond_on_ruled_face, measure, part_ruled  # noqa: E402

from ruled.fit.options import FitOptions  # noqa: E402
from ruled.occ.io import face_area, get_face  # noqa: E402
from ruled.occ.measure import hausdorff  # noqa: E402
from ruled.occ.region import fit_face  # noqa: E402
from ruled.occ.trimmed import result_face  # noqa: E402

N = 24


def _size(face) -> float:
    from OCP.Bnd import Bnd_Box
    from OCP.BRepBndLib import BRepBndLib
    b = Bnd_Box()
    BRepBndLib.Add_s(face, b)
    x0, y0, z0, x1, y1, z1 = b.Get()
    return float(((x1 - x0) ** 2 + (y1 - y0) ** 2 + (z1 - z0) ** 2) ** 0.5)


def _fitted(face, ends: str):
    from OCP.BRepCheck import BRepCheck_Analyzer
    res, slack = fit_face(face, FitOptions(ends=ends))
    out = result_face(res)
    assert BRepCheck_Analyzer(out).IsValid()
    return res, res.error_bound + slack, hausdorff(face, out, N).max, face_area(out, 1e-6) / face_area(face, 1e-6)


@pytest.fixture(scope="module")
def diamond():
    face = diamond_on_ruled_face()
    return face, _fitted(face, "trimmed"), _fitted(face, "pinned")


@pytest.mark.slow
def test_a_ruled_face_cut_by_four_curved_edges_comes_back_near_exact_and_covers_the_face(diamond):
    """The face lies on an exactly ruled surface and none of its four edges is a ruling: pinned at its corners
    the best ruled surface is 5 % of its size away and misses a seventh of it; with the rails past the face it
    is within 2e-3 of its size (0.11 for 6.5 pinned: the DP's 40 samples over the longer span, not yet the
    1e-5 the issue asks), its bound at least the measure, and its area the face's."""
    face, (res, bound, measured, area), (_, pbound, pmeasured, parea) = diamond
    size = _size(face)
    assert res.best.trim is not None
    assert measured <= 2e-3 * size
    assert measured <= bound
    assert abs(area - 1.0) <= 5e-3
    assert measured * 30 <= pmeasured           # pinned: the sagitta of the curved end edges
    assert abs(parea - 1.0) > 0.05              # ... and it misses part of the face
    assert bound < pbound


def test_the_face_mask_by_scanlines_is_the_even_odd_rule_node_by_node():
    """ruled.fit.extend.inside_grid (scanlines over a tensor grid) against the even-odd ray test of every
    node (brute force), on a five-lobed loop with a hole and an irregular grid."""
    import numpy as np

    from ruled.core.region import _crossings_odd
    from ruled.fit.extend import inside_grid
    rng = np.random.default_rng(3)
    th = np.linspace(0, 2 * np.pi, 300, endpoint=False)
    r = 0.3 + 0.1 * np.sin(5 * th)
    outer = np.stack([0.5 + r * np.cos(th), 0.5 + r * np.sin(th)], 1)
    hole = np.stack([0.5 + 0.05 * np.cos(th), 0.45 + 0.05 * np.sin(th)], 1)
    us, vs = np.sort(rng.random(97)), np.sort(rng.random(61))
    U, V = np.meshgrid(us, vs, indexing="ij")
    Q = np.stack([U.ravel(), V.ravel()], 1)
    ref = (_crossings_odd(outer, Q) ^ _crossings_odd(hole, Q)).reshape(U.shape)
    got = inside_grid((outer, hole), us, vs)
    assert ref.sum() > 500 and (~ref).sum() > 500
    assert np.array_equal(got, ref)


@pytest.fixture(scope="module")
def kj66_face_1_to_a_tolerance(tmp_path_factory):
    """`ruled fit kj66 --face 1 --tol 0.005`: (the input face, the one face written, its report)."""
    import json

    from conftest import ruled_here

    from ruled.occ.io import faces_of, read_shape
    src, tmp = data_file("kj66_impeller.step"), tmp_path_factory.mktemp("kj66f1")
    out, rep = str(tmp / "p.step"), str(tmp / "r.json")
    r = ruled_here("fit", src, "--face", "1", "--tol", "0.005", "-o", out, "--report", rep, "--quiet", cwd=tmp)
    assert r.returncode == 0, r.stderr
    assert "one ruled face within 0.005" in r.stdout
    faces = faces_of(read_shape(out))
    assert len(faces) == 1
    with open(rep) as fh:
        return get_face(src, 1), faces[0], json.load(fh)


@pytest.mark.slow
def test_fit_to_a_tolerance_keeps_the_whole_face_when_its_trimmed_fit_holds_it(kj66_face_1_to_a_tolerance):
    """`ruled fit kj66 --face 1 --tol 0.005`: pinned at its corners the face needs 3 strips (its curved end edges
    are 0.0249 from any ruled surface through its rails); with its rails past the face one ruled face holds
    the tolerance: the STEP has one face, within 0.005 of the face by OCCT both ways, its area the face's."""
    face, result, _ = kj66_face_1_to_a_tolerance
    assert hausdorff(face, result, N).max <= 0.005
    assert abs(face_area(result, 1e-6) / face_area(face, 1e-6) - 1.0) <= 5e-3


@pytest.mark.slow
def test_kj66_face_1_trimmed_is_a_tenth_of_part_ruled_between_its_rails(kj66_face_1_to_a_tolerance):
    """kj66 face 1: its end edges are curves 0.6 and 1.4 long whose sagitta sets Part Ruled's (and the
    pinned fit's) error; the trimmed result (the one face of the run above) is under a tenth of the better
    of Part Ruled's two orientations, measured trim-aware both ways, with its bound at least the measure."""
    face, result, rep = kj66_face_1_to_a_tolerance
    assert rep.get("trim", {}).get("ends") == "trimmed"
    measured = measure(face, result, N)
    part = min(measure(face, s, N) for s in part_ruled(face, [0], [2]))
    assert measured <= 0.1 * part
    assert measured <= rep["error_bound"]
