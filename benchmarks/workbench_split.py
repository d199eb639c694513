"""The workbench's RuledSplit on kj66 face 6 at its defaults, timed in FreeCAD's own Python (the NumPy
path when python3-numba is not installed).  Target (issue 17): at most 30 s.  Run it with FreeCAD's
command line, the script first:

    freecadcmd benchmarks/workbench_split.py
"""

import os
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TARGET_S = 30.0


def _load_workbench():
    """The workbench as FreeCAD loads an installed addon: its Init.py, with the repository on sys.path."""
    sys.path.insert(0, ROOT)
    with open(os.path.join(ROOT, "Init.py")) as fh:
        exec(compile(fh.read(), "Init.py", "exec"), {})


def main() -> int:
    _load_workbench()
    import FreeCAD
    import Part
    from ruled_workbench.features import make_ruled_split

    from ruled.core import jit
    doc = FreeCAD.newDocument("Bench")
    src = doc.addObject("Part::Feature", "Src")
    src.Shape = Part.read(os.path.join(ROOT, "tests", "data", "kj66_impeller.step"))
    t0, c0 = time.perf_counter(), time.process_time()
    sp = make_ruled_split(doc, src, "Face7")        # kj66 face 6 (FreeCAD counts from 1)
    doc.recompute()
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    print(f"RuledSplit kj66 face 6 at defaults ({'numba' if jit.enabled() else 'NumPy'} path): {wall:.1f} s wall, "
          f"{cpu:.1f} CPU s (target {TARGET_S:.0f} s, ratio {wall / TARGET_S:.2f}); {sp.Status}, chosen {sp.Chosen}, "
          f"bound {float(sp.ErrorBound):.6g}")
    return 0 if sp.isValid() else 1


# freecadcmd runs the file under its own module name: no __main__ guard (and os._exit, since freecadcmd
# exits 0 whatever a script raises)
_code = 1
try:
    _code = main()
except Exception:
    import traceback
    traceback.print_exc()
sys.stdout.flush()
os._exit(_code)
