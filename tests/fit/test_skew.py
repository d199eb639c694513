"""The face's straightest direction (ruled.fit.face.skew, issue 58), on engine objects alone: a hyperbolic
paraboloid z = x y written over (u, v) with x = u + v - 1, y = u - v (its rulings the diagonals of the (u, v)
square, none of them an iso line), a diamond-shaped face in it.  The direction found is one of the two
diagonals, and the surface's points along it are collinear (checked by an SVD of dense samples, not by the
code's own score); a surface ruled along its iso lines is not worth a parallelogram."""

from __future__ import annotations

from math import comb

import numpy as np

from ruled.core.nurbs import Curve, Surface
from ruled.core.region import Region
from ruled.fit.face.skew import skew_map, straightest, worth_trying


def _bezier(f, p: int, q: int) -> Surface:
    x, y = np.linspace(0, 1, p + 1), np.linspace(0, 1, q + 1)

    def bern(n, t):
        return np.array([[comb(n, k) * tt ** k * (1 - tt) ** (n - k) for k in range(n + 1)] for tt in t])
    U, V = np.meshgrid(x, y, indexing="ij")
    F = f(U.ravel(), V.ravel()).reshape(p + 1, q + 1, 3)
    P = np.einsum("ia,abk,jb->ijk", np.linalg.inv(bern(p, x)), F, np.linalg.inv(bern(q, y)))
    return Surface(P, [0.0] * (p + 1) + [1.0] * (p + 1), [0.0] * (q + 1) + [1.0] * (q + 1), p, q)


def _diamond(S: Surface) -> Region:
    c = [(0.5, 0.15), (0.8, 0.5), (0.5, 0.85), (0.15, 0.45)]
    loop = tuple(Curve(np.array([c[k], c[(k + 1) % 4]]), np.array([0.0, 0.0, 1.0, 1.0]), 1) for k in range(4))
    return Region(S, loop)


def _hypar(u, v):
    x, y = 30.0 * (u + v - 1.0), 30.0 * (u - v)
    return np.stack([x, y, x * y / 30.0], axis=1)


def _collinear(S: Surface, theta: float) -> float:
    """The largest distance from their best line of the surface's points on the line through (0.5, 0.5) along
    theta (the unit square's own directions), 201 of them across the square's middle."""
    s = np.linspace(-0.3, 0.3, 201)
    uv = 0.5 + np.outer(s, [np.cos(theta), np.sin(theta)])
    X = S(uv[:, 0], uv[:, 1])
    Y = X - X.mean(axis=0)
    d = np.linalg.svd(Y, full_matrices=False)[2][0]
    return float(np.linalg.norm(Y - np.outer(Y @ d, d), axis=1).max())


def test_a_hyperbolic_paraboloid_is_straightest_along_a_diagonal_of_its_domain():
    S = _bezier(_hypar, 2, 2)
    theta, score, iso = straightest(_diamond(S))
    assert min(abs(np.degrees(theta) - 45.0), abs(np.degrees(theta) - 135.0)) < 0.01, np.degrees(theta)
    assert _collinear(S, theta) < 1e-9 and _collinear(S, 0.0) > 1.0 and _collinear(S, np.pi / 2) > 1.0
    assert score < 1e-9 < iso and worth_trying(theta, score, iso)
    # the parallelogram along it covers the face's corners (inside its unit square) with the rails across it
    m = skew_map(_diamond(S), theta)
    st = m.invert(np.array([(0.5, 0.15), (0.8, 0.5), (0.5, 0.85), (0.15, 0.45)]))
    assert np.all(st > 0.0) and np.all(st < 1.0)
    d = np.diff(m.raw([0.5, 0.5], [0.0, 1.0]), axis=0)[0]          # a ruling of the parallelogram: along theta
    assert abs(d[0] * np.sin(theta) - d[1] * np.cos(theta)) < 1e-12 * np.linalg.norm(d)


def test_a_surface_ruled_along_its_iso_lines_is_not_worth_a_parallelogram():
    def sheet(u, v):          # ruled along v exactly: z linear in v for each u, curved across
        return np.stack([40.0 * u, 30.0 * v, 3.0 * np.sin(3.0 * u) * v + 2.0 * u ** 2], axis=1)
    S = _bezier(lambda u, v: sheet(u, v), 9, 1)
    theta, score, iso = straightest(_diamond(S))
    assert not worth_trying(theta, score, iso)
    assert _collinear(S, np.pi / 2) < 1e-6 * 50
