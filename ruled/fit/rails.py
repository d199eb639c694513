"""The result's rails rebuilt from a pairing (issue 36): one rail its boundary curve itself, exact (rational
where the boundary is), the other composed with the pairing and fitted in the first one's space, where
that is closer or smaller than both composed (ruled.fit.reparam.fit_boundaries); and a result's rails
compacted to the fewest poles its bound allows."""

from __future__ import annotations

from dataclasses import replace
from typing import Any, Callable, Optional, Union

import numpy as np

from ruled.core.basis import bspline_basis_matrix
from ruled.core.knots import clamp_segment, elevate, insert_knot, knot_multiplicity
from ruled.core.nurbs import Curve, Surface
from ruled.fit.dp.pairing import Pairing, RailPairing
from ruled.fit.reparam import (
    MIN_SPAN,
    Boundaries,
    _continuity,
    _mapped_knots,
    _merge_knots,
    _rotated,
    exact_boundaries,
    fit_boundaries,
    ruled_surface,
)


def _segment(C: Curve, u0: float, L: float, x0: float, x1: float, closed: bool) -> Optional[Curve]:
    """C(u0 + L (x0 + (x1 - x0) s)), s in [0, 1], exactly, as a clamped curve (closed: one period)."""
    if closed:
        return _rotated(C, u0, L, x0, True)
    lo, hi = C.domain
    ua, ub = u0 + L * x0, u0 + L * x1
    slack = 1e-12 * (hi - lo)
    if ua < lo - slack or ub > hi + slack or ub - ua <= 1e-9 * (hi - lo):
        return None
    ua, ub = max(ua, lo), min(ub, hi)
    seg = clamp_segment(C, ua, ub)
    return Curve(seg.poles, (seg.knots - ua) / (ub - ua), seg.degree, seg.weights)


def _rail_design(E: Curve, s: np.ndarray) -> np.ndarray:
    """The basis of E's space at s, rational with E's weights (a curve sum_j M_ij Q_j shares them)."""
    M = bspline_basis_matrix(E.knots, E.degree, s)
    if E.weights is None:
        return M
    M = M * E.weights[None, :]
    return M / M.sum(axis=1, keepdims=True)


def _rail_conditions(E: Curve, ends: np.ndarray, closed: bool, kinks: np.ndarray) -> tuple:
    """(C, d): linear conditions C Q = d on the poles Q of a rail in E's space (E's knots and weights): its
    end points, and a first derivative as continuous as E's where a knot of E's has full multiplicity
    (a rational arc's joint, a degree-elevated curve's knots) and at a closed rail's seam, unless the
    composed rail has a kink of its own there (kinks).  A rail whose derivative jumps where the face's
    does not makes the certificate count a kink there."""
    p, k, n = E.degree, E.knots, E.poles.shape[0]
    w = np.ones(n) if E.weights is None else E.weights
    rows, vals = [np.eye(1, n, 0)[0], np.eye(1, n, n - 1)[0]], [ends[0], ends[1]]
    # (j - 1, j, j + 1, left span, right span): the curve passes through pole j there (both ends' poles at a seam)
    joints: list[tuple[int, Union[int, tuple], int, float, float]] = []
    ks, counts = np.unique(k[p + 1:-p - 1], return_counts=True)
    for x, m in zip(ks, counts):
        if m < p or (kinks.size and np.abs(kinks - x).min() < 1e-6) or _continuity(E, x) < 1:
            continue
        i = int(np.searchsorted(k, x, side="left"))
        joints.append((i - 2, i - 1, i, x - k[i - 1], k[i + p] - x))
    if closed and _continuity_seam(E):
        joints.append((n - 2, (n - 1, 0), 1, k[-1] - k[n - 1], k[p + 1] - k[p]))
    for jm, j, jp, hl, hr in joints:
        jl, jr = (j, j) if isinstance(j, int) else j
        r = np.zeros(n)
        r[jl] += w[jm] / (hl * w[jl])
        r[jm] -= w[jm] / (hl * w[jl])
        r[jp] -= w[jp] / (hr * w[jr])
        r[jr] += w[jp] / (hr * w[jr])
        rows.append(r)
        vals.append(np.zeros_like(ends[0]))
    return np.array(rows), np.array(vals)


