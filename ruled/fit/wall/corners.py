"""Rulings across a wall's corners: where both contours turn at a sharp corner whose joint bows off its chord, the
pieces' result rules the corner by the chord (bottom corner to top corner), as far from the wall as the joint
bows (a line-arc punch: 0.1308).  Pairing the contours' points past the corner does better: over a window about
the corner, the bottom rail's points are paired with the top's anew (a bottleneck path over candidate rulings,
each's distance from the wall's faces sampled), and both rails are reparametrized piecewise linearly along the
path, exactly (a B-spline composed with a piecewise linear map is one, C0 at the breaks).  The result is then
certified whole (ruled.fit.certify.onesided) and kept where its bound is the lower (the punch: 0.0849, measured
0.0837)."""

from __future__ import annotations

import numpy as np

from ruled.core.knots import clamp_segment
from ruled.core.nurbs import Curve, Surface

# a corner's window: this fraction of the shorter of the two pieces beside it, each side; NODES points of each
# rail a side, the pairing's candidates
WINDOW, NODES = 0.05, 12
# points along a candidate ruling for its distance from the wall
RULING_SAMPLES = 16
# a corner's rulings are paired anew where that lowers its farthest ruling by this factor at least
GAIN = 0.95
# the pairing's steps over the candidate points: one rail at most twice the other's pace (no fan: a fan of rulings
# about a point of a rail is a cone whose curvature grows without bound at its apex, where no kerf can follow it)
STEPS = ((1, 1), (2, 1), (1, 2))
# (a node repeated by a step would crawl at this fraction of the window)
EPS = 1e-4


def composed(C: Curve, xs: np.ndarray, ys: np.ndarray) -> Curve:
    """C(tau(x)) for the piecewise linear, increasing tau through (xs, ys) (xs over the new domain [0, 1], ys over
    C's, [0, 1] and round it: C closed, a value past 1 or below 0 is C's a period on): exactly, C's segment over
    each [ys[i], ys[i + 1]] mapped affinely onto [xs[i], xs[i + 1]], the segments joined with knots of full
    multiplicity (C0) at the breaks (a segment across C's seam split there first)."""
    X, Y = [float(x) for x in xs], [float(y) for y in ys]
    i = 0
    while i < len(X) - 1:                       # split where tau crosses a whole period
        k = float(np.floor(Y[i])) + 1.0
        if Y[i] < k < Y[i + 1]:
            X.insert(i + 1, X[i] + (k - Y[i]) * (X[i + 1] - X[i]) / (Y[i + 1] - Y[i]))
            Y.insert(i + 1, k)
        i += 1
    p = C.degree
    poles: list = []
    knots: list = []
    weights: list = []
    for i in range(len(X) - 1):
        sh = np.floor(min(Y[i], Y[i + 1] - 1e-15))
        seg = clamp_segment(C, Y[i] - sh, Y[i + 1] - sh)
        k = np.clip(X[i] + (seg.knots - seg.knots[0]) * (X[i + 1] - X[i]) / (seg.knots[-1] - seg.knots[0]),
                    X[i], X[i + 1])
        w = np.ones(seg.poles.shape[0]) if seg.weights is None else seg.weights
        if i:
            w = w * (weights[-1][-1] / w[0])               # the same weight at the joint
            poles.append(seg.poles[1:])
            weights.append(w[1:])
            knots.append(k[p + 1:-1])
        else:
            poles.append(seg.poles)
            weights.append(w)
            knots.append(k[:-1])
    knots.append([X[-1]])
    W = np.concatenate(weights)
    return Curve(np.concatenate(poles), np.concatenate(knots), p, None if C.weights is None else W)


def _ruled(A: Curve, B: Curve, v_knots) -> Surface:
    from ruled.fit.reparam import _merge_knots
    got = _merge_knots(A, B)
    if got is None:
        return None
    A, B = got
    return Surface(np.stack([A.poles, B.poles], axis=1), A.knots, np.asarray(v_knots, float), A.degree, 1)


def crossed(R: Surface, paths: dict) -> Surface:
    """R (ruled along v, polynomial, clamped, closed, s on [0, 1]) with both rails reparametrized piecewise
    linearly over each corner's window: paths: s_k -> (xs, a, b), the rulings R(a_i) - B(b_i) at the new
    parameters xs_i (increasing, both ends R's own rulings: a = b = xs there)."""
    A = Curve(R.poles[:, 0], R.knots_u, R.degree_u)
    B = Curve(R.poles[:, 1], R.knots_u, R.degree_u)
    got = [(np.array([0.0]),) * 3] + [w for _, w in sorted(paths.items())] + [(np.array([1.0]),) * 3]
    xs, ya, yb = (np.concatenate([np.asarray(w[k], float) for w in got]) for k in range(3))
    keep = np.concatenate([[True], np.diff(xs) > 0])
    return _ruled(composed(A, xs[keep], ya[keep]), composed(B, xs[keep], yb[keep]), R.knots_v)


