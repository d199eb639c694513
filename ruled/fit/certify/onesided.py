"""A certified bound of a wall's closed result (its pieces fitted between the corners both contours share, each
with its end rulings on the corner lines, and joined), each direction of the Hausdorff distance on its own.

The pieces' own certificates (ruled.fit.certify.forward, .reverse) map each piece of the wall onto its piece
of the result, sides to sides: a joint of the wall that bows off its corner line is sent to the corner ruling,
and the bound is at least the bow, though the joint's points lie nearer the result past the corner (0.0025
against 0.00098 on a die's drafted hole).  Taken one way at a time nothing needs to be onto:

    H(S, R) = max(sup_S d(., R), sup_R d(., S)),

and for sup_S d(., R) each cell of a grid on S may be mapped into R by any continuous map: the cell's bound
(its corners' distances plus the interpolation remainder of ruled.fit.certify.forward) holds for every map,
so the smallest over the maps tried bounds the cell.  The maps: closest points on each smooth part of R (R cut
at its kinks, each part clamped: no remainder of a kink), and closest points on the whole of R (a cell whose
corners go to both sides of a corner ruling crosses the kink, whose slope jump costs J ds / 4: the grid's
columns are graded towards every crease, where such cells are).  The same from R's side onto S (ruled.fit.
certify.reverse, S's creases the kinks).  The closest points are seeded from the nearest of dense samples of
the other side, so no pairing is needed.
"""

from __future__ import annotations

import numpy as np

from ruled.core.basis import SpanRangeMax
from ruled.core.distance import project_points
from ruled.core.nurbs import Surface
from ruled.fit.certify.bounds import (
    _knot_grid,
    _nodes_of,
    _polished_feet,
    _rail,
    _twin,
    crease_jumps,
    knot_spans,
)
from ruled.fit.certify.cells import FLOOR, Certificate, _cells_to_split, _corner_max
from ruled.fit.certify.forward import _map_bound
from ruled.fit.certify.reverse import _reverse_cells
from ruled.fit.reparam import Boundaries

# grid cells per smooth part along the ring (at least), and across it (S's v, R's t); refinement rounds
PER_PART, GRID_V, GRID_T, ROUNDS = 48, 60, 30, 6
# graded columns towards each crease: this many, halving from a cell's width
GRADED = 12
# seeds: the other side sampled this many times per grid column, and across
SEED_ALONG, SEED_ACROSS = 4, 33
# the refinement stops before the grid grows past this many times its first size
GROWTH = 16


class _Closed:
    """A pairing's stand-in where only whether the result closes is asked (maps not sent to sides)."""

    def __init__(self, closed: bool):
        self.closed = closed


def _rails(R: Surface, kinks=np.zeros(0)) -> Boundaries:
    return Boundaries(_rail(R, 0), _rail(R, 1), 0.0, np.asarray(kinks, float))


def _graded(creases: np.ndarray, step: float, lo: float, hi: float) -> np.ndarray:
    """Nodes towards each crease from both sides, a cell's width halved GRADED times."""
    d = step * 0.5 ** np.arange(1, GRADED + 1)
    x = np.concatenate([np.concatenate([c - d, c + d]) for c in creases] or [np.zeros(0)])
    return np.mod(x - lo, hi - lo) + lo


def _seeder(T: Surface, n_along: int):
    """A function giving, for points X (N, 3), the parameters (N, 2) of the nearest of T's samples (a grid
    of T's domain, n_along by SEED_ACROSS)."""
    from scipy.spatial import cKDTree
    u0, u1, v0, v1 = T.domain
    uu, vv = np.meshgrid(np.linspace(u0, u1, n_along), np.linspace(v0, v1, SEED_ACROSS), indexing="ij")
    uv = np.stack([uu.ravel(), vv.ravel()], axis=1)
    tree = cKDTree(T(uv[:, 0], uv[:, 1]))
    return lambda X: uv[tree.query(X)[1]]


