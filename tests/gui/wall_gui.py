"""Run by tests/workbench/test_workbench_gui.py inside the FreeCAD GUI (under Xvfb): a part's wall (the
tapered extrusion of tests/wall_parts.py, $RULED_WALL_STEP) selected face by face in the 3D view's selection,
"Fit wall" clicked in the Ruled toolbar (a parametric RuledWall, coloured by its measured distance), the
export panel writing its XYUV G-code, undo, and a screenshot.  Writes wall.json and pictures to
$RULED_GUI_OUT; ends with os._exit."""
import os
import sys

sys.path.insert(0, os.environ["RULED_GUI_LIB"])
from guitools import Results, click_greyed, grab_window, part_document, run_and_exit, shortcut, task_width, toolbar_run  # noqa: E402

OUT = os.environ["RULED_GUI_OUT"]
res = Results()


def main():
    import FreeCADGui
    doc, part = part_document("Wall", "Part", "RULED_WALL_STEP")
    from ruled_workbench import exportpanel, viewproviders
    from ruled_workbench.features import value
    sel = FreeCADGui.Selection
    faces = os.environ["RULED_WALL_FACES"].split(",")
    sel.clearSelection()
    sel.addSelection(part, faces[0])
    res["one_face"] = toolbar_run("Ruled_Wall")           # one face is no wall: the button stays greyed
    # two faces that are not one side wall: the button is greyed, a real click on it says why in the status bar
    # (issue 59); run anyway (a script's runCommand), the panel says so in one line, and no object is made
    from ruled_workbench import commands, state, wallpanel
    sel.addSelection(part, faces[2])
    before = len(doc.Objects)
    res["unrelated_clicked"] = toolbar_run("Ruled_Wall")
    res["unrelated_greyed"] = click_greyed("Ruled_Wall")
    commands.INSTANCES["Ruled_Wall"].Activated()
    for _ in range(5):
        FreeCADGui.updateGui()
    res["refusal"] = None if wallpanel.REFUSED is None else wallpanel.REFUSED.message.text()
    res["refusal_shot"] = grab_window(os.path.join(OUT, "ruled_wall_refusal.png"))
    res["refusal_made"] = len(doc.Objects) - before
    if wallpanel.REFUSED is not None:
        wallpanel.REFUSED.reject()
    sel.clearSelection()
    for name in faces:
        sel.addSelection(part, name)
    before = len(doc.Objects)
    res["clicked"] = toolbar_run("Ruled_Wall")
    for _ in range(5):
        FreeCADGui.updateGui()
    panel = state.ACTIVE
    res["panel"] = type(panel).__name__
    panel.samples.setValue(40)
    res["accepted"] = panel.accept()
    walls = [o for o in doc.Objects if type(getattr(o, "Proxy", None)).__name__ == "RuledWall"]
    res["made"] = len(doc.Objects) - before
    w = walls[0]
    res["state_after_create"] = list(w.State)
    vp = w.ViewObject.Proxy
    res["wall"] = {"valid": w.isValid(), "status": w.Status, "bound": value(w.ErrorBound),
                   "hausdorff": value(w.Hausdorff), "faces": list(w.Faces), "pieces": w.Pieces,
                   "label": w.Label, "closed": bool(w.Shape.Faces and w.Shape.Faces[0].Surface.isUClosed()),
                   "shape_valid": w.Shape.isValid(), "n_faces": len(w.Shape.Faces), "deviation": len(w.Deviation),
                   "vp": type(vp).__name__, "legend_owner": viewproviders.LEGENDS.get(doc.Name, (None,))[0] == w.Name,
                   "legend": list(viewproviders.LEGENDS.get(doc.Name, (None, None, []))[2])}
    part.ViewObject.Visibility = False
    sel.clearSelection()
    view = FreeCADGui.ActiveDocument.ActiveView
    view.viewIsometric()
    view.fitAll()
    FreeCADGui.updateGui()
    res["shot"] = os.path.join(OUT, "ruled_wall.png")
    view.saveImage(res["shot"], 1280, 1024, "White")
    # the colour legend at three window sizes: the main window grabbed as the user sees it (the navigation
    # cube included); where the legend's texts and bar lie, in the view's pixels
    from PySide import QtGui
    mw = FreeCADGui.getMainWindow()
    mw.showNormal()
    mw.move(0, 0)
    res["legend_labels"] = list(viewproviders.LEGENDS[doc.Name][2])
    res["sizes"] = []
    for width, height in ((1280, 1024), (1600, 1000), (1920, 1080)):
        mw.resize(width, height)
        for _ in range(10):
            FreeCADGui.updateGui()
        view.fitAll()
        FreeCADGui.updateGui()
        path = os.path.join(OUT, f"ruled_wall_{width}x{height}.png")
        grab_window(path)
        size = {"window": [mw.width(), mw.height()], "view": list(view.getSize()), "shot": path, "panels": {}}
        # the Fit panel (on a face of the part) and the export panel (on the wall), each on first open: its
        # whole width (size hint and the task box's frame) against the combo view's, and a picture
        for name, select, command, module in (("fit", (part, faces[0]), "Ruled_Fit", state),
                                              ("export", (w,), "Ruled_Export", exportpanel)):
            sel.clearSelection()
            sel.addSelection(*select)
            toolbar_run(command)
            for _ in range(10):
                FreeCADGui.updateGui()
            panel = module.ACTIVE
            shot = grab_window(os.path.join(OUT, f"ruled_{name}_panel_{width}x{height}.png"))
            size["panels"][name] = [panel.form.sizeHint().width() + 40, task_width(panel), shot]
            panel.reject()
        sel.clearSelection()
        res["sizes"].append(size)
    res["bars"] = [[b.metaObject().className(), b.toolTip(), b.format()] for b in mw.findChildren(QtGui.QProgressBar)
                   if b.isVisible()]
    mw.resize(1280, 1024)
    FreeCADGui.updateGui()
    # the export panel takes the wall: the G-code of 'ruled machine --wall ... --xyuv' with the same settings
    sel.addSelection(w)
    res["export_clicked"] = toolbar_run("Ruled_Export")
    ep = exportpanel.ACTIVE
    path = os.path.join(OUT, "panel_wall.ngc")
    ep.format.setCurrentIndex(ep.kinds.index("xyuv"))
    ep.path.setText(path)
    for key, val in {"Units": "mm", "ChordTol": 0.01, "Kerf": 0.15, "Side": "outside", "Planes": "", "Lead": 2.0,
                     "Feed": 100.0, "CamStep": False}.items():
        exportpanel._put(ep.widgets[key], val)
    res["export_text"] = ep.result.text()
    res["export_ok"] = ep.accept()
    res["export_exists"] = os.path.exists(path)
    # undo: the RuledWall goes, the part stays
    FreeCADGui.getMainWindow().activateWindow()
    res["undo_key"] = shortcut("Std_Undo")            # (the keyboard's Undo: Ctrl+Z)
    res["after_undo"] = sorted(o.Name for o in doc.Objects)
    res["legend_after_undo"] = doc.Name in viewproviders.LEGENDS
    # redo: the wall back, with its legend
    res["redo_key"] = shortcut("Std_Redo")
    res["after_redo"] = sorted(o.Name for o in doc.Objects)
    res["legend_after_redo"] = viewproviders.LEGENDS.get(doc.Name, (None,))[0]


run_and_exit(main, res, "wall.json")
