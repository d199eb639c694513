"""Optional numba kernels for B-spline evaluation and ruling distances, with the NumPy code in nurbs.py and
distance.py as their twins (the switch is core.jit).

The kernels compute, point by point, what the vectorized NumPy path computes:
the same B-spline basis (here from per-span power-basis tables evaluated by
Horner's rule, nurbs.taylor_table), the homogeneous tensor contraction and the
rational quotient rule; results agree to round-off, (tests compare them).  numba is
optional: when it is missing (FreeCAD's Python) or RULED_NO_NUMBA=1 is set,
``AVAILABLE`` is False and nurbs.py uses NumPy alone.
"""
from __future__ import annotations

import numpy as np

from ruled.core.jit import AVAILABLE, _run_chunks

if AVAILABLE:
    from numba import njit

    from ruled.core.jit import INLINE

    @njit(cache=True, nogil=True, inline=INLINE)
    def _span(knots, p, n, x):
        # knots[i] <= x < knots[i+1], clipped to [p, n-1] (same as find_spans)
        lo, hi = 0, knots.shape[0]
        while lo < hi:  # searchsorted side='right'
            mid = (lo + hi) // 2
            if knots[mid] <= x:
                lo = mid + 1
            else:
                hi = mid
        i = lo - 1
        if i < p:
            i = p
        if i > n - 1:
            i = n - 1
        return i

    @njit(cache=True, nogil=True, inline=INLINE)
    def _basis_taylor(tab, knots, p, span, x, nder, ders):
        """Basis values and derivatives on a span by Horner's rule: tab[k, span, r, j] is the
        coefficient of (x - knots[span])^j in the k-th derivative of basis function span - p + r."""
        h = x - knots[span]
        for k in range(nder + 1):
            for r in range(p + 1):
                acc = 0.0
                for j in range(p - k, -1, -1):
                    acc = acc * h + tab[k, span, r, j]
                ders[k, r] = acc

    @njit(cache=True, nogil=True)
    def _workspace(pu, pv):
        return np.zeros((3, pu + 1)), np.zeros((3, pv + 1))

    @njit(cache=True, nogil=True, inline=INLINE)
    def _eval_point(hom, ku, kv, tu, tv, pu, pv, u, v, nder, Bu, Bv, out, n):
        """out[n] (6, 3) <- P, Su, Sv, Suu, Suv, Svv at one (u, v) (orders <= nder)."""
        nu, nv = hom.shape[0], hom.shape[1]
        su = _span(ku, pu, nu, u)
        sv = _span(kv, pv, nv, v)
        du = min(nder, pu)
        dv = min(nder, pv)
        _basis_taylor(tu, ku, pu, su, u, du, Bu)
        _basis_taylor(tv, kv, pv, sv, v, dv, Bv)
        for k in range(du + 1, nder + 1):
            for r in range(pu + 1):
                Bu[k, r] = 0.0
        for k in range(dv + 1, nder + 1):
            for r in range(pv + 1):
                Bv[k, r] = 0.0
        a0 = a1 = a2 = a3 = 0.0          # A00
        b0 = b1 = b2 = b3 = 0.0          # A10
        c0 = c1 = c2 = c3 = 0.0          # A01
        d0 = d1 = d2 = d3 = 0.0          # A20
        e0 = e1 = e2 = e3 = 0.0          # A11
        f0 = f1 = f2 = f3 = 0.0          # A02
        for r in range(pu + 1):
            row = su - pu + r
            p0 = p1 = p2 = p3 = 0.0      # T0
            q0 = q1 = q2 = q3 = 0.0      # T1
            w0 = w1 = w2 = w3 = 0.0      # T2
            for s in range(pv + 1):
                col = sv - pv + s
                h0 = hom[row, col, 0]
                h1 = hom[row, col, 1]
                h2 = hom[row, col, 2]
                h3 = hom[row, col, 3]
                bb = Bv[0, s]
                p0 += bb * h0
                p1 += bb * h1
                p2 += bb * h2
                p3 += bb * h3
                if nder >= 1:
                    bb = Bv[1, s]
                    q0 += bb * h0
                    q1 += bb * h1
                    q2 += bb * h2
                    q3 += bb * h3
                if nder >= 2:
                    bb = Bv[2, s]
                    w0 += bb * h0
                    w1 += bb * h1
                    w2 += bb * h2
                    w3 += bb * h3
            g = Bu[0, r]
            a0 += g * p0
            a1 += g * p1
            a2 += g * p2
            a3 += g * p3
            if nder >= 1:
                g1 = Bu[1, r]
                b0 += g1 * p0
                b1 += g1 * p1
                b2 += g1 * p2
                b3 += g1 * p3
                c0 += g * q0
                c1 += g * q1
                c2 += g * q2
                c3 += g * q3
            if nder >= 2:
                g2 = Bu[2, r]
                d0 += g2 * p0
                d1 += g2 * p1
                d2 += g2 * p2
                d3 += g2 * p3
                e0 += g1 * q0
                e1 += g1 * q1
                e2 += g1 * q2
                e3 += g1 * q3
                f0 += g * w0
                f1 += g * w1
                f2 += g * w2
                f3 += g * w3
        P0 = a0 / a3
        P1 = a1 / a3
        P2 = a2 / a3
        out[n, 0, 0] = P0
        out[n, 0, 1] = P1
        out[n, 0, 2] = P2
        if nder >= 1:
            U0 = (b0 - b3 * P0) / a3
            U1 = (b1 - b3 * P1) / a3
            U2 = (b2 - b3 * P2) / a3
            V0 = (c0 - c3 * P0) / a3
            V1 = (c1 - c3 * P1) / a3
            V2 = (c2 - c3 * P2) / a3
            out[n, 1, 0] = U0
            out[n, 1, 1] = U1
            out[n, 1, 2] = U2
            out[n, 2, 0] = V0
            out[n, 2, 1] = V1
            out[n, 2, 2] = V2
            if nder >= 2:
                out[n, 3, 0] = (d0 - 2.0 * b3 * U0 - d3 * P0) / a3
                out[n, 3, 1] = (d1 - 2.0 * b3 * U1 - d3 * P1) / a3
                out[n, 3, 2] = (d2 - 2.0 * b3 * U2 - d3 * P2) / a3
                out[n, 5, 0] = (f0 - 2.0 * c3 * V0 - f3 * P0) / a3
                out[n, 5, 1] = (f1 - 2.0 * c3 * V1 - f3 * P1) / a3
                out[n, 5, 2] = (f2 - 2.0 * c3 * V2 - f3 * P2) / a3
                out[n, 4, 0] = (e0 - b3 * V0 - c3 * U0 - e3 * P0) / a3
                out[n, 4, 1] = (e1 - b3 * V1 - c3 * U1 - e3 * P1) / a3
                out[n, 4, 2] = (e2 - b3 * V2 - c3 * U2 - e3 * P2) / a3

    @njit(cache=True, nogil=True)
    def _surface_eval_range(hom, ku, kv, tu, tv, pu, pv, u, v, nder, out, start, stop):
        Bu, Bv = _workspace(pu, pv)
        for n in range(start, stop):
            _eval_point(hom, ku, kv, tu, tv, pu, pv, u[n], v[n], nder, Bu, Bv, out, n)

    @njit(cache=True, nogil=True, inline=INLINE)
    def _wrap(x, a, b, closed):
        if closed:
            L = b - a
            return a + ((x - a) % L)
        return min(max(x, a), b)

    @njit(cache=True, nogil=True)
    def _rulings_range(hom, ku, kv, tu, tv, pu, pv, dom, closed, uP, uQ, m, iters, ub, dist, feet, tau_out, foot_out,
                       start, stop):
        Bu, Bv = _workspace(pu, pv)
        res_ = np.zeros((1, 6, 3))
        res = res_[0]
        u0, u1, v0, v1 = dom[0], dom[1], dom[2], dom[3]
        P = np.zeros(3)
        Q = np.zeros(3)
        Xs = np.zeros((m, 3))
        UVs = np.zeros((m, 2))
        r0s = np.zeros(m)
        taus = np.zeros(m)
        for kk in range(start, stop):
            a = uP[kk]
            b = uQ[kk]
            _eval_point(hom, ku, kv, tu, tv, pu, pv, _wrap(a, u0, u1, closed), v0, 0, Bu, Bv, res_, 0)
            for c in range(3):
                P[c] = res[0, c]
            _eval_point(hom, ku, kv, tu, tv, pu, pv, _wrap(b, u0, u1, closed), v1, 0, Bu, Bv, res_, 0)
            dd = 0.0
            for c in range(3):
                Q[c] = res[0, c] - P[c]
                dd += Q[c] * Q[c]
            if dd <= 0.0:
                dd = 1.0
            rmax = 0.0
            dmax = 0.0
            # the samples' feet on the segment first; then projections, largest composition distance
            # first: a sample whose r0 is at most the maximum so far cannot raise it (skipped, unless
            # its foot is asked for), so the order leaves the result as it is
            for k in range(m):
                t = (k + 0.5) / m
                uu = _wrap(a * (1 - t) + b * t, u0, u1, closed)
                vv = v0 * (1 - t) + v1 * t
                _eval_point(hom, ku, kv, tu, tv, pu, pv, uu, vv, 0, Bu, Bv, res_, 0)
                tau = 0.0
                for c in range(3):
                    tau += (res[0, c] - P[c]) * Q[c]
                tau = min(max(tau / dd, 0.0), 1.0)
                for c in range(3):
                    Xs[k, c] = P[c] + tau * Q[c]
                r0s[k] = np.sqrt((res[0, 0] - Xs[k, 0]) ** 2 + (res[0, 1] - Xs[k, 1]) ** 2
                                 + (res[0, 2] - Xs[k, 2]) ** 2)
                UVs[k, 0] = uu
                UVs[k, 1] = vv
                taus[k] = tau
                if r0s[k] > rmax:
                    rmax = r0s[k]
            order = np.arange(m) if feet else np.argsort(-r0s)
            for k in order:
                r0 = r0s[k]
                if not feet and r0 <= dmax:
                    break
                X0, X1, X2 = Xs[k, 0], Xs[k, 1], Xs[k, 2]
                uu, vv, tau = UVs[k, 0], UVs[k, 1], taus[k]
                # Gauss-Newton projection of X onto S from (uu, vv)
                u = uu
                v = vv
                best = np.inf
                Fu = uu
                Fv = vv
                for it in range(iters + 1):
                    nd = 1 if it < iters else 0
                    _eval_point(hom, ku, kv, tu, tv, pu, pv, u, v, nd, Bu, Bv, res_, 0)
                    e0 = res[0, 0] - X0
                    e1 = res[0, 1] - X1
                    e2 = res[0, 2] - X2
                    d = np.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
                    if d < best:
                        best = d
                        if feet and d < r0:
                            Fu = u
                            Fv = v
                    if nd == 0:
                        break
                    A_ = res[1, 0] * res[1, 0] + res[1, 1] * res[1, 1] + res[1, 2] * res[1, 2]
                    B_ = res[1, 0] * res[2, 0] + res[1, 1] * res[2, 1] + res[1, 2] * res[2, 2]
                    C_ = res[2, 0] * res[2, 0] + res[2, 1] * res[2, 1] + res[2, 2] * res[2, 2]
                    g1 = res[1, 0] * e0 + res[1, 1] * e1 + res[1, 2] * e2
                    g2 = res[2, 0] * e0 + res[2, 1] * e1 + res[2, 2] * e2
                    lam = 1e-12 * (A_ + C_) + 1e-300
                    A_ += lam
                    C_ += lam
                    det = A_ * C_ - B_ * B_
                    if not abs(det) > 0:
                        det = 1e-300
                    u = _wrap(u - (C_ * g1 - B_ * g2) / det, u0, u1, closed)
                    v = _wrap(v - (A_ * g2 - B_ * g1) / det, v0, v1, False)
                dr = min(r0, best)
                if feet:
                    tau_out[kk, k] = tau
                    foot_out[kk, k, 0] = Fu
                    foot_out[kk, k, 1] = Fv
                if dr > dmax:
                    dmax = dr
            ub[kk] = rmax
            dist[kk] = dmax

    def ruling_distances(hom, ku, kv, tu, tv, pu, pv, dom, closed, uP, uQ, m, iters, ub, dist, tau_out=None,
                         foot_out=None):
        """Fused twin of distance.ruling_distances (one ruling at a time, threads over rulings); with
        tau_out (K, m) and foot_out (K, m, 2) it also returns each sample's segment parameter and the
        parameters of the surface point its distance was measured to."""
        feet = tau_out is not None
        if not feet:
            tau_out = np.zeros((1, 1))
            foot_out = np.zeros((1, 1, 2))

        def run(a, b):
            _rulings_range(hom, ku, kv, tu, tv, pu, pv, dom, closed, uP, uQ, m, iters, ub, dist, feet, tau_out,
                           foot_out, a, b)
        _run_chunks(run, uP.shape[0], 512)

    def surface_eval(hom, ku, kv, tu, tv, pu, pv, u, v, nder, out):
        """out (N, 6, 3): P, Su, Sv, Suu, Suv, Svv (orders above nder left untouched)."""
        def run(a, b):
            _surface_eval_range(hom, ku, kv, tu, tv, pu, pv, u, v, nder, out, a, b)
        _run_chunks(run, u.shape[0])

    @njit(cache=True, nogil=True)
    def _curve_eval_range(hom, knots, tab, p, t, nder, out, start, stop):
        n = hom.shape[0]
        d = hom.shape[1] - 1
        B = np.zeros((nder + 1, p + 1))
        A = np.zeros((3, d + 1))
        dd = min(nder, p)
        for m in range(start, stop):
            sp = _span(knots, p, n, t[m])
            _basis_taylor(tab, knots, p, sp, t[m], dd, B)
            for k in range(nder + 1):
                for c in range(d + 1):
                    acc = 0.0
                    if k <= dd:
                        for r in range(p + 1):
                            acc += B[k, r] * hom[sp - p + r, c]
                    A[k, c] = acc
            w0 = A[0, d]
            for c in range(d):
                out[m, 0, c] = A[0, c] / w0
            if nder >= 1:
                for c in range(d):
                    out[m, 1, c] = (A[1, c] - A[1, d] * out[m, 0, c]) / w0
            if nder >= 2:
                for c in range(d):
                    out[m, 2, c] = (A[2, c] - 2.0 * A[1, d] * out[m, 1, c] - A[2, d] * out[m, 0, c]) / w0

    @njit(cache=True, nogil=True)
    def _feet_range(Ah, Bh, knots, tab, p, X, s0, closed, iters, s_out, t_out, start, stop):
        Bm = np.zeros((3, p + 1))
        n = Ah.shape[0]
        a0 = np.zeros(3)
        a1 = np.zeros(3)
        b0 = np.zeros(3)
        b1 = np.zeros(3)
        for m in range(start, stop):
            s = s0[m]
            best_d = np.inf
            best_s = s
            best_t = 0.0
            for it in range(iters + 1):
                if closed:
                    sw = s % 1.0
                else:
                    sw = min(max(s, 0.0), 1.0)
                sp = _span(knots, p, n, sw)
                _basis_taylor(tab, knots, p, sp, sw, 1, Bm)
                wa0 = 0.0
                wa1 = 0.0
                wb0 = 0.0
                wb1 = 0.0
                for c in range(3):
                    a0[c] = 0.0
                    a1[c] = 0.0
                    b0[c] = 0.0
                    b1[c] = 0.0
                for r in range(p + 1):
                    i = sp - p + r
                    for c in range(3):
                        a0[c] += Bm[0, r] * Ah[i, c]
                        a1[c] += Bm[1, r] * Ah[i, c]
                        b0[c] += Bm[0, r] * Bh[i, c]
                        b1[c] += Bm[1, r] * Bh[i, c]
                    wa0 += Bm[0, r] * Ah[i, 3]
                    wa1 += Bm[1, r] * Ah[i, 3]
                    wb0 += Bm[0, r] * Bh[i, 3]
                    wb1 += Bm[1, r] * Bh[i, 3]
                for c in range(3):
                    a0[c] = a0[c] / wa0
                    a1[c] = (a1[c] - wa1 * a0[c]) / wa0
                    b0[c] = b0[c] / wb0
                    b1[c] = (b1[c] - wb1 * b0[c]) / wb0
                dd = 0.0
                xd = 0.0
                for c in range(3):
                    d = b0[c] - a0[c]
                    dd += d * d
                    xd += (X[m, c] - a0[c]) * d
                t = min(max(xd / (dd if dd > 0 else 1.0), 0.0), 1.0)
                rn = 0.0
                num = 0.0
                den = 0.0
                for c in range(3):
                    F = a0[c] + t * (b0[c] - a0[c])
                    r_ = X[m, c] - F
                    rn += r_ * r_
                    Fs = (1 - t) * a1[c] + t * b1[c]
                    num += r_ * Fs
                    den += Fs * Fs
                dist = np.sqrt(rn)
                if dist < best_d:
                    best_d = dist
                    best_s = sw
                    best_t = t
                s = sw + num / (den if den > 0 else 1.0)
            s_out[m] = best_s
            t_out[m] = best_t

    def segment_feet(Ah, Bh, knots, tab, p, X, s0, closed, iters, s_out, t_out):
        """Fused twin of certify._segment_feet (closest ruling point by Gauss-Newton in s)."""
        def run(a, b):
            _feet_range(Ah, Bh, knots, tab, p, X, s0, closed, iters, s_out, t_out, a, b)
        _run_chunks(run, X.shape[0])

    def curve_eval(hom, knots, tab, p, t, nder, out):
        """out (N, nder+1, d) for homogeneous poles hom (n, d+1)."""
        _run_chunks(lambda a, b: _curve_eval_range(hom, knots, tab, p, t, nder, out, a, b), t.shape[0])
else:  # pragma: no cover - exercised in FreeCAD's Python
    surface_eval = None
    curve_eval = None
    ruling_distances = None
    segment_feet = None
