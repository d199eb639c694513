"""Elber's test surfaces (from his ruledfit script) and other built-in examples."""

from __future__ import annotations

import numpy as np

from ruled.core.nurbs import Curve, Surface

# rows are the v direction, points within a row the u direction
EX1_ROWS = [
    [(-0.4, 0.4, 1), (0, -0.2, 1), (0.4, -0.2, 1), (0.4, 0.4, 1)],
    [(-0.4, 0.4, 0.5), (-0.2, 0.3, 0.5), (0.2, 0.3, 0.5), (0.4, 0.4, 0.5)],
    [(-0.4, 0.4, 0), (-0.4, -0.2, 0), (0, -0.2, 0), (0.4, 0.4, 0)],
]

EX2_ROWS = [
    [(-0.378861, 0.848307, 0.17153), (-0.192145, 0.848307, 0.243203), (0.181287, 0.848307, 0.38655),
     (0.368003, 0.848307, 0.458224)],
    [(-0.39807, 0.451251, 0.753983), (-0.197478, 0.450111, 0.453213), (0.203704, 0.447829, 0.414519),
     (0.404295, 0.446689, 0.676594)],
    [(-0.41622, -0.40055, 0.69209), (-0.211468, -0.397111, 0.287906), (0.198037, -0.390233, 0.334057),
     (0.40279, -0.386794, 0.784392)],
    [(-0.297329, -0.772212, 0.62706), (-0.130127, -0.792265, 0.519956), (0.204279, -0.832371, 0.305749),
     (0.371481, -0.852424, 0.198645)],
]


def _from_rows(rows, knots_u, knots_v, pu, pv) -> Surface:
    P = np.array(rows, dtype=float)          # (nv, nu, 3)
    return Surface(np.transpose(P, (1, 0, 2)), knots_u, knots_v, pu, pv)


def elber_ex1() -> Surface:
    """Bézier, cubic in u, quadratic in v."""
    return _from_rows(EX1_ROWS, [0, 0, 0, 0, 1, 1, 1, 1], [0, 0, 0, 1, 1, 1], 3, 2)


def elber_ex2() -> Surface:
    """B-spline, cubic in u (0,0,0,0,1,1,1,1), quadratic in v (0,0,0,0.5,1,1,1)."""
    return _from_rows(EX2_ROWS, [0, 0, 0, 0, 1, 1, 1, 1], [0, 0, 0, 0.5, 1, 1, 1], 3, 2)


def demo_blade() -> Surface:
    """The demo's face (``ruled demo``): a drafted blade 80 mm long and 40 mm high, its top profile 0.8 of its
    bottom's, turned 6 degrees, and bulged by up to 0.7 mm between them (not ruled: its best ruled surface is
    about 0.29 mm from it).  Cubic along the profile, quadratic up it; a wire machine cuts it with its wire tilted
    at most about 20 degrees."""
    x = np.array([0.0, 16.0, 32.0, 48.0, 64.0, 80.0])
    y = np.array([0.0, 9.0, 14.0, 12.0, 6.0, 0.0])
    bottom = np.column_stack([x, y, np.zeros(6)])
    c, s = np.cos(np.radians(6.0)), np.sin(np.radians(6.0))
    centre = np.array([40.0, 7.0])
    top2 = (np.column_stack([x, y]) - centre) * 0.8 @ np.array([[c, s], [-s, c]]) + centre
    top = np.column_stack([top2, np.full(6, 40.0)])
    mid = 0.5 * (bottom + top)
    mid[1:5, 1] += np.array([0.4, 0.7, 0.7, 0.4])
    return Surface(np.stack([bottom, mid, top], axis=1), np.array([0, 0, 0, 0, 1 / 3, 2 / 3, 1, 1, 1, 1.0]),
                   np.array([0, 0, 0, 1, 1, 1.0]), 3, 2)


EXAMPLES = {"ex1": elber_ex1, "ex2": elber_ex2, "blade": demo_blade}


# Yang et al. 2008, first example: a biquadratic Bézier patch (P_ij, i along u, j along v) and a
# quadratic Bézier domain curve
YANG_NET = [[(0, 2, -1), (2.5, 1, 0), (1, 0, 1.5)],
            [(1, 1, -2), (1, 0, -0.5), (2.5, -1, 0)],
            [(1, 0, -3), (1, -1, -2), (-0.51, -2, -1)]]
