"""Curves on surfaces (Yang et al. 2008), the domain side: Bézier pieces of a domain curve split at its
knots, at the surface's knot lines and into single-sided pieces (§3), the Hausdorff distance of a
piece to its chord (§4, eqs. 13–17) and the 2D tolerance of a knot span (eqs. 7–12).

A piece is a planar Bézier curve given by its control points (d + 1, 2) and the parameter
interval [t0, t1] of the domain curve it came from.  Still to come (the rest of §§4–5): the
subdivision loops for the distance and the angle tolerance, and the mapping of the final
polyline with ruled.compose.
"""

from __future__ import annotations

from dataclasses import dataclass
from math import comb

import numpy as np

from .errors import BadInputError
from .knots import clamp_segment
from .nurbs import Curve, Surface, find_spans

_EPS = 1e-12


@dataclass(frozen=True)
class Piece:
    ctrl: np.ndarray   # (d + 1, 2) Bézier control points in (u, v)
    t0: float          # parameter interval on the domain curve
    t1: float


def bezier_eval(ctrl: np.ndarray, t) -> np.ndarray:
    """Points of the Bézier curve at t (de Casteljau), (N, dim)."""
    t = np.atleast_1d(np.asarray(t, float))
    c = np.broadcast_to(ctrl, (t.size,) + ctrl.shape).copy()
    for _ in range(ctrl.shape[0] - 1):
        c = (1 - t)[:, None, None] * c[:, :-1] + t[:, None, None] * c[:, 1:]
    return c[:, 0]


def bezier_split(ctrl: np.ndarray, t: float) -> tuple[np.ndarray, np.ndarray]:
    """The two halves of a Bézier curve at t (de Casteljau)."""
    left, right = [ctrl[0]], [ctrl[-1]]
    c = ctrl
    while c.shape[0] > 1:
        c = (1 - t) * c[:-1] + t * c[1:]
        left.append(c[0])
        right.append(c[-1])
    return np.array(left), np.array(right[::-1])


def _bernstein_to_power(b: np.ndarray) -> np.ndarray:
    """Power-basis coefficients (ascending) of the scalar Bernstein polynomial with coefficients b."""
    n = b.shape[0] - 1
    a = np.zeros(n + 1)
    for k in range(n + 1):
        for i in range(k + 1):
            a[k] += comb(n, k) * comb(k, i) * (-1) ** (k - i) * b[i]
    return a


def _roots01(b: np.ndarray) -> np.ndarray:
    """Real roots in (0, 1) of a scalar Bernstein polynomial (sorted; none when it vanishes)."""
    a = _bernstein_to_power(np.asarray(b, float))
    if np.all(np.abs(a) <= _EPS * max(1.0, np.abs(b).max())):
        return np.zeros(0)
    r = np.polynomial.polynomial.polyroots(np.trim_zeros(a, "b")) if np.any(a[1:]) else np.zeros(0)
    r = r[np.abs(r.imag) <= 1e-9].real
    return np.sort(r[(r > 1e-9) & (r < 1 - 1e-9)])


def _split_at(piece: Piece, ts: np.ndarray) -> list[Piece]:
    out, rest, lo = [], piece.ctrl, 0.0
    for t in ts:
        s = (t - lo) / (1.0 - lo)
        left, rest = bezier_split(rest, s)
        out.append(left)
        lo = t
    out.append(rest)
    bounds = np.concatenate([[0.0], ts, [1.0]])
    return [Piece(c, piece.t0 + (piece.t1 - piece.t0) * a, piece.t0 + (piece.t1 - piece.t0) * b)
            for c, a, b in zip(out, bounds[:-1], bounds[1:])]


def _cross_with_chord(ctrl: np.ndarray) -> np.ndarray:
    """Bernstein coefficients of (C(t) - P0) x (Pn - P0) (degree unchanged: it is linear in C)."""
    d = ctrl[-1] - ctrl[0]
    w = ctrl - ctrl[0]
    return w[:, 0] * d[1] - w[:, 1] * d[0]


def single_sided(piece: Piece) -> list[Piece]:
    """Split a piece where it crosses its own chord (§3), so every part lies on one side of its chord."""
    ts = _roots01(_cross_with_chord(piece.ctrl))
    if ts.size == 0:
        return [piece]
    return [q for p in _split_at(piece, ts) for q in single_sided(p)]


