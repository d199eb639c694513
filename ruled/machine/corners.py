"""The wire's or tool's offset lines round a crease of the ruled surface (a corner both contours of a wall
share): pivoting round a convex one, stopping where the two offsets meet in a concave one."""

from __future__ import annotations

import math

import numpy as np

SAMPLES = 9        # samples along a ruling for its normals on either side of a crease


def ruling_normals(c: np.ndarray) -> np.ndarray:
    """Unit normals along each ruling from Su x Sv ((k, m, 3)), where that all but vanishes (a singular point:
    a cone's apex, where it is round-off) taken from the nearest sample of the same ruling that has one (a
    developable's normal is constant along a ruling)."""
    ln = np.linalg.norm(c, axis=2)
    zero = ln <= 1e-9 * ln.max(axis=1, keepdims=True)
    n = c / np.where(zero, 1.0, ln)[..., None]
    if not zero.any():
        return n
    n[zero] = 0.0
    for k, j in zip(*np.nonzero(zero)):
        good = np.nonzero(~zero[k])[0]
        if good.size:
            n[k, j] = n[k, good[np.argmin(np.abs(good - j))]]
    return n


def round_corners(lines, us: np.ndarray, a: np.ndarray, b: np.ndarray, tol: float) -> tuple:
    """(us, a, b, the inside corners' normal turns) of the offset lines (lines: ruled.machine.paths.Lines) round each
    crease of R (a C0 ruling: a corner both contours share). Convex on the offset side: the ruling moved by the
    radius along normals turning from the one before the crease to the one after, in steps whose chord stays
    within tol of the arc (a wire of radius k round the corner). Concave: the two offsets cross; one line where
    they meet (the mitre), the offset lines past it on either side (which would cut into the other face) left out."""
    R, k = lines.R, lines.radius
    creases = R.creases(0)
    turns: list = []
    if creases.size == 0 or k <= 0:
        return us, a, b, turns
    L = lines.domain[1] - lines.domain[0]
    for c in creases:
        eps = 1e-9 * L
        ts = np.linspace(lines.t[0], lines.t[1], SAMPLES)
        side = []
        for x in (c - eps, c + eps):
            D = R.evaluate(np.full(ts.size, x), ts, 1)
            n = lines.sign * ruling_normals(np.cross(D.Su, D.Sv)[None])[0].mean(axis=0)
            side.append(n / max(float(np.linalg.norm(n)), 1e-300))
        n0, n1 = side
        A, B = lines.rulings(np.array([c]))
        A, B = A[0], B[0]
        ang = float(np.arccos(np.clip(n0 @ n1, -1.0, 1.0)))
        # convex on the offset side: past the crease the surface turns away from the side the wire is on
        travel = R(np.array([c + 1e3 * eps]), np.array([lines.t[0]]))[0] - A
        if ang < math.radians(0.01):          # (a tangent joint of two faces)
            continue
        i = int(np.searchsorted(us, c - eps))
        if float(n0 @ travel) > 0:
            # concave: the two offsets cross; each guide is held where they meet (the mitre, found with the
            # lines' other loops: ruled.machine.loops), so nothing to add here but the corner's turn
            turns.append(ang)
            continue
        step = 2.0 * math.acos(max(-1.0, 1.0 - tol / k)) if tol < 2 * k else math.pi
        m = max(2, int(math.ceil(ang / step)) + 1)
        f = np.linspace(0.0, 1.0, m)[:, None]
        N = (np.sin((1 - f) * ang) * n0 + np.sin(f * ang) * n1) / math.sin(ang)
        cut = int(np.searchsorted(us, c + eps, side="right"))
        us = np.concatenate([us[:i], np.full(m, c), us[cut:]])
        a = np.concatenate([a[:i], A + k * N, a[cut:]])
        b = np.concatenate([b[:i], B + k * N, b[cut:]])
    return us, a, b, turns


__all__ = ["round_corners", "ruling_normals"]
