"""A planar face is ruled, whatever its shape and its surface's parametrization (issue 58, ruled.fit.face.plane):
flat bicubic surfaces parametrized far from affinely (x = 100 u + 30 u^2 + 30 v^2, y = 80 v + 20 u v), trimmed by a
wavy loop, get their plane trimmed by their edges.  Measured by OCCT (ruled.occ.measure, both ways, and
BRepExtrema alone), areas by BRepGProp."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("OCP")

import wavy_faces as W  # noqa: E402
from trimmed_faces import extrema_measure, face_from_loops  # noqa: E402

from ruled.fit.options import FitOptions  # noqa: E402
from ruled.occ.io import face_area  # noqa: E402
from ruled.occ.measure import hausdorff  # noqa: E402
from ruled.occ.region import fit_face  # noqa: E402
from ruled.occ.trimmed import result_face  # noqa: E402


@pytest.mark.parametrize("skew", [0.0, 0.3])
def test_a_planar_face_trimmed_by_a_wavy_loop_is_its_plane(skew):
    rng = np.random.default_rng(1)
    surf = W._bezier(lambda u, v: np.stack([100 * u + 30 * u * u + skew * 100 * v * v, 80 * v + 20 * u * v,
                                            0 * u], axis=1), 3, 3)
    face = face_from_loops(surf, [W._wavy_loop(rng, (0.5, 0.5), 0.36, 3, 0.1, 3, False)])
    res, slack = fit_face(face, FitOptions(ends="auto"))
    out = result_face(res)
    bound, size = res.error_bound + slack, res.patch.face_size
    h = hausdorff(face, out, 16).max
    a, b = extrema_measure(face, out, 10)
    assert res.patch.plane and "planar" in res.notes[-1]
    assert max(h, a, b) <= bound <= 1e-6 * size, (h, a, b, bound, size)
    assert abs(face_area(out, 1e-6) / face_area(face, 1e-6) - 1.0) < 1e-5
