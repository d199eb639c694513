"""A face closed in one direction (a tube, a closed band, a closed blade skin: its surface's whole rectangle, its
two ends the only boundaries) ruled across its closed direction, both sides folded onto one ruled surface.

Rulings between the face's two ends (the closed fit, ruled.fit.fit2d) span its length; across the closed
direction, two fold lines u = a and u = b (the closed parameter called u here) cut the face into two halves,
S(a + t (b - a), v) and S(a - t (L - (b - a)), v), t in [0, 1], which share their boundaries t = 0 and t = 1.
The ruled fit of their mid-surface M = (half 0 + half 1) / 2 (sampled like a Coons patch, ruled.fit.face.sampled)
has rulings joining the fold lines; each of its candidates is certified against both halves in the same
(s, t) (ruled.fit.certify: both halves share M's boundaries, the pairing's rails), its bound the larger: both
ways, the face is within it of the result.  A tube of radius r is within about r of the ribbon through its
axis; a thin closed blade within its half-thickness of its camber surface.  The fold lines are the pair of
iso lines farthest apart on average (the section's diameter: an airfoil's leading and trailing edges).
"""

from __future__ import annotations

from dataclasses import replace
from typing import Optional

import numpy as np

from ruled.core.edgegap import off_face
from ruled.core.errors import RuledError
from ruled.core.nurbs import Surface
from ruled.core.progress import Progress
from ruled.core.region import Region
from ruled.fit.certify.forward import certified_bound
from ruled.fit.face.patch import EDGE_MARGIN, PATCH_ACCEPT, PATCH_MAX_SPANS, PATCH_TOL, FacePatch, with_iso
from ruled.fit.face.sampled import side_surface
from ruled.fit.fit2d import GRID_FINE, FitResult
from ruled.fit.options import Direction, FitOptions
from ruled.fit.surface import fit_surface

CANDIDATE_LINES = 16    # iso lines across the closed direction tried as fold lines (pairs of them)
WORTH = 0.5             # the fold is fitted where its halves lie closer than this fraction of the other's bound


def closed_axis(S: Surface) -> Optional[int]:
    """0 where S is closed along u only (S(u0, v) = S(u1, v)), 1 along v only, None otherwise."""
    u0, u1, v0, v1 = S.domain
    tol = 1e-7 * max(S.diagonal(), 1e-300)
    x = np.linspace(0.0, 1.0, 17)
    us, vs = u0 + (u1 - u0) * x, v0 + (v1 - v0) * x
    closed = [float(np.linalg.norm(S(np.full(17, u0), vs) - S(np.full(17, u1), vs), axis=1).max()) <= tol,
              float(np.linalg.norm(S(us, np.full(17, v0)) - S(us, np.full(17, v1)), axis=1).max()) <= tol]
    return closed.index(True) if sum(closed) == 1 else None


class FoldMap:
    """One half of the folded face (half 0 or 1) or, with half None, their mid-surface, over the unit square:
    s along the open direction, t from the fold line a to the fold line b (the interface of
    ruled.fit.face.sampled.side_surface's maps; the mid-surface is half 0 plus the offset to the mean)."""

    whole = False
    name = "face folded across its closed direction"
    refine_hint = "the face's fold lines cross its creases; pick rails («rails»)"

    def __init__(self, S: Surface, axis: int, a: float, b: float, half: Optional[int]):
        self.S, self.axis, self.a, self.b, self.half = S, axis, a, b, half
        dom = S.domain
        self.lo, self.hi = dom[2 * axis], dom[2 * axis + 1]          # the closed direction's range
        self.olo, self.ohi = dom[2 - 2 * axis], dom[3 - 2 * axis]    # the open one's

    def _uv(self, s, t, half: int):
        s, t = np.broadcast_arrays(np.asarray(s, float), np.asarray(t, float))
        L = self.hi - self.lo
        w = self.b - self.a
        x = self.a + t * w if half == 0 else self.a - t * (L - w)
        x = self.lo + np.mod(x - self.lo, L)
        y = self.olo + s * (self.ohi - self.olo)
        return (x, y) if self.axis == 0 else (y, x)

    def omega(self, S: Surface, s, t):
        return self._uv(s, t, 0 if self.half is None else self.half)

    def offset(self, s, t):
        if self.half is not None:
            return None
        p0 = self.S(*(np.ravel(x) for x in self._uv(s, t, 0)))
        p1 = self.S(*(np.ravel(x) for x in self._uv(s, t, 1)))
        return 0.5 * (p1 - p0)

    def breaks(self, S: Surface):
        L = self.hi - self.lo
        w = self.b - self.a
        kk = self.a + np.mod(S.interior_knots("uv"[self.axis]) - self.a, L)
        bt = np.concatenate([[0.0, 1.0], (kk[kk < self.b] - self.a) / w, (self.a + L - kk[kk > self.b]) / (L - w)])
        ko = S.interior_knots("vu"[self.axis])
        bs = np.concatenate([[0.0, 1.0], (ko - self.olo) / (self.ohi - self.olo)])
        return _merged(bs), _merged(bt)


