"""Test surfaces built exactly in plain arrays (no engine code beyond the container)."""

from __future__ import annotations

from math import comb

import numpy as np

from ruled.core.nurbs import Surface

CIRCLE_KNOTS = np.array([0, 0, 0, .25, .25, .5, .5, .75, .75, 1, 1, 1], float)


def _circle_poles():
    P = np.array([[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1], [1, 0]], float)
    w = np.array([1, np.sqrt(.5), 1, np.sqrt(.5), 1, np.sqrt(.5), 1, np.sqrt(.5), 1])
    return P, w


def _revolution(prof: np.ndarray, pw: np.ndarray) -> Surface:
    """The rational quadratic profile (r, z) with weights pw turned around the z axis (u: angle)."""
    cp, cw = _circle_poles()
    poles = np.zeros((9, 3, 3))
    weights = np.zeros((9, 3))
    for i in range(9):
        for j in range(3):
            r, z = prof[j]
            poles[i, j] = (r * cp[i, 0], r * cp[i, 1], z)
            weights[i, j] = cw[i] * pw[j]
    return Surface(poles, CIRCLE_KNOTS, [0, 0, 0, 1, 1, 1], 2, 2, weights)


def hyperboloid(a: float = 1.0, c: float = 1.0, zmax: float = 1.0) -> Surface:
    """One-sheet hyperboloid x^2/a^2 + y^2/a^2 - z^2/c^2 = 1 as a surface of revolution.

    u: angle (closed, rational circle), v: the hyperbola profile (rational quadratic conic)
    from z = -zmax to z = zmax.  Every point lies on two straight lines that climb around the axis.
    """
    W = np.arcsinh(zmax / c)
    prof = np.array([[a * np.cosh(W), -c * np.sinh(W)], [a / np.cosh(W), 0.0], [a * np.cosh(W), c * np.sinh(W)]])
    pw = np.array([1.0, np.cosh(W), 1.0])
    return _revolution(prof, pw)


def _bernstein(n, x):
    x = np.asarray(x, float)
    return np.stack([comb(n, k) * x ** k * (1 - x) ** (n - k) for k in range(n + 1)], axis=-1)


def bezier_interpolant(f, pu: int, pv: int) -> Surface:
    """The Bézier surface of degree (pu, pv) interpolating f(u, v) -> (.., 3) at Chebyshev nodes.

    Exact (to round-off) when f is a polynomial of at most that degree."""
    xu = 0.5 - 0.5 * np.cos(np.pi * (np.arange(pu + 1) + 0.5) / (pu + 1))
    xv = 0.5 - 0.5 * np.cos(np.pi * (np.arange(pv + 1) + 0.5) / (pv + 1))
    Bu = _bernstein(pu, xu)
    Bv = _bernstein(pv, xv)
    UU, VV = np.meshgrid(xu, xv, indexing="ij")
    F = f(UU, VV)  # (pu+1, pv+1, 3)
    P = np.einsum("ia,jb,abc->ijc", np.linalg.inv(Bu), np.linalg.inv(Bv), F)
    return Surface(P, [0] * (pu + 1) + [1] * (pu + 1), [0] * (pv + 1) + [1] * (pv + 1), pu, pv)


def twisted_blade(twist_deg: float = 40.0, length: float = 3.0, width: float = 1.0) -> Surface:
    """A ruled blade (Bézier, degree 9 x 1): rulings of length `width` across it, turning by twist_deg about its
    length (x) from one end to the other, its middle line bowed by a tenth of the width."""
    def f(u, v):
        th = np.radians(twist_deg) * (u - 0.5)
        w = (v - 0.5) * width
        return np.stack([length * u, w * np.cos(th), w * np.sin(th) + 0.1 * width * np.sin(np.pi * u)], axis=-1)
    return bezier_interpolant(f, 9, 1)


def bumped_twist(twist_deg: float = 15.0, bump: float = 0.05, sigma: float = 0.3, length: float = 3.0,
                 width: float = 1.0) -> Surface:
    """A twisted ruled strip (rulings `width` long across x, turning by twist_deg over `length`) with a Gaussian
    bump of height `bump` (standard deviation sigma in the unit parameters) along its normal in the middle: not
    ruled (Bézier interpolant, degree 10 x 8: within 4e-6 of it)."""
    def f(u, v):
        th = np.radians(twist_deg) * (u - 0.5)
        w = (v - 0.5) * width
        P = np.stack([length * u, w * np.cos(th), w * np.sin(th)], axis=-1)
        n = np.stack([np.zeros_like(u), -np.sin(th), np.cos(th)], axis=-1)
        g = bump * np.exp(-((u - 0.5) ** 2 + (v - 0.5) ** 2) / (2 * sigma ** 2))
        return P + g[..., None] * n
    return bezier_interpolant(f, 10, 8)


def _cubic(P):
    P = np.asarray(P, float)
    return lambda s: np.einsum("...k,kc->...c", _bernstein(3, s), P)


A_CURVE = [(0, 0, 0), (1, 0.6, 0.2), (2, -0.4, 0.1), (3, 0.2, 0)]
B_CURVE = [(0.2, 0.3, 2), (1.1, -0.5, 2.4), (2.2, 0.8, 1.8), (3.3, 0.1, 2.1)]


