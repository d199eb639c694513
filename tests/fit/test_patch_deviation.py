"""The sampled patch's deviation term alone (issue 72): the patch a face is fitted on (its own parametrization
sampled into a bicubic spline, ruled.fit.face.sampled.side_surface) carries its deviation from the face into the
certified bound, taken at eight points a span (ruled.fit.face.sampled.dense_deviation): within 10 % of a brute
force four times as dense, and above what three points a span (the sampling's own check) find."""

from __future__ import annotations

import os
import sys

import numpy as np
import pytest

sys.path.insert(0, os.path.dirname(os.path.dirname(__file__)))
pytest.importorskip("OCP")


def _patch(key: str):
    from fuzz_faces import face_named

    from ruled.fit.face.fit import _choose_sides
    from ruled.fit.face.patch import region_size
    from ruled.occ.region import face_region
    region = face_region(face_named(key).face)
    size = region_size(region)
    _, m = _choose_sides(region, None, size)
    return region, m, size


@pytest.mark.parametrize("key", ["2d:3402:k55", "2d:3402:k8"])
def test_the_patch_deviation_is_within_ten_percent_of_a_brute_force_measure(key):
    from ruled.fit.face.patch import PATCH_TOL
    from ruled.fit.face.sampled import dense_deviation, side_surface
    region, m, size = _patch(key)
    side = side_surface(region.surface, m, PATCH_TOL * size, 192)
    P = side.surface
    bs, bt = np.unique(P.knots_u), np.unique(P.knots_v)
    brute = dense_deviation(region.surface, m, P, bs, bt, 32)
    three = dense_deviation(region.surface, m, P, bs, bt, 2)     # (the knots and the midpoints)
    assert brute >= side.deviation >= 0.9 * brute, (side.deviation, brute)
    assert side.deviation >= three
