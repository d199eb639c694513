"""Compile the numba kernels once, before the test workers need them (tests/conftest.py starts it).

A clean clone has no compiled kernels: every process that meets a kernel first compiles it (numba caches
it on disk afterwards), and with two test workers and the command-line tests' subprocesses starting
together, the same kernels were compiled several times over.  This runs one small job of each
capability (rational and periodic surfaces too: each kind of input is a kernel signature of its own),
so that the suite finds them compiled.  It asserts nothing: the tests do."""

from __future__ import annotations

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))


def _stamp() -> str:
    """A file that says the kernels of these sources were compiled by this numba (numba's cache is beside the
    sources, keyed by each source file's time and size: an edit, or a clean clone, compiles them again)."""
    import glob
    import hashlib

    import numba
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    h = hashlib.sha1(f"{sys.version} {numba.__version__}".encode())
    for path in sorted(glob.glob(os.path.join(root, "ruled", "*", "kernels.py"))
                       + [os.path.join(root, "ruled", "core", "jit.py")]):
        st = os.stat(path)
        h.update(f"{path} {st.st_mtime_ns} {st.st_size}".encode())
    return os.path.join(root, "ruled", "__pycache__", f"kernels-warm-{h.hexdigest()[:16]}")


def main() -> int:
    from ruled.core import jit
    if not jit.enabled():
        return 0
    stamp = _stamp()
    if os.path.exists(stamp):         # compiled already (the loop while you work): nothing to wait for
        return 0
    _compile()
    os.makedirs(os.path.dirname(stamp), exist_ok=True)
    open(stamp, "w").close()
    return 0


def _compile() -> None:
    import numpy as np
    from cases import hyperboloid, random_surface

    import ruled
    from ruled.examples import cone_examples, elber_ex2, yang_curve, yang_surface
    rng = np.random.default_rng(1)
    for S in (elber_ex2(), hyperboloid(), random_surface(rng), random_surface(rng, periodic_u=True)):
        ruled.fit_surface(S, ruled.FitOptions(samples=12))
    for metric in ("lsad", "sshb"):
        ruled.fit_surface(elber_ex2(), ruled.FitOptions(samples=10, method="4d", elevations=1, metric=metric))
    ruled.split_face(elber_ex2(), ruled.SplitOptions(samples=8, interior=4, fit=ruled.FitOptions(samples=12)))
    ruled.approximate(yang_surface(), yang_curve(), 1e-3)
    from ruled.cone.fatarc import fit_fat_conic
    name, b0, db0, b1, db1, tol, step, height, _ = cone_examples()[2]
    fit_fat_conic(b0, db0, b1, db1, tol, step, h1=height)


if __name__ == "__main__":      # python tests/warm_kernels.py [DONE]: DONE is written when it ends
    try:
        code = main()
    finally:
        if len(sys.argv) > 1:
            with open(sys.argv[1], "w") as fh:
                fh.write("done")
    sys.exit(code)
