"""Plane geometry of conic arcs (Yang & Yang §3-4): a rational quadratic through its control triangle, where
two tangent lines meet, local convexity, the tangent chosen by reflection, barycentric coordinates and the
weight two arcs share."""

from __future__ import annotations

import numpy as np


def conic(P0, R, P2, w: float, t) -> np.ndarray:
    """Points (N, dim) of the standard rational quadratic Bézier arc (P0, R with weight w, P2)."""
    t = np.atleast_1d(np.asarray(t, float))[:, None]
    b0, b1, b2 = (1 - t) ** 2, 2 * w * t * (1 - t), t ** 2
    return (b0 * np.asarray(P0, float) + b1 * np.asarray(R, float) + b2 * np.asarray(P2, float)) / (b0 + b1 + b2)


def _cross(a, b) -> float:
    return float(a[0] * b[1] - a[1] * b[0])


def tangent_lines_meet(A, TA, B, TB):
    """(point, s, u) with point = A + s TA = B + u TB, or None when the lines are parallel."""
    den = _cross(TA, TB)
    scale = np.linalg.norm(TA) * np.linalg.norm(TB)
    if abs(den) <= 1e-14 * scale:
        return None
    d = np.asarray(B, float) - np.asarray(A, float)
    s = _cross(d, TB) / den
    u = _cross(d, TA) / den
    return np.asarray(A, float) + s * np.asarray(TA, float), s, u


def locally_convex(A, TA, B, TB) -> bool:
    """§3.2's first rule for the chord A -> B: the turn from TA to the chord and from the chord to TB
    have the same sign, and the tangent lines meet ahead of A and behind B (the control triangle)."""
    c = np.asarray(B, float) - np.asarray(A, float)
    s1, s2 = _cross(TA, c), _cross(c, TB)
    if not (s1 * s2 > 0):
        return False
    m = tangent_lines_meet(A, TA, B, TB)
    return m is not None and m[1] > 0 and m[2] < 0


def reflect(V, U) -> np.ndarray:
    """Eq. 4: V reflected about the chord direction U."""
    U = np.asarray(U, float) / np.linalg.norm(U)
    W = 2 * (np.asarray(V, float) @ U) * U - np.asarray(V, float)
    return W / np.linalg.norm(W)


def choose_tangent(A, TA, B, V):
    """The tangent at B after the chord A -> B (§3.2): V (eq. 3) when the triangle is locally convex;
    V reflected about the chord (eq. 4) when the turns have opposite signs; otherwise the one
    closest to it, moved towards the circular-arc tangent (TA mirrored about the chord), that is.
    None when no tangent is (TA turns by 90 degrees or more from the chord: the step is too long)."""
    V = np.asarray(V, float) / np.linalg.norm(V)
    if locally_convex(A, TA, B, V):
        return V
    U = np.asarray(B, float) - np.asarray(A, float)
    if _cross(TA, U) * _cross(U, V) < 0:
        V = reflect(V, U)
        if locally_convex(A, TA, B, V):
            return V
    circ = reflect(TA, U)                      # isosceles triangle: convex whenever TA turns < 90 deg to U
    if not locally_convex(A, TA, B, circ):
        return None
    lo, hi = 0.0, 1.0                          # blend V -> circ, keep the convex end
    for _ in range(50):
        m = 0.5 * (lo + hi)
        T = (1 - m) * V + m * circ
        if np.linalg.norm(T) > 0 and locally_convex(A, TA, B, T / np.linalg.norm(T)):
            hi = m
        else:
            lo = m
    T = (1 - hi) * V + hi * circ
    return T / np.linalg.norm(T)


def barycentric(P, A, R, B) -> np.ndarray:
    """Barycentric coordinates (N, 3) of the points P (N, 2) in the triangle (A, R, B)."""
    P = np.atleast_2d(np.asarray(P, float))
    A, R, B = (np.asarray(x, float) for x in (A, R, B))
    det = _cross(R - A, B - A)
    tr = ((R[0] - P[:, 0]) * (B[1] - P[:, 1]) - (R[1] - P[:, 1]) * (B[0] - P[:, 0])) / det
    tb = ((A[0] - P[:, 0]) * (R[1] - P[:, 1]) - (A[1] - P[:, 1]) * (R[0] - P[:, 0])) / det
    return np.stack([tr, 1 - tr - tb, tb], axis=1)


def shared_weight(tri0, pts0, tri1, pts1, default: float = 2.0) -> float:
    """The discrete eq. 5: the weight w with sum over the boundary samples inside their triangle of
    4 w^2 tau0 tau2 - tau1^2 = 0 (Floater's implicit form of the conic), i.e. w^2 = sum tau1^2 /
    (4 sum tau0 tau2); the paper's default 2 when no sample lies inside either triangle."""
    num = den = 0.0
    for tri, pts in ((tri0, pts0), (tri1, pts1)):
        if tri is None or len(pts) == 0:
            continue
        tau = barycentric(pts, *tri)
        inside = np.all(tau >= -1e-12, axis=1)
        num += float((tau[inside, 1] ** 2).sum())
        den += float(4 * (tau[inside, 0] * tau[inside, 2]).sum())
    if den <= 0 or num <= 0:
        return default
    return float(np.sqrt(num / den))


_UNIT: dict = {}


def _unit_grid(n: int) -> np.ndarray:
    g = _UNIT.get(n)
    if g is None:
        g = _UNIT[n] = np.linspace(0.0, 1.0, n)
    return g


def _grid(lo: float, hi: float, n: int) -> np.ndarray:
    """n points from lo to hi (both included), without np.linspace's overhead."""
    g = lo + (hi - lo) * _unit_grid(n)
    g[-1] = hi
    return g
