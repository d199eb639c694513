"""2D dynamic programming over ruling pairs (Elber 2011 §2.2, eqs. 3–4, and §3).

A path runs from ruling (0, 0) to (n_i-1, n_j-1) with moves (i-1, j),
(i, j-1), (i-1, j-1).  The objective is the sum of the ruling costs (the
paper's) or their maximum (minimax, ties broken by the sum).  Cells are
filled one anti-diagonal at a time, vectorized along the diagonal and over a
batch of tables (the shifted starts of a closed boundary).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Optional

import numpy as np

from ruled.core import jit
from ruled.core.errors import InfeasibleError
from ruled.fit.dp import kernels

# move codes stored in the back-pointer table
_DIAG, _UP_I, _UP_J = 0, 1, 2
_TIE = 1e-12


@dataclass(frozen=True)
class DPResult:
    path: np.ndarray  # (K, 2) int pairs (i, j), from start to end
    score: float      # objective value of the path
    max_cost: float   # largest ruling cost on the path
    shift: int = 0    # start shift for closed boundaries


def _fill(C: np.ndarray, objective: str, progress: Optional[Callable] = None):
    """Fill DP tables for a batch C (B, ni, nj). Returns (primary, secondary, back)."""
    B, ni, nj = C.shape
    prim = np.full((B, ni, nj), np.inf)
    sec = np.full((B, ni, nj), np.inf)
    back = np.zeros((B, ni, nj), dtype=np.int8)
    if jit.enabled():
        kernels.dp_fill(np.ascontiguousarray(C, dtype=np.float64), objective != "sum", _TIE, prim, sec, back)
        if progress is not None:
            progress(1, 1)
        return prim, sec, back
    prim[:, 0, 0] = C[:, 0, 0]
    sec[:, 0, 0] = C[:, 0, 0]
    ndiag = ni + nj - 1
    for d in range(1, ndiag):
        i = np.arange(max(0, d - nj + 1), min(ni - 1, d) + 1)
        j = d - i
        c = C[:, i, j]
        cands_p = []
        cands_s = []
        for code, (di, dj) in ((_DIAG, (1, 1)), (_UP_I, (1, 0)), (_UP_J, (0, 1))):
            pi, pj = i - di, j - dj
            ok = (pi >= 0) & (pj >= 0)
            pp = np.full((B, i.size), np.inf)
            ps = np.full((B, i.size), np.inf)
            pp[:, ok] = prim[:, pi[ok], pj[ok]]
            ps[:, ok] = sec[:, pi[ok], pj[ok]]
            cands_p.append(pp)
            cands_s.append(ps)
        P = np.stack(cands_p)  # (3, B, L)
        S = np.stack(cands_s)
        if objective == "sum":
            P = P + c[None]
            S = P
        else:
            P = np.maximum(P, c[None])
            S = S + c[None]
        best = P.min(axis=0)
        tied = P <= best[None] + _TIE * np.maximum(1.0, np.abs(best))[None]
        key = np.where(tied, S, np.inf)
        k = np.argmin(key, axis=0)
        # the first of equal keys wins: diagonal before single steps
        prim[:, i, j] = np.take_along_axis(P, k[None], 0)[0]
        sec[:, i, j] = np.take_along_axis(S, k[None], 0)[0]
        back[:, i, j] = k
        if progress is not None and d % 16 == 0:
            progress(d, ndiag)
    return prim, sec, back


def _trace(back: np.ndarray, end: tuple[int, int]) -> np.ndarray:
    i, j = end
    out = [(i, j)]
    while i > 0 or j > 0:
        k = back[i, j]
        if k == _DIAG:
            i, j = i - 1, j - 1
        elif k == _UP_I:
            i -= 1
        else:
            j -= 1
        out.append((i, j))
    return np.array(out[::-1], dtype=np.int64)


def solve_open(cost: np.ndarray, objective: str = "sum", progress=None) -> DPResult:
    """Optimal path over an (n_i, n_j) cost table with inf for forbidden rulings."""
    prim, sec, back = _fill(cost[None], objective, progress)
    end = (cost.shape[0] - 1, cost.shape[1] - 1)
    score = prim[0, end[0], end[1]]
    if not np.isfinite(score):
        return DPResult(np.zeros((0, 2), np.int64), np.inf, np.inf)
    path = _trace(back[0], end)
    return DPResult(path, float(score), float(cost[path[:, 0], path[:, 1]].max()))


def solve_closed(cost: np.ndarray, objective: str = "sum", progress=None,
                 batch_bytes: int = 512 << 20) -> DPResult:
    """Closed boundaries (Elber §3): every start shift i0, first and last ruling the same line.

    cost: (n, n) over the n distinct samples of each closed boundary.  For
    shift i0 the path runs from (i0, 0) to (i0 + n, n) in unwrapped indices;
    the returned path is in unwrapped indices.  The n shifted tables are
    filled in batches of at most ``batch_bytes``.
    """
    n = cost.shape[0]
    best = (np.inf, np.inf, None, 0)
    for shifts, C in _shifted(cost, batch_bytes):
        prim, sec, back = _fill(C, objective, None)
        end_p = prim[:, n, n]
        end_s = sec[:, n, n]
        for k in range(shifts.size):
            p, s = end_p[k], end_s[k]
            lim = best[0] + _TIE * max(1.0, abs(best[0])) if np.isfinite(best[0]) else np.inf
            if p < best[0] - _TIE * max(1.0, abs(p)) or (p <= lim and s < best[1]):
                best = (p, s, back[k].copy(), int(shifts[k]))
        if progress is not None:
            progress(int(shifts[-1]) + 1, n)
    if not np.isfinite(best[0]):
        return DPResult(np.zeros((0, 2), np.int64), np.inf, np.inf)
    path = _trace(best[2], (n, n))
    path[:, 0] += best[3]
    costs = cost[path[:, 0] % n, path[:, 1] % n]
    return DPResult(path, float(best[0]), float(costs.max()), best[3])


def _shifted(cost: np.ndarray, batch_bytes: int):
    """The tables of every start shift i0 of a closed boundary, C_b[a, b] = cost[(i0 + a) % n, b % n]
    over a, b in 0..n, in batches of at most batch_bytes of DP tables: yields (shifts, C)."""
    n = cost.shape[0]
    a = np.arange(n + 1)
    B = max(1, min(n, batch_bytes // ((n + 1) ** 2 * (8 * 3 + 1))))
    for start in range(0, n, B):
        shifts = np.arange(start, min(n, start + B))
        yield shifts, cost[(shifts[:, None, None] + a[None, :, None]) % n, a[None, None, :] % n]


def shift_scores(cost: np.ndarray, objective: str = "sum", free_start: bool = False,
                 batch_bytes: int = 256 << 20) -> np.ndarray:
    """(n,) the closed program's best score for every start shift (solve_closed's candidates);
    free_start: the first ruling costs nothing (it is counted again as the last)."""
    out = np.empty(cost.shape[0])
    for shifts, C in _shifted(cost, batch_bytes):
        if free_start:
            C[:, 0, 0] = 0.0
        out[shifts] = _fill(C, objective)[0][:, -1, -1]
    return out


def solve(cost: np.ndarray, closed: bool, objective: str = "sum", max_error: Optional[float] = None,
          progress=None) -> DPResult:
    """Optimal pairing; with max_error, rulings costlier than it are forbidden.

    Raises InfeasibleError naming the best achievable largest ruling cost when
    no path satisfies max_error.
    """
    f = solve_closed if closed else solve_open
    if max_error is None:
        return f(cost, objective, progress)
    limited = np.where(cost > max_error, np.inf, cost)
    res = f(limited, objective, progress)
    if np.isfinite(res.score):
        return res
    best = f(cost, "max", None)
    raise InfeasibleError(
        f"no ruling path keeps every ruling within «max_error={max_error:.6g}»: the best achievable "
        f"largest ruling distance at these samples is {best.max_cost:.6g}; raise «max_error» or add «samples»")


def table_bytes(n: int, closed: bool) -> int:
    """Memory a fit with n samples needs at its peak (bytes): the cost table and its row-block
    work arrays, and the DP tables (for closed boundaries one batch of shifted tables, at least
    one table, at most 512 MiB plus one table)."""
    cost = n * n * 8 * 3
    one = (n + 1) ** 2 * (8 * 3 + 1)
    tables = max(one, min(n * one, (512 << 20) + one)) if closed else n * n * (8 * 3 + 1)
    return int(cost + tables * 1.2)
