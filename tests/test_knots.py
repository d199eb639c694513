"""Knot insertion and segments leave the curve unchanged (evaluation before/after)."""
import numpy as np

from cases import hyperboloid, random_surface
from ruled.knots import clamp_segment, insert_knot, knot_multiplicity


def test_insert_and_segment_are_exact(rng):
    for C in (hyperboloid().iso_curve("u", 0.0), random_surface(rng).iso_curve("u", 0.3)):
        t = np.linspace(*C.domain, 201)
        D = insert_knot(C, 0.37, 2)
        assert knot_multiplicity(D.knots, 0.37) == 2
        assert np.abs(D(t) - C(t)).max() < 1e-13
        for a, b in ((0.3, 0.8), (0.0, 0.6), (0.25, 1.0), (0.1, 0.25)):
            E = clamp_segment(C, a, b)
            tt = np.linspace(a, b, 50)
            assert E.domain == (a, b)
            assert np.abs(E(tt) - C(tt)).max() < 1e-13
