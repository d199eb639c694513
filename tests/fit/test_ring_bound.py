"""Rulings paired anew across a wall's corners (ruled.fit.wall.corners), their pieces against brute force; and a
wall's closed result certified as a whole, one way at a time (ruled.fit.certify.onesided), on the drafted hole
of a die (tests/wall_parts.py): its joint at each sharp corner bows 0.0025 off the corner line, where the pieces'
own certificates send it, while its points lie 0.00098 from the result past the corner.  Each direction's bound
against OCCT's measure of that direction alone (ruled.occ.wall.measure_wall: the wall's faces and edges, the
result's corner rulings densely, projected by OCCT onto the other side)."""

from __future__ import annotations

import pytest

pytest.importorskip("OCP")
pytest.importorskip("cadquery")


@pytest.mark.slow
def test_each_way_of_a_die_holes_ring_bound_covers_its_measure_within_twice_it():
    from wall_parts import die_block

    from ruled.fit.certify.onesided import result_to_wall, wall_to_result
    from ruled.fit.options import FitOptions
    from ruled.fit.wall.fit import clamped_u, fit_ring, remapped, smooth_parts
    from ruled.occ.convert import container_to_face
    from ruled.occ.wall import measure_wall, wall_of
    w = wall_of(die_block().wrapped, "hole")
    ring = fit_ring(w.surface, w.breaks, w.corners, FitOptions(), w.size)
    own = max(r.error_bound for r in ring.results)
    R = remapped(clamped_u(ring.surface), 0.0, 1.0, *ring.surface.domain[2:])
    fwd = wall_to_result(w.surface, R, smooth_parts(R, ranges=True, unit=True))
    rev = result_to_wall(w.surface, smooth_parts(w.surface, ranges=True), R)
    h = measure_wall(w.faces, container_to_face(ring.surface), 40)
    # the wall's faces lie within the wall's slack of its joined surface, which the job adds
    assert h.max_a_to_b <= fwd + w.slack and h.max_b_to_a <= rev + w.slack, (fwd, rev, h)
    assert fwd <= 2 * h.max_a_to_b and rev <= 2 * h.max_b_to_a, (fwd, rev, h)
    assert ring.bound <= max(fwd, rev) * (1 + 1e-9) + 1e-9 * w.size and ring.bound < 0.6 * own
    assert own > 2 * h.max                                    # (the premise: the pieces' own bound is the bow)


def test_a_curve_composed_with_a_piecewise_linear_map_is_that_composition_exactly():
    """ruled.fit.wall.corners.composed against C(tau(x)) evaluated pointwise, tau through breaks that cross the
    curve's seam both ways (a closed curve: a value past 1 is a period on)."""
    import numpy as np

    from ruled.core.nurbs import Curve
    from ruled.fit.wall.corners import composed
    rng = np.random.default_rng(5)
    P = rng.normal(size=(9, 3))
    P[-1] = P[0]                                       # closed
    C = Curve(P, np.array([0, 0, 0, 0, 0.2, 0.35, 0.5, 0.7, 0.85, 1, 1, 1, 1.0]), 3)
    for xs, ys in (([0, 0.3, 0.4, 0.5, 1], [0, 0.3, 0.45, 0.5, 1]),
                   ([0, 0.1, 0.9, 1], [0.05, 0.1, 0.9, 1.05]),
                   ([0, 0.1, 0.9, 1], [-0.04, 0.1, 0.9, 0.96])):
        G = composed(C, np.array(xs, float), np.array(ys, float))
        x = np.linspace(0, 1, 1001)
        tau = np.mod(np.interp(x, xs, ys), 1.0)
        assert np.abs(G(x) - C(tau)).max() <= 1e-12 * np.abs(P).max(), (xs, ys)


def test_the_bottleneck_pairing_is_the_best_of_every_monotone_path():
    """ruled.fit.wall.corners._bottleneck against every monotone path of small random cost tables."""
    import itertools

    import numpy as np

    from ruled.fit.wall.corners import STEPS, _bottleneck

    def paths(i, j, n, m):
        if (i, j) == (n - 1, m - 1):
            yield [(i, j)]
            return
        for di, dj in STEPS:
            if i + di < n and j + dj < m:
                for rest in paths(i + di, j + dj, n, m):
                    yield [(i, j)] + rest
    rng = np.random.default_rng(3)
    for n, m in itertools.product((2, 3, 4, 5), (2, 3, 4, 5)):
        C = rng.random((n, m))
        if not any(True for _ in paths(0, 0, n, m)):
            continue
        got = _bottleneck(C)
        best = min((max(C[p] for p in path), sum(C[p] for p in path)) for path in paths(0, 0, n, m))
        assert (max(C[p] for p in got), sum(C[p] for p in got)) == best
        assert got[0] == (0, 0) and got[-1] == (n - 1, m - 1)