def _continuity_seam(E: Curve) -> bool:
    """Whether a closed curve's first derivative is continuous across its seam (measured)."""
    d = E.evaluate(np.array(E.domain), 1)[1]
    return float(np.linalg.norm(d[0] - d[1])) <= 1e-4 * float(np.linalg.norm(d[0]) + np.linalg.norm(d[1]))


def _constrained_lstsq(M: np.ndarray, T: np.ndarray, C: np.ndarray, d: np.ndarray) -> np.ndarray:
    """min |M Q - T| subject to C Q = d (C of full row rank), by the null space of C."""
    Qp = np.linalg.lstsq(C, d, rcond=None)[0]
    _, sv, Vt = np.linalg.svd(C)
    Z = Vt[int(np.count_nonzero(sv > 1e-12 * sv[0])):].T
    y = np.linalg.lstsq(M @ Z, T - M @ Qp, rcond=None)[0]
    return Qp + Z @ y


# the composed rail's knots are refined at most this many times
ROUNDS = 16


def rail_boundaries(C0: Curve, C1: Curve, u0: float, L: float, pairing: Pairing, tol: float, which: str,
                    max_poles: int = 160, focus_of: Optional[Callable] = None):
    """Boundaries in which one rail (which: 'a' the v-min one, 'b' the v-max one) is its boundary curve
    itself over the pairing's range (exact: same degree, raised to 3 at least, same knots and weights)
    and the other, the composition of its curve with the pairing, is fitted in the first one's space
    (its knots, refined where the error exceeds tol, and its weights: a rational rail stays rational, and
    a composed rail that is an affine image of the first, as on a surface of revolution, is exact).
    Returns (Boundaries, RailPairing: the pairing in the result's own s), or None where this does not apply
    (polyline rails, a pairing past the boundary).  focus_of(pairing) -> (s0, s1) or None: the range
    where the tolerance holds (ruled.fit.face.cost.face_span)."""
    closed = pairing.closed
    a, b = pairing.ab(np.array([0.0, 1.0]))
    x0, x1 = (a if which == "a" else b)
    if (closed and abs(x1 - x0 - 1.0) > 1e-9) or x1 - x0 <= 1e-9 or (C0.degree == 1 and C1.degree == 1):
        return None
    pr = RailPairing(pairing, which, float(x0), float(x1))
    C, D = (C0, C1) if which == "a" else (C1, C0)
    other = "b" if which == "a" else "a"
    E = _segment(C, u0, L, float(x0), float(x1), closed)
    if E is None:
        return None
    p = max(3, C0.degree, C1.degree)
    E = elevate(E, p)
    focus = focus_of(pr) if focus_of is not None else None
    lo, hi = D.domain

    def target(s):
        y = pr.ab(s)[1 if which == "a" else 0]
        u = u0 + L * y
        u = lo + np.mod(u - lo, hi - lo) if closed else np.clip(u, lo, hi)
        return D(u)

    sk, mk = _mapped_knots(D, u0, L, pr, other, p)     # where the composed rail's derivatives jump
    ends = target(np.array([0.0, 1.0]))
    if closed:
        ends[1] = ends[0]
    for _round in range(ROUNDS):
        edges = np.unique(E.knots)
        per = 3 * (p + 1)
        sfit = np.concatenate([np.linspace(e0, e1, per, endpoint=False) for e0, e1 in zip(edges[:-1], edges[1:])]
                              + [[1.0]])
        M = _rail_design(E, sfit)
        Q = _constrained_lstsq(M, target(sfit), *_rail_conditions(E, ends, closed, sk))
        schk = np.concatenate([np.linspace(e0, e1, 2 * per + 1)[1:-1] for e0, e1 in zip(edges[:-1], edges[1:])])
        err = np.linalg.norm(_rail_design(E, schk) @ Q - target(schk), axis=1)
        err_fit = np.linalg.norm(M @ Q - target(sfit), axis=1)
        if focus is not None:
            err = np.where((schk >= focus[0]) & (schk <= focus[1]), err, 0.0)
            err_fit = np.where((sfit >= focus[0]) & (sfit <= focus[1]), err_fit, 0.0)
        emax = float(max(err.max(), err_fit.max()))
        span = np.searchsorted(edges, schk, side="right") - 1
        bad = np.unique(span[err > tol])
        bad = bad[edges[bad + 1] - edges[bad] >= 2.0 * MIN_SPAN]
        if emax <= tol or E.poles.shape[0] >= max_poles or bad.size == 0 or _round == ROUNDS - 1:
            break
        for i in bad:
            e0, e1 = edges[i], edges[i + 1]
            inside = (sk > e0 + 0.1 * (e1 - e0)) & (sk < e1 - 0.1 * (e1 - e0))
            if inside.any():     # the composed rail's own kink: a knot of its multiplicity there
                j = int(np.flatnonzero(inside)[0])
                E = insert_knot(E, float(sk[j]), min(int(mk[j]), p - knot_multiplicity(E.knots, float(sk[j]))))
            else:
                E = insert_knot(E, 0.5 * (e0 + e1))
    E = Curve(E.poles, E.knots, p, E.weights, closed)
    F = Curve(Q, E.knots, p, E.weights, closed)
    A, B = (E, F) if which == "a" else (F, E)
    ks, counts = np.unique(E.knots, return_counts=True)
    kinks = ks[(counts >= p) & (ks > 0) & (ks < 1)]
    return Boundaries(A, B, emax, kinks), pr


