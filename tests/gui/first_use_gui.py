"""The first fit in the GUI from a cold kernel cache (a fresh NUMBA_CACHE_DIR; tests/workbench/test_workbench_gui.py
runs it with $RULED_FIRST_SAMPLES 16, by hand at the defaults for the figures of docs/benchmarks.md): the Fit panel's
Preview clicked (QTest) on kj66 face 6, the progress read every 100 ms (its stage and percentage), the stage's line
in the panel, the window grabbed during the first-use stage, then a second Preview.  Writes first_use.json and
first_use_progress.png to $RULED_GUI_OUT."""
import os
import sys
import time

sys.path.insert(0, os.environ["RULED_GUI_LIB"])
from guitools import Results, click, grab_window, part_document, run_and_exit, toolbar_run  # noqa: E402

res = Results()
OUT = os.environ["RULED_GUI_OUT"]


def main():
    import FreeCADGui
    from PySide import QtCore
    doc, imp = part_document("FirstUse")
    from ruled_workbench import state

    from ruled import warm
    FreeCADGui.ActiveDocument.ActiveView.viewIsometric()
    FreeCADGui.ActiveDocument.ActiveView.fitAll()
    res["announced"] = warm.seconds(warm.cold("fit"))
    FreeCADGui.Selection.addSelection(imp, "Face7")
    toolbar_run("Ruled_Fit")
    panel = state.ACTIVE
    real_warm, took = warm.warm, []

    def timed(modules, progress=None):
        t = time.time()
        real_warm(modules, progress)
        took.append(time.time() - t)
    warm.warm = timed
    seen, shots = [], []
    t0 = [time.time()]

    def poll():
        if state.SHOWN:
            seen.append([round(time.time() - t0[0], 2)] + list(state.SHOWN))
        first = [s for s in seen if s[1].startswith("first use")]
        if first and not shots and time.time() - t0[0] - first[0][0] > 1.5:
            shots.append(grab_window(os.path.join(OUT, "first_use_progress.png")))
            label = panel.stage_label          # its own line, wrapped, whole (not cut)
            res["stage_line"] = {"text": label.text(), "wraps": label.wordWrap(), "height": label.height(),
                                 "needs": label.heightForWidth(label.width())}
    timer = QtCore.QTimer()
    timer.timeout.connect(poll)
    timer.start(100)
    times = []
    first_samples = int(os.environ.get("RULED_FIRST_SAMPLES", "40"))
    if first_samples < 40:
        panel.measure.setValue(8)
    for samples in (first_samples, first_samples + 1):
        panel.samples.setValue(samples)
        t0[0] = time.time()
        click(panel.preview_button)       # (a real click: Preview runs the fit, its progress shown meanwhile)
        times.append(time.time() - t0[0])
        if samples == first_samples:
            res["progress"] = list(seen)
            seen.clear()
    timer.stop()
    res["stage_s"] = sum(took)
    res["measured_after"] = warm.seconds(["core", "fit"])        # the estimate kept for the next first use
    res["first_s"], res["later_s"] = times
    res["valid"] = panel.obj.isValid() and panel.obj.Status == "ok"
    res["shot"] = shots[0] if shots else None
    panel.reject()


run_and_exit(main, res, "first_use.json")
