"""A wall's joined surface (its faces as one B-spline surface closed round the ring, ruled.occ.wall) fitted as
one closed ruled surface: with no corner both contours share, one periodic fit; else the ring cut at those
corners into pieces, each fitted with its end rulings on the corner lines (pinned), and the pieces' results
joined into one closed surface whose corner lines are C0 rulings.  Plain arrays only: every host's wall
comes here.  The closed result is certified twice: by the pieces' own certificates and as a whole, one way at
a time (ring_bound), the lower kept."""

from __future__ import annotations

from dataclasses import dataclass
from dataclasses import replace as _replace
from typing import Optional

import numpy as np

from ruled.core.edgerows import CORNER_GRADED_MAX
from ruled.core.errors import BadInputError
from ruled.core.nurbs import Surface
from ruled.fit.wall.join import elevated_u, end_to_end, remapped

# a ring's pieces' bound below this fraction of its size is kept as it is (certified a second time as a whole, one
# way at a time, it could only come down where no CAD tolerance asks)
RING_FLOOR = 1e-6
# ... nor one whose result or joined surface has more smooth parts than this (degree 1 along the ring: every knot a
# crease), whose one-way certificates would map each grid cell into a part of a few cells (the measure's limit
# for its graded corner rulings, the same kind of result); a result whose corners were crossed (ruled.fit.wall.
# corners) has its windows' breaks beside those, certified when the result before the crossing was
RING_PARTS = CORNER_GRADED_MAX


def piece(S: Surface, a: float, b: float) -> Surface:
    """S (clamped along u, with full-multiplicity knots at a and b, or a > b: through its seam u = 1 = 0)
    between u = a and u = b, its u running on from a (past 1 where it wraps)."""
    p = S.degree_u
    k = S.knots_u
    if a < b:
        lo, hi = int(np.searchsorted(k, a, "left")), int(np.searchsorted(k, b, "right"))
        j0 = 0 if a == k[0] else lo - 1                       # the columns at a and b: the curve's poles there
        j1 = S.poles.shape[0] - 1 if b == k[-1] else hi - p - 1
        knots = np.concatenate([[a] * (p + 1), k[(k > a) & (k < b)], [b] * (p + 1)])
        return Surface(S.poles[j0:j1 + 1], knots, S.knots_v, p, S.degree_v,
                       None if S.weights is None else S.weights[j0:j1 + 1])
    if b <= k[0]:
        return piece(S, a, k[-1])
    if a >= k[-1]:
        return piece(S, k[0], b)
    first, second = piece(S, a, k[-1]), piece(S, k[0], b)
    w1 = first.weights if first.weights is not None else np.ones(first.poles.shape[:2])
    w2 = second.weights if second.weights is not None else np.ones(second.poles.shape[:2])
    r = float(np.mean(w1[-1] / w2[0]))
    knots = np.concatenate([first.knots_u[:-1], 1.0 + second.knots_u[p + 1:]])
    W = np.concatenate([w1, r * w2[1:]])
    return Surface(np.concatenate([first.poles, second.poles[1:]]), knots, S.knots_v, p, S.degree_v,
                   W if S.weights is not None else None)


def clamped_u(R: Surface) -> Surface:
    """R clamped along u on its domain (a periodic surface stored unwrapped, as a host's periodic form reads,
    made ordinary: the same geometry on [u0, u1]); R itself when clamped already."""
    from ruled.core.knots import clamp_segment
    from ruled.fit.wall.join import along_u
    k, p = R.knots_u, R.degree_u
    if np.ptp(k[:p + 1]) == 0 and np.ptp(k[-p - 1:]) == 0:
        return R
    u0, u1 = R.domain[:2]
    return along_u(R, lambda c: clamp_segment(c, u0, u1))


def smooth_parts(R: Surface, ranges: bool = False, unit: bool = False) -> list:
    """R cut at its creases along u (C0 rulings) into its smooth parts, each clamped: a closed wall result
    measured part by part (a global distance search does not cross a crease).  ranges: (a, b, part) each, R's
    [a, b] the part; unit: each part's u running on [0, 1] (else on [a, b])."""
    R = clamped_u(R)
    u0, u1 = R.domain[:2]
    cuts = [u0, *[float(c) for c in R.creases(0)], u1]
    out = [(a, b, piece(R, a, b)) for a, b in zip(cuts[:-1], cuts[1:]) if b > a]
    if unit:
        out = [(a, b, remapped(P, 0.0, 1.0, *R.domain[2:])) for a, b, P in out]
    return out if ranges else [P for _, _, P in out]


