"""Curves on surfaces, domain side (Yang et al. §§3–4): pieces, single-sidedness, chord distance."""
import numpy as np
import pytest
from cases import random_surface

from ruled.core.basis import find_spans
from ruled.core.errors import BadInputError
from ruled.core.nurbs import Curve
from ruled.curves.bezier import Piece, _roots01, bezier_eval, domain_pieces, single_sided
from ruled.curves.curve_on_surface import chord_distance, span_tolerance

YANG_CURVE = Curve(np.array([(0.1, 0.1), (0.5, 1.8), (0.8, 0.1)]), [0, 0, 0, 1, 1, 1], 2)  # the paper's example


def _random_domain_curve(rng, degree=3, n=7):
    knots = np.concatenate([np.zeros(degree + 1), np.sort(rng.uniform(0.1, 0.9, n - degree - 1)),
                            np.ones(degree + 1)])
    return Curve(rng.uniform(0.05, 0.95, (n, 2)), knots, degree)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_pieces_cover_the_curve_stay_in_one_span_and_are_single_sided(seed):
    rng = np.random.default_rng(seed)
    S = random_surface(np.random.default_rng(4), pu=3, pv=3, nu=8, nv=7)
    D = _random_domain_curve(rng)
    pieces = domain_pieces(D, S)
    assert pieces[0].t0 == D.domain[0] and pieces[-1].t1 == D.domain[1]
    s = np.linspace(0.0, 1.0, 41)
    for a, b in zip(pieces[:-1], pieces[1:]):
        assert a.t1 == b.t0
    for p in pieces:
        X = bezier_eval(p.ctrl, s)
        assert np.abs(X - D(p.t0 + s * (p.t1 - p.t0))).max() <= 1e-12
        inner = X[1:-1]
        su = find_spans(S.knots_u, S.degree_u, S.poles.shape[0], inner[:, 0])
        sv = find_spans(S.knots_v, S.degree_v, S.poles.shape[1], inner[:, 1])
        assert np.unique(su).size == 1 and np.unique(sv).size == 1
        d = p.ctrl[-1] - p.ctrl[0]
        cross = (X[:, 0] - p.ctrl[0, 0]) * d[1] - (X[:, 1] - p.ctrl[0, 1]) * d[0]
        scale = np.abs(cross).max() + 1e-300
        assert cross.min() >= -1e-9 * scale or cross.max() <= 1e-9 * scale


@pytest.mark.parametrize("seed", range(5))
def test_chord_distance_matches_brute_force(seed):
    rng = np.random.default_rng(seed)
    S = random_surface(np.random.default_rng(4), pu=3, pv=3, nu=8, nv=7)
    for p in domain_pieces(_random_domain_curve(rng), S):
        H, t = chord_distance(p.ctrl)
        X = bezier_eval(p.ctrl, np.linspace(0, 1, 20001))
        P0, d = p.ctrl[0], p.ctrl[-1] - p.ctrl[0]
        s = np.clip((X - P0) @ d / (d @ d), 0, 1)
        brute = np.linalg.norm(X - (P0 + s[:, None] * d), axis=1).max()
        assert H >= brute - 1e-12 and H <= brute + 1e-7


def test_yang_example_domain_curve_stays_one_single_sided_piece():
    S = random_surface(np.random.default_rng(4), pu=2, pv=2, nu=3, nv=3)
    pieces = domain_pieces(YANG_CURVE, S)
    assert len(pieces) == 1  # a parabola arc lies on one side of its chord


def test_span_tolerance_is_eps_over_the_derivative_bounds():
    S = random_surface(np.random.default_rng(4), pu=3, pv=3, nu=8, nv=7, rational=True)
    b = S.derivative_bounds()
    d = span_tolerance(S, 1e-3, 0.5, 0.5, b)
    iu = int(find_spans(S.knots_u, 3, 8, np.array([0.5]))[0]) - 3
    iv = int(find_spans(S.knots_v, 3, 7, np.array([0.5]))[0]) - 3
    assert d == pytest.approx(1e-3 / (b["Su"][iu, iv] + b["Sv"][iu, iv]))
    # the bound holds: points d apart in the span map at most eps apart
    rng = np.random.default_rng(0)
    lo = np.array([S.knots_u[iu + 3], S.knots_v[iv + 3]])
    hi = np.array([S.knots_u[iu + 4], S.knots_v[iv + 4]])
    P = lo + rng.uniform(0, 1, (200, 2)) * (hi - lo)
    ang = rng.uniform(0, 2 * np.pi, 200)
    Q = np.clip(P + d * np.stack([np.cos(ang), np.sin(ang)], axis=1), lo, hi)
    assert np.linalg.norm(S(P[:, 0], P[:, 1]) - S(Q[:, 0], Q[:, 1]), axis=1).max() <= 1e-3