def rebuilt_boundaries(C0: Curve, C1: Curve, u0: float, L: float, pairing: Pairing, tol: float,
                       focus_of: Optional[Callable] = None, exact: bool = False):
    """The result's rails for a pairing: (Boundaries, the pairing in the result's s).  Exact where the
    pairing is a shift; else both composed (fit_boundaries), or, where a boundary is rational and the
    rulings exact (exact: a conic's surface of revolution, say), one rail exact and the other composed
    (rail_boundaries, either way round) when closer (compact_fit makes the result smaller afterwards).
    (Not on a face far from ruled: a rational rail taken as it is, extreme weights and all, can certify
    far looser than composed ones.)"""
    bd = exact_boundaries(C0, C1, u0, L, pairing)
    if bd is not None:
        return bd, pairing
    focus = focus_of(pairing) if focus_of is not None else None
    cands = [(fit_boundaries(C0, C1, u0, L, pairing, tol, focus=focus), pairing)]
    if not (exact and (C0.rational or C1.rational)):
        return cands[0]     # (a polynomial rail taken as it is carries its patch's knots: no smaller, often looser)
    for which in ("a", "b"):
        got = rail_boundaries(C0, C1, u0, L, pairing, tol, which, focus_of=focus_of)
        if got is not None:
            cands.append(got)
    return min(cands, key=lambda c: (c[0].fit_error, c[0].A.poles.shape[0]))


# ----------------------------------------------------------------------------- compaction
def _difference_bound(F: Curve, G: Curve) -> float:
    """An upper bound of max_s |F(s) - G(s)| for two non-rational clamped curves of one degree on one
    range: their largest pole difference once each carries the other's knots (the difference is a spline
    with those poles, inside their convex hull)."""
    merged = _merge_knots(F, G, 1e-13)
    if merged is None:
        return np.inf
    return float(np.linalg.norm(merged[0].poles - merged[1].poles, axis=1).max())