def stacked(surfaces: list, ranges: list, size: float) -> tuple:
    """(Surface, gap): ruled surfaces (v of degree 1), each reparametrized onto its u range, joined end to end
    with full-multiplicity knots (C0) into one, their u degrees raised to the largest (exactly) and each
    rail's weights scaled to agree at the joints (a rail's weights scaled keep the ruled surface as a point
    set: each ruling is still the segment between its rails' points), and the two end rulings met at a joint
    replaced by their mean; gap: the largest distance between joined end rulings (round-off where each ends
    on the same corner line; 4D pieces lift theirs off it).  Each piece moves by at most gap / 2 (a pole moved
    moves the surface by at most as much: its basis functions are positive and sum to one)."""
    p = max(R.degree_u for R in surfaces)
    ps = [elevated_u(remapped(R, a, b, *R.domain[2:]), p) for R, (a, b) in zip(surfaces, ranges)]
    S, offs, _ = end_to_end(ps)
    return S, max(offs)


def own_net(R: Surface, S: Surface, bound: float, size: float) -> float:
    """The smaller of a fit's bound and, where the result R is the ruled surface S itself in another
    representation of the same net (both of degree 1 along the rulings, the same knots up to an affine map,
    each rail's weights the same up to a factor: an exactly ruled wall fitted along its own rulings), the
    largest distance between their poles: each rail of R is then within it of S's (its points convex
    combinations of the pole differences), and so is each ruling, the segment between them."""
    if R.degree_v != 1 or S.degree_v != 1 or R.poles.shape != S.poles.shape or R.degree_u != S.degree_u:
        return bound

    def unit(k):
        return (k - k[0]) / (k[-1] - k[0])
    if np.max(np.abs(unit(R.knots_u) - unit(S.knots_u))) > 1e-12:
        return bound
    wr = R.weights if R.weights is not None else np.ones(R.poles.shape[:2])
    ws = S.weights if S.weights is not None else np.ones(S.poles.shape[:2])
    ratio = wr / ws
    if np.max(np.ptp(ratio, axis=0) / np.max(ratio, axis=0)) > 1e-12:
        return bound
    return min(bound, float(np.max(np.linalg.norm(R.poles - S.poles, axis=2))) + 1e-12 * size)


@dataclass
class RingFit:
    """The pieces' fits (one: a periodic fit of the whole ring), the closed result and its certified bound
    (the faces' own distance from the joined surface, and a periodic result's building, not included)."""

    results: list
    surface: Surface
    bound: float
    periodic: bool
    crossed: int = 0        # corners whose rulings were paired anew across them (ruled.fit.wall.corners)
    plain: Optional[tuple] = None   # where they were: (surface, bound) of the result with the corners' own rulings


