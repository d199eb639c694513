"""Machine-output benchmark, run by ``benchmarks/run.py --suite machine``.

On the one-sheet hyperboloid of tests/cases.py scaled to radius 10 (closed, exactly ruled; its fit is
computed once and not timed): the XYUV contours (planes, synchronized pairs densified and thinned to
the chord tolerance, leads) at chord tolerances 1e-2 and 1e-3, with a kerf (offset lines), and the
flank tool axes with the tool-envelope measure (17 circles per CL point and per move).  Targets: XYUV
at 1e-3 in <= 0.25 s, flank with its envelope in <= 1.5 s, peak traced memory <= 150 MB.  Warm, best of 3.
"""

from __future__ import annotations

import os
import sys
import tracemalloc

from cone import _best

from ruled import FitOptions, fit_surface
from ruled.machine.envelope import tool_envelope
from ruled.machine.paths import MachineOptions, flank_path, side_sign, xyuv_path

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "tests"))
from cases import hyperboloid  # noqa: E402

TARGET_XYUV_S, TARGET_FLANK_S, TARGET_MB = 0.25, 1.5, 150


def bench_machine() -> None:
    S = hyperboloid(10.0, 10.0, 10.0)
    R = fit_surface(S, FitOptions(samples=40)).surface
    sign = side_sign(R, S)
    print("== machine outputs: hyperboloid, radius 10 (closed, exactly ruled)")
    for chord, kerf in ((1e-2, 0.0), (1e-3, 0.0), (1e-3, 0.001)):
        opts = MachineOptions(chord_tol=chord, kerf=kerf)
        t = _best(lambda: xyuv_path(R, opts, sign))
        p = xyuv_path(R, opts, sign)
        tag = f"   XYUV chord {chord:g}{', kerf %g' % kerf if kerf else ''}:"
        ratio = f" (target {TARGET_XYUV_S} s, ratio {t / TARGET_XYUV_S:.2f})" if chord == 1e-3 and not kerf else ""
        print(f"{tag:32s} {t:.3f} s{ratio}, {p.stats['sync_points']} synchronized pairs")
    opts = MachineOptions("flank", chord_tol=1e-3, tool_radius=1.0)

    def flank():
        p = flank_path(R, opts, sign)
        return p, tool_envelope(S, 1.0, p)
    t = _best(flank)
    tracemalloc.start()
    p, env = flank()
    peak = tracemalloc.get_traced_memory()[1] / 2 ** 20
    tracemalloc.stop()
    print(f"   flank r = 1, chord 1e-3 + envelope: {t:.3f} s (target {TARGET_FLANK_S} s, ratio "
          f"{t / TARGET_FLANK_S:.2f}), {p.stats['cl_points']} CL points, {env['samples']} tool circles, peak "
          f"{peak:.0f} MB (target {TARGET_MB}, ratio {peak / TARGET_MB:.2f})")
