"""The switch for the optional numba kernels, shared by every kernel module: ``AVAILABLE`` is True when numba
imports (and RULED_NO_NUMBA is not set); each kernel module (core.kernels, fit.dp.kernels, split.kernels,
curves.kernels, cone.kernels) defines its kernels only then, beside the NumPy twin they must equal.
numba is optional: when it is missing (FreeCAD's Python) or RULED_NO_NUMBA=1 is set, every caller takes
the NumPy path."""
from __future__ import annotations

import os


def _separate_cache() -> None:
    """Inside FreeCAD (its own Python and numba, Debian's 0.56) the compiled kernels go to a cache of their
    own: numba's default, __pycache__ beside the sources, holds index files of the same names for the
    venv's numba, and each numba discards and overwrites the other's (minutes of compiling each time).
    Beside the sources when that folder is writable, else in the user's cache; NUMBA_CACHE_DIR wins."""
    import sys
    if "FreeCAD" not in sys.modules or "NUMBA_CACHE_DIR" in os.environ:
        return
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))     # ruled/
    if os.access(here, os.W_OK):
        d = os.path.join(here, "__pycache__", "numba-freecad")
    else:
        d = os.path.join(os.environ.get("XDG_CACHE_HOME") or os.path.expanduser("~/.cache"), "ruled", "numba-freecad")
    os.environ["NUMBA_CACHE_DIR"] = d


AVAILABLE = False
if os.environ.get("RULED_NO_NUMBA", "") not in ("1", "true", "yes"):
    try:
        _separate_cache()
        import numba
        AVAILABLE = True
        # numba before 0.57 (Debian's 0.56, FreeCAD's Python) inlines at its own IR level so slowly that
        # the kernels took 6 minutes to compile: there the helpers are left to LLVM's inliner
        # and its parallel (prange) compile of the split DP took 4 minutes: there it runs on one thread
        _NEW = tuple(int(x) for x in numba.__version__.split(".")[:2]) >= (0, 57)
        INLINE = "always" if _NEW else "never"
        PARALLEL = _NEW
        # numba's TBB layer, when a system libtbb is present (FreeCAD's packages bring one), spins for
        # ever in its finalizer at interpreter exit: use numba's own thread pool unless told otherwise
        if "NUMBA_THREADING_LAYER" not in os.environ:
            numba.config.THREADING_LAYER = "workqueue"  # type: ignore[attr-defined]
    except Exception:  # numba missing or broken: NumPy path
        AVAILABLE = False


_POOL = None
# the cores this process may use (asked once: the kernels are called thousands of times per fit);
# RULED_THREADS caps them (the batch's workers share the cores)
CORES = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
CORES = max(1, min(CORES, int(os.environ.get("RULED_THREADS") or CORES)))


def _run_chunks(fn, N: int, min_chunk: int = 16384) -> None:
    """Run fn(start, stop) over [0, N) on all cores (the kernels release the GIL)."""
    global _POOL
    k = min(CORES, max(1, N // min_chunk))
    if k <= 1:
        fn(0, N)
        return
    if _POOL is None:
        from concurrent.futures import ThreadPoolExecutor
        _POOL = ThreadPoolExecutor(max_workers=CORES)
    bounds = [(N * i) // k for i in range(k + 1)]
    futs = [_POOL.submit(fn, bounds[i], bounds[i + 1]) for i in range(k)]
    for f in futs:
        f.result()


def enabled() -> bool:
    return AVAILABLE and os.environ.get("RULED_NO_NUMBA", "") not in ("1", "true", "yes")
