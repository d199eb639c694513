"""Optional numba kernel of the split DP (ruled/split.py): the same states in the same order as its
NumPy twin split._fill_numpy, moves in split.MOVES order, a candidate replacing the best only when
strictly better (primary, then secondary).  Tests compare the twins."""

from __future__ import annotations

import numpy as np

from .kernels import AVAILABLE

if AVAILABLE:
    from numba import njit

    @njit(cache=True, nogil=True)
    def fill(A, B, use_max, moves, prim, sec, back):
        n = A.shape[0]
        d = A.shape[2]
        nm = moves.shape[0]
        for i in range(n):
            for j in range(n):
                for a in range(n):
                    for b in range(d):
                        c = max(A[i, a, b], B[j, a, b])
                        if i == 0 and j == 0 and a == 0:
                            prim[0, 0, 0, b] = c
                            sec[0, 0, 0, b] = c
                            back[0, 0, 0, b] = -1
                            continue
                        bp = np.inf
                        bs = np.inf
                        bk = -1
                        for k in range(nm):
                            pi = i - moves[k, 0]
                            pj = j - moves[k, 1]
                            pa = a - moves[k, 2]
                            pb = b - moves[k, 3]
                            if pi < 0 or pj < 0 or pa < 0 or pb < 0 or pb >= d:
                                continue
                            p = prim[pi, pj, pa, pb]
                            if not p < np.inf:
                                continue
                            s = sec[pi, pj, pa, pb]
                            if use_max:
                                np_ = max(p, c)
                                ns = s + c
                            else:
                                np_ = p + c
                                ns = np_
                            if np_ < bp or (np_ == bp and ns < bs):
                                bp = np_
                                bs = ns
                                bk = k
                        prim[i, j, a, b] = bp
                        sec[i, j, a, b] = bs
                        back[i, j, a, b] = bk
