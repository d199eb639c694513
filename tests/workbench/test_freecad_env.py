"""The engine runs unchanged in FreeCAD 0.20's Python (numpy 1.24, scipy 1.10, no OCP), with its NumPy
twins and with the numba kernels under Debian's python3-numba 0.56, and gives the same numbers as in the
venv (the kernels' own outputs bit for bit)."""
import json
import textwrap

import conftest
import numpy as np
import pytest
from conftest import ROOT, run_freecadcmd

pytestmark = pytest.mark.freecad

SCRIPT = textwrap.dedent("""
    import sys, os, json
    sys.path.insert(0, {root!r})
    code = 1
    try:
        import numpy as np, scipy
        from ruled import fit_surface, FitOptions
        from ruled.core import jit
        from ruled.examples import elber_ex1, elber_ex2
        S = elber_ex2()
        rng = np.random.default_rng(7)
        u = rng.uniform(0, 1, 50); v = rng.uniform(0, 1, 50)
        D = S.evaluate(u, v, 2)
        r = fit_surface(elber_ex1(), FitOptions(samples=16))
        r4 = fit_surface(elber_ex2(), FitOptions(samples=12, method="4d", elevations=3, metric="sshb"))
        from ruled.curves.curve_on_surface import approximate
        from ruled.examples import yang_surface, yang_curve
        c = approximate(yang_surface(), yang_curve(), 1e-3, 1.0)
        from ruled.cone.fatarc import fit_fat_conic
        from ruled.examples import cone_examples
        e = cone_examples()[3]
        arcs = fit_fat_conic(*e[1:7], h1=e[7])
        from ruled.split.partition import SplitOptions, split_face
        sp = split_face(elber_ex1(), SplitOptions(samples=10, interior=4, fit=FitOptions(samples=12)))
        split = {{k: [c.curve.poles.tolist(), c.bound] for k, c in sp.candidates.items()}}
        from ruled.core.distance import ruling_distances
        ub, dist = ruling_distances(S, np.linspace(0, 1, 300), 1.0 - 0.7 * np.linspace(0, 1, 300), 9, 3)
        out = {{"split": split, "cos": [c.segments, c.error_bound, c.max_joint_angle_deg, c.curve.poles.tolist()],
               "cone": [[a.A.tolist(), a.B.tolist(), a.w, a.err] for a in arcs],
               "np": np.__version__, "scipy": scipy.__version__, "numba": jit.enabled(),
               "rulings": (ub.tobytes() + dist.tobytes()).hex(), "Pbytes": D.P.tobytes().hex(),
               "P": D.P.tolist(), "Suu": D.Suu.tolist(), "pairs": r.best.pairs.tolist(),
               "bound": r.error_bound, "direction": r.direction,
               "pairs4": r4.best.pairs.tolist(), "bound4": r4.error_bound, "method4": r4.best.method}}
        with open({out!r}, "w") as fh:
            json.dump(out, fh)
        code = 0
    except Exception:
        import traceback; traceback.print_exc()
    sys.stdout.flush(); sys.stderr.flush()
    os._exit(code)
""")


def _freecad_has_numba(tmp_path) -> bool:
    run = run_freecadcmd("import os, importlib.util\n"
                         "print('NUMBA', importlib.util.find_spec('numba') is not None, flush=True)\nos._exit(0)\n",
                         tmp_path)
    return "NUMBA True" in run.stdout


@pytest.mark.parametrize("kernels", [pytest.param("numpy", marks=pytest.mark.slow),
                                     pytest.param("numba", marks=pytest.mark.slow)])   # (the loop: under 3 minutes)
