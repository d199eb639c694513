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

from ruled.core import jit
from ruled.core.distance import lifted_segment_distances, segment_distances
from ruled.core.errors import BadInputError, InfeasibleError, TooBigError, positive
from ruled.core.nurbs import Surface

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
    levels: Optional[np.ndarray] = None   # (L, 3) elevation levels of P, Q and M along the path

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


def _shapes(n: int, d: int, mp: int, mq: int, mm: int) -> list:
    """Shapes of the reduction buffers the fill keeps (see kernels_split.fill)."""
    cur = [(n, n, mp, d, mm), (n, n, mp, mq, d), (n, n, mp, d)]
    prv = [(n, n, mq, d, mm), (n, n, d, mm), (n, n, mq, d), (n, n, d)]
    return cur + prv + prv


def table_bytes(n: int, d: int, mp: int = 1, mq: int = 1, mm: int = 1) -> int:
    """Memory of the split DP: the int16 back pointers of every state, and the reductions of one layer
    (float64 primary and secondary, int32 argument)."""
    states = int(n) ** 3 * int(d) * mp * mq * mm
    red = sum(int(np.prod(sh)) for sh in _shapes(n, d, mp, mq, mm))
    return 2 * states + 20 * red


def split_tables(S: Surface, n: int, d: int, m: int = 9, iters: int = 3, dims: int = 4, levels: int = 0,
                 step: float = 0.0) -> SplitTables:
    """The line metrics of every P-M and M-Q ruling (one-sided distance to S, sampled and refined by
    projection, as the 2D cost table).  5D: M lifted along the normal by step k, k = -levels..levels;
    7D: P, Q and M lifted so.  Tables (n, n, d) for 4D, (n, mp, n, d, mm) otherwise."""
    if dims not in (4, 5, 7):
        raise BadInputError(f"«dims={dims}»: the split DP is 4D, 5D (M elevated) or 7D (P, Q and M elevated)")
    u, vl = m_grid(S, n, d)
    _, _, v0, v1 = S.domain
    if dims == 4 or levels == 0:
        i, a, b = (x.ravel() for x in np.meshgrid(np.arange(n), np.arange(n), np.arange(d), indexing="ij"))
        M = np.stack([u[a], vl[b]], axis=1)
        A = segment_distances(S, np.stack([u[i], np.full(i.size, v0)], axis=1), M, m, iters)[1]
        B = segment_distances(S, M, np.stack([u[i], np.full(i.size, v1)], axis=1), m, iters)[1]
        A, B = A.reshape(n, n, d), B.reshape(n, n, d)
        if dims != 4:
            A, B = A[:, None, :, :, None], B[:, None, :, :, None]
        return SplitTables(u, vl, A, B)
    positive("lift_step", step)
    h = step * (np.arange(2 * levels + 1) - levels)
    hp = h if dims == 7 else np.zeros(1)
    i, e, a, b, f = (x.ravel() for x in np.meshgrid(np.arange(n), np.arange(hp.size), np.arange(n), np.arange(d),
                                                   np.arange(h.size), indexing="ij"))
    M = np.stack([u[a], vl[b]], axis=1)
    shape = (n, hp.size, n, d, h.size)
    A = lifted_segment_distances(S, np.stack([u[i], np.full(i.size, v0)], axis=1), hp[e], M, h[f], m, iters)
    B = lifted_segment_distances(S, M, h[f], np.stack([u[i], np.full(i.size, v1)], axis=1), hp[e], m, iters)
    return SplitTables(u, vl, A.reshape(shape), B.reshape(shape))


def _as5(X: np.ndarray) -> np.ndarray:
    """A table (n, n, d) of a 4D split as the elevated form (n, 1, n, d, 1)."""
    X = np.asarray(X, float)
    return np.ascontiguousarray(X[:, None, :, :, None] if X.ndim == 3 else X)


# which point each axis after the (j, a) cell indices of a reduction buffer belongs to (0 P, 1 Q, 2 row, 3 M)
_AXES = [(0, 2, 3), (0, 1, 2), (0, 2), (1, 2, 3), (2, 3), (1, 2), (2,)]
# the reading pattern t = 4 di + 2 dj + da of a move -> the buffer it reads (cur Q, M, QM; prev P, PQ, PM, PQM)
_PATTERN_BUFFER = {1: 1, 2: 0, 3: 2, 4: 3, 5: 5, 6: 4, 7: 6}


