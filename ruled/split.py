"""Non-isoparametric splits (Wang & Elber, §4), the first part: M-points and the split DP.

A face is cut by an M-curve, a monotone chain of M-points inside it (eq. 20), running from the
u = u_min side to the u = u_max side; each state pairs a P-point on the v = v_min boundary, a
Q-point on the v = v_max boundary and an M-point, that is two rulings P_i M and M Q_j.  P and Q move
forward or stay; M moves left-forward, straight-forward, right-forward or stays; never all three
stay.  The cost of a state is the larger line metric of its two rulings (eq. 7), summed (or its
maximum taken) along the path.  This is the 4D split DP (nothing elevated); the virtual subdivision,
the split faces and the partition to a tolerance build on it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np

from . import kernels
from .distance import segment_distances
from .errors import BadInputError, TooBigError
from .nurbs import Surface

# predecessor offsets (di, dj, da, db): P, Q forward or not; M stays, or moves to the next column and
# one row down, the same row or one row up; never all three stay (the order is the tie-break order)
MOVES = np.array([(di, dj, da, db) for da, db in ((1, 0), (1, -1), (1, 1), (0, 0)) for di in (1, 0)
                  for dj in (1, 0) if (di, dj, da) != (0, 0, 0)], dtype=np.int64)


@dataclass
class SplitTables:
    u: np.ndarray          # (n,) parameters of the P-, Q- and M-columns
    v_levels: np.ndarray   # (d,) the M-rows (eq. 20)
    A: np.ndarray          # (n, n, d): A[i, a, b] line metric of P_i M_ab
    B: np.ndarray          # (n, n, d): B[j, a, b] line metric of M_ab Q_j


@dataclass
class SplitPath:
    path: np.ndarray       # (L, 4) states (i, j, a, b) from the u_min side to the u_max side
    score: float           # the objective's value (sum or max of the state costs)
    objective: str

    def m_curve(self, tables: SplitTables) -> np.ndarray:
        """The M-curve in the parameter domain: (u, v) of its distinct M-points in order."""
        ab = self.path[:, 2:]
        keep = np.concatenate([[True], np.any(np.diff(ab, axis=0) != 0, axis=1)])
        return np.stack([tables.u[ab[keep, 0]], tables.v_levels[ab[keep, 1]]], axis=1)


def m_grid(S: Surface, n: int, d: int):
    """Eq. 20: n columns from u_min to u_max and d interior rows strictly between v_min and v_max."""
    if n < 2 or d < 1:
        raise BadInputError(f"a split needs at least 2 samples along the boundaries and 1 interior row (got n = {n}, "
                            f"d = {d})")
    u0, u1, v0, v1 = S.domain
    a = np.arange(n) / (n - 1)
    b = (np.arange(d) + 1.0) / (d + 1)
    return (1 - a) * u0 + a * u1, (1 - b) * v0 + b * v1


def table_bytes(n: int, d: int) -> int:
    """Memory of the split DP: two float64 score tables and one int8 back-pointer table of n^3 d."""
    return int(n) ** 3 * int(d) * 17


def split_tables(S: Surface, n: int, d: int, m: int = 9, iters: int = 3) -> SplitTables:
    """The line metrics of every P-M and M-Q ruling (one-sided distance to S, sampled and refined by
    projection, as the 2D cost table)."""
    u, vl = m_grid(S, n, d)
    _, _, v0, v1 = S.domain
    i, a, b = np.meshgrid(np.arange(n), np.arange(n), np.arange(d), indexing="ij")
    i, a, b = i.ravel(), a.ravel(), b.ravel()
    M = np.stack([u[a], vl[b]], axis=1)
    A = segment_distances(S, np.stack([u[i], np.full(i.size, v0)], axis=1), M, m, iters)[1]
    B = segment_distances(S, M, np.stack([u[i], np.full(i.size, v1)], axis=1), m, iters)[1]
    return SplitTables(u, vl, A.reshape(n, n, d), B.reshape(n, n, d))


def _fill_numpy(A, B, use_max: bool, prim, sec, back) -> None:
    """The NumPy twin of kernels_split.fill: the same states in the same order, moves in MOVES order,
    a candidate replaces the best only when strictly better (primary, then secondary)."""
    n, _, d = A.shape
    rows = np.arange(d)
    for i in range(n):
        for j in range(n):
            for a in range(n):
                c = np.maximum(A[i, a], B[j, a])
                if i == 0 and j == 0 and a == 0:
                    prim[0, 0, 0] = c
                    sec[0, 0, 0] = c
                    back[0, 0, 0] = -1
                    continue
                bp = np.full(d, np.inf)
                bs = np.full(d, np.inf)
                bk = np.full(d, -1, dtype=np.int8)
                for k, (di, dj, da, db) in enumerate(MOVES):
                    pi, pj, pa = i - di, j - dj, a - da
                    if pi < 0 or pj < 0 or pa < 0:
                        continue
                    pb = rows - db
                    ok = (pb >= 0) & (pb < d)
                    p = np.full(d, np.inf)
                    s = np.full(d, np.inf)
                    p[ok] = prim[pi, pj, pa, pb[ok]]
                    s[ok] = sec[pi, pj, pa, pb[ok]]
                    if use_max:
                        np_, ns = np.maximum(p, c), s + c
                    else:
                        np_ = p + c
                        ns = np_
                    better = (np_ < bp) | ((np_ == bp) & (ns < bs))
                    better &= np.isfinite(p)
                    bp = np.where(better, np_, bp)
                    bs = np.where(better, ns, bs)
                    bk = np.where(better, k, bk).astype(np.int8)
                prim[i, j, a] = bp
                sec[i, j, a] = bs
                back[i, j, a] = bk


def split_dp(tables: SplitTables, objective: str = "sum", memory_cap: Optional[float] = None) -> SplitPath:
    """The optimal M-curve and its pairs of rulings (the 4D split DP), from the P-, Q- and M-points'
    first column to their last; the M-curve may start and end on any row."""
    from .fit import memory_budget
    if objective not in ("sum", "max"):
        raise BadInputError(f"unknown objective {objective!r}: use 'sum' or 'max'")
    A, B = np.ascontiguousarray(tables.A, float), np.ascontiguousarray(tables.B, float)
    n, _, d = A.shape
    need, cap = table_bytes(n, d), memory_budget(memory_cap)
    if need > cap:
        fit_n = int((cap / (17 * d)) ** (1 / 3))
        raise TooBigError(f"the split DP would need {need / 2 ** 20:.0f} MiB (n = {n}, d = {d}) and "
                          f"{cap / 2 ** 20:.0f} MiB may be used; use at most n = {fit_n} samples at d = {d}")
    prim = np.full((n, n, n, d), np.inf)
    sec = np.full((n, n, n, d), np.inf)
    back = np.full((n, n, n, d), -1, dtype=np.int8)
    if kernels.enabled():
        from .kernels_split import fill
        fill(A, B, objective == "max", MOVES, prim, sec, back)
    else:
        _fill_numpy(A, B, objective == "max", prim, sec, back)
    end = prim[n - 1, n - 1, n - 1]
    key = np.lexsort((sec[n - 1, n - 1, n - 1], end))
    b = int(key[0])
    state = np.array([n - 1, n - 1, n - 1, b])
    path = [state.copy()]
    while True:
        k = int(back[tuple(state)])
        if k < 0:
            break
        state = state - MOVES[k]
        path.append(state.copy())
    path = np.array(path[::-1])
    if tuple(path[0, :3]) != (0, 0, 0):
        raise AssertionError("split DP trace did not reach the first column")
    return SplitPath(path, float(end[b]), objective)


def path_score(tables: SplitTables, path: np.ndarray, objective: str) -> float:
    """The objective of a path of states, from the tables (for checks)."""
    c = np.maximum(tables.A[path[:, 0], path[:, 2], path[:, 3]], tables.B[path[:, 1], path[:, 2], path[:, 3]])
    return float(c.max() if objective == "max" else c.sum())