def reparametrized_ruled(gamma: float = 0.5) -> Surface:
    """An exactly ruled surface whose iso-u lines cross the rulings.

    R(s, t) = (1 - t) A(s) + t B(s) with cubic A, B; S(u, v) = R(u + gamma v u (1 - u), v).
    S(u, 0) = A(u) and S(u, 1) = B(h(u)), h(u) = u + gamma u (1 - u): the rulings pair u on the
    first boundary with h^-1(u) on the second, and are curved lines in the (u, v) domain.
    Degree (6, 4), exact."""
    A, B = _cubic(A_CURVE), _cubic(B_CURVE)

    def f(u, v):
        s = u + gamma * v * u * (1 - u)
        return (1 - v)[..., None] * A(s) + v[..., None] * B(s)
    return bezier_interpolant(f, 6, 4)


def random_surface(rng, pu=3, pv=2, nu=7, nv=5, rational=True, periodic_u=False) -> Surface:
    """A random (rational, optionally u-periodic) B-spline surface in the container's layout."""
    from ruled.core.basis import periodic_knots, wrap_periodic_poles
    kv = np.concatenate([np.zeros(pv + 1), np.sort(rng.uniform(0.05, 0.95, nv - pv - 1)), np.ones(pv + 1)])
    if periodic_u:
        m = nu
        br = np.concatenate([[0.0], np.sort(rng.uniform(0.05, 0.95, m - 1)), [1.0]])
        ku = periodic_knots(br * 2.0 + 0.5, pu)
        uniq = rng.normal(size=(m, nv, 3))
        P = wrap_periodic_poles(uniq, pu)
        W = wrap_periodic_poles(rng.uniform(0.5, 2.0, (m, nv)), pu) if rational else None
    else:
        ku = np.concatenate([np.zeros(pu + 1), np.sort(rng.uniform(0.05, 0.95, nu - pu - 1)), np.ones(pu + 1)])
        P = rng.normal(size=(nu, nv, 3))
        W = rng.uniform(0.5, 2.0, (nu, nv)) if rational else None
    return Surface(P, ku, kv, pu, pv, W, periodic_u=periodic_u)


def wavy_sheet(rng, rational: bool = False) -> Surface:
    """A random doubly curved sheet about 5 x 3 (a grid of poles with random offsets of 0.4): random
    faces a CAD user could meet, unlike random_surface's tangles."""
    nu, nv, pu, pv = 6, 4, 3, 2
    X, Y = np.meshgrid(np.linspace(0, 5, nu), np.linspace(0, 3, nv), indexing="ij")
    P = np.stack([X, Y, np.zeros_like(X)], axis=2) + rng.normal(scale=0.4, size=(nu, nv, 3))
    ku = np.concatenate([np.zeros(pu + 1), np.sort(rng.uniform(0.2, 0.8, nu - pu - 1)), np.ones(pu + 1)])
    kv = np.concatenate([np.zeros(pv + 1), np.sort(rng.uniform(0.2, 0.8, nv - pv - 1)), np.ones(pv + 1)])
    W = rng.uniform(0.8, 1.25, (nu, nv)) if rational else None
    return Surface(P, ku, kv, pu, pv, W)


def nearly_closed_strip(gap: float = 1e-3, width: float = 0.02) -> Surface:
    """A narrow strip S(u, v) = C(v) + u w(v) along a curve C that almost closes on itself.

    The v-min and v-max boundaries are short and nearly coincident: rulings joining them lie
    on the surface (one-sided cost about zero) but leave the whole strip uncovered.  Along u the
    strip is exactly ruled.  Degree (1, 3), exact."""
    th = np.linspace(0.0, 2 * np.pi - gap, 12)
    C = np.stack([np.cos(th), np.sin(th), 0.2 * np.sin(2 * th)], axis=1)
    W = np.stack([np.zeros_like(th), np.zeros_like(th), np.full_like(th, width)], axis=1)
    P = np.stack([C, C + W], axis=0)  # (2, 12, 3): u is the width, v runs along the loop
    kv = np.concatenate([[0, 0, 0, 0], np.linspace(0, 1, 10)[1:-1], [1, 1, 1, 1]])
    return Surface(P, [0, 0, 1, 1], kv, 1, 3)


def barrel(bulge: float = 0.2, height: float = 2.0) -> Surface:
    """A closed, doubly curved surface of revolution: the parabola profile r(v) from 1 at both ends to
    1 + bulge/2 at mid height, around the z axis (u: angle, rational circle).  Not ruled."""
    prof = np.array([[1.0, -0.5 * height], [1.0 + bulge, 0.0], [1.0, 0.5 * height]])
    return _revolution(prof, np.ones(3))


def bumped_cone() -> Surface:
    """A quarter of the cone r = 10 - z (45-degree rulings) for z in [0, 3], its two middle rows of
    poles pushed out by 0.02: not ruled, close to a developable."""
    th = np.linspace(0, np.pi / 2, 6)
    rows = []
    for i, z in enumerate(np.linspace(0, 3, 4)):
        r = 10 - z + (0.02 if i in (1, 2) else 0.0)
        rows.append(np.column_stack([r * np.cos(th), r * np.sin(th), np.full_like(th, z)]))
    return Surface(np.array(rows), [0, 0, 0, 0, 1, 1, 1, 1], [0, 0, 0, 0, 1 / 3, 2 / 3, 1, 1, 1, 1], 3, 3)
