"""Line–surface distance against an independent brute force (dense samples + OCCT projection)."""
import numpy as np
import pytest

from cases import hyperboloid
from ruled.distance import ruling_distances
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
