"""Run by tests/workbench/test_workbench_gui.py inside the FreeCAD GUI (under Xvfb), the quick check of the
loop while you work: the Ruled workbench activates, its toolbar holds every command, disabled with nothing
selected and enabled on a face, and a click on "Fit ruled surface" opens its task panel (closed again, no
fit).  Writes smoke.json to $RULED_GUI_OUT; ends with os._exit (FreeCAD exits 0 even when a script raises)."""
import os
import sys

sys.path.insert(0, os.environ["RULED_GUI_LIB"])
from guitools import Results, click_greyed, part_document, run_and_exit, toolbar_actions, toolbar_run  # noqa: E402

res = Results()


def main():
    import FreeCADGui
    from PySide import QtGui
    doc, imp = part_document("Smoke")
    from ruled_workbench import commands, state
    res["names"] = list(commands.NAMES)
    FreeCADGui.Selection.clearSelection()
    for _ in range(20):                   # FreeCAD updates the buttons' state on a timer
        QtGui.QApplication.processEvents()
    actions = toolbar_actions()
    res["toolbar"] = [a.objectName() for a in actions]
    res["enabled_on_nothing"] = [a.objectName() for a in actions if a.isEnabled()]
    # a real click on a greyed command's menu entry and toolbar button says why in the status bar (issue 59)
    res["greyed_menu"] = click_greyed("Ruled_Fit", "menu")
    res["greyed_button"] = click_greyed("Ruled_Replace")
    FreeCADGui.Selection.addSelection(imp, "Face7")
    res["clicked"] = toolbar_run("Ruled_Fit")
    panel = state.ACTIVE
    res["panel"] = type(panel).__name__ if panel is not None else None
    if panel is not None:
        panel.reject()
    res["closed"] = state.ACTIVE is None
    res["objects"] = sorted(o.Name for o in doc.Objects)
    # what the greyed buttons say: their tooltips and status tips name what to select
    res["tips"] = {a.objectName(): [a.toolTip(), a.statusTip()] for a in actions}
    # Edit > Preferences opens with the Ruled page's icon (FreeCAD prints "Cannot find icon" otherwise)
    from PySide import QtCore

    def close_prefs():
        w = QtGui.QApplication.activeModalWidget()
        res["prefs_dialog"] = type(w).__name__ if w is not None else None
        if w is not None:
            w.reject()
    QtCore.QTimer.singleShot(2500, close_prefs)
    FreeCADGui.runCommand("Std_DlgPreferences")


run_and_exit(main, res, "smoke.json")
