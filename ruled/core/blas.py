"""BLAS on one thread while the engine works.

The engine's matrices are small (least squares of a few hundred rows); a threaded BLAS (OpenBLAS, as
numpy and scipy wheels and Debian ship it) runs such calls no faster but keeps its threads spinning
between calls, which costs a fit half again its CPU time.  ``single_threaded()`` sets every OpenBLAS
loaded in the process to one thread for the duration and restores the caller's setting afterwards
(nested and thread-safe); where no OpenBLAS is found (another BLAS, another system) it does nothing.
The command line sets OPENBLAS_NUM_THREADS=1 before numpy loads, to the same effect.
"""

from __future__ import annotations

import contextlib
import ctypes
import functools
import threading

# (get, set) entry points: the system's OpenBLAS, and the symbol-prefixed copies in numpy's and
# scipy's wheels (64-bit and 32-bit integer builds)
_NAMES = (("openblas_get_num_threads", "openblas_set_num_threads"),
          ("scipy_openblas_get_num_threads64_", "scipy_openblas_set_num_threads64_"),
          ("scipy_openblas_get_num_threads", "scipy_openblas_set_num_threads"))
_found: dict = {}       # library path -> (get, set) or None
_lock = threading.Lock()
_depth = 0
_saved: list = []


def _handles() -> list:
    try:
        with open("/proc/self/maps") as fh:
            paths = {ln.split()[-1] for ln in fh if "openblas" in ln.lower() and "/" in ln}
    except OSError:
        return []
    for p in sorted(paths - set(_found)):
        _found[p] = None
        try:
            lib = ctypes.CDLL(p)
        except OSError:
            continue
        for g, s in _NAMES:
            get, set_ = getattr(lib, g, None), getattr(lib, s, None)
            if get is not None and set_ is not None:
                get.restype, get.argtypes = ctypes.c_int, []
                set_.restype, set_.argtypes = None, [ctypes.c_int]
                _found[p] = (get, set_)
                break
    return [h for h in _found.values() if h is not None]


@contextlib.contextmanager
def single_threaded():
    """BLAS on one thread inside the block (see the module doc)."""
    global _depth
    with _lock:
        if _depth == 0:
            _saved[:] = []
            for get, set_ in _handles():
                n = int(get())
                if n > 1:
                    _saved.append((set_, n))
                    set_(1)
        _depth += 1
    try:
        yield
    finally:
        with _lock:
            _depth -= 1
            if _depth == 0:
                for set_, n in _saved:
                    set_(n)
                _saved[:] = []


def one_thread(fn):
    """Decorator: fn runs with BLAS on one thread."""
    @functools.wraps(fn)
    def wrapper(*args, **kwargs):
        with single_threaded():
            return fn(*args, **kwargs)
    return wrapper
