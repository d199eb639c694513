"""The sampled patch's deviation term alone (issue 72): ruled.fit.face.sampled.deviation_bound, the bound the
patch a face is fitted on carries into the certified bound, is never below the deviation itself measured by brute
force on a grid six times as dense; and three points a span (the sampling's own estimate) can miss what it holds."""

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


def _brute(S, m, P, per_span: int) -> float:
    from ruled.fit.face.sampled import _span_grid, _target
    gs, _ = _span_grid(np.unique(P.knots_u), per_span)
    gt, _ = _span_grid(np.unique(P.knots_v), per_span)
    ss, tt = np.meshgrid(gs, gt, indexing="ij")
    return float(np.linalg.norm(_target(S, m, ss, tt) - P(ss.ravel(), tt.ravel()), axis=1).max())


@pytest.mark.parametrize("key", ["2d:3402:k55", "2d:3402:k8"])
def test_the_patch_deviation_bound_is_not_below_a_brute_force_measure(key):
    from ruled.fit.face.patch import PATCH_TOL
    from ruled.fit.face.sampled import deviation_bound, side_surface
    region, m, size = _patch(key)
    side = side_surface(region.surface, m, PATCH_TOL * size, 192)
    P = side.surface
    brute = _brute(region.surface, m, P, 24)
    bound, _, _ = deviation_bound(region.surface, m, P, np.unique(P.knots_u), np.unique(P.knots_v), np.inf)
    assert side.deviation >= bound * (1 - 1e-12) and bound >= brute, (side.deviation, bound, brute)
    assert bound <= 3.0 * brute + 1e-12 * size      # (and not far above it)
