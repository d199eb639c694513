"""Line–surface distance against an independent brute force (dense samples + OCCT projection)."""
import numpy as np
import pytest
from cases import hyperboloid

from ruled.core.distance import ruling_distances
from ruled.core.nurbs import Surface
from ruled.examples import elber_ex1, elber_ex2

OCP = pytest.importorskip("OCP")


def _brute(S, uP, uQ, closed=False, n_line=60):
    """max over dense points of the segment of the exact distance to S (OCCT projection + dense grid)."""
    from OCP.GeomAPI import GeomAPI_ProjectPointOnSurf
    from OCP.gp import gp_Pnt

    from ruled.occ.convert import container_to_bspline
    bs = container_to_bspline(S)
    u0, u1, v0, v1 = S.domain
    gu, gv = np.meshgrid(np.linspace(u0, u1, 200), np.linspace(v0, v1, 200), indexing="ij")
    G = S(gu.ravel(), gv.ravel())
    out = []
    for a, b in zip(uP, uQ):
        P = S(np.array([a]), np.array([v0]))[0]
        Q = S(np.array([b % (u1 - u0) if closed else b]), np.array([v1]))[0]
        worst = 0.0
        for t in np.linspace(0, 1, n_line):
            X = P + t * (Q - P)
            d = np.linalg.norm(G - X, axis=1).min()
            pr = GeomAPI_ProjectPointOnSurf(gp_Pnt(*X), bs, u0, u1, v0, v1)
            if pr.NbPoints() > 0:
                d = min(d, pr.LowerDistance())
            worst = max(worst, d)
        out.append(worst)
    return np.array(out)


@pytest.mark.parametrize("make", [elber_ex1, elber_ex2])
def test_ruling_distance_close_to_brute_force(make, rng):
    S = make()
    uP = rng.uniform(0, 1, 12)
    uQ = rng.uniform(0, 1, 12)
    ub, d = ruling_distances(S, uP, uQ, 31, 6)
    ref = _brute(S, uP, uQ)
    assert (d <= ub + 1e-15).all()
    # both are sampled maxima of the one-sided distance: they agree to the sampling resolution
    assert np.all(np.abs(d - ref) <= 0.01 * ref.max())
    assert np.all(ub >= ref - 0.01 * ref.max())


def test_exact_rulings_of_hyperboloid_have_zero_distance():
    S = hyperboloid()
    x = np.linspace(0, 1, 41)[:-1]
    _, d = ruling_distances(S, x, x + 0.25, 15, 4, True)
    assert d.max() < 1e-9
    _, d2 = ruling_distances(S, x, x - 0.25, 15, 4, True)
    assert d2.max() < 1e-9
    # a non-ruling (iso-parametric line of the revolution surface) is far from the surface
    _, d3 = ruling_distances(S, x, x, 15, 4, True)
    assert d3.min() > 0.1


def test_the_measure_finds_the_nearest_point_where_the_face_folds_at_a_crease():
    """Found by the fuzz test: a face folding back at its creases (degree 2 across them, knots of full
    multiplicity), far from the origin.  OCCT's extrema and a local search from the nearest seed both
    stop on the wrong sheet; measured against itself it read 0.18.  The local searches from several seeds
    and from either side of each crease find the nearest point: the distance is round-off."""
    from ruled.occ.convert import container_to_face
    from ruled.occ.measure import hausdorff
    P = np.array([[[-1.3852, -8.9737, 4.2275], [-3.503, 16.0495, 6.202]],
                  [[0.3133, -12.5721, 2.9011], [-5.4852, 6.1879, 0.7171]],
                  [[-7.4163, -2.9969, -4.5002], [-5.544, 6.1345, -2.0093]],
                  [[1.4578, -9.0196, 0.472], [-2.2848, -0.256, -0.077]],
                  [[-4.0144, -4.0518, 0.4577], [3.6141, 11.1825, 1.7401]],
                  [[-2.4218, -10.5018, 0.5623], [0.684, 9.2002, -1.5922]],
                  [[-0.8414, -4.9564, -2.0135], [4.2152, 5.5238, 8.2566]],
                  [[4.2863, -6.5319, 1.9286], [6.7872, 9.8023, -3.6012]],
                  [[3.9529, -12.2651, 7.8346], [5.4276, 11.3656, -5.2204]],
                  [[6.1853, -9.6285, 0.4894], [-4.0273, 6.3076, -16.7753]]]) + [70000.0, 17800.0, 111000.0]
    ku = [0, 0, 0, 0.00982, 0.01229, 0.01229, 0.02168, 0.02168, 0.02455, 0.03086, 0.0363, 0.0363, 0.0363]
    S = Surface(P, np.array(ku), np.array([0, 0, 0.67737, 0.67737]), 2, 1)
    h = hausdorff(container_to_face(S), container_to_face(S), 16)
    assert h.max <= 1e-9 * S.diagonal(), h


def test_the_measure_states_its_sampling_error_and_keeps_within_it():
    """Issue 22, point 2: the measure is a sampled maximum, so it can only miss a peak between its
    samples, and by at most its stated resolution (the largest gap between neighbouring samples: the
    distance is 1-Lipschitz).  A plane against a sharp bump whose top falls between the samples."""
    from ruled.occ.convert import container_to_face
    from ruled.occ.measure import hausdorff
    k = [0, 0, 0, 0, 1, 1, 1, 1]
    x, y = np.meshgrid(np.linspace(0, 1, 4), np.linspace(0, 1, 4), indexing="ij")
    plane = Surface(np.stack([x, y, 0 * x], 2), k, k, 3, 3)
    n = 15
    kn = np.concatenate([[0] * 4, np.linspace(0, 1, n - 2)[1:-1], [1] * 4])
    X, Y = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n), indexing="ij")
    Z = np.zeros((n, n))
    Z[7, 7] = 0.05
    bump = Surface(np.stack([X, Y, Z], 2), kn, kn, 3, 3)
    U, V = np.meshgrid(np.linspace(0, 1, 2001), np.linspace(0, 1, 2001), indexing="ij")
    true = float(bump(U.ravel(), V.ravel())[:, 2].max())     # the bump's top over the plane
    for m in (8, 12, 20):
        h = hausdorff(container_to_face(plane), container_to_face(bump), m)
        assert h.max <= true + 1e-12 and true <= h.max + h.resolution, (m, h, true)
        # about a cell's diagonal (the bump's clamped parametrization stretches its end cells), not loose
        assert np.sqrt(2) / (m - 1) <= h.resolution <= 2 * np.sqrt(2) / (m - 1)
