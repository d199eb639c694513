"""Elber's test surfaces (from his ruledfit script) and other built-in examples."""

from __future__ import annotations

import numpy as np

from .nurbs import Curve, Surface

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


EXAMPLES = {"ex1": elber_ex1, "ex2": elber_ex2}


# Yang et al. 2008, first example: a biquadratic Bézier patch (P_ij, i along u, j along v) and a
# quadratic Bézier domain curve
YANG_NET = [[(0, 2, -1), (2.5, 1, 0), (1, 0, 1.5)],
            [(1, 1, -2), (1, 0, -0.5), (2.5, -1, 0)],
            [(1, 0, -3), (1, -1, -2), (-0.51, -2, -1)]]
YANG_CURVE = [(0.1, 0.1), (0.5, 1.8), (0.8, 0.1)]


def yang_surface() -> Surface:
    return Surface(np.array(YANG_NET, dtype=float), [0, 0, 0, 1, 1, 1], [0, 0, 0, 1, 1, 1], 2, 2)


def yang_curve() -> Curve:
    return Curve(np.array(YANG_CURVE, dtype=float), [0, 0, 0, 1, 1, 1], 2)
