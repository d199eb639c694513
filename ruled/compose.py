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
from .knots import clamp_segment
from .nurbs import Curve, Surface, find_spans


def _blossom_net(b: np.ndarray, x0: float, x1: float) -> np.ndarray:
    """Bézier control points (axis 0) of the same polynomial on [x0, x1] (x0 > x1 reverses it, x0 = x1
    collapses it), by blossoming: point k is the blossom at (x0 repeated p - k times, x1 k times)."""
    p = b.shape[0] - 1
    out = np.empty_like(b)
    for k in range(p + 1):
        c = b.copy()
        for r in range(p):
            x = x0 if r < p - k else x1
            c = (1.0 - x) * c[:-1] + x * c[1:]
        out[k] = c[0]
    return out


def span_patch(S: Surface, u: float, v: float):
    """The Bézier patch of the knot span containing (u, v): (homogeneous net (p+1, q+1, 4),
    (u_lo, u_hi), (v_lo, v_hi))."""
    pu, pv = S.degree_u, S.degree_v
    nu, nv = S.poles.shape[:2]
    iu = int(find_spans(S.knots_u, pu, nu, np.array([u]))[0])
    iv = int(find_spans(S.knots_v, pv, nv, np.array([v]))[0])
    ua, ub = S.knots_u[iu], S.knots_u[iu + 1]
    va, vb = S.knots_v[iv], S.knots_v[iv + 1]
    H = S._hom  # (nu, nv, 4)
    Cu = clamp_segment(Curve(H.reshape(nu, -1), S.knots_u, pu), ua, ub)
    Hu = Cu.poles.reshape(pu + 1, nv, 4).transpose(1, 0, 2).reshape(nv, -1)
    Cv = clamp_segment(Curve(Hu, S.knots_v, pv), va, vb)
    net = Cv.poles.reshape(pv + 1, pu + 1, 4).transpose(1, 0, 2)
    return net, (float(ua), float(ub)), (float(va), float(vb))


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
    su = ((a[0] - ua) / (ub - ua), (b[0] - ua) / (ub - ua))
    sv = ((a[1] - va) / (vb - va), (b[1] - va) / (vb - va))
    Q = _blossom_net(net, *su)                                           # along u (axis 0)
    Q = _blossom_net(Q.transpose(1, 0, 2), *sv).transpose(1, 0, 2)        # along v
    p, q = S.degree_u, S.degree_v
    R = np.zeros((p + q + 1, 4))
    for k in range(p + 1):
        for m in range(q + 1):
            R[k + m] += comb(p, k) * comb(q, m) / comb(p + q, k + m) * Q[k, m]
    d = p + q
    knots = np.concatenate([np.zeros(d + 1), np.ones(d + 1)])
    w = R[:, 3]
    return Curve(R[:, :3] / w[:, None], knots, d, None if S.weights is None else w)
