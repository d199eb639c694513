"""The first fit in the GUI from a cold kernel cache (run by hand, not in CI: ``benchmarks/run.py`` cannot start
FreeCAD's GUI; see docs/benchmarks.md): the Fit panel's Preview on kj66 face 6, the progress read every 100 ms (its
stage and percentage, the same on every display), the window grabbed during the first-use stage, then a second
Preview.  Writes first_use.json and first_use_progress.png to $RULED_GUI_OUT."""
import os
import sys
import time

sys.path.insert(0, os.environ["RULED_GUI_LIB"])
from guitools import Results, grab_window, run_and_exit, toolbar_run  # noqa: E402

res = Results()
OUT = os.environ["RULED_GUI_OUT"]


def main():
    import FreeCAD
    import FreeCADGui
    import Part
    from PySide import QtCore
    FreeCADGui.activateWorkbench("RuledWorkbench")
    from ruled_workbench import state

    from ruled import warm
    doc = FreeCAD.newDocument("FirstUse")
    imp = doc.addObject("Part::Feature", "Impeller")
    imp.Shape = Part.read(os.environ["RULED_STEP"])
    doc.recompute()
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
    timer = QtCore.QTimer()
    timer.timeout.connect(poll)
    timer.start(100)
    times = []
    for samples in (40, 41):
        panel.samples.setValue(samples)
        t0[0] = time.time()
        panel.preview()
        times.append(time.time() - t0[0])
        if samples == 40:
            res["progress"] = list(seen)
            seen.clear()
    timer.stop()
    res["stage_s"] = sum(took)
    res["measured_after"] = warm.seconds(["core", "fit"])        # the estimate kept for the next first use
    res["first_s"], res["later_s"] = times
    res["shot"] = shots[0] if shots else None
    panel.reject()


run_and_exit(main, res, "first_use.json")
