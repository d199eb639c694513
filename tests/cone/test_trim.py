"""A region cut to strips (ruled.cone.trim.strip_regions), checked by brute force: points in the strip are inside
the region exactly when they are inside one of the pieces (each piece's outer loop less its holes), for loops
that cross the strip's lines many times, holes that cross them and holes inside."""

import numpy as np
import pytest

from ruled.cone.trim import loop_curves, oriented, strip_regions
from ruled.core.region import crossings_odd


def _star(n: int, r0: float, r1: float, centre=(0.0, 0.0), turns: int = 7, phase: float = 0.0) -> np.ndarray:
    t = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
    r = r0 + r1 * np.sin(turns * t + phase)
    return np.stack([centre[0] + r * np.cos(t), centre[1] + r * np.sin(t)], axis=1)


def _inside(loops, X) -> np.ndarray:
    odd = np.zeros(len(X), bool)
    for P, _ in loops:
        odd ^= crossings_odd(P, X)
    return odd


@pytest.mark.parametrize("a, b", [(-0.3, 0.25), (-2.0, -0.5), (0.1, 0.11), (-5.0, 5.0)])
def test_strip_regions_are_the_region_in_the_strip(a, b):
    rng = np.random.default_rng(7)
    outer = _star(400, 1.0, 0.45)
    hole_across = _star(200, 0.18, 0.05, centre=(0.0, 0.05), turns=5)       # crosses the lines of the strips
    hole_inside = _star(100, 0.05, 0.01, centre=(0.6, 0.0), turns=3)
    loops = oriented([(P, np.zeros(len(P), bool)) for P in (outer, hole_across, hole_inside)])
    regions = strip_regions(loops, a, b, 0)
    X = rng.uniform(-1.6, 1.6, size=(40000, 2))
    X = X[(X[:, 0] > a + 1e-9) & (X[:, 0] < b - 1e-9)]
    want = _inside(loops, X)
    got = np.zeros(len(X), bool)
    for reg in regions:
        inside = _inside(reg, X)
        assert not np.any(got & inside)            # the pieces do not overlap
        got |= inside
        P, c = reg[0]
        assert np.all(P[:, 0] >= a - 1e-12) and np.all(P[:, 0] <= b + 1e-12)
        # the piece's outer loop runs counter-clockwise, its holes clockwise
        area = 0.5 * np.sum(P[:, 0] * np.roll(P[:, 1], -1) - np.roll(P[:, 0], -1) * P[:, 1])
        assert area > 0
    assert np.array_equal(got, want), int(np.sum(got != want))
    if a < -4:
        assert len(regions) == 1 and len(regions[0]) == 3     # the whole region, both holes
    # each loop becomes curves between its corners that join end to end
    for reg in regions:
        for P, c in reg:
            curves = loop_curves(P, c)
            ends = [(cv(np.array([cv.domain[0]]))[0], cv(np.array([cv.domain[1]]))[0]) for cv in curves]
            for (_, e), (s, _) in zip(ends, ends[1:] + ends[:1]):
                assert np.linalg.norm(e - s) <= 1e-12


def test_a_strip_the_region_misses_gives_nothing():
    outer = _star(100, 1.0, 0.2)
    loops = oriented([(outer, np.zeros(len(outer), bool))])
    assert strip_regions(loops, 3.0, 4.0, 0) == []
