"""Synchronization of two contours: the parameters at which straight moves on both stay within the chord
tolerance of the contours (the XYUV pairs and the flank path's stations)."""

from __future__ import annotations

import numpy as np

from ruled.core.errors import BadInputError
from ruled.core.nurbs import Surface
from ruled.core.progress import Progress

_SEG_SAMPLES = 15          # samples inside a move for the chord test
_CHUNK = 20000             # parameters evaluated at once


def surface_grid(S: Surface, n: int) -> tuple[np.ndarray, np.ndarray]:
    """((n * n, 2) parameters, (n * n, 3) points) of an n x n grid over S's domain."""
    a0, a1, b0, b1 = S.domain
    uu, vv = np.meshgrid(np.linspace(a0, a1, n), np.linspace(b0, b1, n), indexing="ij")
    uv = np.stack([uu.ravel(), vv.ravel()], axis=1)
    return uv, S(uv[:, 0], uv[:, 1])


def _seeds(S: Surface, X: np.ndarray, n: int = 64) -> np.ndarray:
    """The (u, v) of the nearest point of an n x n grid of S to each point of X."""
    from scipy.spatial import cKDTree
    uv, P = surface_grid(S, n)
    return uv[cKDTree(P).query(X)[1]]


def _samples(f, a: np.ndarray, b: np.ndarray, k: int) -> tuple[np.ndarray, np.ndarray]:
    """k parameters evenly inside each move [a, b] ((n, k)) and the curves there ((n, k, m, 3))."""
    s = np.arange(1, k + 1) / (k + 1)
    uu = a[:, None] + (b - a)[:, None] * s
    flat = uu.ravel()
    # in chunks: an evaluation's temporaries are many times its result (the offset lines' samples)
    parts = [f(flat[i:i + _CHUNK]) for i in range(0, flat.size, _CHUNK)]
    return uu, np.concatenate(parts).reshape(a.size, k, -1, 3)


def straight(fa: np.ndarray, fb: np.ndarray, s: np.ndarray) -> np.ndarray:
    """The machine between two synchronized points ((..., m, 3) each) at the fraction s ((..., 1, 1)): every
    curve's point moving straight (the wire's two guides)."""
    return fa + s * (fb - fa)


def tool_between(fa: np.ndarray, fb: np.ndarray, s: np.ndarray) -> np.ndarray:
    """The flank tool between two CL positions ((..., 2, 3): tip, top) at the fraction s ((..., 1, 1)), as a
    5-axis machine moves it: the tip straight, the axis direction turning linearly (normalized), the tool's
    length linear; (..., 2, 3) tip and top.  (On a long tool this is not the top moving straight: the two part
    by about the length times the square of the turn.)"""
    w = s[..., 0, :]
    ta, tb = fa[..., 0, :], fb[..., 0, :]
    da, db = fa[..., 1, :] - ta, fb[..., 1, :] - tb
    La, Lb = np.linalg.norm(da, axis=-1, keepdims=True), np.linalg.norm(db, axis=-1, keepdims=True)
    A = da / La + w * (db / Lb - da / La)
    T = ta + w * (tb - ta)
    return np.stack([T, T + (La + w * (Lb - La)) * A / np.linalg.norm(A, axis=-1, keepdims=True)], axis=-2)


def _off_chord(X: np.ndarray, uu: np.ndarray, a, b, fa: np.ndarray, fb: np.ndarray, between=straight) -> np.ndarray:
    """Distances between the curve samples X ((n, k, m, 3) at the parameters uu (n, k)) and the machine's
    moves from fa to fb ((n, m, 3)) over [a, b] (`between`), at the same parameter; the largest per move (n,)."""
    s = ((uu - a[:, None]) / (b - a)[:, None])[..., None, None]
    return np.linalg.norm(X - between(fa[:, None], fb[:, None], s), axis=-1).max(axis=(1, 2))