def test_bad_domain_curves_are_refused():
    S = random_surface(np.random.default_rng(4))
    with pytest.raises(BadInputError, match=r"^curve weights must be positive \(the smallest is -2\)$"):
        domain_pieces(Curve(np.zeros((3, 2)) + 0.5, [0, 0, 0, 1, 1, 1], 2, weights=[1, -2, 1]), S)
    with pytest.raises(BadInputError, match="2D"):
        domain_pieces(Curve(np.zeros((3, 3)) + 0.5, [0, 0, 0, 1, 1, 1], 2), S)
    with pytest.raises(BadInputError, match="reaches v = 1.2"):
        domain_pieces(Curve(np.array([(0.2, 0.2), (0.5, 1.2)]), [0, 0, 1, 1], 1), S)
    # control points outside the domain but the curve inside it is accepted (exact coordinate range)
    domain_pieces(Curve(np.array([(0.2, 0.1), (0.5, 1.02), (0.8, 0.1)]), [0, 0, 0, 1, 1, 1], 2), S)


@pytest.mark.parametrize("seed", range(4))
def test_rational_piece_chord_distance_matches_brute_force(seed):
    rng = np.random.default_rng(seed)
    ctrl = rng.uniform(0, 1, (4, 2))
    w = rng.uniform(0.3, 3.0, 4)
    for p in single_sided(Piece(np.concatenate([ctrl * w[:, None], w[:, None]], axis=1), 0.0, 1.0)):
        H, t = chord_distance(p.ctrl, p.hom[:, 2])
        X = bezier_eval(p.hom, np.linspace(0, 1, 20001))
        X = X[:, :2] / X[:, 2:]
        P0, d = X[0], X[-1] - X[0]
        s = np.clip((X - P0) @ d / (d @ d), 0, 1)
        brute = np.linalg.norm(X - (P0 + s[:, None] * d), axis=1).max()
        assert H >= brute - 1e-12 and H <= brute + 1e-7


def test_roots_in_the_unit_interval_match_numpy():
    rng = np.random.default_rng(0)
    P = rng.normal(size=(300, 6))
    P[:40, -1] = 0.0      # lower degree rows
    P[40:60, -2:] = 0.0
    R = _roots01(P)
    for row, r in zip(P, R):
        k = np.max(np.nonzero(row)[0])
        ref = np.roots(row[:k + 1][::-1])
        ref = np.sort(ref[(np.abs(ref.imag) < 1e-9) & (ref.real > 1e-9) & (ref.real < 1 - 1e-9)].real)
        got = np.sort(r[np.isfinite(r)])
        assert got.shape == ref.shape and np.allclose(got, ref, atol=1e-10)


def test_knot_line_crossings_are_exact():
    S = random_surface(np.random.default_rng(4), pu=3, pv=3, nu=8, nv=7)
    D = _random_domain_curve(np.random.default_rng(9))
    ku, kv = set(S.interior_knots("u").tolist()), set(S.interior_knots("v").tolist())
    hits = 0
    for p in domain_pieces(D, S):
        for x in (p.ctrl[0], p.ctrl[-1]):
            hits += (x[0] in ku) + (x[1] in kv)
    assert hits >= 4


def _both_paths(fn, monkeypatch):
    """fn() with the numba kernels (when installed) and with NumPy alone."""
    from ruled.core import jit
    a = fn()
    monkeypatch.setenv("RULED_NO_NUMBA", "1")
    assert not jit.enabled()
    b = fn()
    monkeypatch.delenv("RULED_NO_NUMBA")
    return a, b


