"""Exact composition of domain segments with B-spline surfaces, checked against OCCT's evaluation."""
import numpy as np
import pytest
from cases import random_surface

from ruled.core.basis import find_spans
from ruled.core.errors import BadInputError
from ruled.core.nurbs import Surface
from ruled.curves.compose import compose_segment

OCP = pytest.importorskip("OCP")
from OCP.gp import gp_Pnt  # noqa: E402

from ruled.occ.convert import container_to_bspline  # noqa: E402

YANG_NET = np.array([[(0, 2, -1), (2.5, 1, 0), (1, 0, 1.5)],
                     [(1, 1, -2), (1, 0, -0.5), (2.5, -1, 0)],
                     [(1, 0, -3), (1, -1, -2), (-0.51, -2, -1)]], float)  # P_ij: i along u, j along v


def _occt_points(S, uv):
    g = container_to_bspline(S)
    out = []
    for u, v in uv:
        p = gp_Pnt()
        g.D0(float(u), float(v), p)
        out.append((p.X(), p.Y(), p.Z()))
    return np.array(out)


def _segments_in_spans(S, rng, k):
    """Random segments, each inside one knot-span rectangle of S."""
    segs = []
    u0, u1, v0, v1 = S.domain
    for _ in range(k):
        u, v = rng.uniform(u0, u1), rng.uniform(v0, v1)
        iu = int(find_spans(S.knots_u, S.degree_u, S.poles.shape[0], np.array([u]))[0])
        iv = int(find_spans(S.knots_v, S.degree_v, S.poles.shape[1], np.array([v]))[0])
        lo = np.array([S.knots_u[iu], S.knots_v[iv]])
        hi = np.array([S.knots_u[iu + 1], S.knots_v[iv + 1]])
        segs.append((lo + rng.uniform(0, 1, 2) * (hi - lo), lo + rng.uniform(0, 1, 2) * (hi - lo)))
    return segs


@pytest.mark.parametrize("kind", ["yang", "random", "rational", "periodic"])
def test_composed_segment_is_the_exact_image(kind, rng):
    if kind == "yang":
        S = Surface(YANG_NET, [0, 0, 0, 1, 1, 1], [0, 0, 0, 1, 1, 1], 2, 2)
    else:
        S = random_surface(np.random.default_rng(4), pu=3, pv=3, nu=7, nv=6, rational=kind != "random",
                           periodic_u=kind == "periodic")
    t = np.linspace(0.0, 1.0, 23)
    for a, b in _segments_in_spans(S, rng, 6):
        C = compose_segment(S, a, b)
        assert C.degree == S.degree_u + S.degree_v and C.poles.shape[0] == C.degree + 1
        assert C.rational == S.rational
        uv = (1 - t)[:, None] * a + t[:, None] * b
        ref = _occt_points(S, uv)
        assert np.abs(C(t) - ref).max() <= 1e-12 * max(1.0, np.abs(ref).max())


def test_segment_across_a_knot_line_is_refused():
    S = random_surface(np.random.default_rng(4), pu=3, pv=3, nu=7, nv=6)
    k = S.knots_u[S.degree_u + 1]
    with pytest.raises(BadInputError, match="knot line"):
        compose_segment(S, (k - 0.05, 0.3), (k + 0.05, 0.3))
