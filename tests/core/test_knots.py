"""Knot insertion and segments leave the curve unchanged (evaluation before/after)."""
import numpy as np
from cases import hyperboloid, random_surface

from ruled.core.knots import clamp_segment, insert_knot, knot_multiplicity, span_bezier
from ruled.core.nurbs import Curve


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


def test_span_bezier_matches_clamped_segments():

    rng = np.random.default_rng(3)
    for p in (1, 2, 3, 5):
        n = p + 6
        knots = np.concatenate([np.zeros(p + 1), np.sort(rng.uniform(0, 1, n - p - 1)), np.ones(p + 1)])
        knots[p + 2] = knots[p + 3]             # a double knot
        C = Curve(rng.normal(size=(n, 2)), knots, p, rng.uniform(0.5, 2, n))
        for i in range(p, n):
            if knots[i] == knots[i + 1]:
                continue
            ref = clamp_segment(C, knots[i], knots[i + 1])._hom
            assert np.abs(span_bezier(C._hom, knots, p, i) - ref).max() <= 1e-12