def test_same_numbers_in_freecad_python(tmp_path, kernels):
    """FreeCAD's Python with the NumPy twins (RULED_NO_NUMBA=1) and with Debian's numba: the same fits
    as the venv; with numba, the kernels' ruling distances and surface points bit for bit."""
    if kernels == "numba" and not _freecad_has_numba(tmp_path):
        pytest.skip("FreeCAD's Python has no numba (apt-get install -y python3-numba)")
    out = tmp_path / "fc.json"
    run_freecadcmd(SCRIPT.format(root=ROOT, out=str(out)), tmp_path,
                   env={"RULED_NO_NUMBA": "1" if kernels == "numpy" else "0"})
    fc = json.loads(out.read_text())
    # (Debian 12's FreeCAD 0.20: numpy 1.24; Debian 13's FreeCAD 1.0 in its chroot: numpy 2.2)
    assert fc["np"].startswith("2." if conftest.FREECAD_ROOT else "1."), fc["np"]
    assert fc["numba"] is (kernels == "numba")
    from ruled import FitOptions, fit_surface
    from ruled.core import jit as K
    from ruled.core.distance import ruling_distances
    from ruled.examples import elber_ex1, elber_ex2
    S = elber_ex2()
    rng = np.random.default_rng(7)
    u = rng.uniform(0, 1, 50)
    v = rng.uniform(0, 1, 50)
    D = S.evaluate(u, v, 2)
    if kernels == "numba" and K.enabled():
        ub, dist = ruling_distances(S, np.linspace(0, 1, 300), 1.0 - 0.7 * np.linspace(0, 1, 300), 9, 3)
        assert fc["rulings"] == (ub.tobytes() + dist.tobytes()).hex()
        assert fc["Pbytes"] == D.P.tobytes().hex()
    assert np.abs(np.array(fc["P"]) - D.P).max() < 1e-13
    assert np.abs(np.array(fc["Suu"]) - D.Suu).max() < 1e-11
    r = fit_surface(elber_ex1(), FitOptions(samples=16))
    assert fc["direction"] == r.direction
    assert fc["pairs"] == r.best.pairs.tolist()
    assert abs(fc["bound"] - r.error_bound) <= 1e-6 * r.error_bound
    # the 4D fit: NumPy twins there, numba kernels here (when installed): the same path and bound
    r4 = fit_surface(elber_ex2(), FitOptions(samples=12, method="4d", elevations=3, metric="sshb"))
    assert fc["method4"] == r4.best.method
    assert fc["pairs4"] == r4.best.pairs.tolist()
    assert abs(fc["bound4"] - r4.error_bound) <= 1e-6 * r4.error_bound
    # curves on surfaces: the same segments, bound and curve
    from ruled.curves.curve_on_surface import approximate
    from ruled.examples import yang_curve, yang_surface
    c = approximate(yang_surface(), yang_curve(), 1e-3, 1.0)
    segs, bound, angle, poles = fc["cos"]
    assert segs == c.segments
    assert abs(bound - c.error_bound) <= 1e-9 * c.error_bound and abs(angle - c.max_joint_angle_deg) <= 1e-9
    assert np.abs(np.array(poles) - c.curve.poles).max() <= 1e-12
    # cone splines (example 3b): the same arcs with numpy 1.24 and without numba
    from ruled.cone.fatarc import fit_fat_conic
    from ruled.examples import cone_examples
    e = cone_examples()[3]
    arcs = fit_fat_conic(*e[1:7], h1=e[7])
    assert len(fc["cone"]) == len(arcs)
    for (A, B, w, err), a in zip(fc["cone"], arcs):
        assert np.abs(np.array(A) - a.A).max() <= 1e-9 and np.abs(np.array(B) - a.B).max() <= 1e-9
        assert abs(w - a.w) <= 1e-9 * a.w and abs(err - a.err) <= 1e-9
    # the split (virtual subdivision and side fits): the same curves and bounds
    from ruled.split.partition import SplitOptions, split_face
    sp = split_face(elber_ex1(), SplitOptions(samples=10, interior=4, fit=FitOptions(samples=12)))
    assert set(fc["split"]) == set(sp.candidates)
    for k, c in sp.candidates.items():
        poles, bound = fc["split"][k]
        assert np.abs(np.array(poles) - c.curve.poles).max() <= 1e-12
        assert abs(bound - c.bound) <= 1e-6 * c.bound