def _ruling_costs(S_parts: list, R: Surface, a: np.ndarray, b: np.ndarray, u_of) -> np.ndarray:
    """(a.size, b.size): the largest distance from RULING_SAMPLES points of the segment R(a_i, 0) - R(b_j, 1) to
    the wall's smooth parts."""
    from ruled.core.distance import project_points
    t = np.linspace(0.0, 1.0, RULING_SAMPLES)
    P0, P1 = R(a, np.zeros(a.size)), R(b, np.ones(b.size))
    X = (1 - t)[None, None, :, None] * P0[:, None, None, :] + t[None, None, :, None] * P1[None, :, None, :]
    U = u_of((1 - t)[None, None, :] * a[:, None, None] + t[None, None, :] * b[None, :, None])
    T = np.broadcast_to(t, U.shape)
    X, U, T = X.reshape(-1, 3), U.ravel(), T.ravel()
    d = np.full(X.shape[0], np.inf)
    for lo, hi, P in S_parts:
        if not ((U >= lo - 0.1) & (U <= hi + 0.1)).any():
            continue
        v = P.domain[2] + T * (P.domain[3] - P.domain[2])
        d = np.minimum(d, project_points(P, X, np.stack([np.clip(U, lo, hi), v], axis=1), 8)[1])
    return d.reshape(a.size, b.size, RULING_SAMPLES).max(axis=2)


def _bottleneck(C: np.ndarray) -> list:
    """The monotone path (steps STEPS) from (0, 0) to the last node whose largest cost is the least (ties: the
    least sum), as its nodes."""
    n, m = C.shape
    best = np.full((n, m, 2), np.inf)
    best[0, 0] = (C[0, 0], C[0, 0])
    came = np.zeros((n, m, 2), int)
    for i in range(n):
        for j in range(m):
            if i == 0 and j == 0:
                continue
            for di, dj in STEPS:
                p, q = i - di, j - dj
                if p < 0 or q < 0:
                    continue
                got = (max(best[p, q, 0], C[i, j]), best[p, q, 1] + C[i, j])
                if tuple(got) < tuple(best[i, j]):
                    best[i, j] = got
                    came[i, j] = (p, q)
    path, (i, j) = [(n - 1, m - 1)], (n - 1, m - 1)
    while (i, j) != (0, 0):
        i, j = came[i, j]
        path.append((int(i), int(j)))
    return path[::-1]


def _strict(y: np.ndarray, eps: float) -> np.ndarray:
    """y (non-decreasing) made increasing: each run of equal values spread by eps a step, up from its first (down
    to its last where the run ends y: the ends stay)."""
    y = y.copy()
    k = 0
    while k < y.size:
        e = k
        while e + 1 < y.size and y[e + 1] == y[k]:
            e += 1
        if e > k:
            r = np.arange(e - k + 1)
            y[k:e + 1] = y[k] - eps * r[::-1] if e == y.size - 1 else y[k] + eps * r
        k = e + 1
    return y


def cross_corners(S_parts: list, R: Surface, corners: list, lengths: list, u_of) -> tuple:
    """(surface, count): R with its rulings over each corner's window paired anew (see the module doc), and how
    many corners were.  A window's pairing: the monotone path over NODES points of each rail a side, from the
    window's first ruling to its last, whose farthest ruling from the wall is the nearest; kept where that
    gains GAIN at least on R's own.  corners: R's s at each corner; lengths: per corner the shorter of the two
    pieces beside it (in s); u_of: R's s to the wall's u (round its seam)."""
    paths = {}
    for s, length in zip(corners, lengths):
        w = WINDOW * length
        if s - w <= 0.0 or s + w >= 1.0:
            continue            # (a window across the result's seam: left as it is)
        g = s + np.linspace(-w, w, 2 * NODES + 1)
        C = _ruling_costs(S_parts, R, np.mod(g, 1.0), np.mod(g, 1.0), u_of)
        path = _bottleneck(C)
        worst = max(C[i, j] for i, j in path)
        if worst >= GAIN * float(np.diag(C).max()):
            continue
        # breaks only where the path turns; a fan (one rail still) crawls at EPS of the window instead
        turns = [k for k in range(len(path)) if k in (0, len(path) - 1) or
                 np.subtract(path[k], path[k - 1]).tolist() != np.subtract(path[k + 1], path[k]).tolist()]
        K = len(path) - 1
        x = g[0] + 2 * w * np.array(turns) / K
        a = _strict(g[np.array([path[k][0] for k in turns])], EPS * w)
        b = _strict(g[np.array([path[k][1] for k in turns])], EPS * w)
        paths[s] = (x, a, b)
    return (crossed(R, paths), len(paths)) if paths else (R, 0)


__all__ = ["composed", "crossed", "cross_corners"]
