"""Nearest points of sampled curves: to a polyline of samples, and to the curve itself (no chord's sagitta);
the vectorized golden-section search both this and the pairing's refinement use."""

from __future__ import annotations

from typing import Callable, Optional

import numpy as np

GOLD = 0.5 * (np.sqrt(5.0) - 1.0)


def golden(f: Callable, lo: np.ndarray, hi: np.ndarray, rounds: int,
            progress: Optional[Callable] = None) -> tuple[np.ndarray, np.ndarray]:
    """(x, f(x)): golden-section searches of the vectorized f, one per bracket [lo, hi]."""
    x1 = hi - GOLD * (hi - lo)
    x2 = lo + GOLD * (hi - lo)
    f1, f2 = f(x1), f(x2)
    for r in range(rounds):
        left = f1 <= f2  # minimum in [lo, x2]
        hi = np.where(left, x2, hi)
        lo = np.where(left, lo, x1)
        nx1 = hi - GOLD * (hi - lo)
        nx2 = lo + GOLD * (hi - lo)
        # reuse one evaluation per side
        newx = np.where(left, nx1, nx2)
        fn = f(newx)
        x2, f2, x1, f1 = (np.where(left, x1, nx2), np.where(left, f1, fn),
                          np.where(left, nx1, x2), np.where(left, fn, f2))
        if progress is not None:
            progress(r + 1, rounds)
    return np.where(f1 <= f2, x1, x2), np.minimum(f1, f2)


def to_curve(P: np.ndarray, f, ts: np.ndarray, X: np.ndarray, tree, rounds: int = 30) -> np.ndarray:
    """(N,) the distances from P to the curve f, sampled at the parameters ts as X: golden sections of
    |f(t) - P| over the parameter spans beside P's three nearest samples (points of the curve itself, so
    no chord's sagitta in them)."""
    best = np.full(len(P), np.inf)
    for i in np.atleast_2d(tree.query(P, k=min(3, len(X)))[1].T):
        lo, hi = ts[np.maximum(i - 1, 0)], ts[np.minimum(i + 1, len(ts) - 1)]
        best = np.minimum(best, golden(lambda x: np.linalg.norm(f(x) - P, axis=1), lo, hi, rounds)[1])
    return best


def to_polyline(P: np.ndarray, X: np.ndarray, tree) -> np.ndarray:
    """(N, 3) the nearest points to P on the polyline X: the segments beside its three nearest vertices
    (a closed polyline's two ends are both near its closing point)."""
    best = X[tree.query(P)[1]].copy()
    far = np.linalg.norm(best - P, axis=1)          # |best - P|, kept as best moves
    for i in tree.query(P, k=min(3, len(X)))[1].T:
        for j in (np.maximum(i - 1, 0), np.minimum(i + 1, len(X) - 1)):
            a, d = X[i], X[j] - X[i]
            w = np.clip(((P - a) * d).sum(axis=1) / np.maximum((d * d).sum(axis=1), 1e-300), 0.0, 1.0)
            Q = a + w[:, None] * d
            dq = np.linalg.norm(Q - P, axis=1)
            closer = dq < far
            best[closer], far[closer] = Q[closer], dq[closer]
    return best
