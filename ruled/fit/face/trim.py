"""The result trimmed by the face's edges: the face's boundary mapped onto the ruled surface.

A fit of the face's extended patch E (ruled.fit.face.extend) is certified over the cells that meet the face
only, through a map psi of E's domain onto the result R's (ruled.fit.certify.forward: |E - R o psi| <= B over the
face).  Where psi keeps its orientation on every such cell, the image psi(face) is the region of R's
domain that psi(boundary) encloses, so R restricted to it is within B of the face both ways.  The trim
curves C are cubic B-splines through psi's image of the boundary's samples (the segment of R's rail where
an edge lies on a rail of the patch), within eps of psi(boundary) point by point; the region C encloses
differs from psi(face) only within eps of its boundary, so the trimmed result T is within

    B + eps max sqrt(|R_s|^2 + |R_t|^2)

of the face, both ways (a point of either region is within eps, in R's domain, of the other, and
|R_s d_s + R_t d_t| <= |d| sqrt(|R_s|^2 + |R_t|^2)).  The max is taken where that happens only: over the
spans of R that an eps-box round the trim curve meets, per edge with its own eps (local_speed).  The trim
curve is smooth while psi's image is not (psi is bilinear on the certificate's grid: a kink at each grid
line), so eps is at least those kinks' size; following them with more spans shrinks eps but not the
distance to the face, which the true correspondence sets.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Optional

import numpy as np
from scipy.linalg import cho_factor, cho_solve

from ruled.core.basis import bspline_basis_matrix
from ruled.core.nurbs import Curve
from ruled.fit.certify.cells import RAIL_T, folds

SPANS = (8, 16, 32, 64, 128)   # the trim curves' knot spans, tried in turn
FIT_TOL = 1e-8                      # in R's domain (a unit square): the trim curve follows psi's image to this
CHECK = 4                      # eps checked at this many points per interval of the edge's samples
EPS_MARGIN = 1.5               # eps is sampled: raised by half
ON_RAIL = 1e-4                 # an edge whose (s, t) in the patch is this near t = 0 (1) all along lies on a rail


@dataclass(frozen=True)
class Trim:
    """The face's boundary on the result R: per outer-loop edge a 2D Curve in R's (s, t) (in loop order),
    per hole a tuple of them; eps, how far they are from psi's image of the boundary (in R's domain), and
    added, the part of the bound that covers it (model units)."""

    outer: tuple
    holes: tuple = ()
    eps: float = 0.0
    added: float = 0.0
    own: bool = False       # the face's own curves (psi is the identity to round-off)

    @staticmethod
    def loop(curves: tuple, ccw: bool) -> tuple:
        """A loop of 2D curves running counter-clockwise in (s, t) (ccw: an outer loop, as a host face
        wants it) or clockwise (a hole)."""
        P = np.concatenate([c(np.linspace(c.domain[0], c.domain[1], 65)) for c in curves])
        x, y = P[:, 0], P[:, 1]
        if (np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y) > 0) == ccw:
            return curves
        return tuple(_reversed(c) for c in reversed(curves))


def _reversed(c: Curve) -> Curve:
    a, b = c.domain
    return Curve(c.poles[::-1].copy(), (a + b) - c.knots[::-1], c.degree,
                 None if c.weights is None else c.weights[::-1].copy())


def psi_at(psi: tuple, st: np.ndarray) -> np.ndarray:
    """R's (s, t) at points (N, 2) of E's domain: psi, bilinear on its grid (us, vs, s, t)."""
    us, vs, S, T = psi
    iu = np.clip(np.searchsorted(us, st[:, 0], side="right") - 1, 0, us.size - 2)
    iv = np.clip(np.searchsorted(vs, st[:, 1], side="right") - 1, 0, vs.size - 2)
    a = np.clip((st[:, 0] - us[iu]) / (us[iu + 1] - us[iu]), 0.0, 1.0)
    b = np.clip((st[:, 1] - vs[iv]) / (vs[iv + 1] - vs[iv]), 0.0, 1.0)
    out = []
    for F in (S, T):
        out.append((1 - a) * (1 - b) * F[iu, iv] + a * (1 - b) * F[iu + 1, iv] + (1 - a) * b * F[iu, iv + 1]
                   + a * b * F[iu + 1, iv + 1])
    return np.stack(out, axis=1)


def rail_cells(psi: tuple, segments: list) -> np.ndarray:
    """(nu - 1, nv - 1) the cells of the grid whose images lie along a rail of R (their corners within
    RAIL_T of t = 0 or 1) strictly inside one of the trim's segments on that rail, (rail t, s_lo, s_hi)
    each, by their own width: whatever psi does there, their points go into the trimmed result."""
    us, vs, S, T = psi
    cs = np.stack([S[:-1, :-1], S[1:, :-1], S[:-1, 1:], S[1:, 1:]])
    ct = np.stack([T[:-1, :-1], T[1:, :-1], T[:-1, 1:], T[1:, 1:]])
    lo, hi = cs.min(axis=0), cs.max(axis=0)
    out = np.zeros(lo.shape, bool)
    for r, a, b in segments:
        a, b = min(a, b), max(a, b)
        along = np.abs(ct - r).max(axis=0) <= RAIL_T
        w = hi - lo
        out |= along & (lo >= a + w) & (hi <= b - w)
    return out


def _fit_curve(x: np.ndarray, Y: np.ndarray, ends: tuple, spans: int) -> Curve:
    """A cubic B-spline of `spans` uniform knot spans (fewer where the points are few) through the points
    Y (N, 2) at parameters x by least squares, its end points pinned to ends."""
    spans = min(spans, max(1, (x.size - 1) // 3))
    knots = np.concatenate([[x[0]] * 3, np.linspace(x[0], x[-1], spans + 1), [x[-1]] * 3])
    M = bspline_basis_matrix(knots, 3, x)
    P = np.empty((M.shape[1], 2))
    P[0], P[-1] = ends
    rhs = Y - M[:, :1] * P[0] - M[:, -1:] * P[-1]
    A = M[:, 1:-1]
    try:            # the normal equations (banded, positive definite where every span holds points): fast
        P[1:-1] = cho_solve(cho_factor(A.T @ A), A.T @ rhs)
    except np.linalg.LinAlgError:
        P[1:-1] = np.linalg.lstsq(A, rhs, rcond=None)[0]
    return Curve(P, knots, 3)


def _along(st: np.ndarray, k: int) -> tuple:
    """(x, points): an edge's samples st (N, 2), k points per interval, at x in [0, 1]: the cubic spline
    through them (the edge is a smooth curve, which its samples' polyline cuts across by its sagitta, as
    large as the fit's own error at PER_EDGE samples; linear where the samples are too few)."""
    x = np.linspace(0.0, 1.0, st.shape[0])
    xx = np.linspace(0.0, 1.0, k * (st.shape[0] - 1) + 1)
    if st.shape[0] < 4:
        return xx, np.stack([np.interp(xx, x, st[:, 0]), np.interp(xx, x, st[:, 1])], axis=1)
    from scipy.interpolate import CubicSpline
    return xx, CubicSpline(x, st, axis=0)(xx)


def local_speed(R, P: np.ndarray, pad: float) -> float:
    """A bound of sqrt(|R_s|^2 + |R_t|^2) (so of |dR| / |d(s, t)|) over the boxes spanned by consecutive
    points P (N, 2) of R's domain, padded by pad: the max of R's per-span derivative bounds over the spans
    they meet, clipped to its domain (a box past an end in s meets the spans at both ends: a closed R
    continues there)."""
    b = R.derivative_bounds()
    G = np.sqrt(b["Su"] ** 2 + b["Sv"] ** 2)
    if P.shape[0] < 2:
        P = np.repeat(P, 2, axis=0)
    lo = np.minimum(P[:-1], P[1:]) - pad
    hi = np.maximum(P[:-1], P[1:]) + pad
    u0, u1 = R.domain[0], R.domain[1]
    wraps = (lo[:, 0] < u0) | (hi[:, 0] > u1)

    def span(knots, p, n, t):
        return np.clip(np.searchsorted(knots, t, side="right") - 1, p, n - 1) - p
    nu, nv = R.poles.shape[:2]
    i0, i1 = span(R.knots_u, R.degree_u, nu, lo[:, 0]), span(R.knots_u, R.degree_u, nu, hi[:, 0])
    j0, j1 = span(R.knots_v, R.degree_v, nv, lo[:, 1]), span(R.knots_v, R.degree_v, nv, hi[:, 1])
    m = max(float(G[i0, j0].max()), float(G[i0, j1].max()), float(G[i1, j0].max()), float(G[i1, j1].max()))
    for k in np.flatnonzero((i1 - i0 > 1) | (j1 - j0 > 1)):     # a box over more than two spans (rare)
        m = max(m, float(G[i0[k]:i1[k] + 1, j0[k]:j1[k] + 1].max()))
    for k in np.flatnonzero(wraps):
        m = max(m, float(G[[0, -1], j0[k]:j1[k] + 1].max()))
    return m


def _edge_curve(psi: tuple, st: np.ndarray, ends: tuple, R) -> tuple:
    """(C, eps, added) for one edge of the face, its samples st in E's domain: C through psi's image of the
    edge (_along its samples, CHECK per interval), parametrized by that image's chord length (psi can run
    fast along a short piece of the edge: near a fan of rulings, many rulings meet a short arc), with the
    first of SPANS that follows it there within FIT_TOL (else the last: psi is bilinear on the
    certificate's grid, so its image has a kink at each grid line, which a smooth curve cuts across); eps,
    C's distance from psi's image at CHECK times as many points again, raised by EPS_MARGIN; added, eps
    times R's speed there (local_speed)."""
    xs, stc = _along(st, CHECK)
    y = psi_at(psi, stc)
    x = _chord(y, xs)
    for spans in SPANS:
        C = _fit_curve(x, y, ends, spans)
        if np.abs(C(x) - y).max() <= FIT_TOL:
            break
    xf, stf = _along(st, CHECK * CHECK)
    P = C(np.interp(xf, xs, x))
    eps = EPS_MARGIN * float(np.linalg.norm(P - psi_at(psi, stf), axis=1).max())
    return C, eps, eps * local_speed(R, P, eps + 1.0 / xf.size)


def _chord(y: np.ndarray, xs: np.ndarray) -> np.ndarray:
    """Parameters in [0, 1] for the points y (N, 2) in order: their chord length, blended with xs (a tenth)
    so that no two points share one."""
    d = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(y, axis=0), axis=1))])
    x = 0.9 * d / d[-1] + 0.1 * xs if d[-1] > 0 else xs
    x[0], x[-1] = 0.0, 1.0
    return x