def compact_boundaries(bd: Boundaries, budget: float, n_start: int = 4) -> Optional[tuple]:
    """The rails bd in fewer poles: coarse to fine (uniform spans, bd's kinks kept, each span halved while
    the rails leave the samples farther than a third of the budget), the first whose certified distance
    from bd (_difference_bound, both rails) is within budget and that has fewer poles.  (Boundaries,
    distance) or None (rational or closed rails, or nothing smaller within the budget).  The ruled surface
    between the new rails is then within that distance of the old one everywhere (R is linear in t)."""
    A, B = bd.A, bd.B
    p = A.degree
    n0 = A.poles.shape[0]
    if A.rational or B.rational or A.periodic or not np.isfinite(budget) or budget <= 0.0 or n0 <= n_start + p:
        return None
    lo, hi = A.domain
    if lo != 0.0 or hi != 1.0:
        return None
    kinks = np.unique(bd.kinks)
    br = np.unique(np.concatenate([np.linspace(0.0, 1.0, n_start + 1)[1:-1], kinks]))
    for _round in range(12):
        mult = np.where(np.isin(br, kinks), p, 1)
        knots = np.concatenate([np.zeros(p + 1), np.repeat(br, mult), np.ones(p + 1)])
        n = knots.size - p - 1
        if n >= n0:
            return None
        edges = np.concatenate([[0.0], br, [1.0]])
        per = 3 * (p + 1)
        s = np.concatenate([np.linspace(e0, e1, per, endpoint=False) for e0, e1 in zip(edges[:-1], edges[1:])]
                           + [[1.0]])
        M = bspline_basis_matrix(knots, p, s)
        T = np.hstack([A(s), B(s)])
        ends = np.vstack([T[0], T[-1]])
        Q = _constrained_lstsq(M, T, np.array([np.eye(1, n, 0)[0], np.eye(1, n, n - 1)[0]]), ends)
        A2, B2 = Curve(Q[:, :3], knots, p), Curve(Q[:, 3:], knots, p)
        dist = max(_difference_bound(A2, A), _difference_bound(B2, B))
        if dist <= budget:
            return Boundaries(A2, B2, bd.fit_error + dist, br[mult >= p]), dist
        sc = np.concatenate([np.linspace(e0, e1, 2 * per + 1)[1:-1] for e0, e1 in zip(edges[:-1], edges[1:])])
        err = np.maximum(np.linalg.norm(A2(sc) - A(sc), axis=1), np.linalg.norm(B2(sc) - B(sc), axis=1))
        span = np.searchsorted(edges, sc, side="right") - 1
        bad = np.unique(span[err > budget / 3.0])
        if bad.size == 0:      # the samples are within, the poles not: halve the worst span
            bad = np.array([int(span[np.argmax(err)])])
        br = np.unique(np.concatenate([br, 0.5 * (edges[bad] + edges[bad + 1])]))
    return None


# a result is compacted (fewer poles) as far as this fraction of its certified bound allows
COMPACT = 0.01


def compact_fit(fit: Any, budget: float) -> Any:
    """The fit (an untrimmed ruled.fit.fit2d.DirectionFit) in the fewest poles that keep its certified bound
    within budget of the bound it has (compact_boundaries): the bound grows by the certified distance
    between the two results (recorded as the certificate's compaction, with the poles per rail before it).
    The fit itself where nothing smaller is within budget.  (A trimmed fit keeps its rails: its trim and a
    flank path follow its certificate's map.)"""
    if fit.boundaries is None or fit.trim is not None:
        return fit
    got = compact_boundaries(fit.boundaries, budget)
    if got is None:
        return fit
    bd, dist = got
    cert = fit.certificate
    cert = replace(cert, bound=cert.bound + dist, compaction=cert.compaction + dist,
                   compacted_from=cert.compacted_from or int(fit.boundaries.A.poles.shape[0]))
    return replace(fit, surface=ruled_surface(bd), boundaries=bd, certificate=cert)


