"""Optional numba kernels of the DP tables: dp.py's 2D fill, and of the 4D-DP the SSHB ruling terms,
LSAD, and the table sweep.

Each kernel computes, entry by entry and in the same order of operations,
what its NumPy twin computes (metrics4d.sshb_ruling_tables,
metrics4d.lsad_tables, dp4d._fill_numpy), so both paths give identical
results (tests compare them).  They release the GIL and run on all cores
through jit._run_chunks.
"""

from __future__ import annotations

import numpy as np

from ruled.core.jit import AVAILABLE, _run_chunks

# the 15 moves of eq. (16): (di, dj, dk, dl), PQ moves first, then P, then Q; within a pattern the
# elevation changes in the order 0, -1, +1 (same order as dp4d.MOVES)
_MV = []
for _di, _dj in ((1, 1), (1, 0), (0, 1)):
    for _dk in ((0, -1, 1) if _di else (0,)):
        for _dl in ((0, -1, 1) if _dj else (0,)):
            _MV.append((_di, _dj, _dk, _dl))
MOVES = np.array(_MV, dtype=np.int64)
PATTERN_OF = np.array([0 if (a, b) == (1, 1) else (1 if a else 2) for a, b, _, _ in _MV], dtype=np.int64)
COL = {0: 0, -1: 1, 1: 2}
DK_COL = np.array([COL[int(m[2])] for m in MOVES], dtype=np.int64)
DL_COL = np.array([COL[int(m[3])] for m in MOVES], dtype=np.int64)