def fit_ring(S: Surface, breaks, corners, options, size: float, progress=None) -> RingFit:
    """The joined surface S (u round the ring, the faces' joints at breaks; v from the bottom contour to the
    top) fitted along v as one closed ruled surface; corners: the joints (indices into breaks) both contours
    turn at.  options.samples are spread over the pieces by their share of the ring."""
    from ruled.fit.face.patch import with_iso
    from ruled.fit.fit2d import pinned_at_seam
    from ruled.fit.options import Direction
    from ruled.fit.surface import fit_surface
    opts = _replace(options.checked(), direction=Direction.V)
    cuts = [float(breaks[k]) for k in corners]
    if not cuts:
        res = with_iso(fit_surface(S, opts, progress), progress)
        if not res.best.closed:
            raise BadInputError("the wall's joined surface did not close round the ring (please report the part)")
        return RingFit([res], res.best.surface, own_net(res.best.surface, S, res.error_bound, size), True)
    ranges = [(c, cuts[(i + 1) % len(cuts)]) for i, c in enumerate(cuts)]
    spans = [(b - a) % 1.0 or 1.0 for a, b in ranges]
    results, pieces = [], []
    for i, ((a, b), share) in enumerate(zip(ranges, spans)):
        part = pinned_at_seam(piece(S, a, b))
        pieces.append(part)
        n = max(8, int(round(opts.samples * share)))
        say = None if progress is None else (lambda st, f, i=i: progress(f"piece {i + 1}/{len(ranges)}: {st}", f))
        results.append(with_iso(fit_surface(part, _replace(opts, samples=n).checked(), say), say))
    unwrapped = [(a, a + share) for (a, _), share in zip(ranges, spans)]
    surface, gap = stacked([r.best.surface for r in results], unwrapped, size)
    bound = max(own_net(r.best.surface, p, r.error_bound, size) for r, p in zip(results, pieces)) + 0.5 * gap
    if gap > 1e-9 * size and all(r.other is not None for r in results):
        # 4D pieces lift their end rulings off the corner lines: their 2D fits, which end on them, when the
        # mean of the lifted end rulings costs more than the lift gains
        s2, gap2 = stacked([r.other.surface for r in results], unwrapped, size)
        b2 = max(own_net(r.other.surface, p, r.other.error_bound, size) for r, p in zip(results, pieces)) + 0.5 * gap2
        if b2 < bound:
            surface, bound = s2, b2
            results = [_replace(r, best=r.other, other=r.best) for r in results]
    if bound > RING_FLOOR * size:
        if progress is not None:
            progress("certify the ring", 0.0)
        whole = ring_bound(S, surface)
        bound = min(bound, whole)
        across, count = _across_corners(S, surface, cuts, spans) if np.isfinite(whole) else (surface, 0)
        if count:
            if progress is not None:
                progress("certify the ring, its corners crossed", 0.5)
            b2 = ring_bound(S, across, crossed=True)
            if b2 < bound:
                return RingFit(results, across, b2, False, count, (surface, bound))
    return RingFit(results, surface, bound, False)


def _across_corners(S: Surface, R: Surface, cuts: list, spans: list):
    """(surface, count): R with its rulings paired anew across the corners whose corner ruling lies far from the
    wall (ruled.fit.wall.corners), on R's own domain, and how many; (R, 0) where no corner gains (or R is
    rational)."""
    from ruled.fit.wall.corners import cross_corners
    if R.weights is not None:
        return R, 0
    c0, c1 = R.domain[:2]
    Rn = remapped(clamped_u(R), 0.0, 1.0, *R.domain[2:])
    corners = [((c - c0) / (c1 - c0)) % 1.0 for c in cuts]
    lengths = [min(spans[i], spans[i - 1]) / (c1 - c0) for i in range(len(cuts))]
    got, count = cross_corners(smooth_parts(S, ranges=True), Rn, corners, lengths,
                               lambda x: np.mod(c0 + (c1 - c0) * x - S.domain[0], S.domain[1] - S.domain[0])
                               + S.domain[0])
    return (remapped(got, c0, c1, *R.domain[2:]), count) if count and got is not None else (R, 0)


def ring_bound(S: Surface, R: Surface, crossed: bool = False) -> float:
    """The closed result R certified against the wall's joined surface S as a whole, one way at a time
    (ruled.fit.certify.onesided: where a joint bows off its corner line, its points are nearer the result past
    the corner than the corner ruling the pieces' own certificates send them to), with round-off; inf for a
    polyline wall or result (RING_PARTS; crossed: R is a result whose corners were crossed, its windows' breaks
    not counted)."""
    from ruled.fit.certify.forward import rounding
    from ruled.fit.certify.onesided import result_to_wall, wall_to_result
    Rn = remapped(clamped_u(R), 0.0, 1.0, *R.domain[2:])
    R_parts, S_parts = smooth_parts(Rn, ranges=True, unit=True), smooth_parts(S, ranges=True)
    if max(0 if crossed else len(R_parts), len(S_parts)) > RING_PARTS:
        return np.inf       # (a polyline result or wall: a part per span, each a few grid columns)
    return max(wall_to_result(S, Rn, R_parts), result_to_wall(S, S_parts, Rn)) + rounding(S, R)


__all__ = ["RingFit", "fit_ring", "ring_bound", "piece", "stacked", "own_net", "clamped_u", "smooth_parts"]
