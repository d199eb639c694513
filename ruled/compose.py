"""Exact composition of a domain line segment with a (rational) B-spline surface (Yang et al. 2008, §5).

A segment l(t) = (1 - t) a + t b, t in [0, 1], inside one knot-span rectangle of
S(u, v) maps to the Bézier curve S(l(t)) of degree p + q that lies on S exactly.
Blossoming gives it without any fitting: restricted to the rectangle spanned
by a and b, the patch has the Bézier net Q_kl (blossom values
S(a_u^{p-k} b_u^k ; a_v^{q-l} b_v^l)), and along the rectangle's diagonal

    B_k^p(t) B_l^q(t) = C(p, k) C(q, l) / C(p + q, k + l) B_{k+l}^{p+q}(t),

so the curve's control points are R_m = sum_{k+l=m} C(p,k) C(q,l) / C(p+q,m) Q_kl,
in homogeneous coordinates for rational surfaces.
"""

from __future__ import annotations

from math import comb

import numpy as np

from .errors import BadInputError
from .knots import span_bezier
from .nurbs import Curve, Surface, find_spans


def restrict_matrices(p: int, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Stacked matrices R (N, p + 1, p + 1): the Bernstein coefficients of a degree-p polynomial on
    [a, b] are R @ its coefficients on [0, 1] (a > b reverses, a = b collapses).  Blossoming: row
    k is the blossom at (a repeated p - k times, b k times)."""
    a = np.atleast_1d(np.asarray(a, float))
    b = np.atleast_1d(np.asarray(b, float))
    c = np.broadcast_to(np.eye(p + 1), (a.shape[0], p + 1, p + 1, p + 1)).copy()   # (n, k, control, basis)
    ks = np.arange(p + 1)
    for r in range(p):
        x = np.where(r < p - ks[None, :], a[:, None], b[:, None])[:, :, None, None]
        c = (1 - x) * c[:, :, :-1] + x * c[:, :, 1:]
    return c[:, :, 0, :]


_DIAG: dict = {}


def _diagonal(p: int, q: int) -> np.ndarray:
    """C (p + q + 1, p + 1, q + 1): R_m = sum_kl C[m, k, l] Q_kl along the diagonal of a patch."""
    C = _DIAG.get((p, q))
    if C is None:
        C = np.zeros((p + q + 1, p + 1, q + 1))
        for k in range(p + 1):
            for m in range(q + 1):
                C[k + m, k, m] = comb(p, k) * comb(q, m) / comb(p + q, k + m)
        _DIAG[(p, q)] = C
    return C


def span_patch(S: Surface, u: float, v: float):
    """The Bézier patch of the knot span containing (u, v): (homogeneous net (p+1, q+1, 4),
    (u_lo, u_hi), (v_lo, v_hi))."""
    pu, pv = S.degree_u, S.degree_v
    nu, nv = S.poles.shape[:2]
    iu = int(find_spans(S.knots_u, pu, nu, np.array([u]))[0])
    iv = int(find_spans(S.knots_v, pv, nv, np.array([v]))[0])
    ua, ub = S.knots_u[iu], S.knots_u[iu + 1]
    va, vb = S.knots_v[iv], S.knots_v[iv + 1]
    rows = span_bezier(S._hom, S.knots_u, pu, iu)                          # (pu + 1, nv, 4)
    net = span_bezier(rows.transpose(1, 0, 2), S.knots_v, pv, iv).transpose(1, 0, 2)
    return net, (float(ua), float(ub)), (float(va), float(vb))


def sandwich(Ru: np.ndarray, net: np.ndarray, Rv: np.ndarray) -> np.ndarray:
    """Ru @ net @ Rv^T per patch and coordinate: (N, a, i), (N, i, j, k), (N, b, j) -> (N, a, b, k), summed
    in order (as the numba kernels do)."""
    X = np.zeros((net.shape[0], Ru.shape[1], net.shape[2], net.shape[3]))
    for i in range(net.shape[1]):
        X += Ru[:, :, i, None, None] * net[:, None, i]
    out = np.zeros((net.shape[0], Ru.shape[1], Rv.shape[1], net.shape[3]))
    for j in range(net.shape[2]):
        out += X[:, :, None, j] * Rv[:, None, :, j, None]
    return out


def compose_stack(nets: np.ndarray, lo: np.ndarray, hi: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Homogeneous Bézier control points (N, p + q + 1, 4) of the images of the segments a -> b (N, 2)
    under the Bézier patches with homogeneous nets (N, p + 1, q + 1, 4) over [lo, hi] (N, 2)."""
    p, q = nets.shape[1] - 1, nets.shape[2] - 1
    sa = (a - lo) / (hi - lo)
    sb = (b - lo) / (hi - lo)
    Q = sandwich(restrict_matrices(p, sa[:, 0], sb[:, 0]), nets, restrict_matrices(q, sa[:, 1], sb[:, 1]))
    C = _diagonal(p, q)
    return np.tensordot(Q, C, axes=([1, 2], [1, 2])).transpose(0, 2, 1)


def compose_segment(S: Surface, a, b) -> Curve:
    """The exact image S(l(t)) of the domain segment from a = (u, v) to b as a Bézier curve of
    degree p + q (rational when S is).  The segment must lie in one knot-span rectangle."""
    a = np.asarray(a, float)
    b = np.asarray(b, float)
    mid = 0.5 * (a + b)
    net, (ua, ub), (va, vb) = span_patch(S, mid[0], mid[1])
    tol = 1e-12 * max(ub - ua, vb - va, 1.0)
    for x, lo, hi in ((a[0], ua, ub), (b[0], ua, ub), (a[1], va, vb), (b[1], va, vb)):
        if x < lo - tol or x > hi + tol:
            raise BadInputError(f"the segment {a.tolist()} -> {b.tolist()} crosses a knot line of the surface; "
                                f"split it at the knots first")
    p, q = S.degree_u, S.degree_v
    R = compose_stack(net[None], np.array([[ua, va]]), np.array([[ub, vb]]), a[None], b[None])[0]
    d = p + q
    knots = np.concatenate([np.zeros(d + 1), np.ones(d + 1)])
    w = R[:, 3]
    return Curve(R[:, :3] / w[:, None], knots, d, None if S.weights is None else w)
