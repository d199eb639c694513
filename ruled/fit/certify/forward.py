"""A certified upper bound of the two-sided Hausdorff distance between S and a ruled result R.

Let psi map the domain of S into the domain (s, t) of R (a continuous,
piecewise bilinear map on a grid aligned with the knot spans of S), sending
each boundary side of S's domain into the matching side of R's domain: the
boundary v0 to t = 0 through the pairing (s = a^-1), v1 to t = 1, and for an
open face the first and last u to s = 0 and s = 1.  Such a map is onto R's
domain (its boundary map has degree one), so for every point of S and every
point of R there is a (u, v) with both S(u, v) and R(psi(u, v)) and hence

    H(S, R) <= sup |f(u, v)|,   f = S - R o psi.

On each grid cell f has bounded second derivatives (S is polynomial or rational
inside a knot span; R has a continuous first derivative away from its kink
parameters, the knots of full multiplicity), and bilinear interpolation gives

    sup_cell |f| <= max_corners |f| + (h_u^2 sup|f_uu| + h_v^2 sup|f_vv|) / 8
                   (+ |jump of R_s| (|ds_u| + |ds_v|) / 4 per kink crossed),

with f_uu bounded by the per-span control-net bounds of S_uu and by
R_ss ds^2 + 2 R_st ds dt (psi is linear along each cell edge direction; R_tt
is zero), R's bounds again from control nets (quotient rule when rational).
The derivative jump at a kink is measured from one-sided derivatives.
Interior nodes use the closest point of R (Gauss–Newton over the rulings), or
stay near the pairing's own correspondence; both maps are tried and the
smaller bound kept.  Any choice keeps the bound valid, closer ones make it
tighter.  Rows next to the boundaries are graded and extra columns follow
the pairing where it crawls (fans of rulings), so the cells stay small there.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ruled.core.nurbs import Surface
from ruled.fit.certify.bounds import (
    _knot_grid,
    _nodes_of,
    _pairing_s,
    _polished_feet,
    _segment_feet,
    _snap,
    _twin,
    graded_nodes,
)
from ruled.fit.certify.cells import FLOOR, RAIL_T, Certificate, _cells_to_split, _corner_max, folds
from ruled.fit.certify.remainder import _first_order, _remainder2, _s_range
from ruled.fit.certify.reverse import certify_reverse
from ruled.fit.dp.pairing import Pairing
from ruled.fit.face.extend import face_mask
from ruled.fit.reparam import Boundaries

# the second-order remainder is tried where the bound exceeds the node maximum by this factor
SECOND_ORDER_WHEN = 1.1
# a trimmed result's certificate keeps at most this many other maps (see certify)
ALTERNATIVES = 8
# ... those whose node maximum is below this many times the best bound (a smoother map's trim can cost far less)
TRIM_PRUNE = 2.0
# the refinement rounds stop before a grid this many times the first one
GRID_GROWTH = 8


# round-off of the evaluations the bound rests on (points of S and R, their differences), in units of
# the largest coordinate: a few dozen operations each, each within half an ulp (a face far from the
# origin and tiny carries its coordinates' round-off in every distance)
ROUND_ULPS = 64
# the result as written: a STEP file carries 13-14 significant digits, and a round trip (OCCT's writer and
# reader) moved a result by up to 4e-13 of its largest coordinate on the data files (space ship face 69:
# 7.0e-11 at coordinates up to 185); the bound covers the file, with a margin, at this fraction of it
WRITTEN = 1e-12


def certify(S: Surface, pairing: Pairing, bd: Boundaries, R: Surface,
            target_u: int = 240, target_v: int = 80, rounds: int = 3, rival: float = np.inf) -> Certificate:
    """Certified bound of H(S, R) for a fit oriented along v (see the module doc); the pairing's
    normalized parameters run over S's u-domain.  Cells whose remainder dominates their bound are
    split (up to ``rounds`` times), where psi is steep (fans of rulings, twisted or lifted results),
    unless the rounds left cannot bring the bound below ``rival`` (a bound already certified)."""
    closed = pairing.closed
    u0, u1, v0, v1 = S.domain
    L = u1 - u0
    # nodes where the pairing maps the ruling grid, where a or b crawls (fans of rulings): there
    # a small step in u spans many rulings, and the cells must stay small in s
    sg = np.linspace(0.0, 1.0, 4 * target_u + 1)
    ag, bg = pairing.ab(sg)
    slow_a = np.diff(ag) < 0.5 / (4 * target_u)
    slow_b = np.diff(bg) < 0.5 / (4 * target_u)
    keep_a = np.concatenate([slow_a, [False]]) | np.concatenate([[False], slow_a])
    keep_b = np.concatenate([slow_b, [False]]) | np.concatenate([[False], slow_b])
    xg = np.concatenate([ag[keep_a][::2], bg[keep_b][::2]])
    if closed:
        xg = np.mod(xg, 1.0)
    extra_u = u0 + L * xg
    # graded rows next to both boundaries, where a fan of rulings makes psi steep
    grade = (v1 - v0) / target_v * 0.5 ** np.arange(1, 11)
    extra_v = np.concatenate([v0 + grade, v1 - grade])
    # and at equal steps of arc length where extreme weights make the parameter speed vary
    extra_u = np.concatenate([extra_u, graded_nodes(S, "u", target_u)])
    extra_v = np.concatenate([extra_v, graded_nodes(S, "v", target_v)])
    tw = (_twin(S), _twin(R, ruled=True))
    b = tw[0].derivative_bounds()
    best = prev = None
    others: list = []
    for rnd in range(rounds + 1):
        us, span_u = _knot_grid(S, "u", target_u, extra_u, tw[0])
        vs, span_v = _knot_grid(S, "v", target_v, extra_v, tw[0])
        cert, guide, prev, alts = _grid_bound(S, b, pairing, bd, R, us, vs, span_u, span_v, target_u, tw, prev)
        others.extend(alts)
        if best is None or cert.bound < best.bound:
            best = cert
        split = _cells_to_split(guide[0], guide[1], guide[2], FLOOR * S.diagonal(), uniform=True)
        # each round about halves the excess over the node maximum: stop where even that would not
        # bring the bound below the rival's (the other side's certificate)
        hope = cert.node_max + (cert.bound - cert.node_max) / 2 ** (rounds - rnd)
        if rnd == rounds or split is None or hope >= rival:
            break
        iu, iv = split
        grown = (us.size + np.unique(iu).size) * (vs.size + np.unique(iv).size)
        if grown > GRID_GROWTH * (target_u + 1) * (target_v + 1):
            break       # the next grid would cost more than the bound is worth (an exact fit asks for ever more)
        extra_u = np.concatenate([extra_u, 0.5 * (us[iu] + us[iu + 1])])
        extra_v = np.concatenate([extra_v, 0.5 * (vs[iv] + vs[iv + 1])])
    if others:
        # a trimmed result: the other maps that keep their orientation over the face, lowest bound first, for
        # the trim to choose from (its own part of the bound depends on how smooth the map's image of the
        # face's edges is: ruled.fit.face.trim.with_trim)
        alts = sorted((c for c in others if c is not best), key=lambda c: c.bound)[:ALTERNATIVES]
        best = replace(best, alternatives=tuple(alts))
    return best


def _grid_bound(S, b, pairing, bd, R, us, vs, span_u, span_v, target_u, tw, prev=None):
    """Best bound over the candidate maps psi on one grid, and the map that guides the refinement
    (certificate, per-cell bound, remainder parts): the one whose bound may fall lowest, a quarter of
    its remainder above its node maximum (a map whose nodes are far from R cannot get below them).
    prev: the last round's (us, vs, nodes), whose nodes keep their points and closest points; the
    same is returned for the next round."""
    closed = pairing.closed
    u0, u1, v0, v1 = S.domain
    L = u1 - u0
    nu, nv = us.size, vs.size
    x = (us - u0) / L
    tau = (vs - v0) / (v1 - v0)
    s_init = _pairing_s(pairing, x, tau)
    # per node: its point of S and its closest point on R (pointwise: a node of the last grid keeps them)
    node = np.empty((nu, nv, 5))
    new = np.ones((nu, nv), bool) if prev is None else ~_nodes_of(prev, us, vs, node)
    UU, VV = np.meshgrid(us, vs, indexing="ij")
    node[new, :3] = S(UU[new], VV[new])
    node[new, 3], node[new, 4] = _polished_feet(bd, R, np.ascontiguousarray(node[new, :3]), s_init[new], closed)
    X = np.ascontiguousarray(node[:, :, :3])
    s_feet, t_feet = node[:, :, 3].ravel(), node[:, :, 4].ravel()
    jump = np.abs(s_feet - s_init.ravel())
    if closed:
        jump = np.minimum(jump, 1.0 - jump)
    maps = []
    # Two maps, both valid: closest points (tight where the fit is good), and closest points kept
    # near the pairing's own correspondence (a foot that jumps, to the other sheet of a thin part
    # say, folds psi and inflates the remainder).
    prev = None
    for k, limit in enumerate((np.inf, 0.5 / target_u)):
        s, t = s_feet.copy(), t_feet.copy()
        far = jump > limit
        if k > 0 and np.array_equal(far, prev):
            continue  # the same map again
        prev = far
        if far.any():
            s0, t0 = _segment_feet(bd.A, bd.B, X.reshape(-1, 3)[far], s_init.ravel()[far], closed, iters=0)
            s[far], t[far] = s0, t0
        maps.append((s, t))
    # Smoothed closest points: where the closest ruling jumps (a twisted or lifted result), a
    # smoothed field of s keeps psi continuous at the price of slightly larger node distances.
    ds = (s_feet - s_init.ravel()).reshape(nu, nv)
    if closed:
        ds = ds - np.round(ds)
    for sweeps in (4, 16, 64):
        s = (s_init + _smooth(ds, sweeps)).ravel()
        _, t = _segment_feet(bd.A, bd.B, X.reshape(-1, 3), s, closed, iters=0)
        maps.append((s, t))
    mask = face_mask(S)
    if mask is not None:
        # a trimmed result needs a map that keeps its orientation over the face (ruled.fit.face.trim): the
        # pairing's own correspondence at the grid's own t (psi_u = (s_x, 0), psi_v = (s_tau, 1): it folds
        # nowhere the pairing runs forward), far from the closest points where the face is far from ruled
        maps.append((s_init.ravel().copy(), np.broadcast_to(tau[None, :], (nu, nv)).ravel().copy()))
    best, which, guide, alts = None, 0, None, []

    def reach(c):
        return c.node_max + 0.25 * (c.bound - c.node_max)

    best_folds = False

    def take(out) -> bool:
        # whether out is the new best: a map that folds over the face is the best only where no map keeps its
        # orientation; one that keeps it is among the alternatives (each map checked once)
        nonlocal best_folds
        fo = _folds_face(out[0], mask)
        if mask is not None and not fo:
            alts.append(out[0])
        if best is None or fo < best_folds or (fo == best_folds and out[0].bound < best[0].bound):
            best_folds = fo
            return True
        return False
    for k, (s, t) in enumerate(maps):
        out = _map_bound(S, b, X, us, vs, span_u, span_v, x, s.reshape(nu, nv).copy(), t.reshape(nu, nv).copy(),
                         pairing, bd, R, tw, prune=np.inf if best is None or best_folds
                         else best[0].bound * (1.0 if mask is None else TRIM_PRUNE))
        if out is None:
            continue
        if take(out):
            best, which = out, k
        if guide is None or reach(out[0]) < reach(guide[0]):
            guide = out
    if best[0].bound > SECOND_ORDER_WHEN * best[0].node_max:
        # the remainder dominates (an exact or nearly exact fit): the second-order remainder may be far
        # smaller (see _remainder2); the closest points (smooth where the fit is exact) and the best map
        # again, each cell keeping the smaller of the two
        for s, t in {0: maps[0], which: maps[which]}.values():
            out = _map_bound(S, b, X, us, vs, span_u, span_v, x, s.reshape(nu, nv).copy(),
                             t.reshape(nu, nv).copy(), pairing, bd, R, tw, second=True, prune=best[0].bound)
            if out is None:
                continue
            if take(out):
                best = out
            if reach(out[0]) < reach(guide[0]):
                guide = out
    return best[0], guide, (us, vs, node), alts


def _folds_face(cert: Certificate, mask) -> bool:
    """Whether a masked certificate's map folds over the face's cells (those along R's rails left out:
    ruled.fit.face.trim checks them against the trim's own segments)."""
    if mask is None or cert.psi is None:
        return False
    us, vs, _, t = cert.psi
    ct = np.stack([t[:-1, :-1], t[1:, :-1], t[:-1, 1:], t[1:, 1:]])
    along = (np.abs(ct).max(axis=0) <= RAIL_T) | (np.abs(ct - 1.0).max(axis=0) <= RAIL_T)
    return folds(cert.psi, mask.cells(us, vs) & ~along)


def _smooth(f: np.ndarray, sweeps: int) -> np.ndarray:
    """Repeated 5-point averaging (edges replicated)."""
    g = f.copy()
    for _ in range(sweeps):
        p = np.pad(g, 1, mode="edge")
        g = (4.0 * g + p[:-2, 1:-1] + p[2:, 1:-1] + p[1:-1, :-2] + p[1:-1, 2:]) / 8.0
    return g


def _map_bound(S, b, X, us, vs, span_u, span_v, x, s, t, pairing, bd, R, tw, second=False, prune=np.inf,
               sides=True):
    """The bound of the module doc for one map psi = (s, t) on the grid (us, vs); with ``second``,
    each cell's remainder is the smaller of the first- and the second-order one (_remainder2).  None
    when the map's node maximum is already at least ``prune`` (a bound in hand: this map cannot beat it,
    nor guide the refinement better).  sides=False: psi as given, its sides not sent to R's (each cell's
    bound then holds for the distance from S's points to R alone: ruled.fit.certify.onesided)."""
    closed = pairing.closed
    nu, nv = us.size, vs.size
    if sides:
        _to_sides(X, x, s, t, pairing, bd, closed)
    s = _snap(s, bd.A, closed)
    sw = np.mod(s, 1.0) if closed else s
    Rp = R(sw.ravel(), t.ravel()).reshape(nu, nv, 3)
    f = np.linalg.norm(X - Rp, axis=2)
    # a trimmed result: only the cells that meet the face count (ruled.fit.face.extend)
    mask = face_mask(S)
    cm = None if mask is None else mask.cells(us, vs)
    fmax = float(f.max()) if cm is None else float(_corner_max(f)[cm].max())
    if fmax >= prune:
        return None
    ru, rv = _first_order(S, b, us, vs, span_u, span_v, s, t, bd, R, tw, closed)
    if second:
        # only where it can matter: a cell whose first-order bound is within the node maximum (which the
        # bound is at least) leaves the bound, and the cells the refinement splits, as they are
        need = _corner_max(f) + ru + rv > fmax
        slo, shi = _s_range(s, closed)
        r2u, r2v = _remainder2(S, us, vs, span_u, span_v, s, t, slo, shi, closed, R, bd, tw, need)
        use = r2u + r2v < ru + rv
        ru, rv = np.where(use, r2u, ru), np.where(use, r2v, rv)
    if cm is not None:
        ru, rv = np.where(cm, ru, 0.0), np.where(cm, rv, 0.0)
    rem = ru + rv
    cell = _corner_max(f) + rem
    psi = None
    if cm is not None:
        cell = np.where(cm, cell, 0.0)
        psi = (us.copy(), vs.copy(), s.copy(), t.copy())
    return Certificate(float(cell.max()), fmax, float(rem.max()), (nu, nv), psi=psi), cell, (ru, rv)


def _to_sides(X, x, s, t, pairing, bd, closed) -> None:
    """psi's boundary rows and columns (in place) sent to R's sides, so that psi maps sides to sides."""
    xa = x if not closed else pairing.ab(np.array([0.0]))[0][0] + np.mod(x - pairing.ab(np.array([0.0]))[0][0], 1.0)
    xb = x if not closed else pairing.ab(np.array([0.0]))[1][0] + np.mod(x - pairing.ab(np.array([0.0]))[1][0], 1.0)
    # the boundary rows go to the boundary curves of R at their closest points (seeded by the
    # pairing): any continuous side-to-side map keeps psi onto, and lifted boundaries (4D) are not
    # where the pairing puts them
    for col, xx, C, which in ((0, xa, bd.A, "a"), (-1, xb, bd.B, "b")):
        s0 = pairing.inverse(xx, which)
        sc, _ = _segment_feet(C, C, np.ascontiguousarray(X[:, col]), s0, closed)
        if closed:
            sc = s0 + (np.mod(sc - s0 + 0.5, 1.0) - 0.5)
        s[:, col], t[:, col] = sc, (0.0 if col == 0 else 1.0)
    if not closed:
        for col, sv in ((0, 0.0), (-1, 1.0)):
            a0 = bd.A(np.array([sv]))[0]
            b0 = bd.B(np.array([sv]))[0]
            d = b0 - a0
            dd = max(float(d @ d), 1e-300)
            s[col, 1:-1] = sv
            t[col, 1:-1] = np.clip((X[col, 1:-1] - a0) @ d / dd, 0.0, 1.0)


def rounding(S: Surface, R: Surface) -> float:
    """The round-off of the evaluations a bound of H(S, R) rests on, and of the result as written (ROUND_ULPS,
    WRITTEN)."""
    return (ROUND_ULPS * np.finfo(float).eps + WRITTEN) * max(float(np.abs(S.poles).max()),
                                                             float(np.abs(R.poles).max()))


def certified_bound(S: Surface, pairing: Pairing, bd: Boundaries, R: Surface, target_u: int = 240,
                    target_v: int = 80, cutoff: float = np.inf) -> Certificate:
    """The smaller of the two certified bounds (both valid): from R's side (certify_reverse) and,
    unless that one is already within 2 % of its own node maximum or its node maximum (a sampled
    distance of the fit) is already at least ``cutoff`` (another candidate's bound: this one cannot
    win), from S's side (certify)."""
    rnd = rounding(S, R)
    if face_mask(S) is not None:
        # a trimmed result: the forward map's image of the face is the result (ruled.fit.face.trim)
        fwd = certify(S, pairing, bd, R, target_u, target_v, rival=cutoff)
        alts = tuple(replace(c, bound=c.bound + rnd, rounding=rnd) for c in fwd.alternatives)
        return replace(fwd, bound=fwd.bound + rnd, rounding=rnd, alternatives=alts)
    rev = certify_reverse(S, pairing, R, target_u, max(16, target_v // 2))
    if not (rev.bound <= 1.02 * rev.node_max or rev.node_max >= cutoff):
        fwd = certify(S, pairing, bd, R, target_u, target_v, rival=min(rev.bound, cutoff))
        rev = fwd if fwd.bound < rev.bound else rev
    return replace(rev, bound=rev.bound + rnd, rounding=rnd)