def _merged(b: np.ndarray, tol: float = 1e-9) -> np.ndarray:
    """Sorted breaks in [0, 1] with those closer than tol to the one before dropped (one knot of each half at
    the same place: a span of round-off width would split into poles of no weight)."""
    b = np.unique(np.clip(b, 0.0, 1.0))
    keep = np.concatenate([[True], np.diff(b) > tol])
    b = b[keep]
    b[-1] = 1.0
    return b


def fold_lines(S: Surface, axis: int) -> tuple:
    """(a, b): the two iso lines across the closed direction farthest apart on average along the open one."""
    dom = S.domain
    lo, hi = dom[2 * axis], dom[2 * axis + 1]
    olo, ohi = dom[2 - 2 * axis], dom[3 - 2 * axis]
    x = lo + (hi - lo) * np.arange(CANDIDATE_LINES) / CANDIDATE_LINES
    y = np.linspace(olo, ohi, 9)
    X, Y = np.meshgrid(x, y, indexing="ij")
    P = (S(X.ravel(), Y.ravel()) if axis == 0 else S(Y.ravel(), X.ravel())).reshape(x.size, y.size, 3)
    D = np.linalg.norm(P[:, None] - P[None, :], axis=3).mean(axis=2)
    i, j = np.unravel_index(int(np.argmax(D)), D.shape)
    i, j = min(i, j), max(i, j)
    return float(x[i]), float(x[j])


def half_gap(S: Surface, axis: int, a: float, b: float, n: int = 17) -> float:
    """Half the largest distance between the two halves at the same (s, t) (a tube's radius): about what the fold
    can reach (one surface near both halves), so that a fold that cannot win is not fitted (a guide, not a bound)."""
    x = np.linspace(0.0, 1.0, n)
    s, t = np.meshgrid(x, x, indexing="ij")
    m = FoldMap(S, axis, a, b, 0)
    return 0.5 * float(np.linalg.norm(S(*(np.ravel(c) for c in m._uv(s, t, 0)))
                                      - S(*(np.ravel(c) for c in m._uv(s, t, 1))), axis=1).max())


def fit_folded(region: Region, size: float, opts: FitOptions, progress: Progress = None,
               cutoff: float = np.inf) -> Optional[FitResult]:
    """The folded fit of the module doc, for a face that is its surface's whole rectangle closed in one direction;
    None for any other face, where it cannot be sampled or fitted, or where it cannot beat ``cutoff`` (another
    candidate's bound; not tried where the halves lie farther apart than WORTH of it, half_gap: a fold is worth its
    cost where it may halve the error)."""
    S = region.surface
    axis = closed_axis(S)
    if axis is None or not region.is_rectangle():
        return None
    a, b = fold_lines(S, axis)
    if not b > a or not half_gap(S, axis, a, b) < WORTH * cutoff:
        return None
    tol, accept = PATCH_TOL * size, PATCH_ACCEPT * size
    try:
        mid = side_surface(S, FoldMap(S, axis, a, b, None), tol, PATCH_MAX_SPANS, accept)
        halves = [side_surface(S, FoldMap(S, axis, a, b, k), tol, PATCH_MAX_SPANS, accept) for k in (0, 1)]
        res = with_iso(fit_surface(mid.surface, replace(opts, direction=Direction.V), progress, compact=False),
                       progress)
    except RuledError:
        return None
    # the face's edges off its surface, and a rectangle face short of its surface's rectangle: as the
    # identity patch counts them (ruled.fit.face.fit.face_patch)
    gap = region.rect_slack(gaps=False) + EDGE_MARGIN * off_face(region)
    best = None
    for c in res.candidates.values():
        if isinstance(c, str):
            continue
        bound, cert = 0.0, None
        for h in halves:
            got = certified_bound(h.surface, c.pairing, c.boundaries, c.surface, *GRID_FINE, cutoff)
            got = replace(got, bound=got.bound + h.deviation + gap, map_deviation=h.deviation + gap)
            if cert is None or got.bound > bound:
                bound, cert = got.bound, got
            if not bound < cutoff:
                break
        if bound < cutoff and (best is None or bound < best.error_bound):
            best = replace(c, certificate=cert)
    if best is None:
        return None
    patch = FacePatch(region, mid.surface, gap, False, None, "v", mid.spans, size, fold=(axis, a, b))
    note = (f"the face is closed across its {'uv'[axis]} direction: its two sides, folded along the iso lines "
            f"{'uv'[axis]} = {a:.4g} and {b:.4g}, are both fitted by one ruled surface through its middle, bound "
            f"{best.error_bound:.4g} (the rulings between its ends, {cutoff:.4g})")
    return FitResult(best, {"v": best}, res.options, res.timings, tuple(res.notes) + (note,), None, patch)


__all__ = ["FoldMap", "closed_axis", "fit_folded", "fold_lines"]
