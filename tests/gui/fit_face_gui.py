"""Run by tests/test_workbench_gui.py inside the FreeCAD GUI (under Xvfb): the Ruled workbench, a
face of a STEP selected, "Fit ruled surface" through its task panel, the result's properties, a
screenshot of the coloured result with its rulings, and the STEP export.  Writes result.json and the
pictures to $RULED_GUI_OUT; ends with os._exit (FreeCAD exits 0 even when a script raises)."""
import sys
import os
import json
OUT = os.environ["RULED_GUI_OUT"]
os.makedirs(OUT, exist_ok=True)
code = 1
res = {}


try:
    import FreeCAD
    import FreeCADGui
    import Part
    FreeCADGui.activateWorkbench("RuledWorkbench")
    from ruled_workbench import commands, taskpanels
    res["commands"] = [c for c in commands.NAMES if c in FreeCADGui.listCommands()]
    doc = FreeCAD.newDocument("Gui")
    imp = doc.addObject("Part::Feature", "Impeller")
    imp.Shape = Part.read(os.environ["RULED_STEP"])
    doc.recompute()
    sel = FreeCADGui.Selection
    # bad selections: nothing, an edge, a vertex -> the command is disabled and says why
    bad = []
    for sub in (None, "Edge3", "Vertex2"):
        sel.clearSelection()
        if sub:
            sel.addSelection(imp, sub)
        c = commands.FitCommand()
        active = c.IsActive()
        c.Activated()
        bad.append([sub, active, commands.LAST_MESSAGE])
    res["bad"] = bad
    sel.clearSelection()
    sel.addSelection(imp, "Face7")
    res["active_on_face"] = commands.FitCommand().IsActive()
    FreeCADGui.runCommand("Ruled_Fit")
    panel = taskpanels.ACTIVE
    res["panel"] = panel is not None
    panel.samples.setValue(16)
    panel.measure.setValue(24)
    res["preview"] = panel.preview()
    res["panel_text"] = panel.result.text()
    # OK right after Preview keeps what Preview computed: every run writes its own time in Seconds
    fit_obj, seconds = panel.obj, panel.obj.Seconds
    res["accept"] = panel.accept()
    res["accept_reran"] = fit_obj.Seconds != seconds
    obj = doc.getObject("RuledFit")
    obj.touch()
    doc.recompute()
    res["recompute_reran"] = obj.Seconds != seconds
    res["object"] = {"valid": obj.isValid(), "status": obj.Status, "bound": obj.ErrorBound, "hausdorff": obj.Hausdorff,
                     "rulings": obj.Rulings, "lines": len(obj.RulingLines), "dev": len(obj.Deviation),
                     "mode": obj.ViewObject.DisplayMode, "proxy": type(obj.ViewObject.Proxy).__name__}
    imp.ViewObject.Transparency = 70
    view = FreeCADGui.ActiveDocument.ActiveView
    # look at the result face-on (a blade face is long and thin: seen from an iso view it is a sliver)
    f = obj.Shape.Faces[0]
    u0, u1, v0, v1 = f.ParameterRange
    n = f.normalAt(0.5 * (u0 + u1), 0.5 * (v0 + v1))
    view.setViewDirection((-n.x, -n.y, -n.z))
    sel.clearSelection()
    sel.addSelection(obj)
    FreeCADGui.SendMsgToActiveView("ViewSelection")
    sel.clearSelection()
    FreeCADGui.updateGui()
    shot = os.path.join(OUT, "ruled_fit.png")
    view.saveImage(shot, 1280, 1024, "White")
    res["shot"] = shot
    # a face the engine cannot take (a cone's face: one boundary collapses to the apex): the panel says why
    cone = doc.addObject("Part::Feature", "Cone")
    cone.Shape = Part.makeCone(0, 3, 5).translate(FreeCAD.Vector(200, 0, 0))
    doc.recompute()
    sel.clearSelection()
    sel.addSelection(cone, "Face1")
    FreeCADGui.runCommand("Ruled_Fit")
    bad_panel = taskpanels.ACTIVE
    bad_panel.samples.setValue(12)
    res["bad_face"] = {"accepted": bad_panel.accept(), "text": bad_panel.result.text()}
    bad_panel.reject()
    res["after_cancel"] = [o.Name for o in doc.Objects]
    step = os.path.join(OUT, "ruled_fit.step")
    commands.export_step([obj], step)
    res["step_size"] = os.path.getsize(step)
    # "Export for machining...": the file dialog's XYUV G-code format, its questions answered with their defaults
    from PySide import QtGui
    from ruled_workbench.export import FORMATS
    ngc = os.path.join(OUT, "ruled_fit.ngc")
    label = next(k for k, v in FORMATS.items() if v == "xyuv")
    asked = []
    QtGui.QFileDialog.getSaveFileName = lambda *a, **k: (ngc, label)
    QtGui.QInputDialog.getDouble = lambda parent, title, text, value, *a, **k: (asked.append(text) or value, True)
    sel.clearSelection()
    sel.addSelection(obj)
    FreeCADGui.runCommand("Ruled_Export")
    res["export"] = {"asked": asked, "gcode": os.path.exists(ngc), "message": commands.LAST_MESSAGE}
    # "Split for ruling" on the same face: the panel's preview, then OK; a picture of the split curve
    sel.clearSelection()
    sel.addSelection(imp, "Face7")
    FreeCADGui.runCommand("Ruled_Split")
    sp = taskpanels.ACTIVE
    sp.samples.setValue(12)
    sp.interior.setValue(4)
    sp.fit_samples.setValue(16)
    res["split_preview"] = sp.preview()
    res["split_text"] = sp.result.text()
    seconds = sp.obj.Seconds
    res["split_accept"] = sp.accept()
    res["split_accept_reran"] = doc.getObject("RuledSplit").Seconds != seconds
    so = doc.getObject("RuledSplit")
    res["split"] = {"valid": so.isValid(), "status": so.Status, "chosen": so.Chosen, "bound": so.ErrorBound,
                    "whole": so.WholeBound, "faces": len(so.Shape.Faces), "curve": len(so.SplitCurve)}
    obj.ViewObject.Visibility = False
    sel.clearSelection()
    FreeCADGui.updateGui()
    shot = os.path.join(OUT, "ruled_split.png")
    view.saveImage(shot, 1280, 1024, "White")
    res["split_shot"] = shot
    code = 0
except Exception:
    import traceback
    traceback.print_exc()
json.dump(res, open(os.path.join(OUT, "result.json"), "w"), indent=1)
sys.stdout.flush()
sys.stderr.flush()
os._exit(code)