def trim_of(fit, mask) -> Optional[Trim]:
    """The Trim of a fit of the extended patch (fit.oriented is E, its certificate carries psi), or None
    where psi folds over the face (then the image of the face is not the region its boundary encloses)."""
    cert = fit.certificate
    if cert.psi is None:
        return None
    R = fit.surface
    us, vs = cert.psi[0], cert.psi[1]
    if mask.curves is not None:
        exact = _identity_trim(cert.psi, mask, R)
        if exact is not None:
            return exact
    loops = [mask.edges] + list(mask.hole_edges)
    out, eps, added, segments = [], 0.0, 0.0, []
    for edges in loops:
        # psi's image of each edge's samples; the corners, each its two edges' ends averaged
        ys = [psi_at(cert.psi, st) for st in edges]
        n = len(edges)
        corner = [0.5 * (ys[k][0] + ys[k - 1][-1]) for k in range(n)]
        rails = [0.0 if st[:, 1].max() <= ON_RAIL else 1.0 if st[:, 1].min() >= 1.0 - ON_RAIL else None
                 for st in edges]
        for k in range(n):          # a corner on a rail: on it exactly (its two edges meet there)
            r = rails[k] if rails[k] is not None else rails[k - 1]
            if r is not None:
                corner[k] = np.array([corner[k][0], r])
        curves = []
        for k, st in enumerate(edges):
            ends = (corner[k], corner[(k + 1) % n])
            if rails[k] is not None:
                # an edge on a rail of the patch: the segment of R's rail between its ends' images, which psi's
                # image follows within its distance in t (the same s: psi's s-values parametrize both)
                y = psi_at(cert.psi, _along(st, CHECK)[1])
                e = EPS_MARGIN * float(np.abs(y[:, 1] - rails[k]).max())
                curves.append(Curve(np.array(ends), np.array([0.0, 0, 1, 1]), 1))
                eps, added = max(eps, e), max(added, e * local_speed(R, y, e + 1.0 / y.shape[0]))
                segments.append((rails[k], float(corner[k][0]), float(corner[(k + 1) % n][0])))
                continue
            C, e, a = _edge_curve(cert.psi, st, ends, R)
            eps, added = max(eps, e), max(added, a)
            curves.append(C)
        out.append(tuple(curves))
    if folds(cert.psi, mask.cells(us, vs) & ~rail_cells(cert.psi, segments)) or loops_cross(out):
        return None
    return Trim(out[0], tuple(out[1:]), eps, added)


