"""The result trimmed by the face's edges: the face's boundary mapped onto the ruled surface.

A fit of the face's extended patch E (ruled.fit.extend) is certified over the cells that meet the face
only, through a map psi of E's domain onto the result R's (ruled.fit.certify: |E - R o psi| <= B over the
face).  Where psi keeps its orientation on every such cell, the image psi(face) is the region of R's
domain that psi(boundary) encloses, so R restricted to it is within B of the face both ways.  The trim
curves C are cubic B-splines through psi's image of the boundary's samples (the segment of R's rail where
an edge lies on a rail of the patch), within eps of psi(boundary) point by point; the region C encloses
differs from psi(face) only within eps of its boundary, so the trimmed result T is within

    B + eps (max |R_s| + max |R_t|)

of the face, both ways (a point of either region is within eps, in R's domain, of the other).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Optional

import numpy as np

from ruled.core.basis import bspline_basis_matrix
from ruled.core.nurbs import Curve

SPANS = (8, 16, 32, 64, 128) # the trim curves' knot spans, tried in turn
FIT_TOL = 1e-8                      # in R's domain (a unit square): the trim curve follows psi's image to this
EPS_MARGIN = 1.5               # eps is sampled: raised by half
RAIL_T = 1e-3                  # a cell whose corners map this near a rail of R lies along it
ON_RAIL = 1e-4                 # an edge whose (s, t) in the patch is this near t = 0 (1) all along lies on a rail
FOLD_TOL = 1e-3                # psi's Jacobian below -this of its median on a cell of the face: a fold


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


def folds(psi: tuple, cells: np.ndarray) -> bool:
    """Whether psi fails to keep its orientation on a cell of the mask: its bilinear Jacobian, at each
    corner of each such cell, below -FOLD_TOL of its median somewhere (the grid's rows next to R's rails
    are a hair high, and their nodes go to the rails' closest points: a corner there may come out flat,
    or negative at round-off's scale, without folding anything)."""
    us, vs, S, T = psi
    hu, hv = np.diff(us)[:, None], np.diff(vs)[None, :]

    def edge(F, axis, k):
        # the cell's edge difference along axis at its side k (0 or 1)
        if axis == 0:
            return (F[1:, k:F.shape[1] - 1 + k] - F[:-1, k:F.shape[1] - 1 + k]) / hu
        return (F[k:F.shape[0] - 1 + k, 1:] - F[k:F.shape[0] - 1 + k, :-1]) / hv
    dets = [(edge(S, 0, j0) * edge(T, 1, i0) - edge(S, 1, i0) * edge(T, 0, j0))[cells]
            for j0 in (0, 1) for i0 in (0, 1)]
    d = np.concatenate(dets)
    med = float(np.median(d)) if d.size else 0.0
    return not (med > 0 and d.min() > -FOLD_TOL * med)


def _fit_curve(x: np.ndarray, Y: np.ndarray, ends: tuple) -> Curve:
    """A cubic B-spline through the points Y (N, 2) at parameters x, its end points pinned to ends, with
    the first of SPANS that follows Y within FIT_TOL (else the last)."""
    C = None
    for spans in SPANS:
        spans = min(spans, max(1, (x.size - 1) // 3))
        knots = np.concatenate([[x[0]] * 3, np.linspace(x[0], x[-1], spans + 1), [x[-1]] * 3])
        M = bspline_basis_matrix(knots, 3, x)
        n = M.shape[1]
        P = np.empty((n, 2))
        P[0], P[-1] = ends
        rhs = Y - M[:, :1] * P[0] - M[:, -1:] * P[-1]
        P[1:-1] = np.linalg.lstsq(M[:, 1:-1], rhs, rcond=None)[0]
        C = Curve(P, knots, 3)
        if np.abs(C(x) - Y).max() <= FIT_TOL:
            break
    return C


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
    out, eps, segments = [], 0.0, []
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
        for k, y in enumerate(ys):
            x = np.linspace(0.0, 1.0, y.shape[0])
            st = edges[k]
            if rails[k] is not None:
                # an edge on a rail of the patch: the segment of R's rail between its ends' images, which psi's
                # image follows within its distance in t (the same s: psi's s-values parametrize both)
                curves.append(Curve(np.array([corner[k], corner[(k + 1) % n]]), np.array([0.0, 0, 1, 1]), 1))
                eps = max(eps, float(np.abs(y[:, 1] - rails[k]).max()))
                segments.append((rails[k], float(corner[k][0]), float(corner[(k + 1) % n][0])))
                continue
            C = _fit_curve(x, y, (corner[k], corner[(k + 1) % n]))
            xx = np.linspace(0.0, 1.0, 4 * y.shape[0] - 3)
            # psi's image between the samples: psi of the edge's (s, t), linear between the samples
            st_f = np.stack([np.interp(xx, x, st[:, 0]), np.interp(xx, x, st[:, 1])], axis=1)
            eps = max(eps, float(np.linalg.norm(C(xx) - psi_at(cert.psi, st_f), axis=1).max()))
            curves.append(C)
        out.append(tuple(curves))
    if folds(cert.psi, mask.cells(us, vs) & ~rail_cells(cert.psi, segments)) or loops_cross(out):
        return None
    eps *= EPS_MARGIN
    b = R.derivative_bounds()
    added = eps * (float(b["Su"].max()) + float(b["Sv"].max()))
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
    b = R.derivative_bounds()
    return Trim(mask.curves[0], tuple(mask.curves[1:]), eps, eps * (float(b["Su"].max()) + float(b["Sv"].max())),
                True)


def with_trim(fit, mask):
    """The fit with its Trim and its bound raised by the trim's part; None where it has none."""
    tr = trim_of(fit, mask)
    if tr is None:
        return None
    c = fit.certificate
    cert = replace(c, bound=c.bound + tr.added, map_deviation=c.map_deviation + tr.added)
    return replace(fit, certificate=cert, trim=tr)


__all__ = ["Trim", "trim_of", "with_trim", "psi_at", "loop_polylines", "loops_cross"]
