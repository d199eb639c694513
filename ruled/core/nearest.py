"""Nearest points of sampled curves: to a polyline of samples, and to the curve itself (no chord's sagitta)."""

from __future__ import annotations

import numpy as np


def to_curve(P: np.ndarray, f, ts: np.ndarray, X: np.ndarray, tree, rounds: int = 30) -> np.ndarray:
    """(N,) the distances from P to the curve f, sampled at the parameters ts as X: golden sections of
    |f(t) - P| over the parameter spans beside P's three nearest samples (points of the curve itself, so
    no chord's sagitta in them)."""
    g = 0.5 * (np.sqrt(5.0) - 1.0)
    best = np.full(len(P), np.inf)
    for i in np.atleast_2d(tree.query(P, k=min(3, len(X)))[1].T):
        lo, hi = ts[np.maximum(i - 1, 0)], ts[np.minimum(i + 1, len(ts) - 1)]
        x1, x2 = hi - g * (hi - lo), lo + g * (hi - lo)
        f1, f2 = (np.linalg.norm(f(x) - P, axis=1) for x in (x1, x2))
        for _ in range(rounds):
            left = f1 <= f2
            lo, hi = np.where(left, lo, x1), np.where(left, x2, hi)
            xn = np.where(left, hi - g * (hi - lo), lo + g * (hi - lo))
            fn = np.linalg.norm(f(xn) - P, axis=1)
            x1, f1, x2, f2 = (np.where(left, xn, x2), np.where(left, fn, f2),
                              np.where(left, x1, xn), np.where(left, f1, fn))
        best = np.minimum(best, np.minimum(f1, f2))
    return best


def to_polyline(P: np.ndarray, X: np.ndarray, tree) -> np.ndarray:
    """(N, 3) the nearest points to P on the polyline X: the segments beside its three nearest vertices
    (a closed polyline's two ends are both near its closing point)."""
    best = X[tree.query(P)[1]].copy()
    for i in tree.query(P, k=min(3, len(X)))[1].T:
        for j in (np.maximum(i - 1, 0), np.minimum(i + 1, len(X) - 1)):
            a, d = X[i], X[j] - X[i]
            w = np.clip(((P - a) * d).sum(axis=1) / np.maximum((d * d).sum(axis=1), 1e-300), 0.0, 1.0)
            Q = a + w[:, None] * d
            closer = np.linalg.norm(Q - P, axis=1) < np.linalg.norm(best - P, axis=1)
            best[closer] = Q[closer]
    return best
