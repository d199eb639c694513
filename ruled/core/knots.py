"""Knot tools on curves: Boehm insertion, multiplicities, clamped segments (exact operations)."""

from __future__ import annotations

import numpy as np

from ruled.core.basis import basis_derivatives, bspline_basis_matrix, find_spans
from ruled.core.nurbs import Curve


def insert_knot(C: Curve, u: float, times: int = 1) -> Curve:
    """Boehm knot insertion (in homogeneous coordinates): the same curve with u inserted ``times``."""
    P = C._hom.copy()
    k = C.knots.copy()
    p = C.degree
    for _ in range(times):
        n = P.shape[0]
        i = int(find_spans(k, p, n, np.array([u]))[0])
        Q = np.empty((n + 1, P.shape[1]))
        Q[: i - p + 1] = P[: i - p + 1]
        Q[i + 1:] = P[i:]
        for j in range(i - p + 1, i + 1):
            den = k[j + p] - k[j]
            a = 0.0 if den == 0 else (u - k[j]) / den
            Q[j] = a * P[j] + (1 - a) * P[j - 1]
        P = Q
        k = np.insert(k, i + 1, u)
    w = P[:, -1]
    weights = None if C.weights is None else w
    return Curve(P[:, :-1] / w[:, None], k, p, weights, C.periodic)


def span_bezier(H: np.ndarray, knots: np.ndarray, p: int, i: int) -> np.ndarray:
    """Bézier coefficients (p + 1, ...) of the spline with coefficients H (n, ...) on its knot span
    [knots[i], knots[i + 1]] (non-empty): coefficient k is the blossom at (knots[i] p - k times,
    knots[i + 1] k times), by de Boor's triangle, all k at once."""
    a, b = knots[i], knots[i + 1]
    ks = np.arange(p + 1)
    d = np.broadcast_to(H[i - p: i + 1], (p + 1,) + H[i - p: i + 1].shape).astype(float)   # (k, j, ...)
    extra = (1,) * (H.ndim - 1)
    for r in range(1, p + 1):
        j = np.arange(i - p + r, i + 1)
        x = np.where(r - 1 < p - ks, a, b)[:, None]
        alpha = ((x - knots[j]) / (knots[j + p + 1 - r] - knots[j])).reshape((p + 1, j.size) + extra)
        d = (1 - alpha) * d[:, :-1] + alpha * d[:, 1:]
    return d[:, 0]


def knot_multiplicity(knots: np.ndarray, u: float, tol: float = 0.0) -> int:
    return int(np.sum(np.abs(knots - u) <= tol))


def clamp_segment(C: Curve, a: float, b: float) -> Curve:
    """The piece of C on [a, b] (inside its domain) as a clamped curve, by knot insertion."""
    p = C.degree
    for x in (a, b):
        m = knot_multiplicity(C.knots, x)
        if m < p:
            C = insert_knot(C, x, p - m)
    k = C.knots
    inner = k[(k > a) & (k < b)]
    knots = np.concatenate([np.full(p + 1, a), inner, np.full(p + 1, b)])
    last_a = int(np.searchsorted(k, a, side="right")) - 1  # last occurrence of a
    first = last_a - p  # C(a) is this pole when a has multiplicity >= p
    n = knots.size - p - 1
    P = C.poles[first: first + n]
    W = None if C.weights is None else C.weights[first: first + n]
    return Curve(P, knots, p, W)


def elevate(C: Curve, q: int) -> Curve:
    """C raised to degree q >= its own, exactly (to round-off): every knot's multiplicity raised by q - p
    (the same continuity), the homogeneous coefficients solved from samples of C in each span (the
    curve lies in that space, so the least-squares solution is it)."""
    p = C.degree
    if q <= p:
        return C
    k = C.knots
    lo, hi = C.domain
    ks, mult = np.unique(k[(k > lo) & (k < hi)], return_counts=True)
    knots = np.concatenate([np.full(q + 1, lo), np.repeat(ks, mult + (q - p)), np.full(q + 1, hi)])
    edges = np.concatenate([[lo], ks, [hi]])
    x = np.concatenate([np.linspace(a, b, q + 3) for a, b in zip(edges[:-1], edges[1:])])
    n = C.poles.shape[0]
    spans = find_spans(k, p, n, x)
    B = basis_derivatives(k, p, spans, x, 0)[0]
    H = np.einsum("nj,njd->nd", B, C._hom[spans[:, None] - p + np.arange(p + 1)[None, :]])
    M = bspline_basis_matrix(knots, q, x)
    sol = np.linalg.lstsq(M, H, rcond=None)[0]
    w = sol[:, -1]
    return Curve(sol[:, :-1] / w[:, None], knots, q, None if C.weights is None else w, C.periodic)