def _buffers(n, d, mp, mq, mm):
    """The reduction buffers as views of three flat arrays (primary, secondary, argument), and the
    reading geometry of each move pattern: (offset, cell size, strides of P, Q, row and M levels)."""
    shapes = _shapes(n, d, mp, mq, mm)
    sizes = [int(np.prod(sh)) for sh in shapes]
    offs = np.concatenate([[0], np.cumsum(sizes)])
    FP, FS = np.full(offs[-1], np.inf), np.full(offs[-1], np.inf)
    FG = np.zeros(offs[-1], dtype=np.int32)
    red = []
    for k, sh in enumerate(shapes):
        red += [X[offs[k]:offs[k + 1]].reshape(sh) for X in (FP, FS, FG)]
    geo = np.zeros((8, 6), dtype=np.int64)
    for t, k in _PATTERN_BUFFER.items():
        sh = shapes[k]
        st = np.cumprod((list(sh[2:]) + [1])[::-1])[::-1][1:]   # element strides of the trailing axes
        geo[t, 0], geo[t, 1] = offs[k], int(np.prod(sh[2:]))
        for ax, stride in zip(_AXES[k], st):
            geo[t, 2 + ax] = stride
    return tuple(red), (FP, FS, FG, geo)


def _lexmin(P: np.ndarray, S: np.ndarray, G: np.ndarray, axes: tuple):
    """Over the given axes of each cell (a leading axis of cells, then the cell's axes; the listed
    axes moved last, in their order: the last varies fastest), the first entry with the smallest
    (primary, secondary) pair; G holds each entry's combined index."""
    axes = tuple(x + 1 for x in axes)
    keep = [k for k in range(P.ndim) if k not in axes]
    order = keep + list(axes)
    shape = [P.shape[k] for k in keep] + [-1]
    P, S, G = (np.transpose(X, order).reshape(shape) for X in (P, S, G))
    pm = P.min(axis=-1, keepdims=True)
    Sm = np.where(P == pm, S, np.inf)
    k = np.argmin(Sm, axis=-1)[..., None]
    return (np.take_along_axis(P, k, -1)[..., 0], np.take_along_axis(Sm, k, -1)[..., 0],
            np.take_along_axis(G, k, -1)[..., 0])