if AVAILABLE:
    from numba import njit

    from ruled.core.jit import INLINE

    @njit(cache=True, nogil=True)
    def _dp_fill_range(C, use_max, tie, prim, sec, back, b0, b1):
        ni, nj = C.shape[1], C.shape[2]
        for b in range(b0, b1):
            prim[b, 0, 0] = C[b, 0, 0]
            sec[b, 0, 0] = C[b, 0, 0]
            for d in range(1, ni + nj - 1):
                for i in range(max(0, d - nj + 1), min(ni - 1, d) + 1):
                    j = d - i
                    c = C[b, i, j]
                    bp = np.inf
                    bs = np.inf
                    bk = 0
                    # the same order and tie rule as the NumPy twin (dp._fill)
                    P0 = np.inf
                    P1 = np.inf
                    P2 = np.inf
                    S0 = np.inf
                    S1 = np.inf
                    S2 = np.inf
                    if i >= 1 and j >= 1:
                        P0 = prim[b, i - 1, j - 1]
                        S0 = sec[b, i - 1, j - 1]
                    if i >= 1:
                        P1 = prim[b, i - 1, j]
                        S1 = sec[b, i - 1, j]
                    if j >= 1:
                        P2 = prim[b, i, j - 1]
                        S2 = sec[b, i, j - 1]
                    if use_max:
                        P0 = max(P0, c)
                        P1 = max(P1, c)
                        P2 = max(P2, c)
                        S0 = S0 + c
                        S1 = S1 + c
                        S2 = S2 + c
                    else:
                        P0 = P0 + c
                        P1 = P1 + c
                        P2 = P2 + c
                        S0 = P0
                        S1 = P1
                        S2 = P2
                    best = min(P0, min(P1, P2))
                    lim = best + tie * max(1.0, abs(best))
                    bk = -1
                    if P0 <= lim:
                        bk = 0
                        bs = S0
                        bp = P0
                    if P1 <= lim and (bk < 0 or S1 < bs):
                        bk = 1
                        bs = S1
                        bp = P1
                    if P2 <= lim and (bk < 0 or S2 < bs):
                        bk = 2
                        bs = S2
                        bp = P2
                    if bk < 0:
                        bk = 0
                        bp = P0
                        bs = S0
                    prim[b, i, j] = bp
                    sec[b, i, j] = bs
                    back[b, i, j] = bk

    def dp_fill(C, use_max, tie, prim, sec, back):
        """Twin of dp._fill: the whole table, threads over the batch of shifted tables."""
        _run_chunks(lambda a, b: _dp_fill_range(C, use_max, tie, prim, sec, back, a, b), C.shape[0], 1)

    @njit(cache=True, nogil=True, inline=INLINE)
    def _f32_up(x):
        y = np.float32(x)
        if np.float64(y) < x:
            y = np.nextafter(y, np.float32(np.inf))
        return y

    @njit(cache=True, nogil=True, inline=INLINE)
    def _normal_d2(lam, rr, r2n):
        """|r + lam N|^2 = |r|^2 + lam (2 r.N + lam) (metrics4d)."""
        return rr + lam * (r2n + lam)

    @njit(cache=True, nogil=True, inline=INLINE)
    def _qm(Muu, Muv, Mvv, su, sv):
        return (Muu * su * su + 2.0 * Muv * su * sv) + Mvv * sv * sv

    @njit(cache=True, nogil=True)
    def _sshb_range(e, uA, uB, v0, v1, fu, fv, rr, r2n, al, be, Au, Av, Bu, Bv, Muu, Muv, Mvv,
                    c, es, dku, dkv, i0, i1):
        n = rr.shape[1]
        K = e.shape[0]
        ns = rr.shape[2]
        cm = np.empty(K)
        em = np.empty(K)
        mu = np.empty(K)
        mv = np.empty(K)
        pu = np.empty(K)
        pv = np.empty(K)
        for i in range(i0, i1):
            for j in range(n):
                for k in range(K):
                    ek = e[k]
                    for l in range(K):  # nodes in order along the ruling, l innermost (independent)
                        cm[l] = max(abs(ek), abs(e[l]))
                        em[l] = 0.0
                        mu[l] = 0.0
                        mv[l] = 0.0
                        pu[l] = uA[i]
                        pv[l] = v0
                    for q in range(ns + 1):
                        if q < ns:
                            a_ = al[i, j, q]
                            b_ = be[i, j, q]
                            rq = rr[i, j, q]
                            r2 = r2n[i, j, q]
                            au = Au[i, j, q]
                            bu = Bu[i, j, q]
                            av = Av[i, j, q]
                            bv = Bv[i, j, q]
                            fuq = fu[i, j, q]
                            fvq = fv[i, j, q]
                            for l in range(K):
                                lam = ek * a_ + e[l] * b_
                                d2 = _normal_d2(lam, rq, r2)
                                du = ek * au + e[l] * bu
                                dv = ek * av + e[l] * bv
                                adu = abs(du)
                                adv = abs(dv)
                                cm[l] = max(cm[l], np.sqrt(max(d2, 0.0)) + 0.5 * _qm(Muu, Muv, Mvv, adu, adv))
                                mu[l] = max(mu[l], adu)
                                mv[l] = max(mv[l], adv)
                                nu_ = fuq + du
                                nv_ = fvq + dv
                                su = abs(nu_ - pu[l])
                                sv = abs(nv_ - pv[l])
                                em[l] = max(em[l], 0.125 * _qm(Muu, Muv, Mvv, su, sv))
                                pu[l] = nu_
                                pv[l] = nv_
                        else:
                            for l in range(K):
                                su = abs(uB[i, j] - pu[l])
                                sv = abs(v1 - pv[l])
                                em[l] = max(em[l], 0.125 * _qm(Muu, Muv, Mvv, su, sv))
                    for l in range(K):
                        c[i, j, k, l] = _f32_up(cm[l])
                        es[i, j, k, l] = _f32_up(em[l])
                        dku[i, j, k, l] = _f32_up(mu[l])
                        dkv[i, j, k, l] = _f32_up(mv[l])

    def sshb_rulings(e, uA, uB, v0, v1, fu, fv, rr, r2n, al, be, Au, Av, Bu, Bv, Muu, Muv, Mvv, c, es, dku, dkv):
        """Twin of metrics4d.sshb_ruling_tables (threads over i)."""
        _run_chunks(lambda a, b: _sshb_range(e, uA, uB, v0, v1, fu, fv, rr, r2n, al, be, Au, Av, Bu, Bv,
                                             Muu, Muv, Mvv, c, es, dku, dkv, a, b), rr.shape[0], 1)

    @njit(cache=True, nogil=True)
    def _lsad_range(e, rr, r2n, al, be, out, i0, i1):
        n = rr.shape[1]
        K = e.shape[0]
        m = rr.shape[2]
        best = np.empty(K)
        for i in range(i0, i1):
            for j in range(n):
                for k in range(K):
                    ek = e[k]
                    for l in range(K):
                        b0 = max(abs(ek), abs(e[l]))
                        best[l] = b0 * b0
                    for q in range(m):
                        a_ = al[i, j, q]
                        b_ = be[i, j, q]
                        rq = rr[i, j, q]
                        r2 = r2n[i, j, q]
                        for l in range(K):
                            best[l] = max(best[l], _normal_d2(ek * a_ + e[l] * b_, rq, r2))
                    for l in range(K):
                        out[i, j, k, l] = _f32_up(np.sqrt(best[l]))

    def lsad(e, rr, r2n, al, be, out):
        """Twin of the NumPy loop in metrics4d.lsad_tables (threads over i)."""
        _run_chunks(lambda a, b: _lsad_range(e, rr, r2n, al, be, out, a, b), rr.shape[0], 1)

    @njit(cache=True, nogil=True, inline=INLINE)
    def _take(p, s, bp, bs, tie):
        """The selection rule of dp4d (one pass, in move order): a clearly smaller objective, or an
        objective tied within the tolerance with a smaller secondary (NaN-safe: an empty entry,
        bp = inf, takes any finite candidate)."""
        t = tie * max(1.0, abs(bp))
        return (p < bp - t) | ((p <= bp + t) & (s < bs))

    @njit(cache=True, nogil=True)
    def _fill_cells(sshb, use_max, tie, closed, n, shift, lc, c, es, dku, dkv, area, d0u, d0v, t0, g0, gP, gQ,
                    Mq, limit, start, moves, pat_of, dk_col, dl_col, ni, nj, d, i0, u_lo, u_hi, prim, sec, back, src):
        """Entries (i, j = d - i, k, all l) of one anti-diagonal for the work units u in [u_lo, u_hi),
        unit u being cell i = i0 + u // K and row k = u % K; moves in order, l innermost."""
        K = prim.shape[2]
        inf = np.inf
        Muu = Mq[0]
        Muv = Mq[1]
        Mvv = Mq[2]
        for u in range(u_lo, u_hi):
            i = i0 + u // K
            k = u % K
            j = d - i
            wi = i % n
            wj = (j + shift) % n
            last = closed and i == ni - 1 and j == nj - 1
            if i == 0 and j == 0:
                for l in range(K):
                    v = np.float64(lc[wi, wj, k, l]) if not sshb else 0.0
                    if not v <= limit or (start >= 0 and k * K + l != start):
                        v = inf
                    prim[i, j, k, l] = v
                    sec[i, j, k, l] = v
                    back[i, j, k, l] = -1
                    src[i, j, k, l] = k * K + l
                continue
            for l in range(K):
                prim[i, j, k, l] = inf
                sec[i, j, k, l] = inf
                back[i, j, k, l] = 0
                src[i, j, k, l] = -1
            for mv in range(15):
                di = moves[mv, 0]
                dj = moves[mv, 1]
                dl = moves[mv, 3]
                kp = k - moves[mv, 2]
                if i < di or j < dj or kp < 0 or kp >= K:
                    continue
                pi = i - di
                pj = j - dj
                wpi = pi % n
                wpj = (pj + shift) % n
                pat = pat_of[mv]
                a0 = area[pat, wi, wj] if sshb else 0.0
                u0_ = d0u[pat, wi, wj] if sshb else 0.0
                v0_ = d0v[pat, wi, wj] if sshb else 0.0
                tt = t0[pat, wi, wj] if sshb else 0.0
                gg = (g0[pat, wi, wj] + (gP[dk_col[mv], wi, k] if di == 1 else 0.0)) if sshb else 0.0
                dlc = dl_col[mv]
                for l in range(max(0, dl), min(K, K + dl)):
                    lp = l - dl
                    if sshb:
                        gq = gQ[dlc, wj, l] if dj == 1 else 0.0
                        du = u0_ + (np.float64(dku[wi, wj, k, l]) + np.float64(dku[wpi, wpj, kp, lp]))
                        dv = v0_ + (np.float64(dkv[wi, wj, k, l]) + np.float64(dkv[wpi, wpj, kp, lp]))
                        w = ((max(np.float64(c[wi, wj, k, l]), np.float64(c[wpi, wpj, kp, lp]))
                              + max(np.float64(es[wi, wj, k, l]), np.float64(es[wpi, wpj, kp, lp])))
                             + 0.125 * _qm(Muu, Muv, Mvv, du, dv)) + (0.25 * (gg + gq)) * tt
                        ws = a0 * w
                    else:
                        w = np.float64(lc[wi, wj, k, l])
                        ws = w
                    pp = prim[pi, pj, kp, lp]
                    if use_max:
                        pv = max(pp, w)
                        sv = sec[pi, pj, kp, lp] + ws
                    else:
                        pv = pp + ws
                        sv = pv
                    zp = src[pi, pj, kp, lp]
                    ok = (w <= limit) & ((not last) | (zp == k * K + l))
                    pv = pv if ok else inf
                    sv = sv if ok else inf
                    tk = _take(pv, sv, prim[i, j, k, l], sec[i, j, k, l], tie)
                    if tk:
                        prim[i, j, k, l] = pv
                        sec[i, j, k, l] = sv
                        back[i, j, k, l] = mv
                        src[i, j, k, l] = zp

    @njit(cache=True, nogil=True)
    def _fill_lsad_sum(n, shift, lc, limit, moves, d, i0, u_lo, u_hi, prim, sec, back, src):
        """The LSAD sum objective (w depends only on the new ruling): per entry the first strict
        minimum of the 15 predecessors' scores, plus w.  Open tables only (no end constraint)."""
        K = prim.shape[2]
        inf = np.inf
        for u in range(u_lo, u_hi):
            i = i0 + u // K
            k = u % K
            j = d - i
            wi = i % n
            wj = (j + shift) % n
            for l in range(K):
                w = np.float64(lc[wi, wj, k, l])
                if i == 0 and j == 0:
                    v = w if w <= limit else inf
                    prim[i, j, k, l] = v
                    sec[i, j, k, l] = v
                    back[i, j, k, l] = -1
                    src[i, j, k, l] = k * K + l
                    continue
                best = inf
                bk = 0
                bz = -1
                for mv in range(15):
                    pi = i - moves[mv, 0]
                    pj = j - moves[mv, 1]
                    kp = k - moves[mv, 2]
                    lp = l - moves[mv, 3]
                    if pi < 0 or pj < 0 or kp < 0 or kp >= K or lp < 0 or lp >= K:
                        continue
                    v = prim[pi, pj, kp, lp]
                    if v < best:
                        best = v
                        bk = mv
                        bz = src[pi, pj, kp, lp]
                v = best + w if w <= limit else inf
                if not v < inf:
                    bk = 0
                    bz = -1
                prim[i, j, k, l] = v
                sec[i, j, k, l] = v
                back[i, j, k, l] = bk
                src[i, j, k, l] = bz

    def fill(sshb, use_max, tie, closed, n, shift, lc, c, es, dku, dkv, area, d0u, d0v, t0, g0, gP, gQ, Mq, limit,
             start, prim, sec, back, src):
        """Twin of dp4d._fill_numpy: the whole table, anti-diagonal by anti-diagonal, the cells of a
        diagonal split over the cores."""
        ni, nj = prim.shape[0], prim.shape[1]
        K = prim.shape[2]
        fast = not sshb and not use_max and not closed and start < 0
        for d in range(ni + nj - 1):
            lo = max(0, d - nj + 1)
            hi = min(ni - 1, d) + 1

            def run(a, b, d=d, lo=lo):
                if fast:
                    _fill_lsad_sum(n, shift, lc, limit, MOVES, d, lo, a, b, prim, sec, back, src)
                    return
                _fill_cells(sshb, use_max, tie, closed, n, shift, lc, c, es, dku, dkv, area, d0u, d0v, t0, g0, gP, gQ,
                            Mq, limit, start, MOVES, PATTERN_OF, DK_COL, DL_COL, ni, nj, d, lo, a, b, prim, sec, back,
                            src)
            _run_chunks(run, (hi - lo) * K, 2 * K)
else:  # pragma: no cover - exercised in FreeCAD's Python
    sshb_rulings = None
    lsad = None
    fill = None
    dp_fill = None
