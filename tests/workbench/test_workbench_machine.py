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
        from ruled_workbench.export import export
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


@pytest.mark.slow     # (14 s: the loop stays under 3 minutes; CI runs it)
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
    mill = json.loads((tmp_path / "mill.json").read_text())
    env = mill["tool_envelope"]["with_moves"]      # the twisted hyperboloid: reported (the positions hold the
    assert 0 < env["overcut"] < 0.3 and 0 < env["undercut"] < 0.3     # overcut at the CL points: it is between)
    # the two measures' overcuts, the larger the figure, within the gouge tolerance (issue 72)
    oc = mill["overcut"]
    assert oc["larger"] == max(oc["swept_tool"], oc["tool_envelope"]) <= mill["machine"]["positions"]["gouge_tol"]


BLADE = """
import FreeCAD, Part
from ruled_workbench.features import make_ruled_fit
from ruled_workbench.export import export
doc = FreeCAD.newDocument("B")
imp = doc.addObject("Part::Feature", "Impeller")
imp.Shape = Part.read(STEP)
fit = make_ruled_fit(doc, imp, "Face7", MeasureSamples=12)
doc.recompute()
out["fit"] = {"valid": fit.isValid(), "bound": float(fit.ErrorBound), "hausdorff": float(fit.Hausdorff),
              "trimmed_result": fit.Shape.Faces[0].Area < 0.999 * fit.Shape.Faces[0].Surface.toShape().Area}
export([fit], os.path.join(TMP, "blade.ngc"), "xyuv", chord_tol=0.002)
export([fit], os.path.join(TMP, "mill.apt"), "flank", tool_radius=0.05)
"""


@pytest.mark.slow
def test_export_for_machining_of_a_trimmed_fit_follows_that_fit(tmp_path):
    """Issue 55: Export for machining of the RuledFit of kj66's Face7 (its result trimmed by the face's edges, as
    'ruled fit' returns it) follows that result, not the fit pinned to the face's corners: the report's fit is
    the object's own bound (<= 0.0005, against the pinned fit's 0.0023) with no warning; the G-code, replayed
    through gcodeparser, sweeps lines within bound + chord of the bounded face and the face within that of the
    lines (trim-aware, measured with OCCT here); the flank tool's over- and undercut at its CL points against
    the bounded face are within the bound + 1e-5, and the face's points against the tool swept through its moves
    within the gouge tolerance over."""
    from conftest import data_file, freecad_json
    from machine_helpers import check_sync, lines_3d, trim_aware_cut

    from ruled.occ.io import get_face
    step = data_file("kj66_impeller.step")
    out = freecad_json(f"STEP, TMP = {step!r}, {str(tmp_path)!r}\n" + BLADE, tmp_path, 1200)
    fit = out["fit"]
    assert fit["valid"] and fit["trimmed_result"] and 0 < fit["hausdorff"] <= fit["bound"] <= 5e-4, fit
    rep = json.loads((tmp_path / "blade.json").read_text())
    assert rep["fit"]["error_bound"] == pytest.approx(fit["bound"], rel=1e-12) and not rep["warnings"], rep
    parsed, kinds = check_sync(str(tmp_path / "blade.ngc"), str(tmp_path / "blade.csv"))
    lo, hi = lines_3d(parsed[[k == "cut" for k in kinds]], rep)
    to_swept, d, kept = trim_aware_cut(get_face(step, 6), lo, hi, every=2)
    assert kept > 100 and np.abs(d).max() <= fit["bound"] + 0.002 and to_swept <= fit["bound"] + 0.002
    assert rep["cut"]["max"] <= rep["cut"]["bound"] == pytest.approx(fit["bound"] + 0.002, rel=1e-9)
    # issue 71, one file from every door: the command line's file of the same face and settings, named alike, is
    # the workbench's byte for byte (LinuxCNC's post; the wire's cut measured alike, from its lines)
    from ruled.cli.main import main
    os.makedirs(tmp_path / "cli")
    cli = str(tmp_path / "cli" / "blade.ngc")
    assert main(["machine", step, "--face", "6", "--xyuv", "--chord-tol", "0.002", "-o", cli, "--report",
                 str(tmp_path / "cli" / "blade.json"), "--measure-samples", "20", "--quiet"]) == 0
    assert open(cli, "rb").read() == (tmp_path / "blade.ngc").read_bytes()
    mine = json.loads((tmp_path / "cli" / "blade.json").read_text())["cut"]
    for k in ("overcut", "undercut"):
        assert abs(rep["cut"][k] - mine[k]) <= 1e-6 * 10, (k, rep["cut"][k], mine[k])
    env = json.loads((tmp_path / "mill.json").read_text())
    cl = env["tool_envelope"]["cl_positions"]
    assert env["fit"]["error_bound"] == rep["fit"]["error_bound"] and not env["warnings"]
    assert max(cl["overcut"], cl["undercut"]) <= fit["bound"] + 1e-5, cl
    # issue 61: the tool's positions fitted to the face's envelope, as 'ruled machine --flank' fits them: the face's
    # points (FreeCAD's, of the face inside its edges) against the tool swept through the moves within the gouge
    # tolerance (the fit's bound) over, the axis turning at most 2 degrees a move
    sw, pos = env["swept_tool"], env["machine"]["positions"]
    assert "after" in pos and pos["gouge_tol"] == env["fit"]["error_bound"], pos
    assert sw["unreached"] == 0 and sw["overcut"] <= pos["gouge_tol"] and sw["axis_angle_max_deg"] <= 2.0, sw


FALLBACK_AXIS = "0.3864,-0.7174,0.5798"     # 88 degrees from a ruling of face 8's trimmed fit, 60 from its pinned one's


@pytest.mark.slow
def test_a_trimmed_fit_that_cannot_be_machined_falls_back_saying_so_in_freecad(tmp_path):
    """Issue 55, no silent fallback: along an axis that a ruling of kj66 Face9's trimmed fit (and none of its
    pinned fit's) nearly lies across, Export for machining follows the pinned fit, and its warning gives both
    figures (the report's "warnings" and "fallback")."""
    from conftest import data_file, freecad_json
    step = data_file("kj66_impeller.step")
    body = BLADE.replace('"Face7"', '"Face9"').replace(
        'export([fit], os.path.join(TMP, "blade.ngc"), "xyuv", chord_tol=0.002)',
        f'export([fit], os.path.join(TMP, "blade.ngc"), "xyuv", axis={FALLBACK_AXIS!r})').replace(
        'export([fit], os.path.join(TMP, "mill.apt"), "flank", tool_radius=0.05)', "")
    out = freecad_json(f"STEP, TMP = {step!r}, {str(tmp_path)!r}\n" + body, tmp_path, 1200)
    rep = json.loads((tmp_path / "blade.json").read_text())
    fb, w = rep["fallback"], rep["warnings"][0]
    assert fb["trimmed_bound"] == pytest.approx(out["fit"]["bound"]) and fb["pinned_bound"] > 5 * fb["trimmed_bound"]
    assert w.startswith("the wire follows the corner-pinned fit (bound ") and "degrees from the machine axis" in w
    assert f"the trimmed fit is bound {out['fit']['bound']:.4g}, measured {out['fit']['hausdorff']:.4g}" in w, w
    assert rep["fit"]["error_bound"] == fb["pinned_bound"]
