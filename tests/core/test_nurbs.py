"""NURBS core: evaluation against OCCT as the oracle, invariants, bounds, numba/NumPy twins."""
import numpy as np
import pytest
from cases import hyperboloid, random_surface

from ruled.core import jit
from ruled.core.basis import basis_derivatives, find_spans, periodic_knots
from ruled.core.nurbs import Curve, Surface

OCP = pytest.importorskip("OCP")


def _occt_d2(bs, u, v):
    from OCP.gp import gp_Pnt, gp_Vec
    p = gp_Pnt()
    vs = [gp_Vec() for _ in range(5)]
    bs.D2(float(u), float(v), p, *vs)
    d1u, d1v, d2u, d2v, d2uv = vs
    return [np.array(x.Coord()) for x in (p, d1u, d1v, d2u, d2uv, d2v)]


def _compare_with_occt(S, rng, n=40):
    from ruled.occ.convert import container_to_bspline
    bs = container_to_bspline(S)
    u0, u1, v0, v1 = S.domain
    u = rng.uniform(u0, u1, n)
    v = rng.uniform(v0, v1, n)
    D = S.evaluate(u, v, 2)
    mine = [D.P, D.Su, D.Sv, D.Suu, D.Suv, D.Svv]
    worst = 0.0
    for k in range(n):
        ref = _occt_d2(bs, u[k], v[k])
        for a, b in zip(ref, mine):
            worst = max(worst, float(np.linalg.norm(a - b[k]) / max(1.0, np.linalg.norm(a))))
    return worst


@pytest.mark.parametrize("rational", [False, True])
@pytest.mark.parametrize("periodic", [False, True])
@pytest.mark.parametrize("degrees", [(3, 2), (2, 3), (5, 1)])
def test_evaluator_matches_occt(rng, rational, periodic, degrees):
    for _ in range(3):
        S = random_surface(rng, pu=degrees[0], pv=degrees[1], nu=8, nv=6, rational=rational, periodic_u=periodic)
        assert _compare_with_occt(S, rng) < 1e-9


def test_periodic_with_multiple_seam_knot_matches_occt(rng):
    p = 3
    for m0 in (1, 2, 3):
        flat = np.concatenate([[0.0] * m0, [0.2, 0.45, 0.45, 0.7, 0.85]])
        n = flat.size
        ku = np.concatenate([flat[n - p:] - 1.0, flat, flat[: p + 1] + 1.0])
        uniq = rng.normal(size=(n, 3, 3))
        S = Surface(np.concatenate([uniq, uniq[:p]]), ku, [0, 0, 0, 1, 1, 1], p, 2, periodic_u=True)
        assert _compare_with_occt(S, rng) < 1e-9


def test_rational_surface_of_revolution_matches_occt(rng):
    assert _compare_with_occt(hyperboloid(), rng) < 1e-9


def test_reading_occt_periodic_surface_round_trip(rng):
    from ruled.occ.convert import bspline_surface_to_container, container_to_bspline
    S = random_surface(rng, periodic_u=True, rational=True)
    bs = container_to_bspline(S)
    assert bs.IsUPeriodic()
    back = bspline_surface_to_container(bs)
    assert back.periodic_u
    u = rng.uniform(*S.domain[:2], 50)
    v = rng.uniform(*S.domain[2:], 50)
    assert np.abs(back(u, v) - S(u, v)).max() < 1e-12


def test_partition_of_unity_and_derivative_sum(rng):
    knots = np.array([0, 0, 0, 0, 0.2, 0.2, 0.5, 0.9, 1, 1, 1, 1.0])
    x = rng.uniform(0, 1, 200)
    spans = find_spans(knots, 3, knots.size - 4, x)
    B = basis_derivatives(knots, 3, spans, x, 2)
    assert np.allclose(B[0].sum(axis=1), 1.0, atol=1e-14)
    assert np.allclose(B[1].sum(axis=1), 0.0, atol=1e-12)
    assert np.allclose(B[2].sum(axis=1), 0.0, atol=1e-10)
    assert (B[0] >= -1e-15).all()


def test_periodic_knots_layout():
    k = periodic_knots(np.array([0.0, 0.3, 0.6, 1.0]), 2)
    assert k.size == 3 + 2 * 2 + 1
    assert np.allclose(k[2:6] - k[2], [0.0, 0.3, 0.6, 1.0])


def test_iso_curve_matches_surface(rng):
    S = random_surface(rng, rational=True)
    C = S.iso_curve("u", 0.37)
    t = rng.uniform(0, 1, 30)
    assert np.abs(C(t) - S(t, np.full(30, 0.37))).max() < 1e-13
    D = S.iso_curve("v", 0.61)
    assert np.abs(D(t) - S(np.full(30, 0.61), t)).max() < 1e-13


def test_derivative_bounds_hold(rng):
    """Per-span bounds of |S_uu|, |S_uv|, |S_vv| against dense sampling (brute force)."""
    for rational in (False, True):
        S = random_surface(rng, rational=rational)
        b = S.derivative_bounds()
        u = rng.uniform(0, 1, 20000)
        v = rng.uniform(0, 1, 20000)
        D = S.evaluate(u, v, 2)
        iu = find_spans(S.knots_u, S.degree_u, S.poles.shape[0], u) - S.degree_u
        iv = find_spans(S.knots_v, S.degree_v, S.poles.shape[1], v) - S.degree_v
        for key, val in (("Su", D.Su), ("Sv", D.Sv), ("Suu", D.Suu), ("Suv", D.Suv), ("Svv", D.Svv)):
            assert (np.linalg.norm(val, axis=1) <= b[key][iu, iv] * (1 + 1e-12)).all(), key