def domain_pieces(D: Curve, S: Surface) -> list[Piece]:
    """§3: the Bézier pieces of the (polynomial, 2D) domain curve D, split at its knots, where it
    crosses an interior knot line of S, and into single-sided pieces."""
    if D.rational:
        raise BadInputError("rational domain curves are not supported yet; give a polynomial B-spline or "
                            "a polyline of (u, v) points")
    if D.poles.shape[1] != 2:
        raise BadInputError("the domain curve must have 2D (u, v) points")
    lo, hi = D.domain
    br = np.unique(D.knots[(D.knots > lo) & (D.knots < hi)])
    edges = np.concatenate([[lo], br, [hi]])
    ku = np.unique(S.interior_knots("u"))
    kv = np.unique(S.interior_knots("v"))
    out = []
    for a, b in zip(edges[:-1], edges[1:]):
        ctrl = clamp_segment(D, a, b).poles
        piece = Piece(ctrl, float(a), float(b))
        ts = [_roots01(ctrl[:, 0] - k) for k in ku] + [_roots01(ctrl[:, 1] - k) for k in kv]
        ts = np.unique(np.concatenate(ts)) if ts else np.zeros(0)
        for p in _split_at(piece, ts):
            out.extend(single_sided(p))
    return out


def chord_distance(ctrl: np.ndarray) -> tuple[float, float]:
    """H(C, chord) of a single-sided planar Bézier curve and its chord (§4): the largest distance of
    the candidate points (ends, tangent parallel to the chord (eq. 15), the crossings of the end
    perpendiculars, and the points whose tangent is perpendicular to the line to an end (eqs.
    16–17)).  Returns (distance, parameter of the farthest point)."""
    P0, Pn = ctrl[0], ctrl[-1]
    d = Pn - P0
    L2 = float(d @ d)
    n = ctrl.shape[0] - 1
    cand = [np.array([0.0, 1.0])]
    if n >= 2:
        diff = n * (ctrl[1:] - ctrl[:-1])                          # derivative's Bernstein net (degree n - 1)
        V = np.array([-d[1], d[0]])
        cand.append(_roots01(diff @ V))                            # eq. 15
        cand.append(_roots01((ctrl - P0) @ d))                     # perpendicular at P0
        cand.append(_roots01((ctrl - Pn) @ d))                     # perpendicular at Pn
        for E in (P0, Pn):                                         # eqs. 16-17 on a fine grid, polished
            t = np.linspace(0.0, 1.0, 8 * n + 1)
            f = np.einsum("ij,ij->i", _deriv(ctrl, t), bezier_eval(ctrl, t) - E)
            sign = np.nonzero(np.sign(f[:-1]) * np.sign(f[1:]) < 0)[0]
            for k in sign:
                a, b = t[k], t[k + 1]
                fa = f[k]
                for _ in range(60):  # bisection
                    m = 0.5 * (a + b)
                    fm = float(_deriv(ctrl, [m])[0] @ (bezier_eval(ctrl, m)[0] - E))
                    a, b, fa = (a, m, fa) if fa * fm <= 0 else (m, b, fm)
                cand.append(np.array([0.5 * (a + b)]))
    t = np.concatenate(cand)
    X = bezier_eval(ctrl, t)
    s = np.clip(((X - P0) @ d) / L2, 0.0, 1.0) if L2 > 0 else np.zeros(t.size)
    dist = np.linalg.norm(X - (P0 + s[:, None] * d), axis=1)
    k = int(np.argmax(dist))
    return float(dist[k]), float(t[k])


def _deriv(ctrl: np.ndarray, t) -> np.ndarray:
    n = ctrl.shape[0] - 1
    return n * bezier_eval(ctrl[1:] - ctrl[:-1], t)


def span_tolerance(S: Surface, eps: float, u: float, v: float, bounds: dict | None = None) -> float:
    """Eq. 12: the domain tolerance d of the knot span containing (u, v) so that a domain polyline
    within d of the domain curve maps within eps of its exact image: d = eps / (max|S_u| + max|S_v|)
    over the span (rigorous control-net bounds, rational surfaces included)."""
    b = bounds if bounds is not None else S.derivative_bounds()
    iu = int(find_spans(S.knots_u, S.degree_u, S.poles.shape[0], np.array([u]))[0]) - S.degree_u
    iv = int(find_spans(S.knots_v, S.degree_v, S.poles.shape[1], np.array([v]))[0]) - S.degree_v
    return float(eps / (b["Su"][iu, iv] + b["Sv"][iu, iv]))
