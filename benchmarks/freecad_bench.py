"""What the FreeCAD benchmarks share (run by ``freecadcmd benchmarks/<script>.py``): a cold kernel cache unless
RULED_BENCH_WARM is set, the workbench loaded as FreeCAD loads an installed addon, a document holding the kj66
impeller, and the script's end (freecadcmd exits 0 whatever a script raises: os._exit with main's code)."""

import os
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def cold_cache() -> None:
    """A fresh NUMBA_CACHE_DIR (set before the workbench and numba load), unless RULED_BENCH_WARM=1."""
    if not os.environ.get("RULED_BENCH_WARM"):
        os.environ["NUMBA_CACHE_DIR"] = tempfile.mkdtemp(prefix="ruled-bench-numba-")


def impeller_document():
    """(document, its part holding kj66_impeller.step), the workbench loaded (its Init.py, the repository on
    sys.path)."""
    sys.path.insert(0, ROOT)
    with open(os.path.join(ROOT, "Init.py")) as fh:
        exec(compile(fh.read(), "Init.py", "exec"), {})
    import FreeCAD
    import Part
    doc = FreeCAD.newDocument("Bench")
    src = doc.addObject("Part::Feature", "Src")
    src.Shape = Part.read(os.path.join(ROOT, "tests", "data", "kj66_impeller.step"))
    return doc, src


def finish(main) -> None:
    """Run main() and end the process with its code (1 when it raised, the traceback printed)."""
    code = 1
    try:
        code = main()
    except Exception:
        import traceback
        traceback.print_exc()
    sys.stdout.flush()
    os._exit(code)
