"""Optional numba kernels of curves on surfaces: the chord distance of each piece and its local
gradient bound.

Each kernel computes, piece by piece and in the same order of operations, what its NumPy twin in
curve_on_surface.py and compose.py compute (_farthest, SpanPatches.local_bounds): the same power coefficients,
polynomial products, root formulas (closed forms up to degree 2, the companion matrix's
eigenvalues above, two Newton steps), candidates in the same order, and the same restricted nets.
Tests compare the twins.
"""

from __future__ import annotations

import numpy as np

from ruled.core.jit import AVAILABLE

if AVAILABLE:
    from numba import njit

    @njit(cache=True, nogil=True)
    def _horner(a, d, t):
        out = 0.0
        for j in range(d, -1, -1):
            out = out * t + a[j]
        return out

    @njit(cache=True, nogil=True)
    def _roots01(P, k1, imag_tol, out):
        """Real roots in (0, 1) of the power polynomial P[:k1]; writes them (NaN-padded) to out[:k1-1]
        in the order the NumPy twin produces."""
        for i in range(k1 - 1):
            out[i] = np.nan
        if k1 < 2:
            return
        scale = 0.0
        for i in range(k1):
            scale = max(scale, abs(P[i]))
        d = 0
        for i in range(k1 - 1, -1, -1):
            if abs(P[i]) > 1e-13 * scale:
                d = i
                break
        if d < 1:
            return
        a = np.empty(d + 1)
        for i in range(d + 1):
            a[i] = P[i] / P[d]
        r = np.empty(d)
        if d == 1:
            r[0] = -a[0]
        elif d == 2:
            a0, a1 = a[0], a[1]
            disc = a1 * a1 - 4 * a0
            ok = disc >= -(imag_tol * (1 + abs(a1))) ** 2
            sq = np.sqrt(max(disc, 0.0))
            qq = -0.5 * (a1 + (sq if a1 >= 0 else -sq))
            r[0] = qq
            r[1] = a0 / qq if qq != 0 else 0.0
            if not ok:
                r[0] = np.nan
                r[1] = np.nan
        else:
            C = np.zeros((d, d))
            for i in range(1, d):
                C[i, i - 1] = 1.0
            for i in range(d):
                C[i, d - 1] = -a[i]
            ev = np.linalg.eigvals(C.astype(np.complex128))
            for i in range(d):
                re, im = ev[i].real, ev[i].imag
                r[i] = re if abs(im) <= imag_tol * (1 + abs(re)) else np.nan
        da = np.empty(d)
        for i in range(d):
            da[i] = a[i + 1] * (i + 1)
        for _ in range(2):
            for i in range(d):
                x = r[i]
                f = _horner(a, d, x)
                g = _horner(da, d - 1, x)
                step = f / g if (g != 0 and np.isfinite(g)) else 0.0
                r[i] = x - (step if abs(step) < 1e-3 else 0.0)
        for i in range(d):
            x = r[i]
            out[i] = x if (x > 1e-9 and x < 1 - 1e-9) else np.nan

    @njit(cache=True, nogil=True)
    def _mul(a, na, b, nb, out):
        for i in range(na + nb - 1):
            out[i] = 0.0
        for i in range(na):
            for j in range(nb):
                out[i + j] += a[i] * b[j]

    @njit(cache=True, nogil=True)
    def farthest(H, M, poly, out_h, out_t):
        """Chord distance and farthest parameter of every single-sided piece (N, n + 1, 3), n >= 2."""
        N, n1 = H.shape[0], H.shape[1]
        n = n1 - 1
        kN = 2 * n if not poly else n            # coefficients of the derivative numerators
        A = np.empty((n1, 3))
        Nu = np.empty(kN)
        Nv = np.empty(kN)
        Cu = np.empty(n1)
        Cv = np.empty(n1)
        one = np.empty(n1)
        tmp1 = np.empty(2 * n)
        tmp2 = np.empty(2 * n)
        kc = kN + n1 - 1                          # coefficients of eqs. 16-17
        poly15 = np.empty(kN)
        perp = np.empty(n1)
        crit = np.empty(kc)
        eu = np.empty(n1)
        ev = np.empty(n1)
        t1 = np.empty(kc)
        t2 = np.empty(kc)
        roots = np.empty(max(kc, kN, n1))
        cand = np.empty(3 + (kN - 1) + 2 * (n1 - 1) + 2 * (kc - 1))
        for p in range(N):
            for k in range(n1):
                for c in range(3):
                    A[k, c] = 0.0
                for j in range(n1):
                    for c in range(3):
                        A[k, c] += M[k, j] * H[p, j, c]
            p0u, p0v = H[p, 0, 0] / H[p, 0, 2], H[p, 0, 1] / H[p, 0, 2]
            pnu, pnv = H[p, n, 0] / H[p, n, 2], H[p, n, 1] / H[p, n, 2]
            du, dv = pnu - p0u, pnv - p0v
            if poly:
                w0 = H[p, 0, 2]
                for k in range(n1):
                    Cu[k] = A[k, 0] / w0
                    Cv[k] = A[k, 1] / w0
                    one[k] = 1.0 if k == 0 else 0.0
                for k in range(n):
                    Nu[k] = Cu[k + 1] * (k + 1)
                    Nv[k] = Cv[k + 1] * (k + 1)
                n_one = 1
            else:
                dw = np.empty(n)
                dAu = np.empty(n)
                dAv = np.empty(n)
                for k in range(n):
                    dw[k] = A[k + 1, 2] * (k + 1)
                    dAu[k] = A[k + 1, 0] * (k + 1)
                    dAv[k] = A[k + 1, 1] * (k + 1)
                for k in range(n1):
                    Cu[k] = A[k, 0]
                    Cv[k] = A[k, 1]
                    one[k] = A[k, 2]
                _mul(dAu, n, one, n1, tmp1)
                _mul(Cu, n1, dw, n, tmp2)
                for k in range(kN):
                    Nu[k] = tmp1[k] + (-tmp2[k])
                _mul(dAv, n, one, n1, tmp1)
                _mul(Cv, n1, dw, n, tmp2)
                for k in range(kN):
                    Nv[k] = tmp1[k] + (-tmp2[k])
                n_one = n1
            nc = 0
            cand[0] = 0.0
            cand[1] = 1.0
            cand[2] = 0.5
            nc = 3
            for k in range(kN):
                poly15[k] = (-Nu[k]) * dv + Nv[k] * du
            _roots01(poly15, kN, 1e-7, roots)
            for i in range(kN - 1):
                cand[nc] = roots[i]
                nc += 1
            L2 = du * du + dv * dv
            inside = True
            for k in range(n1):
                x = (H[p, k, 0] / H[p, k, 2] - p0u) * du + (H[p, k, 1] / H[p, k, 2] - p0v) * dv
                if not (x >= 0 and x <= L2):
                    inside = False
            if not inside:
                base_c = nc + 2 * (n1 - 1)        # candidate order: perpendiculars at P0, Pn, then eqs. 16, 17
                for e in range(2):
                    Eu = p0u if e == 0 else pnu
                    Ev = p0v if e == 0 else pnv
                    for k in range(n1):
                        eu[k] = Cu[k] + ((-Eu) * one[k] if k < n_one else 0.0)
                        ev[k] = Cv[k] + ((-Ev) * one[k] if k < n_one else 0.0)
                        perp[k] = eu[k] * du + ev[k] * dv
                    _roots01(perp, n1, 1e-7, roots)
                    for i in range(n1 - 1):
                        cand[nc + e * (n1 - 1) + i] = roots[i]
                    _mul(Nu, kN, eu, n1, t1)
                    _mul(Nv, kN, ev, n1, t2)
                    for k in range(kc):
                        crit[k] = t1[k] + t2[k]
                    _roots01(crit, kc, 1e-7, roots)
                    for i in range(kc - 1):
                        cand[base_c + e * (kc - 1) + i] = roots[i]
                nc = base_c + 2 * (kc - 1)
            best, bt = -2.0, 0.0
            for i in range(nc):
                t = cand[i]
                isnan = np.isnan(t)
                tt = 0.0 if isnan else t
                W = _horner(A[:, 2], n, tt)
                xu = _horner(A[:, 0], n, tt) / W
                xv = _horner(A[:, 1], n, tt) / W
                if L2 > 0:
                    s = ((xu - p0u) * du + (xv - p0v) * dv) / L2
                    s = min(max(s, 0.0), 1.0)
                else:
                    s = 0.0
                eu0 = xu - (p0u + s * du)
                ev0 = xv - (p0v + s * dv)
                dist = -1.0 if isnan else np.sqrt(eu0 * eu0 + ev0 * ev0)
                if dist > best:
                    best, bt = dist, tt
            out_h[p] = best
            out_t[p] = bt

    @njit(cache=True, nogil=True)
    def _restrict(p, a, b, R):
        """R (p + 1, p + 1) for [a, b], as curve_on_surface.restrict_matrices (blossoming)."""
        c = np.zeros((p + 1, p + 1))
        for k in range(p + 1):
            for ctrl in range(p + 1):
                for col in range(p + 1):
                    c[ctrl, col] = 1.0 if ctrl == col else 0.0
            m = p + 1
            for r in range(p):
                x = a if r < p - k else b
                for ctrl in range(m - 1):
                    for col in range(p + 1):
                        c[ctrl, col] = (1 - x) * c[ctrl, col] + x * c[ctrl + 1, col]
                m -= 1
            for col in range(p + 1):
                R[k, col] = c[0, col]

    @njit(cache=True, nogil=True)
    def _sandwich(Ru, net, Rv, out):
        A, I = Ru.shape[0], Ru.shape[1]
        B, J = Rv.shape[0], Rv.shape[1]
        X = np.zeros((A, J, 4))
        for i in range(I):
            for a in range(A):
                for j in range(J):
                    for c in range(4):
                        X[a, j, c] += Ru[a, i] * net[i, j, c]
        for a in range(A):
            for b in range(B):
                for c in range(4):
                    out[a, b, c] = 0.0
        for j in range(J):
            for a in range(A):
                for b in range(B):
                    for c in range(4):
                        out[a, b, c] += X[a, j, c] * Rv[b, j]

    @njit(cache=True, nogil=True)
    def _hull(dsub, cx, cy, cz, r, wmin):
        num = 0.0
        dwm = 0.0
        for a in range(dsub.shape[0]):
            for b in range(dsub.shape[1]):
                Dw = dsub[a, b, 3]
                x = dsub[a, b, 0] - Dw * cx
                y = dsub[a, b, 1] - Dw * cy
                z = dsub[a, b, 2] - Dw * cz
                num = max(num, np.sqrt(x * x + y * y + z * z))
                dwm = max(dwm, abs(Dw))
        return (num + dwm * r) / wmin

    @njit(cache=True, nogil=True)
    def local_bounds(sid, lo, hi, nets, du, dv, slo, shi, out):
        N = sid.shape[0]
        p, q = nets.shape[1] - 1, nets.shape[2] - 1
        Ru = np.empty((p + 1, p + 1))
        Rv = np.empty((q + 1, q + 1))
        Ru1 = np.empty((max(p, 1), max(p, 1)))
        Rv1 = np.empty((max(q, 1), max(q, 1)))
        sub = np.empty((p + 1, q + 1, 4))
        subu = np.empty((max(p, 1), q + 1, 4))
        subv = np.empty((p + 1, max(q, 1), 4))
        for n in range(N):
            s = sid[n]
            a0 = (lo[n, 0] - slo[s, 0]) / (shi[s, 0] - slo[s, 0])
            a1 = (lo[n, 1] - slo[s, 1]) / (shi[s, 1] - slo[s, 1])
            b0 = (hi[n, 0] - slo[s, 0]) / (shi[s, 0] - slo[s, 0])
            b1 = (hi[n, 1] - slo[s, 1]) / (shi[s, 1] - slo[s, 1])
            _restrict(p, a0, b0, Ru)
            _restrict(q, a1, b1, Rv)
            _sandwich(Ru, nets[s], Rv, sub)
            mn = np.full(3, np.inf)
            mx = np.full(3, -np.inf)
            wmin = np.inf
            for i in range(p + 1):
                for j in range(q + 1):
                    w = sub[i, j, 3]
                    wmin = min(wmin, w)
                    for c in range(3):
                        x = sub[i, j, c] / w
                        mn[c] = min(mn[c], x)
                        mx[c] = max(mx[c], x)
            cx, cy, cz = 0.5 * (mn[0] + mx[0]), 0.5 * (mn[1] + mx[1]), 0.5 * (mn[2] + mx[2])
            ex, ey, ez = mx[0] - mn[0], mx[1] - mn[1], mx[2] - mn[2]
            r = 0.5 * np.sqrt(ex * ex + ey * ey + ez * ez)
            mu = 0.0
            mv = 0.0
            if p:
                _restrict(p - 1, a0, b0, Ru1)
                _sandwich(Ru1[:p, :p], du[s], Rv, subu)
                mu = _hull(subu, cx, cy, cz, r, wmin)
            if q:
                _restrict(q - 1, a1, b1, Rv1)
                _sandwich(Ru, dv[s], Rv1[:q, :q], subv)
                mv = _hull(subv, cx, cy, cz, r, wmin)
            out[n] = np.hypot(mu, mv)

    @njit(cache=True, nogil=True)
    def first_cross(H, M, out):
        """The first parameter in (0, 1) where each piece crosses its own chord (NaN when none), as
        curve_on_surface._single_sided_stack finds it."""
        N, n1 = H.shape[0], H.shape[1]
        b = np.empty(n1)
        a = np.empty(n1)
        r = np.empty(max(n1 - 1, 1))
        for p in range(N):
            p0u, p0v = H[p, 0, 0] / H[p, 0, 2], H[p, 0, 1] / H[p, 0, 2]
            du = H[p, n1 - 1, 0] / H[p, n1 - 1, 2] - p0u
            dv = H[p, n1 - 1, 1] / H[p, n1 - 1, 2] - p0v
            for j in range(n1):
                b[j] = (H[p, j, 0] - H[p, j, 2] * p0u) * dv - (H[p, j, 1] - H[p, j, 2] * p0v) * du
            for k in range(n1):
                a[k] = 0.0
                for j in range(n1):
                    a[k] += M[k, j] * b[j]
            _roots01(a, n1, 1e-7, r)
            best = np.nan
            for i in range(n1 - 1):
                if not np.isnan(r[i]) and (np.isnan(best) or r[i] < best):
                    best = r[i]
            out[p] = best
