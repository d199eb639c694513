"""Optional numba kernel of the split DP (ruled/split/mcurve.py), 4D, 5D and 7D alike: the same cells in the
same order as its NumPy twin split._fill_numpy, the reductions over freed elevations in increasing
combined index, moves in split.MOVES order, a candidate replacing the best only when strictly better
(primary, then secondary).  Tests compare the twins."""

from __future__ import annotations

import numpy as np

from ruled.core.jit import AVAILABLE

if AVAILABLE:
    from numba import njit, prange

    from ruled.core.jit import PARALLEL

    @njit(cache=True, nogil=True)
    def _better(p, s, bp, bs):
        return p < bp or (p == bp and s < bs)

    @njit(cache=True, nogil=True)
    def _cell(i, j, a, A, B, use_max, moves, red, flat, back, endp, ends, Vp, Vs, C, Bk):
        """One cell (i, j, a): every elevation level and row; then its reductions (the scratch arrays
        Vp ... Bk are the cell's own)."""
        n, mp, _, d, mm = A.shape
        mq = B.shape[1]
        (cQp, cQs, cQa, cMp, cMs, cMa, cQMp, cQMs, cQMa,
         pPp, pPs, pPa, pPQp, pPQs, pPQa, pPMp, pPMs, pPMa, pPQMp, pPQMs, pPQMa,
         nPp, nPs, nPa, nPQp, nPQs, nPQa, nPMp, nPMs, nPMa, nPQMp, nPQMs, nPQMa) = red
        nmv = moves.shape[0]
        for ep in range(mp):
            for eq in range(mq):
                for b in range(d):
                    for em in range(mm):
                        C[ep, eq, b, em] = max(A[i, ep, a, b, em], B[j, eq, a, b, em])
        if i == 0 and j == 0 and a == 0:
            Vp[:] = C
            Vs[:] = C
            back[0, 0, 0] = -1
        else:
            FP, FS, FG, geo = flat
            Vp[:] = np.inf
            Vs[:] = np.inf
            Bk[:] = -1
            for k in range(nmv):
                di = moves[k, 0]
                dj = moves[k, 1]
                da = moves[k, 2]
                db = moves[k, 3]
                if i - di < 0 or j - dj < 0 or a - da < 0:
                    continue
                t = 4 * di + 2 * dj + da
                base = geo[t, 0] + ((j - dj) * n + (a - da)) * geo[t, 1]
                sp, sq, sb, sm = geo[t, 2], geo[t, 3], geo[t, 4], geo[t, 5]
                for ep in range(mp):
                    for eq in range(mq):
                        for b in range(max(0, db), min(d, d + db)):
                            x0 = base + ep * sp + eq * sq + (b - db) * sb
                            for em in range(mm):
                                x = x0 + em * sm
                                p = FP[x]
                                if not p < np.inf:
                                    continue
                                c = C[ep, eq, b, em]
                                if use_max:
                                    q = max(p, c)
                                    qs = FS[x] + c
                                else:
                                    q = p + c
                                    qs = q
                                if _better(q, qs, Vp[ep, eq, b, em], Vs[ep, eq, b, em]):
                                    Vp[ep, eq, b, em] = q
                                    Vs[ep, eq, b, em] = qs
                                    Bk[ep, eq, b, em] = k + nmv * FG[x]
            back[i, j, a] = Bk
        # the cell's reductions over freed elevations (increasing combined index)
        for ep in range(mp):
            for b in range(d):
                for em in range(mm):
                    bp, bs, bg = np.inf, np.inf, 0
                    for eq in range(mq):
                        if _better(Vp[ep, eq, b, em], Vs[ep, eq, b, em], bp, bs):
                            bp, bs, bg = Vp[ep, eq, b, em], Vs[ep, eq, b, em], mp * eq
                    cQp[j, a, ep, b, em], cQs[j, a, ep, b, em], cQa[j, a, ep, b, em] = bp, bs, bg
                for eq in range(mq):
                    bp, bs, bg = np.inf, np.inf, 0
                    for em in range(mm):
                        if _better(Vp[ep, eq, b, em], Vs[ep, eq, b, em], bp, bs):
                            bp, bs, bg = Vp[ep, eq, b, em], Vs[ep, eq, b, em], mp * mq * em
                    cMp[j, a, ep, eq, b], cMs[j, a, ep, eq, b], cMa[j, a, ep, eq, b] = bp, bs, bg
                bp, bs, bg = np.inf, np.inf, 0
                for em in range(mm):
                    for eq in range(mq):
                        if _better(Vp[ep, eq, b, em], Vs[ep, eq, b, em], bp, bs):
                            bp, bs, bg = Vp[ep, eq, b, em], Vs[ep, eq, b, em], mp * (eq + mq * em)
                cQMp[j, a, ep, b], cQMs[j, a, ep, b], cQMa[j, a, ep, b] = bp, bs, bg
        for b in range(d):
            for em in range(mm):
                for eq in range(mq):
                    bp, bs, bg = np.inf, np.inf, 0
                    for ep in range(mp):
                        if _better(Vp[ep, eq, b, em], Vs[ep, eq, b, em], bp, bs):
                            bp, bs, bg = Vp[ep, eq, b, em], Vs[ep, eq, b, em], ep
                    nPp[j, a, eq, b, em], nPs[j, a, eq, b, em], nPa[j, a, eq, b, em] = bp, bs, bg
                bp, bs, bg = np.inf, np.inf, 0
                for eq in range(mq):
                    for ep in range(mp):
                        if _better(Vp[ep, eq, b, em], Vs[ep, eq, b, em], bp, bs):
                            bp, bs, bg = Vp[ep, eq, b, em], Vs[ep, eq, b, em], ep + mp * eq
                nPQp[j, a, b, em], nPQs[j, a, b, em], nPQa[j, a, b, em] = bp, bs, bg
            for eq in range(mq):
                bp, bs, bg = np.inf, np.inf, 0
                for em in range(mm):
                    for ep in range(mp):
                        if _better(Vp[ep, eq, b, em], Vs[ep, eq, b, em], bp, bs):
                            bp, bs, bg = Vp[ep, eq, b, em], Vs[ep, eq, b, em], ep + mp * mq * em
                nPMp[j, a, eq, b], nPMs[j, a, eq, b], nPMa[j, a, eq, b] = bp, bs, bg
            bp, bs, bg = np.inf, np.inf, 0
            for em in range(mm):
                for eq in range(mq):
                    for ep in range(mp):
                        if _better(Vp[ep, eq, b, em], Vs[ep, eq, b, em], bp, bs):
                            bp, bs, bg = Vp[ep, eq, b, em], Vs[ep, eq, b, em], ep + mp * (eq + mq * em)
            nPQMp[j, a, b], nPQMs[j, a, b], nPQMa[j, a, b] = bp, bs, bg
        if i == n - 1 and j == n - 1 and a == n - 1:
            endp[:] = Vp
            ends[:] = Vs

    @njit(cache=True, nogil=True, parallel=PARALLEL)
    def fill(A, B, use_max, moves, red, flat, back, endp, ends):
        """A (n, mp, n, d, mm), B (n, mq, n, d, mm); red: the reduction buffers, views of the flat arrays
        in flat = (primary, secondary, argument, reading geometry of each move pattern) (split._buffers);
        back (n, n, n, mp, mq, d, mm) int16: move + 15 * combined index of the freed elevations.  The
        cells of one layer i are swept by anti-diagonals of (j, a), each in parallel (a cell reads
        only earlier diagonals of its layer and the previous layer's P-reductions)."""
        n, mp, _, d, mm = A.shape
        mq = B.shape[1]
        # scratch per position on a diagonal: the values, costs and moves of a cell
        Vp = np.empty((n, mp, mq, d, mm))
        Vs = np.empty((n, mp, mq, d, mm))
        C = np.empty((n, mp, mq, d, mm))
        Bk = np.empty((n, mp, mq, d, mm), dtype=np.int16)
        (_, _, _, _, _, _, _, _, _,
         pPp, pPs, pPa, pPQp, pPQs, pPQa, pPMp, pPMs, pPMa, pPQMp, pPQMs, pPQMa,
         nPp, nPs, nPa, nPQp, nPQs, nPQa, nPMp, nPMs, nPMa, nPQMp, nPQMs, nPQMa) = red
        for i in range(n):
            for sd in range(2 * n - 1):
                lo = max(0, sd - n + 1)
                hi = min(sd, n - 1)
                for jj in prange(hi - lo + 1):
                    j = lo + jj
                    _cell(i, j, sd - j, A, B, use_max, moves, red, flat, back, endp, ends, Vp[jj], Vs[jj], C[jj],
                          Bk[jj])
            # the next layer reads this one's P-reductions
            pPp[:], pPs[:], pPa[:] = nPp, nPs, nPa
            pPQp[:], pPQs[:], pPQa[:] = nPQp, nPQs, nPQa
            pPMp[:], pPMs[:], pPMa[:] = nPMp, nPMs, nPMa
            pPQMp[:], pPQMs[:], pPQMa[:] = nPQMp, nPQMs, nPQMa
