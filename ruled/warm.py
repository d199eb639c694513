"""The first use of the numba kernels: which kernel modules (ruled/<package>/kernels.py) a capability needs
that numba's on-disk cache holds nothing of yet, and one small job per module that compiles them, so that a
front door says so and shows it ("first use: preparing the fast kernels, once, about N s") instead of a long
silent first fit.  numba compiles a kernel on its first call and caches it on disk; later processes load it.
"""

from __future__ import annotations

import glob
import os

from ruled.core import jit

# the kernel modules each capability runs
NEEDS = {"fit": ("core", "fit"), "wall": ("core", "fit"), "split": ("core", "fit", "split", "curves"),
         "partition": ("core", "fit", "split", "curves"), "cone": ("core", "fit", "cone"),
         "curve": ("core", "curves")}
# seconds to compile each module's kernels with FreeCAD's numba (Debian's 0.56) on this 2-core machine, from
# an empty cache (each module's _job, in order: core 4.6 with the fit's, split 8.0, curves 4.1, cone 1.3),
# rounded up
SECONDS = {"core": 4, "fit": 2, "split": 9, "curves": 5, "cone": 2}


# where each module's kernels.py lies, under ruled/
FOLDERS = {"core": "core", "fit": os.path.join("fit", "dp"), "split": "split", "curves": "curves", "cone": "cone"}


def _cached(module: str) -> bool:
    """numba's cache holds compiled kernels of ruled/<folder>/kernels.py (in NUMBA_CACHE_DIR when set, a folder
    per package, named after the package's folder; else beside the sources)."""
    import numba
    here = os.path.dirname(os.path.abspath(__file__))
    folder = FOLDERS.get(module, module)
    user = getattr(numba.config, "CACHE_DIR", "") or ""
    where = os.path.join(user, f"{os.path.basename(folder)}_*") if user else os.path.join(here, folder, "__pycache__")
    return bool(glob.glob(os.path.join(where, "kernels.*.nbi")))


def cold(capability: str) -> list:
    """The kernel modules the capability needs that are not compiled yet (none without numba)."""
    if not jit.enabled():
        return []
    return [m for m in NEEDS.get(capability, ()) if not _cached(m)]


def _measured_path() -> str:
    """Where the kernels' measured compile times are kept: numba's cache folder (NUMBA_CACHE_DIR when set),
    else the package's own __pycache__, beside the kernels they time."""
    import numba
    folder = getattr(numba.config, "CACHE_DIR", "") or os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                                                     "__pycache__")
    return os.path.join(folder, "ruled-kernel-seconds.json")


def _measured() -> dict:
    import json
    try:
        with open(_measured_path()) as fh:
            got = json.load(fh)
        return {k: float(v) for k, v in got.items() if isinstance(v, (int, float)) and v > 0}
    except (OSError, ValueError, ImportError):
        return {}


def _module_seconds(m: str) -> float:
    """A module's compile time: as measured the last time it compiled here (kept in the cache), else
    SECONDS's estimate."""
    return _measured().get(m, SECONDS.get(m, 20))


def seconds(modules) -> int:
    return int(round(sum(_module_seconds(m) for m in modules)))


def _keep(measured: dict) -> None:
    """The compile times just measured, kept for the next first use (a cache cleared, another numba)."""
    import json
    got = {**_measured(), **measured}
    try:
        os.makedirs(os.path.dirname(_measured_path()), exist_ok=True)
        with open(_measured_path(), "w") as fh:
            json.dump(got, fh)
    except OSError:         # (a read-only installation: the estimates stay SECONDS's)
        pass


def _job(module: str) -> None:
    """A small job that calls the module's kernels (so that numba compiles and caches them)."""
    import ruled
    from ruled.examples import cone_examples, elber_ex2, yang_curve, yang_surface
    if module in ("core", "fit"):
        ruled.fit_surface(elber_ex2(), ruled.FitOptions(samples=12))
    elif module == "split":
        ruled.split_face(elber_ex2(), ruled.SplitOptions(samples=8, interior=4, fit=ruled.FitOptions(samples=12)))
    elif module == "curves":
        ruled.approximate(yang_surface(), yang_curve(), 1e-3)
    elif module == "cone":
        from ruled.cone.fatarc import fit_fat_conic
        _, b0, db0, b1, db1, tol, step, height, _ = cone_examples()[2]
        fit_fat_conic(b0, db0, b1, db1, tol, step, h1=height)


def warm(modules, progress=None) -> None:
    """Compile the modules' kernels, reporting progress(stage, fraction) by their expected seconds (and, where
    progress has ``expect``, the whole stage's expected time, so that its display moves while a module compiles);
    each module's compile timed and kept (_keep) for the next estimate."""
    import time
    expect = {m: _module_seconds(m) for m in modules}
    total, done = max(sum(expect.values()), 1e-9), 0.0
    stage = f"first use: preparing the fast kernels, once (about {seconds(modules)} s)"
    if progress is not None:
        progress(stage, 0.0)
        if hasattr(progress, "expect"):
            progress.expect(total)
    took = {}
    for m in modules:
        if progress is not None:
            progress(stage, done / total)
        t0 = time.perf_counter()
        _job(m)
        took[m] = time.perf_counter() - t0
        done += expect[m]
    _keep(took)
    if progress is not None:
        progress(stage, 1.0)


__all__ = ["cold", "warm", "seconds", "NEEDS", "SECONDS"]
