"""What a wire cuts, from its lines alone (ruled.machine.wirecut): the nearest point of the swept surface against
brute force where the path twists (the nearest lines need not bracket the nearest point), and the sides of a closed
loop whose path folds back on itself (a swept normal turns over there: the winding number does not)."""

import numpy as np


def _brute(lower, upper, X, fractions=4001, along=4001):
    """The distance from each X to the lines across every move, on a dense grid of fractions and wire points."""
    s = np.linspace(0.0, 1.0, fractions)[:, None, None]
    t = np.linspace(0.0, 1.0, along)[None, :, None]
    best = np.full(len(X), np.inf)
    for m in range(1, len(lower)):
        a = lower[m - 1] + s * (lower[m] - lower[m - 1])
        b = upper[m - 1] + s * (upper[m] - upper[m - 1])
        P = (a + t * (b - a)).reshape(-1, 3)
        for i, x in enumerate(X):
            best[i] = min(best[i], float(np.sqrt(((P - x) ** 2).sum(axis=1)).min()))
    return best


def test_the_nearest_point_of_a_twisting_sweep_is_found_where_the_nearest_lines_miss_it():
    """A path whose wire sweeps through a point in one long move while five short moves crowd 0.38 from it (as
    at a crossed corner of a wall's fit: the nearest lines need not bracket the nearest point): swept_nearest
    within the brute force's grid of it (and its golden sections' 1e-8), at that point and at random ones."""
    from ruled.machine.wirecut import swept_nearest
    rng = np.random.default_rng(11)
    xy = [(0.9, 0.45), (0.7, 0.4), (0.6, 0.38), (0.5, 0.4), (0.3, 0.45), (-1.3, 0.0), (1.3, 0.0), (100.0, 100.0)]
    lower = np.array([(x, y, 0.0) for x, y in xy])
    upper = np.array([(x, y, 2.0) for x, y in xy])
    X = np.vstack([[[0.6, 0.0, 1.0]], rng.normal(scale=0.5, size=(12, 3)) + [0.5, 0.2, 1.0]])
    d, q, m, s = swept_nearest(lower, upper, np.arange(1, len(lower)), X)
    ref = _brute(lower[:-1], upper[:-1], X, 1301, 201)       # (the far move: no nearest point there)
    assert np.all(d <= ref + 1e-8) and np.all(d >= ref - 2.6 / 1300), np.c_[d, ref]
    assert np.allclose(np.linalg.norm(q - X, axis=1), d)
    assert d[0] <= 1e-8 and m[0] == 6, (d[0], m[0])
    # the premise: every line of the path lies 0.38 or more from the point
    assert np.linalg.norm(lower[:, :2] - X[0, :2], axis=1).min() >= 0.38


def test_a_folded_loop_round_a_box_leaves_the_kerf_and_its_margin_and_cuts_nothing():
    """A square wire loop round a box 10 x 10 x 5 at the kerf plus 0.05 off its sides, upright, the path
    doubling back on itself once along a side (as at a crossed corner's crease): every design point is 0.05
    from the cut (material left), none cut past, by the measure's own figures."""
    import cadquery as cq

    from ruled.machine.wirecut import wire_cut
    from ruled.occ.wirecut import FacesTarget
    kerf, margin = 0.15, 0.05
    d = kerf + margin
    box = cq.Workplane("XY").box(10, 10, 5, centered=False).val()
    sides = [f.wrapped for f in box.Faces() if abs(f.normalAt().z) < 0.5]
    xy = [(-d, -d), (4.0, -d), (6.0, -d), (5.0, -d), (10 + d, -d), (10 + d, 10 + d), (-d, 10 + d), (-d, -d)]
    lower = np.array([(x, y, -1.0) for x, y in xy])
    upper = np.array([(x, y, 6.0) for x, y in xy])
    got = wire_cut(FacesTarget(sides, 1.0, "the box"), lower, upper, np.arange(1, len(lower)), 12, kerf)
    assert got["overcut"] <= 1e-9, got["overcut_at"]
    assert abs(got["design_to_cut"] - margin) <= 1e-6 and abs(got["undercut"] - margin) <= 1e-6, got