YANG_CURVE = [(0.1, 0.1), (0.5, 1.8), (0.8, 0.1)]


def yang_surface() -> Surface:
    knots = np.array([0, 0, 0, 1, 1, 1], float)
    return Surface(np.array(YANG_NET, dtype=float), knots, knots.copy(), 2, 2)


def yang_curve() -> Curve:
    return Curve(np.array(YANG_CURVE, dtype=float), np.array([0, 0, 0, 1, 1, 1], float), 2)


# Yang & Yang 2006: the three examples' extended boundaries (planar curves v -> (N, 2) with their
# derivatives), in closed form (Bernstein sums), so that they evaluate the same with or without numba
def _bezier2d(P):
    from math import comb
    P = np.asarray(P, float)
    n = len(P) - 1
    B = [comb(n, i) for i in range(n + 1)]
    dP = n * np.diff(P, axis=0)

    def f(v):
        v = np.clip(np.atleast_1d(np.asarray(v, float)), 0, 1)[:, None]
        return sum(B[i] * v ** i * (1 - v) ** (n - i) * P[i] for i in range(n + 1))

    def df(v):
        v = np.clip(np.atleast_1d(np.asarray(v, float)), 0, 1)[:, None]
        return sum(comb(n - 1, i) * v ** i * (1 - v) ** (n - 1 - i) * dP[i] for i in range(n))
    return f, df


def _spiral():
    k = 3.5 * np.pi

    def b0(v):
        v = np.atleast_1d(v)
        return np.stack([(0.2 + v) * np.cos(k * v), (0.2 + v) * np.sin(k * v)], axis=1)

    def db0(v):
        v = np.atleast_1d(v)
        a = k * v
        return np.stack([np.cos(a) - (0.2 + v) * k * np.sin(a), np.sin(a) + (0.2 + v) * k * np.cos(a)], axis=1)
    return b0, db0, (lambda v: 1.5 * b0(v)), (lambda v: 1.5 * db0(v))


def cone_examples() -> list:
    """(name, b0, db0, b1, db1, tolerance, step, height, the paper's patch count) of Yang & Yang's
    examples 1, 2, 3a and 3b, in their extended form (the original surface lies between
    0.8 b0 + 0.2 b1 and 0.2 b0 + 0.8 b1)."""
    b0, db0 = _bezier2d([(0, 1.5), (0, 1.5), (0, 0), (0, 0), (1, -0.075), (1, -0.075), (3, 0), (3, 0), (3, 1.5),
                         (3, 1.5)])
    b1, db1 = _bezier2d([(0, 1.5), (0, 0.5), (0, 0), (0, 0), (0.5, 0), (2.5, 0), (3, 0), (3, 0), (3, 0.5), (3, 1.5)])
    c0, dc0 = _bezier2d([(-2, -2), (4, 8), (5, -8), (12, 1)])

    def p(v):
        v = np.atleast_1d(v)
        a, b = np.tan(np.pi / 8 * np.cos(np.pi * v)), np.pi / 2 + 0.1 * np.sin(np.pi * v)
        return 3 * np.stack([a * np.cos(b), a * np.sin(b)], axis=1)

    def dp(v):
        v = np.atleast_1d(v)
        x = np.pi / 8 * np.cos(np.pi * v)
        a, da = np.tan(x), -(np.pi ** 2 / 8) * np.sin(np.pi * v) / np.cos(x) ** 2
        b, db = np.pi / 2 + 0.1 * np.sin(np.pi * v), 0.1 * np.pi * np.cos(np.pi * v)
        return 3 * np.stack([da * np.cos(b) - a * np.sin(b) * db, da * np.sin(b) + a * np.cos(b) * db], axis=1)

    def c1(v):
        return c0(v) + p(v)

    def dc1(v):
        return dc0(v) + dp(v)
    s0, ds0, s1, ds1 = _spiral()
    return [("1", s0, ds0, s1, ds1, 1e-3, 0.5, 1.0, 7), ("2", b0, db0, b1, db1, 0.06, 0.1, 1.0, 16),
            ("3a", c0, dc0, c1, dc1, 0.2, 0.3, 3.0, 7), ("3b", c0, dc0, c1, dc1, 0.1, 0.1, 3.0, 15)]