def _fill_numpy(A, B, use_max: bool, red, back, endp, ends, moves: np.ndarray = MOVES) -> None:
    """The NumPy twin of kernels_split.fill: per layer i, the cells (j, a) of one anti-diagonal at once
    (a cell reads only earlier diagonals of its layer and the previous layer's P-reductions), every
    elevation and row of each at once; per entry the same operations in the same order as the kernel."""
    n, mp, _, d, mm = A.shape
    mq = B.shape[1]
    (cQp, cQs, cQa, cMp, cMs, cMa, cQMp, cQMs, cQMa,
     pPp, pPs, pPa, pPQp, pPQs, pPQa, pPMp, pPMs, pPMa, pPQMp, pPQMs, pPQMa,
     nPp, nPs, nPa, nPQp, nPQs, nPQa, nPMp, nPMs, nPMa, nPQMp, nPQMs, nPQMa) = red
    shape = (mp, mq, d, mm)
    ep, eq, em = np.arange(mp)[:, None, None], np.arange(mq)[None, :, None], np.arange(mm)[None, None, :]
    G1 = np.broadcast_to((ep + mp * (eq + mq * em))[:, :, None, :], shape)   # combined index of (ep, eq, em)
    nmv = len(moves)

    def shift(X, db):
        """X[:, ..., b - db, ...] along the row axis (axis 3: after the cells' axis), inf outside."""
        out = np.full(X.shape, np.inf) if X.dtype.kind == "f" else np.zeros(X.shape, X.dtype)
        if db == 0:
            out[...] = X
        elif db > 0:
            out[:, :, :, 1:] = X[:, :, :, :-1]
        else:
            out[:, :, :, :-1] = X[:, :, :, 1:]
        return out

    for i in range(n):
        for sd in range(2 * n - 1):
            J = np.arange(max(0, sd - n + 1), min(n - 1, sd) + 1)
            Aa = sd - J
            m = J.size
            full = (m,) + shape
            G = np.broadcast_to(G1, full)
            c = np.maximum(A[i, :, Aa][:, :, None, :, :], B[J, :, Aa][:, None, :, :, :])
            if i == 0 and sd == 0:
                Vp, Vs = c.copy(), c.copy()
                back[0, 0, 0] = -1
            else:
                bp, bs = np.full(full, np.inf), np.full(full, np.inf)
                bk = np.full(full, -1, dtype=np.int64)
                for k, (di, dj, da, db) in enumerate(moves):
                    ok = (i - di >= 0) & (J - dj >= 0) & (Aa - da >= 0)
                    if not ok.any():
                        continue
                    jj, aa = np.maximum(J - dj, 0), np.maximum(Aa - da, 0)
                    if di == 0 and dj == 0:
                        src = [X[jj, aa][:, :, :, :, None] for X in (cMp, cMs, cMa)]
                    elif di == 0 and da == 0:
                        src = [X[jj, aa][:, :, None, :, :] for X in (cQp, cQs, cQa)]
                    elif di == 0:
                        src = [X[jj, aa][:, :, None, :, None] for X in (cQMp, cQMs, cQMa)]
                    elif dj == 0 and da == 0:
                        src = [X[jj, aa][:, None] for X in (pPp, pPs, pPa)]
                    elif da == 0:
                        src = [X[jj, aa][:, None, None] for X in (pPQp, pPQs, pPQa)]
                    elif dj == 0:
                        src = [X[jj, aa][:, None, :, :, None] for X in (pPMp, pPMs, pPMa)]
                    else:
                        src = [X[jj, aa][:, None, None, :, None] for X in (pPQMp, pPQMs, pPQMa)]
                    p, s, g = (shift(np.broadcast_to(X, full), db) for X in src)
                    if use_max:
                        q, qs = np.maximum(p, c), s + c
                    else:
                        q = p + c
                        qs = q
                    better = ((q < bp) | ((q == bp) & (qs < bs))) & np.isfinite(p) & ok[:, None, None, None, None]
                    bp, bs = np.where(better, q, bp), np.where(better, qs, bs)
                    bk = np.where(better, k + nmv * g, bk)
                Vp, Vs = bp, bs
                back[i, J, Aa] = bk
            # reductions (axes of a cell: 0 ep, 1 eq, 2 b, 3 em; the later listed axis varies fastest)
            cQp[J, Aa], cQs[J, Aa], cQa[J, Aa] = _lexmin(Vp, Vs, G, (1,))
            cMp[J, Aa], cMs[J, Aa], cMa[J, Aa] = _lexmin(Vp, Vs, G, (3,))
            cQMp[J, Aa], cQMs[J, Aa], cQMa[J, Aa] = _lexmin(Vp, Vs, G, (3, 1))
            nPp[J, Aa], nPs[J, Aa], nPa[J, Aa] = _lexmin(Vp, Vs, G, (0,))
            nPQp[J, Aa], nPQs[J, Aa], nPQa[J, Aa] = _lexmin(Vp, Vs, G, (1, 0))
            nPMp[J, Aa], nPMs[J, Aa], nPMa[J, Aa] = _lexmin(Vp, Vs, G, (3, 0))
            nPQMp[J, Aa], nPQMs[J, Aa], nPQMa[J, Aa] = _lexmin(Vp, Vs, G, (3, 1, 0))
        for dst, src in zip((pPp, pPs, pPa, pPQp, pPQs, pPQa, pPMp, pPMs, pPMa, pPQMp, pPQMs, pPQMa),
                            (nPp, nPs, nPa, nPQp, nPQs, nPQa, nPMp, nPMs, nPMa, nPQMp, nPQMs, nPQMa)):
            dst[...] = src
    endp[...] = Vp[-1]
    ends[...] = Vs[-1]


def check_memory(n: int, d: int, mp: int = 1, mq: int = 1, mm: int = 1, memory_cap: Optional[float] = None) -> None:
    """Refuse, with the estimate and what fits, a split DP larger than the memory cap."""
    from ruled.fit.fit2d import memory_budget
    need, cap = table_bytes(n, d, mp, mq, mm), memory_budget(memory_cap)
    if need > cap:
        fit_n = n
        while fit_n > 2 and table_bytes(fit_n, d, mp, mq, mm) > cap:
            fit_n -= 1
        raise TooBigError(f"the split DP would need {need / 2 ** 20:.0f} MiB (n = {n}, d = {d}, elevation levels "
                          f"{mp} x {mq} x {mm}) and {cap / 2 ** 20:.0f} MiB may be used; use at most n = {fit_n} "
                          f"samples, or fewer interior rows or elevations")


