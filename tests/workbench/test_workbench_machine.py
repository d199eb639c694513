"""Export for machining in FreeCAD (freecadcmd, Debian's FreeCAD 0.20, no OCP): XYUV G-code and CSV,
flank APT, STEP with rulings, from a RuledFit object; the files are read back here by the independent
G-code parser and measured with OCCT like the command line's."""
import json
import os
import textwrap

import numpy as np
import pytest
from conftest import WORKBENCH_LOADER, run_freecadcmd

pytestmark = pytest.mark.freecad

SCRIPT = textwrap.dedent("""
    code = 1
    try:
        import json, sys
        sys.path.insert(0, {tests!r})
        import FreeCAD, Part
        from cases import hyperboloid
        from ruled_workbench.adapter import surface_to_face
        from ruled_workbench.features import make_ruled_fit
        from ruled_workbench.commands import export
        doc = FreeCAD.newDocument("M")
        src = doc.addObject("Part::Feature", "Hyperboloid")
        src.Shape = surface_to_face(hyperboloid(10.0, 10.0, 10.0))
        fit = make_ruled_fit(doc, src, "Face1", Samples=40, MeasureSamples=12)
        doc.recompute()
        out = {{"fit_valid": fit.isValid()}}
        export([fit], os.path.join({tmp!r}, "hyp.ngc"), "xyuv", chord_tol=0.01)
        export([fit], os.path.join({tmp!r}, "mill.apt"), "flank", chord_tol=0.01, tool_radius=1.0)
        export([fit], os.path.join({tmp!r}, "hyp.step"), "step-rulings", chord_tol=0.01)
        try:
            export([fit, src], os.path.join({tmp!r}, "two.ngc"), "xyuv")
        except Exception as exc:
            out["two"] = str(exc)
        json.dump(out, open(os.path.join({tmp!r}, "out.json"), "w"))
        code = 0
    except Exception:
        import traceback; traceback.print_exc()
    sys.stdout.flush(); sys.stderr.flush()
    os._exit(code)
""")


def test_export_for_machining_in_freecadcmd(tmp_path):
    from cases import hyperboloid
    from conftest import HERE
    from machine_helpers import check_sync, lines_3d, parse_apt, rebuilt_error
    from OCP.TopAbs import TopAbs_EDGE, TopAbs_FACE
    from OCP.TopExp import TopExp_Explorer

    from ruled.occ.convert import container_to_face
    from ruled.occ.io import read_shape

    run = run_freecadcmd(WORKBENCH_LOADER + SCRIPT.format(tmp=str(tmp_path), tests=HERE), tmp_path, 900)
    assert "Traceback" not in run.stdout + run.stderr, run.stdout + run.stderr
    out = json.loads((tmp_path / "out.json").read_text())
    assert out["fit_valid"]
    assert "one ruled fit at a time" in out["two"]
    rep = json.loads((tmp_path / "hyp.json").read_text())
    parsed, kinds = check_sync(str(tmp_path / "hyp.ngc"), str(tmp_path / "hyp.csv"))
    cut = parsed[[k == "cut" for k in kinds]]
    lo, hi = lines_3d(cut, rep)
    face = container_to_face(hyperboloid(10.0, 10.0, 10.0))
    h = rebuilt_error(face, face, lo, hi, "v", 30)
    assert h.max <= 0.01 + 1e-9
    assert rep["cut"]["max"] == pytest.approx(h.max, abs=0.003)       # FreeCAD's measure agrees
    tip, axis = parse_apt(str(tmp_path / "mill.apt"))
    assert len(tip) > 10 and np.allclose(np.linalg.norm(axis, axis=1), 1.0, atol=1e-8)
    shape = read_shape(str(tmp_path / "hyp.step"))

    def count(kind):
        ex, n = TopExp_Explorer(shape, kind), 0
        while ex.More():
            n += 1
            ex.Next()
        return n
    assert count(TopAbs_FACE) == 1 and count(TopAbs_EDGE) > 20
    assert os.path.exists(tmp_path / "mill.csv")
    env = json.loads((tmp_path / "mill.json").read_text())["tool_envelope"]["cl_positions"]
    assert 0 < env["overcut"] < 0.3 and 0 < env["undercut"] < 0.3     # the twisted hyperboloid: reported