class _Known:
    """Values computed at a grid's nodes, per map, kept for the next round's grid (whose nodes that the last one
    had get them again: the same node, the same seed, the same closest point)."""

    def __init__(self):
        self.last = {}

    def at(self, key, xs: np.ndarray, ys: np.ndarray, cols: slice, compute) -> np.ndarray:
        """(columns, ys.size, 2): the values at the grid's columns cols, the last grid's where it had the node,
        compute(mask) (the values at the nodes of the mask, (k, 2)) at the others; all kept for the next grid."""
        values = np.full((xs.size, ys.size, 2), np.nan)
        if key in self.last:
            _nodes_of(self.last[key], xs, ys, values)
        sub = values[cols]
        new = np.isnan(sub[:, :, 0])
        if new.any():
            sub[new] = compute(new)
            values[cols] = sub
        self.last[key] = (xs, ys, values)
        return sub


def _min_cells(cells: list) -> tuple:
    """Per cell, the smallest of the maps' bounds, with its remainder's two parts."""
    C = np.stack([c for c, _ in cells])
    k = np.argmin(C, axis=0)[None]
    ru = np.take_along_axis(np.stack([r[0] for _, r in cells]), k, 0)[0]
    rv = np.take_along_axis(np.stack([r[1] for _, r in cells]), k, 0)[0]
    return np.take_along_axis(C, k, 0)[0], ru, rv


def _rounds(xs: np.ndarray, ys: np.ndarray, cells_of, floor: float) -> float:
    """The smallest bound over up to ROUNDS refinements of the grid (xs, ys): cells_of(xs, ys) -> (cell, one
    part of the remainder, the other); the cells dominated by their remainder are halved each round
    (ruled.fit.certify.cells), while the grid stays within GROWTH times its first size."""
    best, first = np.inf, xs.size * ys.size
    for rnd in range(ROUNDS + 1):
        cell, ru, rv = cells_of(xs, ys)
        rem = ru + rv
        cert = Certificate(float(cell.max()), float((cell - rem).max()), float(rem.max()), (xs.size, ys.size))
        best = min(best, cert.bound)
        split = None if rnd == ROUNDS else _cells_to_split(cert, cell, (ru, rv), floor, uniform=True)
        if split is None:
            break
        iu, iv = split
        xs = np.unique(np.concatenate([xs, 0.5 * (xs[iu] + xs[iu + 1])]))
        ys = np.unique(np.concatenate([ys, 0.5 * (ys[iv] + ys[iv + 1])]))
        if xs.size * ys.size > GROWTH * first:
            break
    return best


def _columns(seed: np.ndarray, a: float, c: float, step: float):
    """The grid's columns (a slice) whose nodes' seeds fall in [a, c] or within two steps of the seeds' samples
    of it (the nearest sample may lie across the part's end from the nearest point), a column more on each
    side (the cells along the part), or None."""
    hit = np.nonzero(((seed >= a - 2 * step) & (seed <= c + 2 * step)).any(axis=1))[0]
    if hit.size == 0:
        return None
    return slice(max(int(hit[0]) - 1, 0), min(int(hit[-1]) + 2, seed.shape[0]))


def _sub(spans: tuple, cols: slice) -> tuple:
    """The cells' span ranges of a slice of the grid's columns."""
    return spans[0][cols.start:cols.stop - 1], spans[1][cols.start:cols.stop - 1]


def _placed(got: tuple, cols: slice, shape: tuple) -> tuple:
    """A sub-grid's (cell, (u part, v part)) in the whole grid's cells, infinity elsewhere."""
    cell, (ru, rv) = got
    full = [np.full(shape, np.inf), np.zeros(shape), np.zeros(shape)]
    for F, g in zip(full, (cell, ru, rv)):
        F[cols.start:cols.stop - 1] = g
    return full[0], (full[1], full[2])