def _turns(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Degrees between the lines of a and b ((n, 2, 3): a line's two points)."""
    da, db = a[:, 1] - a[:, 0], b[:, 1] - b[:, 0]
    c = np.einsum("ij,ij->i", da, db) / (np.linalg.norm(da, axis=1) * np.linalg.norm(db, axis=1))
    return np.degrees(np.arccos(np.clip(c, -1.0, 1.0)))


def sync_params(f, u0: float, u1: float, tol: float, seeds=(), max_points: int = 200000,
                progress: Progress = None, safety: float = 0.95, max_turn: float = 0.0,
                between=straight) -> np.ndarray:
    """The parameters of the synchronized points: the moves between consecutive values of f ((n, m, 3),
    m curves moving together) stay within safety * tol of every curve at the same u.  Bisection from
    the seeds until every move is within tol / 16 at 15 samples inside it (densify: only the halves of
    the moves that failed are sampled again; the deviation goes with the square of the move, so the
    dense moves are about a quarter of the longest that pass), then a greedy pass over the dense points
    that keeps the longest moves within tol at every sample taken while densifying (thin: no new
    evaluations).  max_turn > 0 (two curves: the ends of a line): no move turns the line by more than
    max_turn degrees either.  between: how the machine moves from one synchronized point to the next (straight,
    or tool_between for a flank tool)."""
    user_tol, tol = tol, safety * tol
    dense_tol = tol / 16.0
    u = np.unique(np.concatenate([[u0, u1], np.clip(np.asarray(seeds, float), u0, u1)]))
    vals = f(u)
    k = _SEG_SAMPLES
    su, sx = _samples(f, u[:-1], u[1:], k)
    dev = _off_chord(sx, su, u[:-1], u[1:], vals[:-1], vals[1:], between)
    for it in range(64):
        if progress:
            progress("synchronized points", min(0.8, 0.05 * it))
        over = dev > dense_tol
        if max_turn > 0:
            over |= _turns(vals[:-1], vals[1:]) > max_turn
        bad = np.nonzero(over)[0]
        if bad.size == 0:
            break
        # the deviation of a smooth move goes with its length squared: it needs about sqrt(dev / dense_tol)
        # pieces; far past the limit, refused now rather than after millions of evaluations
        need = u.size + float(np.sqrt(dev[bad] / dense_tol).sum())
        if u.size + bad.size > 4 * max_points or need > 16 * max_points:
            raise BadInputError(f"the chord tolerance {user_tol:.3g} needs more than {max_points} synchronized "
                                f"points; raise «chord_tol»")
        a, b = u[bad], u[bad + 1]
        mid = 0.5 * (a + b)
        fm = f(mid)
        na, nb = np.concatenate([a, mid]), np.concatenate([mid, b])
        fa, fb = np.concatenate([vals[bad], fm]), np.concatenate([fm, vals[bad + 1]])
        nsu, nsx = _samples(f, na, nb, k)
        ndev = _off_chord(nsx, nsu, na, nb, fa, fb, between)
        kept = np.ones(u.size - 1, bool)
        kept[bad] = False
        starts = np.concatenate([u[:-1][kept], na])
        order = np.argsort(starts, kind="stable")
        su = np.concatenate([su[kept], nsu])[order]
        sx = np.concatenate([sx[kept], nsx])[order]
        dev = np.concatenate([dev[kept], ndev])[order]
        pts = np.concatenate([u, mid])
        po = np.argsort(pts, kind="stable")
        u, vals = pts[po], np.concatenate([vals, fm])[po]
    else:
        raise BadInputError(f"the contours cannot be followed within «chord_tol={user_tol:.3g}» (a kink or a "
                            f"jump); raise «chord_tol»")
    # every sample in parameter order: the points themselves and the samples inside each move
    n = u.size
    U = np.concatenate([u[:-1, None], su], axis=1).ravel()
    X = np.concatenate([vals[:-1, None], sx], axis=1).reshape(-1, *vals.shape[1:])
    pos = np.arange(n) * (k + 1)

    def passes(i, j):
        lo, hi = pos[i] + 1, pos[j]
        s = ((U[lo:hi] - u[i]) / (u[j] - u[i]))[:, None, None]
        lin = between(vals[i][None], vals[j][None], s)
        if max_turn > 0 and _turns(vals[i][None], vals[j][None])[0] > max_turn:
            return False
        return bool(np.linalg.norm(X[lo:hi] - lin, axis=-1).max() <= tol)

    keep: list = [0]
    i = 0
    while i < n - 1:
        if progress and len(keep) % 50 == 0:
            progress("synchronized points", 0.8 + 0.2 * i / n)
        good, step = i + 1, 1
        while good + step <= n - 1 and passes(i, good + step):     # gallop ...
            good += step
            step *= 2
        hi = min(good + step, n)                                    # ... then bisect [good, hi)
        while hi - good > 1:
            mid = (good + hi) // 2
            if passes(i, mid):
                good = mid
            else:
                hi = mid
        keep.append(good)
        i = good
    if progress:
        progress("synchronized points", 1.0)
    return u[np.array(keep)]
