"""Run by tests/test_workbench_gui.py inside the FreeCAD GUI (under Xvfb): the Ruled workbench, a
face of a STEP selected, "Fit ruled surface" through its task panel, the result's properties, a
screenshot of the coloured result with its rulings, and the STEP export.  Writes result.json and the
pictures to $RULED_GUI_OUT; ends with os._exit (FreeCAD exits 0 even when a script raises)."""
import os
import sys

sys.path.insert(0, os.environ["RULED_GUI_LIB"])
from guitools import Results, click_preview, part_document, run_and_exit, task_width, toolbar_run  # noqa: E402

OUT = os.environ["RULED_GUI_OUT"]
os.makedirs(OUT, exist_ok=True)
res = Results()


def extra_checks(doc, imp, obj, res):
    """Progress during a fit, Cancel of a running fit, the colour legend, the panel's width, double-click
    to edit, and save / reopen with a clean report view."""
    import time

    import FreeCAD
    import FreeCADGui
    from PySide import QtCore, QtGui
    from ruled_workbench import state, viewproviders
    mw = FreeCADGui.getMainWindow()
    sel = FreeCADGui.Selection
    obj.ViewObject.Visibility = True
    res["legend"] = list(viewproviders.LEGENDS.get(doc.Name, (None, None, []))[2])
    owner = doc.getObject(viewproviders.LEGENDS.get(doc.Name, (None,))[0] or "")
    res["legend_hausdorff"] = float(owner.Hausdorff) if owner is not None else None
    # "Fit several faces": two blade faces and the sphere's face (refused): three objects, one invalid; at
    # quick defaults set as a user sets them (Edit > Preferences > Ruled), then the defaults again
    prefs = FreeCAD.ParamGet("User parameter:BaseApp/Preferences/Mod/Ruled/Fit")
    prefs.SetInt("Samples", 16)
    prefs.SetInt("MeasureSamples", 12)
    sel.clearSelection()
    for o, sub in ((imp, "Face7"), (imp, "Face8"), (doc.getObject("Sphere"), "Face1")):
        sel.addSelection(o, sub)
    before = {o.Name for o in doc.Objects}
    res.setdefault("toolbar", []).append(toolbar_run("Ruled_FitMany"))
    new = [o for o in doc.Objects if o.Name not in before]
    res["many"] = [[o.Source[1][0], o.isValid(), o.Status, o.Samples] for o in new]
    prefs.RemInt("Samples")
    prefs.RemInt("MeasureSamples")
    for o in new:
        doc.removeObject(o.Name)
    doc.recompute()
    # a fit of several seconds: the status bar's progress bar, read every 100 ms while it runs
    seen, same = [], []

    def poll():
        bars = [b for b in mw.findChildren(QtGui.QProgressBar) if b.isVisible()]
        seen.append(tuple((b.value(), b.maximum()) for b in bars))
        # the status bar's text and bar and the panel's bar at one instant (issue 59: one progress)
        ours = [b.value() for b in bars if b.toolTip().startswith(("Ruled is computing", "the running computation"))]
        same.append([mw.statusBar().currentMessage(), ours])
    timer = QtCore.QTimer()
    timer.timeout.connect(poll)
    timer.start(100)
    sel.clearSelection()
    sel.addSelection(imp, "Face7")
    res.setdefault("toolbar", []).append(toolbar_run("Ruled_Fit"))
    p2 = state.ACTIVE
    res["panel_width"] = [p2.form.sizeHint().width() + 40, task_width(p2)]
    p2.method.setCurrentIndex(p2.method.findText("2d"))
    res["4d_disabled_in_2d"] = not p2.elevations.isEnabled() and not p2.step.isEnabled()
    p2.method.setCurrentIndex(p2.method.findText("4d"))
    res["4d_enabled_in_4d"] = p2.elevations.isEnabled()
    p2.method.setCurrentIndex(p2.method.findText("2d"))
    res["tooltips"] = all(w.toolTip() for w in (p2.method, p2.samples, p2.objective, p2.max_error, p2.direction,
                                                  p2.elevations, p2.step, p2.metric, p2.measure, p2.preview_button))
    p2.samples.setValue(60)
    p2.measure.setValue(30)
    t0 = time.time()
    res["progress_ok"] = click_preview(p2)
    res["progress_fit_s"] = time.time() - t0
    timer.stop()
    res["progress_readings"] = sorted({v for v in seen if v})
    res["panel_progress"] = sorted(set(p2.progress_seen))
    res["progress_same"] = [x for x in same if len(x[1]) == 2 and " % (Esc stops)" in x[0]]
    p2.reject()
    # Cancel while a fit of tens of seconds runs, by real input (QTest's mouse and key events through the
    # application): meanwhile the window takes clicks (the combo view's Model tab, the tree, the 3D view),
    # each seen within a poll of 10 ms on a Qt timer (which runs only while the window processes events);
    # then Cancel (and, the second time, Esc) closes the panel, the document as it was
    from guitools import click, combo_tab, key, task_button, tree_item
    from guitools import view3d as viewer
    from ruled_workbench import viewproviders
    FreeCADGui.ActiveDocument.ActiveView.viewIsometric()
    FreeCADGui.ActiveDocument.ActiveView.fitAll()
    for how in ("cancel", "esc"):
        before = sorted(o.Name for o in doc.Objects)
        sel.clearSelection()
        sel.addSelection(imp, "Face7")
        res.setdefault("toolbar", []).append(toolbar_run("Ruled_Fit"))
        p3 = state.ACTIVE
        p3.samples.setValue(150)
        p3.measure.setValue(80)
        live = {}

        def until(name, cond, t0, live=live):
            if cond():
                live[name] = time.time() - t0
            elif time.time() - t0 > 5:
                live[name] = None
            else:
                QtCore.QTimer.singleShot(10, lambda: until(name, cond, t0))

        def model_tab(live=live):
            bar, pos = combo_tab("Model")
            t0 = time.time()
            click(bar, pos)
            until("model_tab", lambda: bar.tabText(bar.currentIndex()) == "Model", t0)

        def tree(live=live):
            vp, pos = tree_item("Impeller")
            sel.clearSelection()
            t0 = time.time()
            click(vp, pos)
            until("tree", lambda: [o.Name for o in sel.getSelection()] == ["Impeller"], t0)

        def view3d(live=live):
            vp = viewer().viewport()
            view = FreeCADGui.ActiveDocument.ActiveView
            x, y = view.getPointOnScreen(imp.Shape.BoundBox.Center)      # the impeller there selects a face
            w, h = view.getSize()
            sel.clearSelection()
            t0 = time.time()
            click(vp, QtCore.QPoint(int(x * vp.width() / w), int(vp.height() * (1 - y / h))))
            until("view", lambda: bool(sel.getSelection()), t0)

        def tasks_tab(live=live):
            bar, pos = combo_tab("Tasks")
            click(bar, pos)

        def stop(live=live, p3=p3, how=how):
            live["busy"] = p3.busy
            live["t"] = time.time()
            if how == "cancel":
                click(task_button("Cancel"))
            else:
                key(mw, QtCore.Qt.Key_Escape)
        if how == "cancel":
            # (the tree's first click after the Model tab is shown only makes its item current, idle or busy)
            model_tab()
            vp, pos = tree_item("Impeller")
            click(vp, pos)
            tasks_tab()
            sel.clearSelection()
        steps = [(1000, model_tab), (1600, tree), (2200, view3d), (2800, tasks_tab), (3400, stop)] \
            if how == "cancel" else [(2000, stop)]
        for ms, fn in steps:
            QtCore.QTimer.singleShot(ms, fn)
        t0 = time.time()
        click(p3.preview_button)                              # returns when the computation has ended
        t1 = time.time()
        for _ in range(5):
            QtGui.QApplication.processEvents()
        names = sorted(o.Name for o in doc.Objects)
        owner = viewproviders.LEGENDS.get(doc.Name, (None,))[0]
        res[how] = {"busy_at_stop": live.get("busy"), "run_s": t1 - t0,
                    "latency_s": t1 - live["t"] if "t" in live else None,
                    "objects_same": names == before, "legend_ok": owner is None or owner in names,
                    "panel_closed": state.ACTIVE is None,
                    "responses": {k: live.get(k) for k in ("model_tab", "tree", "view")}}
    # double-click on the RuledFit: its own panel, editing it
    obj.ViewObject.Proxy.doubleClicked(obj.ViewObject)
    ed = state.ACTIVE
    res["edit"] = {"opened": ed is not None and ed.editing and ed.obj.Name == obj.Name,
                   "samples": ed.samples.value() if ed else None}
    if ed is not None:
        ed.reject()
    res["edit"]["closed"] = state.ACTIVE is None
    # save, close, reopen: nothing in the report view but the usual, the objects valid, the same results
    report = [w for w in mw.findChildren(QtGui.QTextEdit) if "Report" in w.objectName()]
    bound = float(obj.ErrorBound)
    path = os.path.join(OUT, "gui.FCStd")
    doc.saveAs(path)
    name = doc.Name
    FreeCAD.closeDocument(name)
    FreeCADGui.updateGui()           # the messages so far reach the report view (they are queued) ...
    if report:
        report[0].clear()            # ... and go: only what reopening prints remains
    d2 = FreeCAD.openDocument(path)
    FreeCADGui.updateGui()
    text = report[0].toPlainText() if report else ""
    o2 = d2.getObject("RuledFit")
    o2.touch()
    d2.recompute()
    b2 = float(o2.ErrorBound)
    res["reopen"] = {"report_found": bool(report), "traceback": "Traceback" in text or "Error" in text,
                     "text": text[-1500:], "valid": [o.isValid() for o in d2.Objects if hasattr(o, "Proxy")],
                     # (a saved document's shapes differ from the STEP's in their last digits: the pinned bound
                     # of kj66 Face7 moves by 1e-14 of itself, the trimmed one, whose certificate counts the
                     # cells that meet the face, by up to 2e-6: a cell on the face's edge changes its side)
                     "same": abs(b2 - bound) <= 1e-5 * bound, "bounds": [bound, b2],
                     "proxies": sorted(type(o.Proxy).__name__ for o in d2.Objects if hasattr(o, "Proxy"))}
    shot = os.path.join(OUT, "ruled_reopen.png")
    FreeCADGui.ActiveDocument.ActiveView.saveImage(shot, 1280, 1024, "White")
    res["reopen_shot"] = shot


