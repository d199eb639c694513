"""A wall's closed result certified as a whole, one way at a time (ruled.fit.certify.onesided), on the drafted hole
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