def _local(g: np.ndarray, a: float, c: float) -> np.ndarray:
    """A whole surface's parameters g as a part's on [0, 1] (the part is its [a, c]), clamped."""
    return np.clip((g - a) / (c - a), 0.0, 1.0)


def wall_to_result(S: Surface, R: Surface, R_parts: list) -> float:
    """A certified bound of sup d(x, R) over the wall's points x.  S: the wall's joined surface (closed along u,
    its creases the faces' joints); R: the result (ruled along v, closed along u, s on [0, 1]); R_parts: (a, c,
    part) for R cut at its kinks, each part's s on [0, 1] (R's [a, c])."""
    u0, u1, v0, v1 = S.domain
    Sb = _twin(S)
    b = Sb.derivative_bounds()
    kinks = np.array([a for a, _, _ in R_parts if a > 0.0])
    parts = [(a, c, Q, _rails(Q), _twin(Q, ruled=True)) for a, c, Q in R_parts]
    whole = (_rails(R, kinks), _twin(R, ruled=True))
    target = PER_PART * len(R_parts)
    creases = np.concatenate([[u0], S.creases(0)])
    seeds = _seeder(R, SEED_ALONG * target)
    known = _Known()

    def cells_of(us, vs):
        span_u, span_v = knot_spans(Sb, "u", us), knot_spans(Sb, "v", vs)
        UU, VV = np.meshgrid(us, vs, indexing="ij")
        X = np.ascontiguousarray(S(UU.ravel(), VV.ravel()).reshape(us.size, vs.size, 3))
        seed = seeds(X.reshape(-1, 3))[:, 0].reshape(us.size, vs.size)
        x = (us - u0) / (u1 - u0)
        out, best_d = [], np.full(X.shape[:2], np.inf)
        best_s, best_t = np.zeros(X.shape[:2]), np.zeros(X.shape[:2])
        for p, (a, c, Q, bd, tw) in enumerate(parts):
            cols = _columns(seed, a, c, 1.0 / (SEED_ALONG * target))
            if cols is None:
                continue
            Xc = np.ascontiguousarray(X[cols])

            def feet(new, Xc=Xc, cols=cols, a=a, c=c, Q=Q, bd=bd):
                s, t = _polished_feet(bd, Q, np.ascontiguousarray(Xc[new]), _local(seed[cols][new], a, c), False)
                return np.stack([np.clip(s, 0.0, 1.0), np.clip(t, 0.0, 1.0)], axis=1)
            sub = known.at(p, us, vs, cols, feet)
            s, t = sub[:, :, 0].copy(), sub[:, :, 1].copy()
            d = np.linalg.norm(Xc - Q(s.ravel(), t.ravel()).reshape(Xc.shape), axis=2)
            better = d < best_d[cols]
            best_d[cols] = np.where(better, d, best_d[cols])
            best_s[cols] = np.where(better, a + (c - a) * s, best_s[cols])
            best_t[cols] = np.where(better, t, best_t[cols])
            got = _map_bound(S, b, Xc, us[cols], vs, _sub(span_u, cols), span_v, x[cols], s, t, _Closed(False), bd,
                             Q, (Sb, tw), sides=False)
            out.append(_placed(got[1:], cols, (us.size - 1, vs.size - 1)))
        got = _map_bound(S, b, X, us, vs, span_u, span_v, x, best_s, best_t, _Closed(True), whole[0], R,
                         (Sb, whole[1]), sides=False)
        out.append(got[1:])
        return _min_cells(out)
    us = _knot_grid(S, "u", target, _graded(creases, (u1 - u0) / target, u0, u1), Sb)[0]
    vs = _knot_grid(S, "v", GRID_V, None, Sb)[0]
    return _rounds(us, vs, cells_of, FLOOR * S.diagonal())