def main():
    import FreeCAD
    import FreeCADGui
    import Part
    doc, imp = part_document("Gui")
    from ruled_workbench import commands, state
    res["commands"] = [c for c in commands.NAMES if c in FreeCADGui.listCommands()]
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
    res.setdefault("toolbar", []).append(toolbar_run("Ruled_Fit"))
    panel = state.ACTIVE
    res["panel"] = panel is not None
    panel.samples.setValue(16)
    panel.measure.setValue(24)
    res["preview"] = click_preview(panel)
    res["panel_text"] = panel.result.text()
    FreeCADGui.updateGui()       # the report view's lines of this fit (its notes and warnings: queued till now)
    from PySide import QtGui as _QtGui
    views = [w for w in FreeCADGui.getMainWindow().findChildren(_QtGui.QTextEdit) if "Report" in w.objectName()]
    res["fit_report"] = [x for x in views[0].toPlainText().splitlines() if panel.obj.Label + ": " in x]
    # OK right after Preview keeps what Preview computed: every run writes its own time in Seconds
    fit_obj, seconds = panel.obj, panel.obj.Seconds
    res["accept"] = panel.accept()
    res["accept_reran"] = fit_obj.Seconds != seconds
    obj = doc.getObject("RuledFit")
    obj.touch()
    doc.recompute()
    res["recompute_reran"] = obj.Seconds != seconds
    res["object"] = {"valid": obj.isValid(), "status": obj.Status, "bound": float(obj.ErrorBound),
                     "hausdorff": float(obj.Hausdorff), "bound_unit": str(obj.ErrorBound.Unit),
                     "rulings": obj.Rulings, "lines": len(obj.RulingLines), "dev": len(obj.Deviation),
                     "mode": obj.ViewObject.DisplayMode, "proxy": type(obj.ViewObject.Proxy).__name__,
                     "label": obj.Label}
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
    # a face the engine cannot take (a sphere's: both boundaries collapse to its poles, and it is closed
    # across them): the panel says why
    sphere = doc.addObject("Part::Feature", "Sphere")
    sphere.Shape = Part.makeSphere(3).translate(FreeCAD.Vector(200, 0, 0))
    doc.recompute()
    sel.clearSelection()
    sel.addSelection(sphere, "Face1")
    res.setdefault("toolbar", []).append(toolbar_run("Ruled_Fit"))
    bad_panel = state.ACTIVE
    bad_panel.samples.setValue(12)
    from PySide import QtGui
    report = [w for w in FreeCADGui.getMainWindow().findChildren(QtGui.QTextEdit) if "Report" in w.objectName()]
    FreeCADGui.updateGui()
    report[0].clear()
    accepted = bad_panel.accept()
    FreeCADGui.updateGui()
    res["bad_face"] = {"accepted": accepted, "text": bad_panel.result.text(),
                       "report": [x for x in report[0].toPlainText().splitlines() if x.strip()]}
    bad_panel.reject()
    res["after_cancel"] = [o.Name for o in doc.Objects]
    # a planar face (issue 59): answered at once, exact: the panel says so, one colour, the legend 'exact'
    import time

    from ruled_workbench import viewproviders
    sel.clearSelection()
    sel.addSelection(imp, "Face4")
    toolbar_run("Ruled_Fit")
    pp = state.ACTIVE
    t0 = time.monotonic()
    ok = click_preview(pp)
    res["planar"] = {"preview": ok, "seconds": time.monotonic() - t0, "text": pp.result.text(),
                     "legend": list(viewproviders.LEGENDS.get(doc.Name, (None, None, []))[2])}
    pp.reject()
    step = os.path.join(OUT, "ruled_fit.step")
    from ruled_workbench.export import export_step
    export_step([obj], step)
    res["step_size"] = os.path.getsize(step)
    # "Split for ruling" on the same face: the panel's preview, then OK; a picture of the split curve
    sel.clearSelection()
    sel.addSelection(imp, "Face7")
    res.setdefault("toolbar", []).append(toolbar_run("Ruled_Split"))
    sp = state.ACTIVE
    sp.samples.setValue(12)
    sp.interior.setValue(4)
    sp.fit_samples.setValue(16)
    res["split_preview"] = sp.preview()
    res["split_text"] = sp.result.text()
    seconds = sp.obj.Seconds
    res["split_accept"] = sp.accept()
    res["split_accept_reran"] = doc.getObject("RuledSplit").Seconds != seconds
    so = doc.getObject("RuledSplit")
    res["split"] = {"valid": so.isValid(), "status": so.Status, "chosen": so.Chosen, "bound": float(so.ErrorBound),
                    "whole": float(so.WholeBound), "faces": len(so.Shape.Faces), "curve": len(so.SplitCurve)}
    obj.ViewObject.Visibility = False
    sel.clearSelection()
    FreeCADGui.updateGui()
    shot = os.path.join(OUT, "ruled_split.png")
    view.saveImage(shot, 1280, 1024, "White")
    res["split_shot"] = shot
    extra_checks(doc, imp, obj, res)


run_and_exit(main, res, "result.json")