def loop_polylines(loops, per_curve: int) -> list:
    """Each loop of 2D curves (end to end) as a closed polyline (N, 2): per_curve samples of each curve, its
    last (the next curve's first) left out."""
    return [np.concatenate([c(np.linspace(c.domain[0], c.domain[1], per_curve))[:-1] for c in loop])
            for loop in loops]


def loops_cross(loops: list, points: int = 2048) -> bool:
    """Whether the loops of 2D curves (sampled as polylines of about `points` in all) cross themselves or
    each other: a trim whose image of the face's boundary does so bounds no face (psi's image of a smooth
    edge can wiggle where psi does, far from ruled).  Compared in blocks of segments (memory ~ block x n)."""
    per_curve = int(np.clip(points // max(1, sum(len(lp) for lp in loops)), 9, 65))
    P, nxt = loop_polylines(loops, per_curve), []
    k0 = 0
    for pts in P:
        nxt.append(k0 + (np.arange(pts.shape[0]) + 1) % pts.shape[0])
        k0 += pts.shape[0]
    A = np.concatenate(P)
    to = np.concatenate(nxt)
    B = A[to]
    n = A.shape[0]

    def side(p, q, r):
        return (q[..., 0] - p[..., 0]) * (r[..., 1] - p[..., 1]) - (q[..., 1] - p[..., 1]) * (r[..., 0] - p[..., 0])
    step = max(1, 2_000_000 // max(n, 1))
    J = np.arange(n)
    for lo in range(0, n, step):
        i = np.arange(lo, min(n, lo + step))[:, None]
        keep = (J[None, :] > i) & (to[i] != J[None, :]) & (to[J][None, :] != i)
        a, b, c, d = A[i], B[i], A[None, :], B[None, :]
        hit = (side(a, b, c) * side(a, b, d) < 0) & (side(c, d, a) * side(c, d, b) < 0) & keep
        if hit.any():
            return True
    return False


IDENTITY = 1e-12     # psi within this of the identity (in R's domain): the face's own curves are the trim


def _identity_trim(psi: tuple, mask, R) -> Optional[Trim]:
    """The Trim where psi is the identity to round-off (the result is the patch itself, as for a face whose
    own surface is ruled along its iso lines): the face's own curves, exactly, eps psi's distance from the
    identity at the boundary's samples; None where psi is farther from it."""
    us, vs, S, T = psi
    UU, VV = np.meshgrid(us, vs, indexing="ij")
    if max(float(np.abs(S - UU).max()), float(np.abs(T - VV).max())) > IDENTITY:
        return None
    st = np.concatenate(list(mask.edges) + [e for h in mask.hole_edges for e in h])
    eps = EPS_MARGIN * float(np.abs(psi_at(psi, st) - st).max())
    added = max(eps * local_speed(R, e, eps + 1.0 / e.shape[0])
                for e in list(mask.edges) + [e for h in mask.hole_edges for e in h])
    return Trim(mask.curves[0], tuple(mask.curves[1:]), eps, added, True)


def with_trim(fit, mask):
    """The fit with its Trim and its bound raised by the trim's part; None where it has none.  Of the
    certificate's maps (its own and its alternatives, each a valid certificate), the one whose bound plus
    its trim's part is the smallest: the map with the lowest bound may follow the closest points of a face
    far from ruled, whose image of the face's edges is too jagged for a smooth trim curve."""
    first = fit.certificate
    best, total = None, np.inf
    for c in sorted((first,) + tuple(first.alternatives), key=lambda c: c.bound):
        if c.bound >= total:
            break
        tr = trim_of(replace(fit, certificate=c), mask)
        if tr is not None and c.bound + tr.added < total:
            best, total = (c, tr), c.bound + tr.added
    if best is None:
        return None
    c, tr = best
    cert = replace(c, bound=c.bound + tr.added, map_deviation=c.map_deviation + tr.added, alternatives=())
    return replace(fit, certificate=cert, trim=tr)


__all__ = ["Trim", "trim_of", "with_trim", "psi_at", "loop_polylines", "loops_cross"]