@pytest.mark.parametrize("deg,rational", [(2, False), (3, True), (5, False), (5, True)])
def test_numba_kernels_and_numpy_twins_agree_bit_for_bit(deg, rational, monkeypatch):
    from ruled.curves import bezier
    from ruled.curves import curve_on_surface as cos
    rng = np.random.default_rng(deg)
    P = rng.uniform(0, 1, (150, deg + 1, 2))
    w = rng.uniform(0.5, 2, (150, deg + 1)) if rational else np.ones((150, deg + 1))
    H = np.concatenate([P * w[..., None], w[..., None]], axis=2)
    c0, c1 = _both_paths(lambda: bezier._first_cross(H), monkeypatch)
    assert np.array_equal(c0, c1, equal_nan=True)
    H, t0, t1, _ = bezier._single_sided_stack(H, np.zeros(150), np.ones(150))
    (h0, t0_), (h1, t1_) = _both_paths(lambda: cos._farthest(H), monkeypatch)
    assert np.array_equal(h0, h1) and np.array_equal(t0_, t1_)
    S = random_surface(np.random.default_rng(4), pu=3, pv=2, nu=8, nv=7, rational=rational)
    from ruled.curves.compose import SpanPatches
    sp = SpanPatches(S)
    sid = sp.of(rng.uniform(0.01, 0.99, (200, 2)))
    _, _, _, slo, shi = sp.arrays()
    lo = slo[sid] + rng.uniform(0, 0.5, (200, 2)) * (shi[sid] - slo[sid])
    hi = lo + rng.uniform(0, 0.5, (200, 2)) * (shi[sid] - slo[sid])
    hi[:10, 0] = lo[:10, 0]                   # boxes of zero width (a piece along an iso-line)
    g0, g1 = _both_paths(lambda: sp.local_bounds(sid, lo, hi), monkeypatch)
    assert np.array_equal(g0, g1)


def test_whole_approximation_is_the_same_on_both_paths(monkeypatch):
    from ruled.curves.curve_on_surface import approximate
    from ruled.examples import yang_curve, yang_surface
    S = random_surface(np.random.default_rng(5), pu=3, pv=3, nu=8, nv=8, rational=True)
    for surf, D in ((yang_surface(), yang_curve()), (S, _random_domain_curve(np.random.default_rng(2)))):
        a, b = _both_paths(lambda: approximate(surf, D, 1e-3 * surf.diagonal(), 1.0), monkeypatch)
        assert a.segments == b.segments and a.error_bound == b.error_bound
        assert np.array_equal(a.curve.poles, b.curve.poles) and np.array_equal(a.curve.knots, b.curve.knots)


def test_a_smooth_domain_curve_through_points():
    """Picked points are joined by a C2 cubic spline (quadratic through three, a line through two): it passes
    through every point, has no corner there (its tangent turns continuously), and repeated points are
    dropped."""
    import numpy as np

    from ruled.curves.domain import smooth_curve
    P = np.array([(0.1, 0.2), (0.5, 0.7), (0.5, 0.7), (0.8, 0.3), (0.9, 0.9), (0.3, 0.95)])
    C = smooth_curve(P)
    assert C.degree == 3
    t = np.linspace(*C.domain, 20001)
    X = C(t)
    for p in np.unique(P, axis=0):
        assert np.min(np.linalg.norm(X - p, axis=1)) <= 1e-3
    d1 = np.diff(X, axis=0)
    turn = np.degrees(np.arccos(np.clip((d1[:-1] * d1[1:]).sum(1) / (np.linalg.norm(d1[:-1], axis=1)
                                                                    * np.linalg.norm(d1[1:], axis=1)), -1, 1)))
    assert turn.max() < 0.5                     # between samples 1/20000 apart: no corner anywhere
    assert smooth_curve(P[:2]).degree == 1 and smooth_curve(P[[0, 1, 3]]).degree == 2


def test_a_commands_first_use_is_known_from_numbas_cache(tmp_path):
    """ruled.warm: with an empty numba cache every kernel module a split needs is cold (the workbench then
    compiles them first, saying so); the estimate is their listed seconds."""
    import subprocess
    import sys

    from conftest import ROOT
    code = ("from ruled import warm; from ruled.core import jit; "
            "print(warm.cold('split') if jit.enabled() else 'no numba', "
            "warm.seconds(warm.cold('split')))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, timeout=120,
                         env={**__import__("os").environ, "NUMBA_CACHE_DIR": str(tmp_path)}).stdout
    from ruled import warm
    from ruled.core import jit
    if jit.enabled():
        assert out.split("]")[0] + "]" == "['core', 'fit', 'split', 'curves']", out
        assert int(out.split()[-1]) == sum(warm.SECONDS[m] for m in ("core", "fit", "split", "curves"))