def split_dp(tables: SplitTables, objective: str = "sum", memory_cap: Optional[float] = None,
             end_row: Optional[int] = None) -> SplitPath:
    """The optimal M-curve and its pairs of rulings (the 4D, 5D or 7D split DP), from the P-, Q- and
    M-points' first column to their last; the M-curve may start and end on any row (or end on
    end_row).  Tables (n, n, d) are 4D; (n, mp, n, d, mm) carry elevation levels of P (or Q) and M."""
    A, B = _as5(tables.A), _as5(tables.B)
    n, mp, _, d, mm = A.shape
    mq = B.shape[1]
    back, endp, ends = _sweep(A, B, objective, memory_cap, MOVES)
    if end_row is not None:
        keep = np.zeros(d, bool)
        keep[end_row] = True
        endp = np.where(keep[None, None, :, None], endp, np.inf)
    key = np.lexsort((ends.ravel(), endp.ravel()))
    ep, eq, b, em = (int(x) for x in np.unravel_index(int(key[0]), endp.shape))
    score = float(endp[ep, eq, b, em])
    if not np.isfinite(score):
        raise InfeasibleError("no split path: every M-curve meets an infinite cost")
    st = [n - 1, n - 1, n - 1, b, ep, eq, em]
    trace = [list(st)]
    nmv = len(MOVES)
    while True:
        code = int(back[st[0], st[1], st[2], st[4], st[5], st[3], st[6]])
        if code < 0:
            break
        k, g = code % nmv, code // nmv
        di, dj, da, db = (int(x) for x in MOVES[k])
        st = [st[0] - di, st[1] - dj, st[2] - da, st[3] - db,
              g % mp if di else st[4], (g // mp) % mq if dj else st[5], g // (mp * mq) if da else st[6]]
        trace.append(list(st))
    path = np.array(trace[::-1], dtype=np.int64)
    if tuple(path[0, :3]) != (0, 0, 0):
        raise AssertionError("split DP trace did not reach the first column")
    return SplitPath(path[:, :4], score, objective, path[:, 4:])


def _sweep(A, B, objective: str, memory_cap, moves: np.ndarray):
    """One fill of the split DP's tables with the given moves: (back pointers, end primaries, end
    secondaries)."""
    if objective not in ("sum", "max"):
        raise BadInputError(f"unknown objective {objective!r}: use 'sum' or 'max'")
    n, mp, _, d, mm = A.shape
    mq = B.shape[1]
    if len(MOVES) * mp * mq * mm > 32000:
        raise BadInputError(f"too many elevation levels ({mp} x {mq} x {mm}); use at most 13 levels per point")
    check_memory(n, d, mp, mq, mm, memory_cap)
    red, flat = _buffers(n, d, mp, mq, mm)
    back = np.empty((n, n, n, mp, mq, d, mm), dtype=np.int16)
    endp, ends = np.empty((mp, mq, d, mm)), np.empty((mp, mq, d, mm))
    if jit.enabled():
        from ruled.split.kernels import fill
        fill(A, B, objective == "max", moves, red, flat, back, endp, ends)
    else:
        _fill_numpy(A, B, objective == "max", red, back, endp, ends, moves)
    return back, endp, ends


def row_scores(tables: SplitTables, objective: str = "sum", memory_cap: Optional[float] = None) -> np.ndarray:
    """(d,) the split DP's best score along each M-row alone (the split DP on that row's tables), all
    rows in one sweep: the moves that change row left out, no row ever meets another (inf: none)."""
    back, endp, _ = _sweep(_as5(tables.A), _as5(tables.B), objective, memory_cap, MOVES[MOVES[:, 3] == 0])
    return endp.min(axis=(0, 1, 3))


def path_score(tables: SplitTables, path: np.ndarray, objective: str, levels: Optional[np.ndarray] = None) -> float:
    """The objective of a path of states (and elevation levels), from the tables (for checks)."""
    A, B = _as5(tables.A), _as5(tables.B)
    e = np.zeros((len(path), 3), np.int64) if levels is None else levels
    c = np.maximum(A[path[:, 0], e[:, 0], path[:, 2], path[:, 3], e[:, 2]],
                   B[path[:, 1], e[:, 1], path[:, 2], path[:, 3], e[:, 2]])
    return float(c.max() if objective == "max" else c.sum())