def result_to_wall(S: Surface, S_parts: list, R: Surface) -> float:
    """A certified bound of sup d(y, S) over the result's points y (S, R as wall_to_result; S_parts: (a, c,
    part) for S cut at its creases, each part's u on its own [a, c])."""
    u0, u1, v0, v1 = S.domain
    L = u1 - u0
    Rb = _twin(R, ruled=True)
    Rss_span = Rb.derivative_bounds()["Suu"][:, 0]
    none = (np.zeros(0), np.zeros(0))

    def maxima(T):
        Tb = _twin(T)
        bT = Tb.derivative_bounds()
        return {k: SpanRangeMax(Tb.knots_u, Tb.degree_u, bT[k].max(axis=1)) for k in ("Suu", "Suv", "Svv")}
    parts = [(a, c, Q, maxima(Q)) for a, c, Q in S_parts]
    whole = (maxima(S), (crease_jumps(S, 0, True), crease_jumps(S, 1)))
    target = PER_PART * len(S_parts)
    seeds = _seeder(S, SEED_ALONG * target)
    known = _Known()

    def cells_of(ss, tt):
        span_s = knot_spans(Rb, "u", ss)
        SS, TT = np.meshgrid(ss, tt, indexing="ij")
        Y = R(SS.ravel(), TT.ravel()).reshape(ss.size, tt.size, 3)
        seed = seeds(Y.reshape(-1, 3)).reshape(ss.size, tt.size, 2)
        out, best_d, best = [], np.full(SS.shape, np.inf), np.zeros(SS.shape + (2,))
        for p, (a, c, Q, M) in enumerate(parts):
            cols = _columns(seed[:, :, 0], a, c, L / (SEED_ALONG * target))
            if cols is None:
                continue
            Yc = np.ascontiguousarray(Y[cols])

            def feet(new, Yc=Yc, cols=cols, a=a, c=c, Q=Q):
                sd = seed[cols][new]
                return project_points(Q, np.ascontiguousarray(Yc[new]),
                                      np.stack([np.clip(sd[:, 0], a, c), sd[:, 1]], axis=1), 8)[0]
            uv = known.at(p, ss, tt, cols, feet)
            d = np.linalg.norm(Yc - Q(uv[:, :, 0].ravel(), uv[:, :, 1].ravel()).reshape(Yc.shape), axis=2)
            better = d < best_d[cols]
            best_d[cols] = np.where(better, d, best_d[cols])
            best[cols] = np.where(better[:, :, None], uv, best[cols])
            f, rs, rt = _reverse_cells(Q, Yc, ss[cols], _sub(span_s, cols), tt, uv[:, :, 0], uv[:, :, 1], False, M,
                                       Rss_span, (none, none))
            out.append(_placed((_corner_max(f) + rs + rt, (rs, rt)), cols, (ss.size - 1, tt.size - 1)))
        # the whole of S: u continuous across its seam (unwrapped along t at the first row, then along s)
        U = best[:, :, 0].copy()
        U[0] = np.unwrap(U[0], period=L)
        U = np.unwrap(U, period=L, axis=0)
        f, rs, rt = _reverse_cells(S, Y, ss, span_s, tt, U, best[:, :, 1], True, whole[0], Rss_span, whole[1])
        out.append((_corner_max(f) + rs + rt, (rs, rt)))
        return _min_cells(out)
    kinks = np.concatenate([[0.0], R.creases(0)])
    ss = _knot_grid(R, "u", target, _graded(kinks, 1.0 / target, 0.0, 1.0), Rb)[0]
    return _rounds(ss, np.linspace(0.0, 1.0, GRID_T + 1), cells_of, FLOOR * R.diagonal())


def ring_bound(S: Surface, S_parts: list, R: Surface, R_parts: list) -> float:
    """A certified bound of H(S, R) for a wall's joined surface S and its closed result R (see the module doc
    and wall_to_result, result_to_wall)."""
    return max(wall_to_result(S, R, R_parts), result_to_wall(S, S_parts, R))


__all__ = ["ring_bound", "wall_to_result", "result_to_wall"]
