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

from ruled.core import jit
from ruled.core.basis import find_spans
from ruled.core.errors import BadInputError
from ruled.core.knots import span_bezier
from ruled.core.nurbs import Curve, Surface
from ruled.curves import kernels as kernels_cos


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


def _bernstein(n: int, t: np.ndarray) -> np.ndarray:
    """Bernstein basis values (N, n + 1) at t (N,)."""
    k = np.arange(n + 1)
    c = np.array([comb(n, i) for i in k], float)
    return c * t[:, None] ** k * (1 - t[:, None]) ** (n - k)


class SpanPatches:
    """The Bézier patches of S by knot span, built when a piece first needs them, with their
    derivative nets (in the surface's parameters)."""

    def __init__(self, S: Surface):
        self.S = S
        self.p, self.q = S.degree_u, S.degree_v
        self.index: dict = {}
        self.nets: list = []
        self.du: list = []
        self.dv: list = []
        self.lo: list = []
        self.hi: list = []
        self._arrays = None

    def of(self, X: np.ndarray) -> np.ndarray:
        """Span numbers of the points X (N, 2)."""
        S = self.S
        iu = find_spans(S.knots_u, self.p, S.poles.shape[0], X[:, 0])
        iv = find_spans(S.knots_v, self.q, S.poles.shape[1], X[:, 1])
        code = iu * S.knots_v.shape[0] + iv
        uniq, first, inv = np.unique(code, return_index=True, return_inverse=True)
        ids = np.empty(uniq.shape[0], int)
        for m, (c, k) in enumerate(zip(uniq.tolist(), first.tolist())):
            j = self.index.get(c)
            if j is None:
                net, ur, vr = span_patch(S, float(X[k, 0]), float(X[k, 1]))
                j = len(self.nets)
                self.index[c] = j
                self.nets.append(net)
                self.du.append(np.diff(net, axis=0) * (self.p / (ur[1] - ur[0])))
                self.dv.append(np.diff(net, axis=1) * (self.q / (vr[1] - vr[0])))
                self.lo.append((ur[0], vr[0]))
                self.hi.append((ur[1], vr[1]))
                self._arrays = None
            ids[m] = j
        return ids[inv.ravel()]

    def arrays(self):
        if self._arrays is None:
            self._arrays = tuple(np.array(x) for x in (self.nets, self.du, self.dv, self.lo, self.hi))
        return self._arrays

    def local_bounds(self, sid: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        """Rigorous bounds of sqrt(max|S_u|^2 + max|S_v|^2) over the boxes [lo, hi] (N, 2), each inside
        its span: the patch and its derivative nets restricted to the box, convex hull property and,
        for rational patches, the quotient rule with the smallest weight."""
        nets, du, dv, slo, shi = self.arrays()
        if jit.enabled():
            out = np.empty(sid.shape[0])
            kernels_cos.local_bounds(sid, np.ascontiguousarray(lo), np.ascontiguousarray(hi), nets, du, dv, slo, shi,
                                     out)
            return out
        p, q = self.p, self.q
        a = (lo - slo[sid]) / (shi[sid] - slo[sid])
        b = (hi - slo[sid]) / (shi[sid] - slo[sid])
        Ru, Rv = restrict_matrices(p, a[:, 0], b[:, 0]), restrict_matrices(q, a[:, 1], b[:, 1])
        sub = sandwich(Ru, nets[sid], Rv)
        w = sub[..., 3]
        X = sub[..., :3] / w[..., None]
        Xf = X.reshape(X.shape[0], -1, 3)
        c = 0.5 * (Xf.min(axis=1) + Xf.max(axis=1))
        r = 0.5 * np.linalg.norm(Xf.max(axis=1) - Xf.min(axis=1), axis=1)
        wmin = w.reshape(w.shape[0], -1).min(axis=1)

        def hull(dsub):
            Dw = dsub[..., 3].reshape(dsub.shape[0], -1)
            D3 = dsub[..., :3].reshape(dsub.shape[0], -1, 3)
            num = np.linalg.norm(D3 - Dw[..., None] * c[:, None], axis=2).max(axis=1)
            return (num + np.abs(Dw).max(axis=1) * r) / wmin

        mu = hull(sandwich(restrict_matrices(p - 1, a[:, 0], b[:, 0]), du[sid], Rv)) if p else 0.0
        mv = hull(sandwich(Ru, dv[sid], restrict_matrices(q - 1, a[:, 1], b[:, 1]))) if q else 0.0
        return np.hypot(mu, mv)

    def jacobian(self, sid: np.ndarray, X: np.ndarray) -> np.ndarray:
        """(S_u, S_v) as (N, 2, 3) of each point's span patch at X (eqs. 21–22; rational patches by
        the quotient rule), so one-sided at knot lines where S is only C0."""
        nets, du, dv, slo, shi = self.arrays()
        s = (X - slo[sid]) / (shi[sid] - slo[sid])
        bu, bv = _bernstein(self.p, s[:, 0]), _bernstein(self.q, s[:, 1])

        def ev(bu, net, bv):
            return ((bu[:, :, None, None] * net).sum(axis=1) * bv[:, :, None]).sum(axis=1)
        Hh = ev(bu, nets[sid], bv)
        out = np.zeros((X.shape[0], 2, 3))
        if self.p:
            Hu = ev(_bernstein(self.p - 1, s[:, 0]), du[sid], bv)
            out[:, 0] = (Hu[:, :3] - Hh[:, :3] / Hh[:, 3:] * Hu[:, 3:]) / Hh[:, 3:]
        if self.q:
            Hv = ev(bu, dv[sid], _bernstein(self.q - 1, s[:, 1]))
            out[:, 1] = (Hv[:, :3] - Hh[:, :3] / Hh[:, 3:] * Hv[:, 3:]) / Hh[:, 3:]
        return out
