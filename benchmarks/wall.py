"""A part's wall as one closed ruled surface, run by ``benchmarks/run.py --suite wall``: CPU seconds of the
whole ``ruled fit INPUT --wall auto`` process (start-up, read, join, fit, measure, write) on a wall of six
faces with 40 samples per face, fitted closed (a smooth loft from a hexagon through two circles, not ruled:
no corner both contours share), in 2D (target 10 CPU s) and 4D (target 60 CPU s)."""

from __future__ import annotations

import json
import os
import sys
import tempfile

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
