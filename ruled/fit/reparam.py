"""From a DP pairing to a smooth ruled surface (Elber eq. 5, beyond the paper: §5b/§6 of the issue).

Coordinates: a boundary parameter u is written u = u0 + L x with x the
normalized parameter (L the range, or the period of a closed boundary).  A
pairing is a monotone path of (a, b) = (x on C0, x on C1).  It is handled in
rotated coordinates sigma = (a + b) / 2, delta = (b - a) / 2: every DP move
increases sigma, so the path is a function delta(sigma) with |delta'| <= 1;
a smooth pairing with |delta'| <= 1 - eps is strictly monotone in both a and b.

1. refine_pairing: for every sigma of a fine grid, a bounded golden-section
   search of delta within one sample step of the DP path, minimizing the
   ruling's line–surface distance (so the pairing is no longer limited to
   the sample grid).
2. fit_delta: a cubic B-spline delta(sigma) by least squares with the slope
   bound |delta'| <= 1 - eps on its derivative control points (hence
   strictly monotone a and b everywhere), fixed ends (open) or periodic.
3. fit_boundaries: A(s) ~ C0(a(s)) and B(s) ~ C1(b(s)) in one shared spline
   space (the boundaries' own knots mapped through the pairing, plus knots
   inserted where the error exceeds the tolerance), so that the ruled
   surface R(s, t) = (1 - t) A(s) + t B(s) is one compact B-spline face.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, Optional

import numpy as np

from ruled.core.basis import bspline_basis_matrix
from ruled.core.knots import clamp_segment, insert_knot, knot_multiplicity
from ruled.core.nurbs import Curve, Surface
from ruled.fit.dp.pairing import Pairing


# ----------------------------------------------------------------------------- boundary curves
def _continuity(C: Curve, u: float) -> int:
    """Order of parametric continuity of C at u, measured: 0 (C' jumps), 1 (C'' jumps) or 2."""
    lo, hi = C.domain
    h = 1e-7 * (hi - lo)
    if u - h <= lo or u + h >= hi:
        return 2
    d = C.evaluate(np.array([u - h, u + h]), 2)
    for order in (1, 2):
        a, b = d[order][0], d[order][1]
        scale = float(np.linalg.norm(a) + np.linalg.norm(b)) + 1e-300
        # the change over 2h of a smooth derivative is O(h); a jump is O(1)
        if float(np.linalg.norm(a - b)) > 1e-4 * scale:
            return order - 1
    return 2


def _mapped_knots(C: Curve, u0: float, L: float, pairing: Any, which: str, p: int):
    """Interior knots of C mapped into s through the pairing, with the multiplicity they need in
    a degree-p space to keep C's measured continuity there."""
    lo, hi = C.domain
    ks = np.unique(C.knots)
    ks = ks[(ks > lo) & (ks < hi)]
    if ks.size == 0:
        return np.zeros(0), np.zeros(0, int)
    mult = np.array([max(1, p - _continuity(C, k)) for k in ks])
    x = (ks - u0) / L
    a, b = pairing.ab(np.array([0.0, 1.0]))
    f0, f1 = (a if which == "a" else b)
    if pairing.closed:
        shifts = np.arange(np.floor(f0) - 1, np.ceil(f1) + 1)
        xx = (x[None, :] + shifts[:, None]).ravel()
        mm = np.tile(mult, shifts.size)
        sel = (xx > f0) & (xx < f1)
        x, mult = xx[sel], mm[sel]
    s = pairing.inverse(x, which)
    if pairing.closed:  # the seam s = 0 = 1 is a break too
        s = np.where(s > 1 - 1e-9, 0.0, s)
        s = np.where(s < 1e-9, 0.0, s)
        return s, mult
    keep = (s > 1e-9) & (s < 1 - 1e-9)
    return s[keep], mult[keep]


def _space(breaks: np.ndarray, mult: np.ndarray, p: int, closed: bool):
    """Knot vector for interior breaks (sorted, in (0,1)) with the given multiplicities."""
    if closed:
        if breaks.size == 0 or breaks[0] > 1e-9:
            breaks = np.concatenate([[0.0], breaks])
            mult = np.concatenate([[1], mult])
        flat = np.repeat(breaks, mult)
        n = flat.size
        if n < p + 1:
            # too few spans for a periodic space: uniform breaks added between the given ones
            extra = np.linspace(0.0, 1.0, p + 2)[1:-1]
            extra = extra[np.min(np.abs(extra[:, None] - breaks[None, :]), axis=1) > 1e-3]
            order = np.argsort(np.concatenate([breaks, extra]), kind="stable")
            return _space(np.concatenate([breaks, extra])[order],
                          np.concatenate([mult, np.ones(extra.size, int)])[order], p, closed)
        knots = np.concatenate([flat[n - p:] - 1.0, flat, flat[: p + 1] + 1.0])
        return knots, n
    flat = np.repeat(breaks, mult)
    knots = np.concatenate([np.zeros(p + 1), flat, np.ones(p + 1)])
    return knots, knots.size - p - 1


def _design(knots, p, n_unique, s, closed):
    M = bspline_basis_matrix(knots, p, s)
    if closed:
        F = M[:, :n_unique].copy()
        F[:, :p] += M[:, n_unique:]
        return F
    return M


# the two boundaries' knots mapped through the pairing closer than this (in s) become one break: a
# cluster of knots a few 1e-6 apart makes a span whose derivative bounds (and the certificate) explode
KNOT_MERGE = 1e-4
MIN_SPAN = 1.0 / 640       # the smallest span the boundary fit's refinement makes (a quarter of 1 / max_poles)


def _merge(breaks, mult, tol=1e-7):
    """Sorted breaks with near-duplicates merged (keeping the larger multiplicity, at the position of
    the break that has it)."""
    order = np.argsort(breaks)
    b, k = breaks[order], mult[order]
    out_b, out_k = [], []
    for x, kk in zip(b, k):
        if out_b and x - out_b[-1] < tol:
            if kk > out_k[-1]:
                out_b[-1] = x
            out_k[-1] = max(out_k[-1], kk)
            continue
        out_b.append(x)
        out_k.append(kk)
    return np.array(out_b), np.array(out_k, int)


@dataclass(frozen=True)
class Boundaries:
    A: Curve
    B: Curve
    fit_error: float  # largest sampled |A(s) - C0(a(s))|, |B(s) - C1(b(s))|
    kinks: np.ndarray  # s of knots of multiplicity p, where R_s may jump


def fit_boundaries(C0: Curve, C1: Curve, u0: float, L: float, pairing: Pairing, tol: float,
                   max_poles: int = 160, n_uniform: int = 8, lift: Optional[Callable] = None,
                   focus: Optional[tuple] = None) -> Boundaries:
    """A ~ C0(u0 + L a(s)), B ~ C1(u0 + L b(s)) in one shared spline space (see module doc).

    lift(s, ua, ub) -> (offset_A (N, 3), offset_B (N, 3)), optional: the ends are moved by these
    offsets (the 4D fit's elevations along the normal) before fitting.  focus (s0, s1), optional: the
    range of s whose rulings meet a face the result is trimmed by (pairing.face_span); the tolerance
    is kept there only (the rest is trimmed away), and fit_error is measured there."""
    closed = pairing.closed
    # polyline boundaries stay polylines (piecewise-bilinear result); otherwise at least cubic
    p = 1 if (C0.degree == 1 and C1.degree == 1) else max(3, C0.degree, C1.degree)
    sa, ka = _mapped_knots(C0, u0, L, pairing, "a", p)
    sb, kb = _mapped_knots(C1, u0, L, pairing, "b", p)
    br, kk = _merge(np.concatenate([sa, sb]), np.concatenate([ka, kb]), KNOT_MERGE)
    uni = (np.arange(1, n_uniform) / n_uniform)
    if br.size:
        dmin = np.min(np.abs(uni[:, None] - br[None, :]), axis=1)
        uni = uni[dmin > 0.3 / n_uniform]
    br, kk = _merge(np.concatenate([br, uni]), np.concatenate([kk, np.ones(uni.size, int)]))
    # the boundaries' own breaks, mapped, come on top of the poles the refinement may add
    max_poles += int(kk.sum())
    lo0, hi0 = C0.domain

    def target(s):
        a, b = pairing.ab(s)
        ua, ub = u0 + L * a, u0 + L * b
        if closed:
            ua = lo0 + np.mod(ua - lo0, hi0 - lo0)
            ub = lo0 + np.mod(ub - lo0, hi0 - lo0)
        else:
            ua = np.clip(ua, lo0, hi0)
            ub = np.clip(ub, lo0, hi0)
        if lift is None:
            return C0(ua), C1(ub)
        oa, ob = lift(s, ua, ub)
        return C0(ua) + oa, C1(ub) + ob

    for _round in range(12):
        knots, nu = _space(br, kk, p, closed)
        edges = np.unique(np.concatenate([[0.0], br, [1.0]]))
        per = 3 * (p + 1)
        sfit = np.concatenate([np.linspace(e0, e1, per, endpoint=False) for e0, e1 in zip(edges[:-1], edges[1:])]
                              + ([] if closed else [[1.0]]))
        M = _design(knots, p, nu, sfit, closed)
        TA, TB = target(sfit)
        sol, *_ = np.linalg.lstsq(M, np.hstack([TA, TB]), rcond=None)
        # error check on a denser, shifted set
        schk = np.concatenate([np.linspace(e0, e1, 2 * per + 1)[1:-1] for e0, e1 in zip(edges[:-1], edges[1:])])
        Mc = _design(knots, p, nu, schk, closed)
        CA, CB = target(schk)
        R = Mc @ sol
        err = np.maximum(np.linalg.norm(R[:, :3] - CA, axis=1), np.linalg.norm(R[:, 3:] - CB, axis=1))
        R0 = M @ sol
        err_fit = np.maximum(np.linalg.norm(R0[:, :3] - TA, axis=1), np.linalg.norm(R0[:, 3:] - TB, axis=1))
        if focus is not None:
            err = np.where((schk >= focus[0]) & (schk <= focus[1]), err, 0.0)
            err_fit = np.where((sfit >= focus[0]) & (sfit <= focus[1]), err_fit, 0.0)
        emax = max(err.max(), err_fit.max())
        if emax <= tol or nu >= max_poles:
            break
        span = np.searchsorted(edges, schk, side="right") - 1
        bad = np.unique(span[err > tol])
        # never below MIN_SPAN of the range: halving a span again and again at a kink of the target
        # makes ill-conditioned poles whose derivative bounds ruin the certificate (issue 22)
        bad = bad[edges[bad + 1] - edges[bad] >= 2.0 * MIN_SPAN]
        if bad.size == 0:
            break
        mids = 0.5 * (edges[bad] + edges[bad + 1])
        br, kk = _merge(np.concatenate([br, mids]), np.concatenate([kk, np.ones(mids.size, int)]))
    poles_A, poles_B = sol[:, :3], sol[:, 3:]
    if closed:
        poles_A = np.concatenate([poles_A, poles_A[:p]])
        poles_B = np.concatenate([poles_B, poles_B[:p]])
    else:
        # interpolate the corners exactly: the ends of a clamped spline are its end poles
        e0A, e0B = target(np.array([0.0, 1.0]))
        poles_A[0], poles_A[-1] = e0A[0], e0A[1]
        poles_B[0], poles_B[-1] = e0B[0], e0B[1]
    A = Curve(poles_A, knots, p, periodic=closed)
    B = Curve(poles_B, knots, p, periodic=closed)
    return Boundaries(A, B, float(emax), br[kk >= p])


def ruled_surface(bd: Boundaries) -> Surface:
    """R(s, t) = (1 - t) A(s) + t B(s) as a B-spline surface of degree (p, 1).

    A and B share knots (and weights, when rational), so R is linear along every ruling."""
    poles = np.stack([bd.A.poles, bd.B.poles], axis=1)
    w = None if bd.A.weights is None else np.stack([bd.A.weights, bd.A.weights], axis=1)
    return Surface(poles, bd.A.knots, np.array([0.0, 0.0, 1.0, 1.0]), bd.A.degree, 1, w,
                   periodic_u=bd.A.periodic)


# ----------------------------------------------------------------------------- exact shifts
def _rotated(C: Curve, u0: float, L: float, a0: float, closed: bool) -> Curve:
    """C(u0 + L (a0 + s)), s in [0, 1], exactly (same degree and weights), as a clamped curve."""
    lo, hi = C.domain
    if not closed:
        return Curve(C.poles, (C.knots - u0) / L, C.degree, C.weights)
    us = lo + (hi - lo) * (a0 - np.floor(a0))
    kn = C.knots[np.abs(C.knots - us) <= 1e-12 * (hi - lo)]
    if kn.size:  # snap to a knot: no sliver spans
        us = float(kn[0])
    C = clamp_segment(C, lo, hi)  # clamped representation of the whole period
    if us - lo <= 1e-14 * (hi - lo) or hi - us <= 1e-14 * (hi - lo):
        return Curve(C.poles, (C.knots - lo) / L, C.degree, C.weights, True)
    p = C.degree
    c1 = clamp_segment(C, us, hi)
    c2 = clamp_segment(C, lo, us)
    h1 = c1._hom
    h2 = c2._hom * (h1[-1, -1] / c2._hom[0, -1])  # same weight at the junction
    hom = np.concatenate([h1, h2[1:]])
    knots = np.concatenate([(c1.knots[:-1] - us) / L, (c2.knots[p + 1:] - lo + (hi - us)) / L])
    w = hom[:, -1]
    return Curve(hom[:, :-1] / w[:, None], knots, p, None if C.weights is None else w, True)


def _merge_knots(A: Curve, B: Curve, tol: float = 1e-12):
    """Insert into each curve the knots of the other (snapping values closer than tol)."""
    ka = np.unique(A.knots)
    kb = np.unique(B.knots)
    for x in kb:
        near = ka[np.abs(ka - x) <= tol]
        y = near[0] if near.size else x
        need = knot_multiplicity(B.knots, x) - knot_multiplicity(A.knots, y)
        if need > 0:
            A = insert_knot(A, y, need)
    ka = np.unique(A.knots)
    for x in ka:
        near = np.unique(B.knots)[np.abs(np.unique(B.knots) - x) <= tol]
        y = near[0] if near.size else x
        need = knot_multiplicity(A.knots, x) - knot_multiplicity(B.knots, y)
        if need > 0:
            B = insert_knot(B, y, need)
    if A.knots.shape != B.knots.shape or np.abs(A.knots - B.knots).max() > tol:
        return None
    return A, Curve(B.poles, A.knots, B.degree, B.weights, A.periodic)


def exact_boundaries(C0: Curve, C1: Curve, u0: float, L: float, pairing: Pairing) -> Optional[Boundaries]:
    """When the pairing is a pure shift (iso-parametric rulings, or a constant offset around a
    closed face), the composed boundaries are the input curves re-knotted: rebuild them exactly."""
    s = np.linspace(0.0, 1.0, 257)
    a, b = pairing.ab(s)
    d = 0.5 * (b - a)
    if np.abs(d - d[0]).max() > 1e-12 or C0.degree != C1.degree or pairing.span != 1.0:
        return None
    if not pairing.closed and abs(d[0]) > 1e-12:
        return None
    A = _rotated(C0, u0, L, float(a[0]), pairing.closed)
    B = _rotated(C1, u0, L, float(b[0]), pairing.closed)
    merged = _merge_knots(A, B)
    if merged is None:
        return None
    A, B = merged
    if (A.weights is None) != (B.weights is None):
        return None
    if A.weights is not None:
        ratio = B.weights / A.weights
        if np.abs(ratio / ratio[0] - 1.0).max() > 1e-12:
            return None
        B = Curve(B.poles, B.knots, B.degree, A.weights, A.periodic)
    lo0, hi0 = C0.domain
    ua = lo0 + np.mod(u0 + L * a - lo0, hi0 - lo0) if pairing.closed else np.clip(u0 + L * a, lo0, hi0)
    ub = lo0 + np.mod(u0 + L * b - lo0, hi0 - lo0) if pairing.closed else np.clip(u0 + L * b, lo0, hi0)
    err = max(np.linalg.norm(A(s) - C0(ua), axis=1).max(), np.linalg.norm(B(s) - C1(ub), axis=1).max())
    ks, counts = np.unique(A.knots, return_counts=True)
    kinks = ks[(counts >= A.degree) & (ks > 0) & (ks < 1)]
    return Boundaries(A, B, float(err), kinks)
