"""Virtual subdivision (ruled.split.strips): graph curves, the Coons map of a strip, and the side surface's
deviation from S o Omega measured at points of its own choosing."""

import numpy as np

from ruled.examples import elber_ex2
from ruled.split.strips import Strip, graph_curve, iso_curve, side_surface


def _wavy(S):
    u0, u1, v0, v1 = S.domain
    return graph_curve(np.linspace(u0, u1, 24), lambda u: v0 + (v1 - v0) * (0.5 + 0.15 * np.sin(5 * u)))


def test_graph_curve_reproduces_its_parameter_and_interpolates():
    c = graph_curve(np.linspace(0.0, 2.0, 20), lambda u: np.cos(u))
    x = np.linspace(0.0, 2.0, 301)
    P = c(x)
    assert np.abs(P[:, 0] - x).max() < 1e-14
    assert np.abs(P[:, 1] - np.cos(x)).max() < 1e-4
    g = c.poles[:, 0]
    assert np.abs(c(g)[:, 1] - np.cos(g)).max() < 1e-13


def test_coons_map_meets_the_strip_boundaries():
    S = elber_ex2()
    u0, u1, v0, v1 = S.domain
    c = _wavy(S)
    st = Strip(c, None)
    s = np.linspace(0, 1, 50)
    u, v = st.omega(S, s, np.zeros(50))
    assert np.allclose(u, u0 + s * (u1 - u0)) and np.allclose(v, c(u)[:, 1], atol=1e-15)
    assert np.allclose(st.omega(S, s, np.ones(50))[1], v1)
    lo, hi = Strip(None, c).cut(S, iso_curve(u0, u1, 0.3 * v0 + 0.7 * v1))
    assert lo.hi is hi.lo and lo.lo is None and hi.hi is c


def test_side_surface_follows_the_composition(rng):
    S = elber_ex2()
    tol = 1e-6 * S.diagonal()
    for st in (Strip(None, _wavy(S)), Strip(_wavy(S), None)):
        side = side_surface(S, st, tol)
        assert side.deviation <= tol
        s, t = rng.random(4000), rng.random(4000)
        u, v = st.omega(S, s, t)
        err = np.linalg.norm(side.surface(s, t) - S(u, v), axis=1).max()
        assert err <= 2 * tol, err
    whole = side_surface(S, Strip())
    assert whole.surface is S and whole.deviation == 0.0
