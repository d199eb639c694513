"""The 4D dynamic program over elevated ruling pairs (Wang & Elber §2.3–2.4, eqs. 15–19).

A table entry (i, j, k, l) is the ruling from P_{i,k} to Q_{j,l} (level
indices k, l in [0, 2m]).  It is reached by one of the 15 moves of eq. (16):
P and Q each move forward (keeping, lowering or raising their elevation by
one level) or stay (keeping it), not both staying.  A move's cost is

* SSHB: the bound of metrics4d for the bilinear patch of the two rulings,
  area-weighted (area of the supporting region S_b) for the sum objective
  (eq. 10/15), plain for the max objective (eq. 11/17);
* LSAD: the line metric of the new ruling (eqs. 6–7; unweighted like the
  2D cost, so that m = 0 is the 2D program).

The max objective breaks ties by the sum of the same costs: moves are tried
in a fixed order and a move replaces the best so far when its objective is
smaller by more than a relative 1e-12, or tied within it with a smaller sum.  Start and end
elevations are free; at the end, among entries with the same objective, the
least |k| + |l| (the least elevated end ruling) wins.  A closed boundary is
solved for the shifts q of the Q samples (eq. 18–19) in increasing order of a lower bound of their
score (shift_bounds), until that bound exceeds the best score found; each entry records the
start elevation its path came from, and the last ruling must return to it,
so the first and last rulings are the same line (§2.4).

The table is swept anti-diagonal by anti-diagonal in (i, j): every entry of
a diagonal depends only on the two previous diagonals.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any, Callable, Optional

import numpy as np

from ruled.core import jit
from ruled.core.errors import InfeasibleError
from ruled.fit.dp import kernels as kernels4d
from ruled.fit.dp.kernels import DK_COL, DL_COL, MOVES, PATTERN_OF

_TIE = 1e-12


@dataclass(frozen=True)
class Tables:
    """Everything a sweep reads.  SSHB: the ruling terms c, es, dku, dkv (n, n, K, K) float32 and a
    metrics4d.PatchTerms; LSAD: lc (n, n, K, K) float32."""

    sshb: bool
    n: int
    K: int
    lc: Optional[np.ndarray] = None
    ruling: Optional[tuple] = None      # (c, es, dku, dkv)
    terms: Optional[Any] = None         # metrics4d.PatchTerms
    limit: float = np.inf  # moves costlier than this are forbidden (the max-error constraint)
    start: int = -1        # when >= 0, the only allowed start levels k * K + l

    def arrays(self) -> tuple[np.ndarray, ...]:
        z4 = np.zeros((1, 1, 1, 1), np.float32)
        z3 = np.zeros((1, 1, 1))
        lc = self.lc if self.lc is not None else z4
        if not self.sshb:
            return (lc, z4, z4, z4, z4, z3, z3, z3, z3, z3, z3, z3, np.zeros(3))
        t = self.terms
        return (lc, *self.ruling, t.area, t.d0u, t.d0v, t.t0, t.g0, t.gP, t.gQ, np.array(t.M, float))


@dataclass(frozen=True)
class DP4Result:
    path: np.ndarray   # (T, 4) int (i, j, k, l), level indices k, l in [0, 2m]; unwrapped when closed
    score: float       # objective value
    secondary: float   # sum of the costs (the tie-break of the max objective)
    max_cost: float    # largest move cost on the path
    shift: int = 0


def table_bytes(n: int, K: int, closed: bool, sshb: bool, ns: int = 16) -> int:
    """Peak memory of a 4D fit (bytes): cost tables, ruling nodes and the DP tables (one set,
    (n + 1)^2 K^2 for a closed boundary, whose shifts are solved one after the other, plus the
    best shift's back-pointers)."""
    cost = n * n * K * K * 4 * (4 if sshb else 1)
    nodes = n * n * ns * 8 * 24
    side = n + 1 if closed else n
    dp = side * side * K * K * ((8 + 8 + 1 + 2) + (1 if closed else 0))
    return int((cost + nodes + dp) * 1.15)


def _fill_numpy_lsad_sum(T: Tables, prim, sec, back, src):
    """Twin of kernels4d._fill_lsad_sum: the first strict minimum of the predecessors, plus w."""
    ni, nj, K = prim.shape[0], prim.shape[1], prim.shape[2]
    kk, ll = np.meshgrid(np.arange(K), np.arange(K), indexing="ij")
    for d in range(ni + nj - 1):
        i = np.arange(max(0, d - nj + 1), min(ni - 1, d) + 1)
        j = d - i
        w = T.lc[i, j].astype(np.float64)
        if d == 0:
            v = np.where(w <= T.limit, w, np.inf)
            prim[0, 0], sec[0, 0], back[0, 0], src[0, 0] = v[0], v[0], -1, kk * K + ll
            continue
        best = np.full((i.size, K, K), np.inf)
        bk = np.zeros((i.size, K, K), np.int64)
        bz = np.full((i.size, K, K), -1, np.int64)
        for mv in range(15):
            di, dj, dk, dl = (int(x) for x in MOVES[mv])
            okc = (i >= di) & (j >= dj)
            kp, lp = kk - dk, ll - dl
            oke = (kp >= 0) & (kp < K) & (lp >= 0) & (lp < K)
            pi, pj = np.maximum(i - di, 0), np.maximum(j - dj, 0)
            v = prim[pi[:, None, None], pj[:, None, None], np.clip(kp, 0, K - 1)[None], np.clip(lp, 0, K - 1)[None]]
            z = src[pi[:, None, None], pj[:, None, None], np.clip(kp, 0, K - 1)[None], np.clip(lp, 0, K - 1)[None]]
            take = okc[:, None, None] & oke[None] & (v < best)
            best = np.where(take, v, best)
            bk = np.where(take, mv, bk)
            bz = np.where(take, z, bz)
        v = np.where(w <= T.limit, best + w, np.inf)
        fin = v < np.inf
        prim[i, j], sec[i, j] = v, v
        back[i, j] = np.where(fin, bk, 0)
        src[i, j] = np.where(fin, bz, -1)


def _fill_numpy(T: Tables, use_max: bool, closed: bool, shift: int, prim, sec, back, src):
    if not T.sshb and not use_max and not closed and T.start < 0:
        return _fill_numpy_lsad_sum(T, prim, sec, back, src)
    ni, nj, K = prim.shape[0], prim.shape[1], prim.shape[2]
    n = T.n
    kk, ll = np.meshgrid(np.arange(K), np.arange(K), indexing="ij")
    f64 = np.float64
    for d in range(ni + nj - 1):
        i = np.arange(max(0, d - nj + 1), min(ni - 1, d) + 1)
        j = d - i
        wi, wj = i % n, (j + shift) % n
        if d == 0:
            v = T.lc[wi[0], wj[0]].astype(f64) if not T.sshb else np.zeros((K, K))
            v = np.where((v <= T.limit) & ((T.start < 0) | (kk * K + ll == T.start)), v, np.inf)
            prim[0, 0], sec[0, 0], back[0, 0], src[0, 0] = v, v, -1, kk * K + ll
            continue
        BP = np.full((i.size, K, K), np.inf)
        BS = np.full((i.size, K, K), np.inf)
        BK = np.zeros((i.size, K, K), np.int64)
        BZ = np.full((i.size, K, K), -1, np.int64)
        for mv in range(15):
            di, dj, dk, dl = (int(x) for x in MOVES[mv])
            okc = (i >= di) & (j >= dj)
            if not okc.any():
                continue
            ci = np.nonzero(okc)[0]
            pi, pj = i[ci] - di, j[ci] - dj
            kp, lp = kk - dk, ll - dl
            oke = (kp >= 0) & (kp < K) & (lp >= 0) & (lp < K)
            kq, lq = np.clip(kp, 0, K - 1), np.clip(lp, 0, K - 1)
            pp = prim[pi[:, None, None], pj[:, None, None], kq[None], lq[None]]
            ps = sec[pi[:, None, None], pj[:, None, None], kq[None], lq[None]]
            zs = src[pi[:, None, None], pj[:, None, None], kq[None], lq[None]]
            valid = oke[None] & (pp < np.inf)
            if closed:
                last = (i[ci] == ni - 1) & (j[ci] == nj - 1)
                valid &= ~last[:, None, None] | (zs == (kk * K + ll)[None])
            a, b = wi[ci], wj[ci]
            if T.sshb:
                pat = int(PATTERN_OF[mv])
                wpi, wpj = pi % n, (pj + shift) % n
                tm = T.terms

                def cur(x):
                    return x[a[:, None, None], b[:, None, None], kk[None], ll[None]].astype(f64)

                def prv(x):
                    return x[wpi[:, None, None], wpj[:, None, None], kq[None], lq[None]].astype(f64)
                c_, es_, dku_, dkv_ = T.ruling
                gq = tm.gQ[int(DL_COL[mv]), b[:, None, None], ll[None]] if dj == 1 else np.zeros((ci.size, K, K))
                gp = tm.gP[int(DK_COL[mv]), a[:, None, None], kk[None]] if di == 1 else np.zeros((ci.size, K, K))
                g = (tm.g0[pat, a, b][:, None, None] + gp) + gq
                du = tm.d0u[pat, a, b][:, None, None] + (cur(dku_) + prv(dku_))
                dv = tm.d0v[pat, a, b][:, None, None] + (cur(dkv_) + prv(dkv_))
                Muu, Muv, Mvv = tm.M
                w = ((np.maximum(cur(c_), prv(c_)) + np.maximum(cur(es_), prv(es_)))
                     + 0.125 * ((Muu * du * du + 2.0 * Muv * du * dv) + Mvv * dv * dv)) \
                    + (0.25 * g) * tm.t0[pat, a, b][:, None, None]
                ws = tm.area[pat, a, b][:, None, None] * w
            else:
                w = T.lc[a[:, None, None], b[:, None, None], kk[None], ll[None]].astype(f64)
                ws = w
            valid &= w <= T.limit
            if use_max:
                P = np.maximum(pp, w)
                S = ps + ws
            else:
                P = pp + ws
                S = P
            bp, bs = BP[ci], BS[ci]
            t = _TIE * np.maximum(1.0, np.abs(bp))
            P = np.where(valid, P, np.inf)
            S = np.where(valid, S, np.inf)
            with np.errstate(invalid="ignore"):
                take = (P < bp - t) | ((P <= bp + t) & (S < bs))
            BP[ci] = np.where(take, P, bp)
            BS[ci] = np.where(take, S, bs)
            BK[ci] = np.where(take, mv, BK[ci])
            BZ[ci] = np.where(take, zs, BZ[ci])
        prim[i, j] = BP
        sec[i, j] = BS
        back[i, j] = BK
        src[i, j] = BZ


def _fill(T: Tables, use_max: bool, closed: bool, shift: int, side: int):
    K = T.K
    prim = np.empty((side, side, K, K))
    sec = np.empty((side, side, K, K))
    back = np.empty((side, side, K, K), np.int8)
    src = np.empty((side, side, K, K), np.int16)
    if jit.enabled():
        lc, c, es, dku, dkv, area, d0u, d0v, t0, g0, gP, gQ, Mq = T.arrays()
        kernels4d.fill(T.sshb, use_max, _TIE, closed, T.n, shift, lc, c, es, dku, dkv, area, d0u, d0v, t0, g0, gP,
                       gQ, Mq, float(T.limit), int(T.start), prim, sec, back, src)
    else:
        _fill_numpy(T, use_max, closed, shift, prim, sec, back, src)
    return prim, sec, back, src


def _end(prim, sec, m: int):
    """Best end entry: least objective, then least secondary, then least |k| + |l|."""
    P = prim[-1, -1]
    S = sec[-1, -1]
    best = P.min()
    if not np.isfinite(best):
        return None
    tied = P <= best + _TIE * max(1.0, abs(best))
    sbest = S[tied].min()
    tied &= S <= sbest + _TIE * max(1.0, abs(sbest))
    K = P.shape[0]
    k, l = np.meshgrid(np.arange(K), np.arange(K), indexing="ij")
    elev = np.where(tied, np.abs(k - m) + np.abs(l - m), np.iinfo(np.int64).max)
    idx = np.unravel_index(int(np.argmin(elev)), elev.shape)
    return int(idx[0]), int(idx[1])


def _trace(back, end4) -> np.ndarray:
    i, j, k, l = end4
    out = [(i, j, k, l)]
    while i > 0 or j > 0:
        di, dj, dk, dl = (int(x) for x in MOVES[int(back[i, j, k, l])])
        i, j, k, l = i - di, j - dj, k - dk, l - dl
        out.append((i, j, k, l))
    return np.array(out[::-1], dtype=np.int64)


def move_costs(T: Tables, path: np.ndarray) -> np.ndarray:
    """The (unweighted) cost of each move of a path (T - 1,), recomputed from the tables; the path
    in unwrapped indices (on a closed boundary its Q indices include the start shift)."""
    from ruled.fit.dp.metrics4d import sshb_move
    n = T.n
    out = []
    for a, b in zip(path[:-1], path[1:]):
        di, dj, dk, dl = (int(x) for x in (b - a))
        wi, wj = b[0] % n, b[1] % n
        if not T.sshb:
            out.append(float(T.lc[wi, wj, b[2], b[3]]))
            continue
        pat = 0 if (di, dj) == (1, 1) else (1 if di else 2)
        wpi, wpj = a[0] % n, a[1] % n
        cur = tuple(float(x[wi, wj, b[2], b[3]]) for x in T.ruling)
        prev = tuple(float(x[wpi, wpj, a[2], a[3]]) for x in T.ruling)
        out.append(sshb_move(T.terms, prev, cur, pat, wi, wj, int(b[2]), int(b[3]), dk, dl))
    return np.array(out)


def solve_open(T: Tables, objective: str = "sum") -> DP4Result:
    m = (T.K - 1) // 2
    prim, sec, back, src = _fill(T, objective == "max", False, 0, T.n)
    end = _end(prim, sec, m)
    if end is None:
        return DP4Result(np.zeros((0, 4), np.int64), np.inf, np.inf, np.inf)
    path = _trace(back, (T.n - 1, T.n - 1) + end)
    mc = move_costs(T, path)
    return DP4Result(path, float(prim[-1, -1][end]), float(sec[-1, -1][end]), float(mc.max()) if mc.size else 0.0)


def solve_closed(T: Tables, objective: str = "sum", progress: Optional[Callable] = None) -> DP4Result:
    """Every shift q of the Q samples; the first and the last ruling are the same line.

    The coincidence is enforced as the paper does (each entry keeps the start elevation of its
    path; the last ruling must return to it), which can leave no path for a shift.  If no shift
    has one, the program runs again with the start fixed at zero elevation, where the path that
    keeps every elevation at zero always exists."""
    res = _solve_closed(T, objective, progress)
    if not np.isfinite(res.score) and T.start < 0:
        m = (T.K - 1) // 2
        res = _solve_closed(replace(T, start=m * T.K + m), objective, progress)
    return res


def shift_bounds(T: Tables, use_max: bool) -> np.ndarray:
    """A lower bound of every shift's best score (n,): the 2D program over the least cost of a move
    into each ruling at any elevations and of any pattern (LSAD: the ruling's metric; SSHB: a move's
    bound is at least what it has with the previous ruling's terms left out, c + es of the new
    ruling, (Muu du^2 + 2 Muv du dv + Mvv dv^2) / 8 with du = d0u + dku and dv = d0v + dkv of the new
    ruling, and g0 t0 / 4, every term left out being non-negative; area-weighted for the sum
    objective; the first ruling costs nothing).  The shift here moves Q (j): the 2D program's, which
    moves its first index, on the transposed costs (its moves are symmetric)."""
    from ruled.fit.dp.dp2d import shift_scores
    n = T.n
    if T.sshb:
        tm = T.terms
        Muu, Muv, Mvv = tm.M
        c, es, dku, dkv = (x.reshape(n, n, -1).astype(np.float64) for x in T.ruling)
        node = np.full((n, n), np.inf)
        for p in range(tm.area.shape[0]):
            du, dv = tm.d0u[p][..., None] + dku, tm.d0v[p][..., None] + dkv
            per = (c + es + 0.125 * ((Muu * du * du + 2.0 * Muv * du * dv) + Mvv * dv * dv)).min(axis=2) \
                + 0.25 * tm.g0[p] * tm.t0[p]
            node = np.minimum(node, per if use_max else tm.area[p] * per)
    else:
        node = T.lc.reshape(n, n, -1).min(axis=2).astype(np.float64)
    return shift_scores(np.ascontiguousarray(node.T), "max" if use_max else "sum", free_start=T.sshb)


def _solve_closed(T: Tables, objective: str, progress: Optional[Callable]) -> DP4Result:
    """Every shift, in increasing order of its lower bound (shift_bounds), until the bound exceeds
    the best score found: the same result as solving them all (ties go to the lower shift)."""
    n, m = T.n, (T.K - 1) // 2
    lb = shift_bounds(T, objective == "max")
    best = None
    for cnt, q in enumerate(np.argsort(lb, kind="stable")):
        q = int(q)
        if best is not None and lb[q] > best[0] + _TIE * max(1.0, abs(best[0])):
            break
        prim, sec, back, src = _fill(T, objective == "max", True, q, n + 1)
        end = _end(prim, sec, m)
        if progress is not None:
            progress(cnt + 1, n)
        if end is None:
            continue
        p, s = float(prim[-1, -1][end]), float(sec[-1, -1][end])
        if best is None or p < best[0] - _TIE * max(1.0, abs(p)) or (
                p <= best[0] + _TIE * max(1.0, abs(best[0])) and (s < best[1] or (s == best[1] and q < best[2]))):
            best = (p, s, q, _trace(back, (n, n) + end))
    if progress is not None:
        progress(n, n)
    if best is None:
        return DP4Result(np.zeros((0, 4), np.int64), np.inf, np.inf, np.inf)
    p, s, q, path = best
    path = path.copy()
    path[:, 1] += q
    mc = move_costs(T, path)
    return DP4Result(path, p, s, float(mc.max()), q)


def solve(T: Tables, closed: bool, objective: str = "sum", max_error: Optional[float] = None,
          progress: Optional[Callable] = None) -> DP4Result:
    """Optimal elevated pairing; with max_error, moves costlier than it are forbidden (SSHB: the
    patch bound; LSAD: the ruling's distance).  InfeasibleError names the best achievable."""
    def run(tables):
        return solve_closed(tables, objective, progress) if closed else solve_open(tables, objective)
    if max_error is None:
        return run(T)
    res = run(replace(T, limit=float(max_error)))
    if np.isfinite(res.score) and res.max_cost <= max_error:
        return res
    best = solve_closed(T, "max") if closed else solve_open(T, "max")
    raise InfeasibleError(
        f"no elevated ruling path keeps every {'patch bound' if T.sshb else 'ruling distance'} within "
        f"«max_error={max_error:.6g}»: the best achievable at these samples is {best.max_cost:.6g}; "
        f"raise «max_error», add «samples» or «elevations»")
