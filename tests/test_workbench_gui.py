"""The workbench in FreeCAD's GUI under Xvfb (Debian's FreeCAD 0.20, installed by .ci/run): the
repository linked into a fresh user Mod folder, a face of kj66_impeller.step selected, the command run
through its task panel, the result object and its properties, bad selections refused with a
message, and a screenshot of the coloured result with its rulings in artifacts/gui/ (look at it)."""
import json
import os
import shutil
import subprocess

import pytest

from conftest import ROOT, data_file

pytestmark = [pytest.mark.freecad, pytest.mark.gui]


def test_fit_through_the_task_panel(tmp_path):
    if shutil.which("freecad") is None or shutil.which("xvfb-run") is None:
        pytest.skip("the FreeCAD GUI or xvfb-run is not installed (apt-get install -y freecad xvfb)")
    step = data_file("kj66_impeller.step")
    home = tmp_path / "home"
    (home / "Mod").mkdir(parents=True)
    os.symlink(ROOT, home / "Mod" / "Ruled")                 # the README's install: a link into the Mod folder
    out = os.path.join(ROOT, "artifacts", "gui")
    shutil.rmtree(out, ignore_errors=True)
    env = {**os.environ, "QTWEBENGINE_DISABLE_SANDBOX": "1", "FREECAD_USER_HOME": str(home),
           "RULED_STEP": step, "RULED_GUI_OUT": out}
    env.pop("QT_QPA_PLATFORM", None)
    run = subprocess.run(["xvfb-run", "-a", "-s", "-screen 0 1280x1024x24", "freecad",
                          os.path.join(ROOT, "tests", "gui", "fit_face_gui.py")],
                         capture_output=True, text=True, timeout=900, env=env)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    r = json.load(open(os.path.join(out, "result.json")))
    assert r["commands"] == ["Ruled_Fit", "Ruled_FitMany", "Ruled_Split", "Ruled_Export"]
    for sub, active, msg in r["bad"]:
        assert not active and msg and "\n" not in msg
        assert ("nothing is selected" in msg) if sub is None else (sub in msg and "not a face" in msg)
    assert r["active_on_face"] and r["panel"] and r["preview"] and r["accept"]
    # OK keeps what Preview computed (each run writes its own time; a recompute does change it)
    assert not r["accept_reran"] and not r["split_accept_reran"] and r["recompute_reran"]
    o = r["object"]
    assert o["valid"] and o["status"] == "ok" and o["proxy"] == "ViewProviderRuledFit" and o["mode"] == "Deviation"
    assert "Length" in o["bound_unit"]            # the results are lengths, shown in the user's units
    assert o["bound"] >= o["hausdorff"] > 0 and o["lines"] == 2 * o["rulings"] and o["dev"] == 24 * 24
    assert "certified bound" in r["panel_text"] and "red" in r["panel_text"]
    assert os.path.getsize(r["shot"]) > 20_000 and r["step_size"] > 1000
    ex = r["export"]
    assert ex["gcode"] and len(ex["asked"]) == 2 and "Kerf" in ex["asked"][1], ex
    from test_machine import check_sync
    ngc = os.path.join(os.path.dirname(r["shot"]), "ruled_fit.ngc")
    parsed, kinds = check_sync(ngc, ngc[:-4] + ".csv")
    assert kinds.count("cut") > 10
    # a face the engine refuses: the panel stays open with the reason; Cancel removes the object again
    assert not r["bad_face"]["accepted"] and r["bad_face"]["text"].startswith("Cannot fit:")
    assert sorted(r["after_cancel"]) == ["Cone", "Impeller", "RuledFit"]
    # "Split for ruling": previewed and kept, the two fitted sides and the split curve, better than one strip
    assert r["split_preview"] and r["split_accept"] and "kept the" in r["split_text"]
    sp = r["split"]
    assert sp["valid"] and sp["status"] == "ok" and sp["faces"] == 2 and sp["curve"] == 101
    assert sp["chosen"] in ("optimal", "best-iso", "iso-0.5") and 0 < sp["bound"] < sp["whole"]
    assert os.path.getsize(r["split_shot"]) > 20_000
    _check_everyday_use(r)


def _check_everyday_use(r):
    """Progress, Cancel, the legend, the panel, double-click, several faces, save and reopen (the GUI
    script's extra_checks)."""
    # the colour legend in the view: a title and five values in the user's units, 0 to the largest
    title, *values = r["legend"]
    assert "distance to the face" in title and len(values) == 5
    assert values[0].startswith("0") and all(any(u in v for u in ("mm", "µm", "nm", "m")) for v in values)
    # "Fit several faces": one RuledFit per face; the refused face is an invalid object with its reason
    assert [m[:2] for m in r["many"]] == [["Face7", True], ["Face8", True], ["Face1", False]]
    assert r["many"][2][2] and "\n" not in r["many"][2][2]
    # the fit panel fits the combo view at 1280 x 1024, every field has a tooltip, 4d options only in 4d
    width, combo = r["panel_width"]
    assert combo is None or width <= combo, r["panel_width"]
    assert r["tooltips"] and r["4d_disabled_in_2d"] and r["4d_enabled_in_4d"]
    # progress of a fit of several seconds: the status bar's bar and the panel's, many readings each
    assert r["progress_ok"] and r["progress_fit_s"] > 2
    assert len(r["progress_readings"]) >= 3 and len(r["panel_progress"]) >= 3
    # Cancel while a fit runs: stopped within 2 s, the panel closed, the document as before
    c = r["cancel"]
    assert c["clicked"] and c["returned"] is False and c["latency_s"] < 2.0, c
    assert c["objects_same"] and c["panel_closed"]
    # double-click opens the object's own panel (editing it), Cancel closes it
    assert r["edit"]["opened"] and r["edit"]["closed"] and r["edit"]["samples"] == 16
    # save and reopen in the GUI: nothing in the report view, the objects with their code, the same results
    ro = r["reopen"]
    assert ro["report_found"] and not ro["traceback"], ro["text"]
    assert all(ro["valid"]) and ro["same"] and ro["proxies"] == ["RuledFit", "RuledSplit"]
    assert os.path.getsize(r["reopen_shot"]) > 20_000
