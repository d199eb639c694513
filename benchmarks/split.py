"""Split benchmark (Wang & Elber §4), run by ``benchmarks/run.py --suite split``.

Targets (issue 7): the 4D split DP at n = 30, d = 10 (a 30 x 30 x 30 x 10 table) in <= 0.5 s; the 7D
split DP at (30 x 5)^3 x 10 in <= 2.5 s with <= 150 MB peak.  Printed: the DP alone (warm, best of 5;
numba kernel, and its NumPy twin in a subprocess with RULED_NO_NUMBA=1), its peak traced memory, and the
line-metric tables it reads (every P-M and M-Q ruling on Elber's ex2, lifted for 5D and 7D).
"""

from __future__ import annotations

import os
import subprocess
import sys
import time
import tracemalloc

from cone import _best

from ruled.examples import elber_ex2
from ruled.split.mcurve import split_dp, split_tables, table_bytes

N, D, TARGET_S = 30, 10, 0.5
LEVELS, TARGET_7D_S, TARGET_7D_MB = 2, 2.5, 150


def bench_split() -> None:
    print(f"== split DP (Wang & Elber §4, 4D): n = {N}, d = {D}, table {table_bytes(N, D) / 2 ** 20:.1f} MiB")
    t0 = time.perf_counter()
    T = split_tables(elber_ex2(), N, D)
    t_tab = time.perf_counter() - t0
    t = _best(lambda: split_dp(T))
    r = split_dp(T)
    print(f"   line-metric tables (ex2): {t_tab:.2f} s;  DP: {t:.3f} s (target {TARGET_S} s, "
          f"ratio {t / TARGET_S:.2f}), path of {len(r.path)} states, score {r.score:.4g}")
    code = ("import sys, time; sys.path.insert(0, %r); from split import N, D; from ruled.examples import elber_ex2\n"
            "from ruled.split.mcurve import split_dp, split_tables\n"
            "T = split_tables(elber_ex2(), N, D); t = time.perf_counter(); split_dp(T); print(time.perf_counter() - t)"
            % os.path.dirname(__file__))
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         env={**os.environ, "RULED_NO_NUMBA": "1"})
    if out.returncode == 0:
        print(f"   NumPy only (RULED_NO_NUMBA=1): DP {float(out.stdout.split()[-1]):.2f} s")
    for dims in (5, 7):
        t0 = time.perf_counter()
        T = split_tables(elber_ex2(), N, D, dims=dims, levels=LEVELS, step=0.01)
        t_tab = time.perf_counter() - t0
        t = _best(lambda: split_dp(T), 3)
        tracemalloc.start()
        r = split_dp(T)
        peak = tracemalloc.get_traced_memory()[1] / 1e6
        tracemalloc.stop()
        m = 2 * LEVELS + 1
        size = f"({N} x {m})^3 x {D}" if dims == 7 else f"{N}^3 x {D} x {m}"
        target = f" (target {TARGET_7D_S} s, ratio {t / TARGET_7D_S:.2f}; {TARGET_7D_MB} MB, ratio " \
                 f"{peak / TARGET_7D_MB:.2f})" if dims == 7 else ""
        print(f"== split DP {dims}D: {size}, {m} levels: DP {t:.3f} s, peak {peak:.0f} MB{target}; lifted tables "
              f"{t_tab:.1f} s; score {r.score:.4g}")
