"""Optional numba kernels of the cone-spline fitting: exact closest points on a tabulated boundary
(cone.Track) and on a rational quadratic arc (cone.Conic).

Each kernel computes, point by point and in the same order of operations, what its NumPy twin
cone.project computes with Track / Conic: the nearest of the given samples (first of equals),
Newton steps on (c - X) . c' = 0 clipped to the samples' neighbouring interval, and the better of
the sample and the Newton point.  Tests compare the twins.
"""

from __future__ import annotations

import numpy as np

from ruled.core.jit import AVAILABLE

if AVAILABLE:
    from numba import njit

    @njit(cache=True, nogil=True)
    def _locate(tt, v):
        if v < 0.0:
            v = 0.0
        if v > 1.0:
            v = 1.0
        i = np.searchsorted(tt, v, side="right") - 1
        if i > tt.shape[0] - 2:
            i = tt.shape[0] - 2
        return i, v

    @njit(cache=True, nogil=True)
    def _param(tt, hh, v):
        i, v = _locate(tt, v)
        s = (v - tt[i]) / hh[i]
        return i, hh[i], s, s * s, s * s * s

    @njit(cache=True, nogil=True)
    def _track_point(tt, P, D, hh, v, out):
        i, h, s, s2, s3 = _param(tt, hh, v)
        for c in range(2):
            out[c] = ((2 * s3 - 3 * s2 + 1) * P[i, c] + (s3 - 2 * s2 + s) * h * D[i, c]
                      + (-2 * s3 + 3 * s2) * P[i + 1, c] + (s3 - s2) * h * D[i + 1, c])

    @njit(cache=True, nogil=True)
    def _track_all3(tt, P, D, hh, v, X, X1, X2):
        i, h, s, s2, s3 = _param(tt, hh, v)
        for c in range(2):
            P0 = P[i, c]
            P1 = P[i + 1, c]
            D0 = h * D[i, c]
            D1 = h * D[i + 1, c]
            dP = P1 - P0
            X[c] = P0 + s * D0 + s2 * (3 * dP - 2 * D0 - D1) + s3 * (D0 + D1 - 2 * dP)
            X1[c] = (D0 + 2 * s * (3 * dP - 2 * D0 - D1) + 3 * s2 * (D0 + D1 - 2 * dP)) / h
            X2[c] = (2 * (3 * dP - 2 * D0 - D1) + 6 * s * (D0 + D1 - 2 * dP)) / (h * h)

    @njit(cache=True, nogil=True)
    def _conic_point(Q, w, t, out):
        a = (1 - t) ** 2
        b = 2 * w * t * (1 - t)
        c2 = t * t
        for c in range(2):
            out[c] = (a * Q[0, c] + b * Q[1, c] + c2 * Q[2, c]) / (a + b + c2)

    @njit(cache=True, nogil=True)
    def _conic_all3(Q, w, t, X, X1, X2):
        u = 1 - t
        Dn = u * u + 2 * w * t * u + t * t
        D1 = -2 * u + 2 * w * (1 - 2 * t) + 2 * t
        for c in range(2):
            P0, R, P2 = Q[0, c], Q[1, c], Q[2, c]
            N = u * u * P0 + 2 * w * t * u * R + t * t * P2
            N1 = -2 * u * P0 + 2 * w * (1 - 2 * t) * R + 2 * t * P2
            C = N / Dn
            C1 = (N1 - C * D1) / Dn
            X[c] = C
            X1[c] = C1
            X2[c] = (2 * P0 - 4 * w * R + 2 * P2 - 2 * C1 * D1 - C * (4.0 - 4.0 * w)) / Dn

    @njit(cache=True, nogil=True)
    def _project(kind, tt, P, D, hh, Q, w, ts, X, iters, xout, dout):
        n = ts.shape[0]
        F = np.empty((n, 2))
        buf = np.empty(2)
        for j in range(n):
            if kind == 0:
                _track_point(tt, P, D, hh, ts[j], buf)
            else:
                _conic_point(Q, w, ts[j], buf)
            F[j, 0] = buf[0]
            F[j, 1] = buf[1]
        Y, Y1, Y2 = np.empty(2), np.empty(2), np.empty(2)
        for p in range(X.shape[0]):
            k = 0
            best = np.inf
            for j in range(n):
                dx = X[p, 0] - F[j, 0]
                dy = X[p, 1] - F[j, 1]
                d2 = dx ** 2 + dy ** 2
                if d2 < best:
                    best = d2
                    k = j
            x0 = ts[k]
            a = ts[max(k - 1, 0)]
            b = ts[min(k + 1, n - 1)]
            x = x0
            for _ in range(iters):
                if kind == 0:
                    _track_all3(tt, P, D, hh, x, Y, Y1, Y2)
                else:
                    _conic_all3(Q, w, x, Y, Y1, Y2)
                r0 = Y[0] - X[p, 0]
                r1 = Y[1] - X[p, 1]
                g = r0 * Y1[0] + r1 * Y1[1]
                gp = (Y1[0] * Y1[0] + Y1[1] * Y1[1]) + (r0 * Y2[0] + r1 * Y2[1])
                step = g / gp if gp > 0 else 0.0
                x = min(max(x - step, a), b)
            if kind == 0:
                _track_point(tt, P, D, hh, x, buf)
            else:
                _conic_point(Q, w, x, buf)
            dist = np.sqrt((buf[0] - X[p, 0]) ** 2 + (buf[1] - X[p, 1]) ** 2)
            d0 = np.sqrt(best)
            if dist > d0:
                xout[p] = x0
                dout[p] = d0
            else:
                xout[p] = x
                dout[p] = dist


if AVAILABLE:
    @njit(cache=True, nogil=True)
    def _evaluate(kind, tt, P, D, hh, Q, w, v, order, out):
        Y, Y1, Y2 = np.empty(2), np.empty(2), np.empty(2)
        for j in range(v.shape[0]):
            if order == 0:
                if kind == 0:
                    _track_point(tt, P, D, hh, v[j], Y)
                else:
                    _conic_point(Q, w, v[j], Y)
                out[0, j, 0] = Y[0]
                out[0, j, 1] = Y[1]
            else:
                if kind == 0:
                    _track_all3(tt, P, D, hh, v[j], Y, Y1, Y2)
                else:
                    _conic_all3(Q, w, v[j], Y, Y1, Y2)
                for c in range(2):
                    out[0, j, c] = Y[c]
                    out[1, j, c] = Y1[c]
                    out[2, j, c] = Y2[c]


def evaluate(kind: int, tt, P, D, hh, Q, w: float, v, order: int) -> np.ndarray:
    """order 0: points (1, N, 2); order 2: points, first and second derivatives (3, N, 2)."""
    v = np.ascontiguousarray(np.atleast_1d(np.asarray(v, dtype=np.float64)).ravel())
    out = np.empty((1 if order == 0 else 3, v.shape[0], 2))
    _evaluate(kind, tt, P, D, hh, Q, float(w), v, order, out)
    return out


def project(kind: int, tt, P, D, hh, Q, w: float, ts, X, iters: int):
    """kind 0: the Track (tt, P, D, hh); 1: the Conic (control points Q (3, 2), weight w)."""
    xo = np.empty(X.shape[0])
    do = np.empty(X.shape[0])
    _project(kind, tt, P, D, hh, Q, float(w), ts, np.ascontiguousarray(X, dtype=np.float64), iters, xo, do)
    return xo, do