def net_bound(S: Any, pairing: Any, bd: Boundaries) -> Optional[float]:
    """For a result ruled along S's own v-lines (the pairing the identity, the rails S's boundary curves
    re-knotted: ruled.fit.reparam.exact_boundaries), both polynomial: an upper bound of
    sup |S(u, v) - R(psi(u, v))| for a map psi of S's domain onto R's (see below), hence of their distance,
    from S's poles and R's rails' poles alone.  None where this does not apply (rational or periodic
    surfaces, another pairing)."""
    A, B = bd.A, bd.B
    q, kv = S.degree_v, S.knots_v
    clamped = np.all(kv[:q + 1] == kv[0]) and np.all(kv[-q - 1:] == kv[-1])     # (its rows 0 and -1 its rails)
    if S.weights is not None or A.rational or B.rational or S.periodic_u or S.periodic_v or not clamped:
        return None
    u0, u1, v0, v1 = S.domain
    ku = (S.knots_u - u0) / (u1 - u0)
    if (A.degree != S.degree_u or A.knots.shape != ku.shape or np.abs(A.knots - ku).max() > 1e-12
            or not np.array_equal(A.knots, B.knots)):
        return None
    s = np.linspace(0.0, 1.0, 33)
    a, b = pairing.ab(s)
    if max(np.abs(a - s).max(), np.abs(b - s).max()) > 1e-12:
        return None
    # S's poles P_ij = A_i + G_ij D_i + N_ij (D = B - A, G_ij in [0, 1], N_ij the rest), so that
    # S(u, v) = A(s) + sum_i N_i(u) g_i(v) D_i + sum_ij N_i M_j N_ij with g_i(v) = sum_j M_j(v) G_ij in [0, 1].
    # psi = (s(u), gbar(u, v)), gbar = sum_i N_i(u) g_i(v): continuous, in R's domain, sides to sides; and
    # S - R o psi = sum_i N_i (g_i - gbar)(D_i - D(s)) + sum_ij N_i M_j N_ij (the sum_i N_i (g_i - gbar) D(s)
    # part is zero), each bounded over a knot span of u by its p + 1 poles' spreads: a face parametrized
    # along its rulings otherwise than affinely in v (an interpolated one) is certified as close as it is.
    # The same surfaces with every knot span split in NET_PIECES: their nets lie closer to them.
    Sn = Surface(S.poles, ku, (S.knots_v - v0) / (v1 - v0), S.degree_u, S.degree_v)
    Sn = Sn.subdivided(NET_PIECES, NET_PIECES)
    Rn = ruled_surface(bd).subdivided(NET_PIECES, 1)
    if not np.array_equal(Sn.knots_u, Rn.knots_u):
        return None
    return _net_distance(Sn, Rn.poles[:, 0], Rn.poles[:, 1])


# knot spans are split in this many pieces for net_bound
NET_PIECES = 4


def _net_distance(S: Any, A: np.ndarray, B: np.ndarray) -> float:
    """net_bound's figure for S's poles and the rails' poles A, B (one knot vector along u)."""
    D = B - A
    G = np.clip(np.einsum("ijk,ik->ij", S.poles - A[:, None, :], D)
                / np.maximum((D * D).sum(axis=1), 1e-300)[:, None], 0.0, 1.0)
    G[:, 0], G[:, -1] = 0.0, 1.0        # gbar exactly 0 and 1 on the rails (psi takes sides to sides)
    rest = float(np.linalg.norm(S.poles - A[:, None, :] - G[:, :, None] * D[:, None, :], axis=2).max())
    p = S.degree_u
    win = np.lib.stride_tricks.sliding_window_view
    Gw = win(G, p + 1, axis=0)                      # (spans, nv, p + 1)
    spread_g = (Gw.max(axis=2) - Gw.min(axis=2)).max(axis=1)
    Dw = win(D, p + 1, axis=0)                      # (spans, 3, p + 1)
    spread_d = np.linalg.norm(Dw[:, :, :, None] - Dw[:, :, None, :], axis=1).max(axis=(1, 2))
    return rest + float((spread_g * spread_d).max())
