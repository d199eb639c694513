"""A part's wall as one closed ruled surface, run by ``benchmarks/run.py --suite wall``: CPU seconds of the
whole ``ruled fit INPUT --wall auto`` process (start-up, read, join, fit, measure, write) on a wall of six
faces with 40 samples per face, fitted closed (a smooth loft from a hexagon through two circles, not ruled:
no corner both contours share), in 2D (target 10 CPU s) and 4D (target 60 CPU s); and the whole ``ruled machine
INPUT --wall auto --xyuv --kerf 0.15`` of two stars with sharp concave corners (a drafted one, with OCCT's fan
cones there, and a ruled loft, with creases), CPU seconds (target 30) and peak memory (target 1 GB)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time

from job import RULED, _child, _line

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def bench_wall() -> None:
    sys.path.insert(0, ROOT)
    from ruled.occ.io import write_step
    from tests.wall_parts import hexagon_to_circles
    print("== a wall of six faces, 40 samples per face, closed (CPU seconds of the whole process)")
    with tempfile.TemporaryDirectory() as d:
        part = os.path.join(d, "wall.step")
        write_step(hexagon_to_circles().wrapped, part)
        for method, target in (("2d", 10.0), ("4d", 60.0)):
            rep = os.path.join(d, f"{method}.json")
            cmd = [RULED, "fit", part, "--wall", "auto", "--method", method, "-o", os.path.join(d, "r.step"),
                   "--report", rep, "--quiet"]
            wall, cpu, rc = _child(cmd)
            if rc != 0:
                print(f"   ruled fit --wall auto --method {method}: exit {rc}")
                continue
            r = json.load(open(rep))
            _line(f"ruled fit --wall auto --method {method} (6 faces)", cpu, target, "CPU s")
            print(f"      closed {r['closed']}, {r['samples']} samples, bound {r['error_bound']:.4g}, measured "
                  f"{r['hausdorff']['max']:.4g}, {r['result']['poles'][0]} poles, wall {wall:.1f} s")
    bench_kerf()


def _child_peak(cmd: list) -> tuple:
    """(wall s, CPU s, peak resident MB, return code) of one process (its own rusage, os.wait4)."""
    t0 = time.perf_counter()
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    _, status, ru = os.wait4(p.pid, 0)
    p.returncode = os.waitstatus_to_exitcode(status)
    return time.perf_counter() - t0, ru.ru_utime + ru.ru_stime, ru.ru_maxrss / 1024.0, p.returncode


def bench_kerf() -> None:
    sys.path.insert(0, ROOT)
    from ruled.occ.io import write_step
    from tests.wall_parts import lofted_star, polygon_star
    print("== a wall's loop with the kerf round sharp concave corners (the whole process)")
    with tempfile.TemporaryDirectory() as d:
        for name, build in (("drafted star", polygon_star), ("lofted star", lofted_star)):
            part = os.path.join(d, "star.step")
            write_step(build().wrapped, part)
            rep = os.path.join(d, "m.json")
            wall, cpu, peak, rc = _child_peak([RULED, "machine", part, "--wall", "auto", "--xyuv", "--kerf", "0.15",
                                               "-o", os.path.join(d, "m.ngc"), "--report", rep, "--quiet"])
            if rc != 0:
                print(f"   ruled machine {name} --kerf 0.15: exit {rc}")
                continue
            r = json.load(open(rep))
            _line(f"ruled machine --wall auto --xyuv --kerf 0.15, {name}", cpu, 30.0, "CPU s")
            _line("   its peak memory", peak, 1024.0, "MB")
            print(f"      {r['machine']['moves']} moves, cut {r['cut']['max']:.4g} (bound {r['cut']['bound']:.4g}), "
                  f"wall {wall:.1f} s")