@pytest.mark.parametrize("degrees", [(3, 2), (4, 3), (2, 2)])
def test_third_derivative_bounds_hold_against_occt(rng, degrees):
    """Per-span bounds of the third derivatives (the certificate's second-order remainder) against
    OCCT's own third derivatives (Geom_BSplineSurface::D3) at random points, rational surfaces too."""
    from OCP.gp import gp_Pnt, gp_Vec

    from ruled.occ.convert import container_to_bspline
    for rational in (False, True):
        S = random_surface(rng, pu=degrees[0], pv=degrees[1], nu=8, nv=6, rational=rational)
        bs = container_to_bspline(S)
        b = S.third_derivative_bounds()
        u = rng.uniform(0, 1, 300)
        v = rng.uniform(0, 1, 300)
        iu = find_spans(S.knots_u, S.degree_u, S.poles.shape[0], u) - S.degree_u
        iv = find_spans(S.knots_v, S.degree_v, S.poles.shape[1], v) - S.degree_v
        for k in range(u.size):
            p, vs = gp_Pnt(), [gp_Vec() for _ in range(9)]
            bs.D3(float(u[k]), float(v[k]), p, *vs)
            # D3 order: D1U D1V D2U D2V D2UV D3U D3V D3UUV D3UVV
            ref = {"Suuu": vs[5], "Svvv": vs[6], "Suuv": vs[7], "Suvv": vs[8]}
            for key, vec in ref.items():
                assert vec.Magnitude() <= b[key][iu[k], iv[k]] * (1 + 1e-9) + 1e-9, (key, rational)


@pytest.mark.parametrize("periodic", [False, True])
def test_subdivided_twin_is_the_same_surface_with_sound_local_bounds(rng, periodic):
    """The certificate's bounding twin (knot spans split, S.subdivided): the same surface by OCCT's
    evaluation, and its per-span bounds still hold against dense samples (brute force)."""
    from OCP.gp import gp_Pnt

    from ruled.occ.convert import container_to_bspline
    S = random_surface(rng, pu=3, pv=2, nu=7, nv=5, rational=True, periodic_u=periodic)
    T = S.subdivided(5, 3)
    assert T.poles.shape[0] > S.poles.shape[0] and T.poles.shape[1] > S.poles.shape[1]
    bs, bt = container_to_bspline(S), container_to_bspline(T)
    u0, u1, v0, v1 = S.domain
    u, v = rng.uniform(u0, u1, 200), rng.uniform(v0, v1, 200)
    for k in range(u.size):
        a, b = gp_Pnt(), gp_Pnt()
        bs.D0(float(u[k]), float(v[k]), a)
        bt.D0(float(u[k]), float(v[k]), b)
        assert a.Distance(b) <= 1e-12 * S.diagonal()
    u, v = rng.uniform(u0, u1, 20000), rng.uniform(v0, v1, 20000)
    D = S.evaluate(u, v, 2)
    b = T.derivative_bounds()
    iu = find_spans(T.knots_u, T.degree_u, T.poles.shape[0], u) - T.degree_u
    iv = find_spans(T.knots_v, T.degree_v, T.poles.shape[1], v) - T.degree_v
    for key, val in (("Su", D.Su), ("Sv", D.Sv), ("Suu", D.Suu), ("Suv", D.Suv), ("Svv", D.Svv)):
        assert (np.linalg.norm(val, axis=1) <= b[key][iu, iv] * (1 + 1e-12)).all(), key


def test_subdivided_twin_tightens_rational_third_derivative_bounds():
    """The hyperboloid's rational circle: the quotient-rule bound of |S_uuu| over a quarter-circle
    span is far above the true value; over 12 pieces per span it is several times smaller."""
    S = hyperboloid()
    whole = S.third_derivative_bounds()["Suuu"].max()
    split = S.subdivided(12, 1).third_derivative_bounds()["Suuu"].max()
    assert split < 0.5 * whole, (split, whole)


@pytest.mark.skipif(not jit.AVAILABLE, reason="numba is not installed")
def test_numba_and_numpy_paths_agree(rng, monkeypatch):
    from ruled.core.distance import ruling_distances
    for S, closed in ((random_surface(rng, rational=True), False), (hyperboloid(), True)):
        u = rng.uniform(*S.domain[:2], 3000)
        v = rng.uniform(*S.domain[2:], 3000)
        Dn = S.evaluate(u, v, 2)
        a = rng.uniform(0, 1, 500)
        b = rng.uniform(0, 1, 500)
        r1 = ruling_distances(S, a, b, 9, 3, closed)
        C = S.iso_curve("u", S.domain[2])
        c1 = C.evaluate(u.clip(*C.domain), 2)
        monkeypatch.setattr(jit, "AVAILABLE", False)
        Dp = S.evaluate(u, v, 2)
        r2 = ruling_distances(S, a, b, 9, 3, closed)
        C2 = Curve(C.poles, C.knots, C.degree, C.weights)
        c2 = C2.evaluate(u.clip(*C.domain), 2)
        monkeypatch.setattr(jit, "AVAILABLE", True)
        for f in ("P", "Su", "Sv", "Suu", "Suv", "Svv"):
            x, y = getattr(Dn, f), getattr(Dp, f)
            assert np.abs(x - y).max() <= 1e-11 * max(1.0, np.abs(y).max()), f
        assert np.abs(r1[0] - r2[0]).max() < 1e-12
        assert np.abs(r1[1] - r2[1]).max() < 1e-12
        for x, y in zip(c1, c2):
            assert np.abs(x - y).max() <= 1e-11 * max(1.0, np.abs(y).max())
