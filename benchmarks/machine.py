"""Machine-output benchmark, run by ``benchmarks/run.py --suite machine``.

On the one-sheet hyperboloid of tests/cases.py scaled to radius 10 (closed, exactly ruled; its fit is
computed once and not timed): the XYUV contours (planes, synchronized pairs densified and thinned to
the chord tolerance, leads) at chord tolerances 1e-2 and 1e-3, with a kerf (offset lines), and the
flank tool axes with the tool-envelope measure (17 circles per CL point and per move).  Targets: XYUV
at 1e-3 in <= 0.25 s, flank with its envelope in <= 1.5 s, peak traced memory <= 150 MB.  Warm, best of 3.

Issue 61, the flank tool's positions fitted to the face's envelope (CPU seconds): the hyperboloid (r = 1) and
the twisted blade of tests/cases.py (40 degrees over 1.5, r = 0.05) in the engine, beside their offset rulings,
with each one's largest deviation (the face's points against the swept tool); and the whole job of
``ruled machine kj66 --face 6 --flank --tool-radius 0.05`` (start-up, read, fit, positions, measures, write),
envelope and offset.
"""

from __future__ import annotations

import os
import sys
import tempfile
import time
import tracemalloc

import numpy as np
from cone import _best

from ruled import FitOptions, fit_surface
from ruled.machine.envelope import tool_envelope
from ruled.machine.flank import flank_path
from ruled.machine.paths import MachineOptions, side_sign, xyuv_path

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "tests"))
from cases import hyperboloid, twisted_blade  # noqa: E402
from job import DATA, RULED, USER_ENV, _child  # noqa: E402

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
    _envelope(S, R, sign)
    _replay()


def _replay() -> None:
    """Issue 71: the wire's whole job and its file's replay (start-up, read, LinuxCNC's interpreter where it is
    installed, the measure), CPU seconds of the whole processes, best of 2."""
    from ruled.machine import linuxcnc
    print("== the wire's file and its replay (kj66 face 6, CPU s of the whole process, best of 2)")
    with tempfile.TemporaryDirectory() as d:
        ngc = os.path.join(d, "k6.ngc")
        runs = {"ruled machine kj66 face 6 --xyuv (and LinuxCNC's check)":
                [RULED, "machine", DATA, "--face", "6", "--xyuv", "--quiet", "-o", ngc],
                "ruled replay k6.ngc --against kj66 --face 6": [RULED, "replay", ngc, "--against", DATA, "--face", "6",
                                                                "--quiet"]}
        cpu = {}
        for what, cmd in runs.items():
            _child(cmd, USER_ENV)
            cpu[what] = min(_child(cmd, USER_ENV)[1] for _ in range(2))
            print(f"   {what:62s} {cpu[what]:7.3f} CPU s")
        lc = linuxcnc.check(ngc) if linuxcnc.available() else None
        c0 = time.perf_counter()
        if lc is not None:
            linuxcnc.check(ngc)
        print("   LinuxCNC's interpreter on the file: "
              + ("not installed" if lc is None else f"{lc['moves']} moves, {time.perf_counter() - c0:.3f} s wall"))


def _envelope(S, R, sign) -> None:
    """Issue 61: the envelope positions against the offset rulings, engine and whole job."""
    from ruled.machine.flank import machine_path
    from ruled.machine.swept import swept_measure
    print("== flank tool positions fitted to the envelope (CPU s; the largest deviation: the face's points "
          "against the swept tool)")
    blade = twisted_blade(40.0, 1.5)
    cases = (("hyperboloid r = 1", S, R, sign, 1.0),
             ("twisted blade 40 deg, r = 0.05", blade, fit_surface(blade, FitOptions()).surface, 1.0, 0.05))
    for name, SS, RR, sg, r in cases:
        a0, a1, b0, b1 = SS.domain
        uu, vv = np.meshgrid(np.linspace(a0, a1, 97), np.linspace(b0, b1, 31), indexing="ij")
        X = SS(uu.ravel(), vv.ravel())
        dev = {}
        for pos in ("offset", "envelope"):
            opts = MachineOptions("flank", tool_radius=r, positions=pos)
            c0 = time.process_time()
            p = machine_path(RR, SS, opts, sg)
            c = time.process_time() - c0
            m = swept_measure(p, X)
            dev[pos] = max(m["overcut"], m["undercut"])
            print(f"   {name:32s} {pos:8s} {c:7.3f} CPU s, {p.stats['cl_points']} CL points, overcut "
                  f"{m['overcut']:.3g}, undercut {m['undercut']:.3g}, axis turn {m['axis_angle_max_deg']:.2f} deg")
        print(f"   {name:32s} largest deviation: envelope / offset {dev['envelope'] / dev['offset']:.3f} (target "
              f"<= 0.3)")
    with tempfile.TemporaryDirectory() as d:
        for pos in ("envelope", "offset"):
            cmd = [RULED, "machine", DATA, "--face", "6", "--flank", "--tool-radius", "0.05", "--positions", pos,
                   "--quiet", "-o", os.path.join(d, f"k6-{pos}.apt")]
            _child(cmd, USER_ENV)
            cpu = min(_child(cmd, USER_ENV)[1] for _ in range(2))
            print(f"   ruled machine kj66 face 6 --flank --tool-radius 0.05 --positions {pos:8s} {cpu:7.3f} CPU s "
                  f"(the whole job)")
