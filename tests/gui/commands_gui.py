"""Run by tests/test_workbench_gui.py inside the FreeCAD GUI (under Xvfb): "Fit to tolerance", "Cone
spline" and "Curve on face" from their toolbar entries through their task panels on faces of kj66 (and
a cone), undo, the export panel writing G-code, APT and a STEP for CAM, the preferences page; with
RULED_GUI_PHASE=restart, a second start that reads back what the export panel remembered.  Writes
commands.json (restart.json) and pictures to $RULED_GUI_OUT; ends with os._exit."""
import json
import math
import os
import sys

sys.path.insert(0, os.environ["RULED_GUI_LIB"])
from guitools import Results, click_view, part_document, run_and_exit, settle, shortcut, toolbar_run  # noqa: E402

OUT = os.environ["RULED_GUI_OUT"]
PHASE = os.environ.get("RULED_GUI_PHASE", "main")
os.makedirs(OUT, exist_ok=True)
res = Results()


def panel_width(mw, panel):
    """[the panel's whole width (its size hint and the task box's frame), the combo view's width]."""
    import FreeCADGui
    from guitools import task_width
    FreeCADGui.updateGui()
    return [panel.form.sizeHint().width() + 40, task_width(panel)]


def shoot(name, obj=None):
    import FreeCADGui
    view = FreeCADGui.ActiveDocument.ActiveView
    if obj is not None:
        FreeCADGui.Selection.clearSelection()
        FreeCADGui.Selection.addSelection(obj)
        FreeCADGui.SendMsgToActiveView("ViewSelection")
        FreeCADGui.Selection.clearSelection()
    FreeCADGui.updateGui()
    path = os.path.join(OUT, name)
    view.saveImage(path, 1280, 1024, "White")
    return path


def _said(mw, start: str) -> str:
    """The report view's last line with `start` in it (what a panel printed there)."""
    import FreeCADGui
    from PySide import QtGui
    for _ in range(3):
        FreeCADGui.updateGui()
    lines = [ln for w in mw.findChildren(QtGui.QTextEdit) if "Report" in w.objectName()
             for ln in w.toPlainText().splitlines() if start in ln]
    return lines[-1] if lines else ""


def grab(widget, name):
    import FreeCADGui
    for _ in range(3):
        FreeCADGui.updateGui()
    path = os.path.join(OUT, name)
    widget.grab().save(path)
    return path


def only(doc, *visible):
    for o in doc.Objects:
        if hasattr(o, "ViewObject") and o.ViewObject is not None:
            o.ViewObject.Visibility = o in visible


def face_on(view, face):
    u0, u1, v0, v1 = face.ParameterRange
    n = face.normalAt(0.5 * (u0 + u1), 0.5 * (v0 + v1))
    view.setViewDirection((-n.x, -n.y, -n.z))
    settle()


def main():
    import FreeCAD
    import FreeCADGui
    import Part
    from PySide import QtGui
    doc, imp = part_document("Cmds")
    from ruled_workbench import commands, exportpanel, state
    from ruled_workbench.features import make_ruled_fit, value
    mw = FreeCADGui.getMainWindow()
    res["commands"] = [c for c in commands.NAMES if c in FreeCADGui.listCommands()]
    sel = FreeCADGui.Selection
    view = FreeCADGui.ActiveDocument.ActiveView
    imp.ViewObject.Transparency = 70
    face7 = imp.Shape.getElement("Face7")

    # Fit to tolerance: one strip's bound first, then a tolerance below it
    sel.clearSelection()
    sel.addSelection(imp, "Face7")
    res["partition_toolbar"] = toolbar_run("Ruled_Partition")
    p = state.ACTIVE
    res["widths"] = [panel_width(mw, p)]
    p.samples.setValue(10)
    p.interior.setValue(4)
    p.fit_samples.setValue(16)
    p.measure.setValue(10)
    p.tol.setValue(1000.0)
    p.preview()
    whole = value(p.obj.ErrorBound)
    p.tol.setValue(round(0.8 * whole, 4))
    ok = p.preview()
    seconds = p.obj.Seconds
    res["partition_text"] = p.result.text()
    o = p.obj
    res["partition_accept"] = ok and p.accept()
    res["partition"] = {"whole": whole, "tol": value(o.Tolerance), "strips": o.Strips, "bound": value(o.ErrorBound),
                        "hausdorff": value(o.Hausdorff), "bounds": list(o.StripBounds), "valid": o.isValid(),
                        "status": o.Status, "reran": o.Seconds != seconds, "dev": len(o.Deviation),
                        "faces": len(o.Shape.Faces), "vp": type(o.ViewObject.Proxy).__name__,
                        "legend": o.Name == __import__("ruled_workbench.viewproviders", fromlist=["x"]).LEGENDS.get(
                            doc.Name, [None])[0]}
    name = o.Name
    only(doc, o)
    face_on(view, face7)
    res["partition_shot"] = shoot("ruled_partition.png", o)
    n = len(doc.Objects)
    shortcut("Std_Undo")          # the keyboard's Undo and Redo, for real
    res["partition_undo"] = [len(doc.Objects) == n - 1, doc.getObject(name) is None]
    shortcut("Std_Redo")
    res["partition_undo"].append(doc.getObject(name) is not None)

    # Cone spline of a cone's face, through the panel
    cone = doc.addObject("Part::Feature", "Cone")
    cone.Shape = Part.makeCone(10, 6, 8).translate(FreeCAD.Vector(150, 0, 0))
    doc.recompute()
    sel.clearSelection()
    sel.addSelection(cone, "Face1")
    res["cone_toolbar"] = toolbar_run("Ruled_Cone")
    c = state.ACTIVE
    res["widths"].append(panel_width(mw, c))
    c.tol.setValue(0.001)
    c.measure.setValue(8)
    res["cone_fit_first_enabled"] = c.fit_first.isEnabled()
    res["cone_preview"] = c.preview()
    res["cone_text"] = c.result.text()
    co = c.obj
    res["cone_accept"] = c.accept()
    res["cone"] = {"valid": co.isValid(), "status": co.Status, "patches": co.Patches, "developable": co.Developable,
                   "bound": value(co.ErrorBound), "hausdorff": value(co.Hausdorff), "faces": len(co.Shape.Faces)}
    only(doc, co)
    view.viewIsometric()
    res["cone_shot"] = shoot("ruled_cone.png", co)
    # ... and of a RuledFit of the blade face (kj66's blades twist: the reason, one line, if refused)
    fit = make_ruled_fit(doc, imp, "Face7", Samples=16, MeasureSamples=8)
    doc.recompute()
    sel.clearSelection()
    sel.addSelection(fit)
    toolbar_run("Ruled_Cone")
    c2 = state.ACTIVE
    res["cone_of_fit_fit_first_enabled"] = c2.fit_first.isEnabled()
    c2.tol.setValue(0.05)
    c2.measure.setValue(6)
    c2.preview()
    res["cone_of_fit"] = {"valid": c2.obj.isValid(), "status": c2.obj.Status, "text": c2.result.text(),
                          "fit_bound": value(c2.obj.FitBound), "fit": value(fit.ErrorBound)}
    c2.reject()

    # Replace in part: the fit's result sewn into the impeller in place of Face7 (a parametric copy)
    sel.clearSelection()
    sel.addSelection(fit)
    before_replace = len(doc.Objects)
    res["replace_toolbar"] = toolbar_run("Ruled_Replace")
    rp = [o for o in doc.Objects if type(getattr(o, "Proxy", None)).__name__ == "RuledReplace"]
    if rp:
        r0 = rp[0]
        area = fit.Shape.Area
        ruled = [f for f in r0.Shape.Faces if f.Surface.TypeId == "Part::GeomBSplineSurface"
                 and 1 in (f.Surface.UDegree, f.Surface.VDegree) and abs(f.Area - area) <= 1e-3 * area]
        res["replace"] = {"objects": len(doc.Objects) - before_replace, "valid": r0.isValid(), "status": r0.Status,
                          "closed": r0.ClosedSolid, "shape_valid": r0.Shape.isValid(), "faces": len(r0.Shape.Faces),
                          "source_faces": len(imp.Shape.Faces), "solids": len(r0.Shape.Solids),
                          "source_solids": len(imp.Shape.Solids),
                          "all_closed": all(x.isClosed() and x.isValid() for x in r0.Shape.Solids),
                          "volume": r0.Shape.Volume, "source_volume": imp.Shape.Volume,
                          "tol": value(r0.EdgeTolerance), "bound": value(fit.ErrorBound), "ruled_faces": len(ruled),
                          "label": r0.Label, "hidden": [not imp.ViewObject.Visibility, not fit.ViewObject.Visibility],
                          "state": list(r0.State)}
        shown = {o.Name: o.ViewObject.Visibility for o in doc.Objects if getattr(o, "ViewObject", None)}
        only(doc, r0)
        face_on(view, face7)
        res["replace_shot"] = shoot("ruled_replace.png", r0)
        for o in doc.Objects:
            if o.Name in shown:
                o.ViewObject.Visibility = shown[o.Name]
        r0.ViewObject.Visibility = False
        imp.ViewObject.Visibility = True
    else:
        res["replace"] = None

    # Curve on face from a sketch: a line and an arc in the unit square of the face's parameter range, where
    # the (trimmed) face is
    u0, u1, v0, v1 = face7.ParameterRange

    def inside(a, b):
        return face7.isPartOfDomain(u0 + a * (u1 - u0), v0 + b * (v1 - v0))
    grid = [(i / 20, j / 20) for i in range(1, 20) for j in range(1, 20) if inside(i / 20, j / 20)]
    a0, b0 = grid[0]
    a1, b1 = max(grid, key=lambda g: (g[0] - a0) ** 2 + (g[1] - b0) ** 2 if all(
        inside(a0 + t * (g[0] - a0), b0 + t * (g[1] - b0)) for t in [x / 40 for x in range(41)]) else -1)
    r = 0.01
    ac, bc = max(grid, key=lambda g: sum(inside(g[0] + 2 * r * da, g[1] + 2 * r * db) for da in (-1, 0, 1)
                                         for db in (-1, 0, 1)))      # a point well inside
    sk = doc.addObject("Sketcher::SketchObject", "Sketch")
    sk.addGeometry(Part.LineSegment(FreeCAD.Vector(a0, b0, 0), FreeCAD.Vector(a1, b1, 0)))
    sk.addGeometry(Part.ArcOfCircle(Part.Circle(FreeCAD.Vector(ac, bc, 0), FreeCAD.Vector(0, 0, 1), r), 0.3, 2.8))
    res["sketch"] = {"line": [a0, b0, a1, b1], "arc": [ac, bc, r], "centre_inside": inside(ac, bc)}
    doc.recompute()
    sel.clearSelection()
    sel.addSelection(imp, "Face7")
    sel.addSelection(sk)
    res["curve_toolbar"] = toolbar_run("Ruled_Curve")
    k = state.ACTIVE
    res["widths"].append(panel_width(mw, k))
    k.tol.setValue(0.001)
    res["curve_pick_enabled_with_sketch"] = k.pick_button.isEnabled()
    res["curve_preview"] = k.preview()
    res["curve_text"] = k.result.text()
    ko = k.obj
    k.accept()
    res["curve"] = {"valid": ko.isValid(), "status": ko.Status, "edges": len(ko.Shape.Edges),
                    "bound": value(ko.ErrorBound), "hausdorff": value(ko.Hausdorff), "on": value(ko.OnFace),
                    "on_face": max(face7.distToShape(Part.Vertex(q))[0] for e in ko.Shape.Edges
                                   for q in e.discretize(Number=40))}
    # ... and through points picked on the face in the 3D view (the blade face on its own: in the part,
    # the other blades hide it)
    blade = doc.addObject("Part::Feature", "Blade")
    blade.Shape = face7.copy()
    doc.recompute()
    only(doc, blade)
    face_on(view, face7)
    sel.clearSelection()
    sel.addSelection(blade, "Face1")
    FreeCADGui.SendMsgToActiveView("ViewSelection")
    sel.clearSelection()
    sel.addSelection(blade, "Face1")
    toolbar_run("Ruled_Curve")
    k2 = state.ACTIVE
    k2.pick_button.setChecked(True)
    FreeCADGui.updateGui()
    along = sorted(grid, key=lambda g: g[1])         # along the blade, one way
    spread = along[::max(1, len(along) // 6)]
    inside = [(u0 + a * (u1 - u0), v0 + b * (v1 - v0)) for a, b in spread]
    picked, targets = [], []
    for uv in inside[:6]:          # real clicks on the view (issue 59)
        q = face7.valueAt(*uv)
        before = len(k2.points)
        click_view(view, view.getPointOnScreen(q))
        if len(k2.points) > before:
            picked.append(list(view.getPointOnScreen(q)))
            targets.append(tuple(q))
    res["picked"] = picked
    res["pick_selection"] = [(s.ObjectName, list(s.SubElementNames)) for s in sel.getSelectionEx()]
    width, height = view.getSize()
    n = len(k2.points)
    click_view(view, (3, height - 3))           # the background, in a corner: no point, a word, no selection
    res["background_click"] = {"points": len(k2.points) - n, "status": mw.statusBar().currentMessage(),
                               "selection": [s.ObjectName for s in sel.getSelectionEx()]}
    # each pick marked in the 3D view, numbered (issue 59): as many markers as points
    res["pick_marks"] = {"marks": k2.marks.getChild(1).point.getNum() if k2.marks is not None else 0,
                         "points": len(k2.points), "shot": shoot("ruled_curve_picks.png")}
    # seen edge-on, a face shows as little more than its edges: a click there takes the face under them
    fu0, fu1, fv0, fv1 = face7.ParameterRange
    mid = face7.valueAt(0.5 * (fu0 + fu1), 0.5 * (fv0 + fv1))
    du = face7.Surface.getDN(0.5 * (fu0 + fu1), 0.5 * (fv0 + fv1), 1, 0)
    view.setViewDirection((du.x, du.y, du.z))
    settle()
    n = len(k2.points)
    sel.clearSelection()
    click_view(view, view.getPointOnScreen(mid))
    taken = len(k2.points) > n
    res["edge_pick"] = {"taken": taken, "on_face": face7.distToShape(Part.Vertex(k2.points[-1]))[0]
                        if taken else None, "selection": [s.ObjectName for s in sel.getSelectionEx()]}
    if taken:
        k2.points.pop()
    face_on(view, face7)
    FreeCADGui.updateGui()
    # a click on one of the face's edges, face on: snapped onto the face, the selection unchanged
    n = len(k2.points)
    rim = blade.Shape.Edges[0]
    click_view(view, view.getPointOnScreen(rim.valueAt(sum(rim.ParameterRange) / 2)))
    taken = len(k2.points) > n
    res["rim_pick"] = {"taken": taken, "on_face": face7.distToShape(Part.Vertex(k2.points[-1]))[0]
                       if taken else None, "selection": [s.ObjectName for s in sel.getSelectionEx()]}
    if taken:
        k2.points.pop()
    k2.tol.setValue(0.001)
    res["points_preview"] = k2.preview()
    ko2 = k2.obj
    k2.accept()
    def turn_at(edge, p):
        """The angle (degrees) between the edge's tangents just before and just after its point nearest p."""
        t = edge.Curve.parameter(p)
        a, b = edge.ParameterRange
        h = 1e-6 * (b - a)
        t1, t2 = edge.tangentAt(max(a, t - h)), edge.tangentAt(min(b, t + h))
        return math.degrees(t1.getAngle(t2))
    res["points"] = {"valid": ko2.isValid(), "status": ko2.Status, "n": len(ko2.Points),
                     "bound": value(ko2.ErrorBound), "hausdorff": value(ko2.Hausdorff),
                     "angle": float(ko2.Angle), "turns": [turn_at(ko2.Shape.Edges[0], p) for p in ko2.Points]
                     if ko2.Shape.Edges else None,
                     "near_targets": max((ko2.Shape.distToShape(Part.Vertex(FreeCAD.Vector(*t)))[0] for t in targets),
                                         default=None),
                     "on_face": max(face7.distToShape(Part.Vertex(q))[0] for q in ko2.Shape.Edges[0].discretize(
                         Number=40)) if ko2.Shape.Edges else None}
    only(doc, blade, ko, ko2)
    blade.ViewObject.Transparency = 50
    sel.clearSelection()
    res["curve_shot"] = shoot("ruled_curve.png")

    # Export for machining of a fit trimmed by its face's edges along an axis a ruling of it nearly lies across
    # (and none of its pinned fit's): the panel writes the pinned fit's path and stays open, saying so with
    # both figures (issue 55)
    fb = make_ruled_fit(doc, imp, "Face9", MeasureSamples=0)
    doc.recompute()
    sel.clearSelection()
    sel.addSelection(fb)
    toolbar_run("Ruled_Export")
    ep = exportpanel.ACTIVE
    ep.format.setCurrentIndex(ep.kinds.index("xyuv"))
    ep.path.setText(os.path.join(OUT, "fallback.ngc"))
    exportpanel._put(ep.widgets["Axis"], "0.3864, -0.7174, 0.5798")
    accepted = ep.accept()
    FreeCADGui.updateGui()
    res["fallback"] = {"ok": accepted, "text": ep.result.text(), "open": exportpanel.ACTIVE is ep,
                       "exists": os.path.exists(os.path.join(OUT, "fallback.ngc")), "bound": value(fb.ErrorBound),
                       "shot": grab(mw, "ruled_export_fallback.png")}
    ep.reject()
    doc.removeObject(fb.Name)       # (the reopened document's figures are compared below for the others)
    # Export for machining: one panel, the files the command line writes with the same settings
    mfit = make_ruled_fit(doc, imp, "Face7", MeasureSamples=0)      # the defaults: 2d, 40 samples
    doc.recompute()
    # STEP still chosen, the file named wall.ngc: the format follows the extension (said in the panel), and the
    # panel's Write (a real click) shows the cut's figures, the panel open
    from guitools import click
    sel.clearSelection()
    sel.addSelection(mfit)
    toolbar_run("Ruled_Export")
    ep = exportpanel.ACTIVE
    ep.format.setCurrentIndex(ep.kinds.index("step"))
    ngc = os.path.join(OUT, "panel_as_wire.ngc")
    ep.path.setText(ngc)
    for key, val in {"Axis": "", "Units": "mm", "ChordTol": 0.01, "Kerf": 0.0, "Side": "outside", "Planes": "",
                     "Lead": 2.0, "Feed": 50.0, "CamStep": False}.items():
        exportpanel._put(ep.widgets[key], val)
    click(ep.write_button)
    for _ in range(5):
        FreeCADGui.updateGui()
    with open(ngc) as fh:
        head = fh.read(200)
    res["export_by_extension"] = {"kind": ep.kind(), "text": ep.result.text(), "open": exportpanel.ACTIVE is ep,
                                  "gcode": "ruled XYUV wire path" in head.splitlines()[0],
                                  "shot": grab(mw, "ruled_export_figures.png")}
    with open(os.path.join(OUT, "panel_as_wire.json")) as fh:
        res["export_by_extension"]["cut"] = json.load(fh).get("cut")
    ep.reject()
    exports = {}
    from guitools import choose
    for fmt, path, settings in (
            ("xyuv", os.path.join(OUT, "panel_wire.gcode"), {"Axis": "", "Units": "inch", "ChordTol": 0.01,
                                                        "Kerf": 0.1, "Side": "outside", "Planes": "", "Lead": 2.0,
                                                        "Feed": 50.0, "CamStep": True, "WirePower": 800.0,
                                                        "Dwell": 1.5, "Letters": "", "PostFile": "",
                                                        "Compensation": ""}),
            ("flank", os.path.join(OUT, "panel_mill.apt"), {"Units": "mm", "ChordTol": 0.01, "ToolRadius": 3.0,
                                                       "Taper": 5.0, "Feed": 80.0, "CamStep": False,
                                                       "CornerRadius": 0.5})):
        sel.clearSelection()
        sel.addSelection(mfit)
        toolbar_run("Ruled_Export")
        ep = exportpanel.ACTIVE
        ep.format.setCurrentIndex(ep.kinds.index(fmt))
        if fmt == "xyuv":       # the post and its settings by real clicks (issue 71): the post list, feed mode, home
            res["post_list"] = [ep.widgets["Post"].itemText(i) for i in range(ep.widgets["Post"].count())]
            res["post_chosen"] = choose(ep.widgets["Post"], "grbl") and choose(ep.widgets["FeedMode"], "g94")
            from PySide import QtCore
            home = ep.widgets["Home"]               # (a click on its box: the widget is wider than the box)
            for _ in range(2 if home.isChecked() else 1):
                click(home, QtCore.QPoint(8, home.height() // 2))
            res["home_clicked"] = home.isChecked()
            res["suffix_follows_post"] = ep.path.text().endswith(".gcode")
        ep.path.setText(path)
        for key, val in settings.items():
            exportpanel._put(ep.widgets[key], val)
        enabled = {key: w.isEnabled() for key, w in ep.widgets.items()}
        res.setdefault("export_width", panel_width(mw, ep))
        tips = all(w.toolTip() for w in ep.widgets.values()) and bool(ep.format.toolTip())
        shot = grab(mw, f"ruled_export_{fmt}.png")
        text = ep.result.text()
        ok = ep.accept()
        exports[fmt] = {"ok": ok, "text": ep.result.text() if not ok else text, "enabled": enabled, "tooltips": tips,
                        "shot": shot, "said": _said(mw, f"Ruled: Wrote {os.path.basename(path)}"),
                        "exists": os.path.exists(path), "closed": exportpanel.ACTIVE is None}
    res["export"] = exports
    # Replay of the panel's file against Face7 (issue 71): the wire drawn beside the blade, coloured by its cut
    commands.CHOOSE_FILE = lambda: os.path.join(OUT, "panel_wire.gcode")
    sel.clearSelection()
    sel.addSelection(imp, "Face7")
    res["replay_toolbar"] = toolbar_run("Ruled_Replay")
    rp = [o for o in doc.Objects if type(getattr(o, "Proxy", None)).__name__ == "RuledReplay"]
    if rp:
        ro = rp[0]
        only(doc, imp, ro)
        imp.ViewObject.Transparency = 60
        res["replay"] = {"valid": ro.isValid(), "status": ro.Status, "lines": len(ro.Shape.Edges),
                         "moves": ro.Moves, "overcut": value(ro.Overcut), "undercut": value(ro.Undercut),
                         "reader": ro.Reader, "colours": len(set(map(tuple, ro.ViewObject.LineColorArray))),
                         "label": ro.Label}
        res["replay_shot"] = shoot("ruled_replay.png", ro)
        imp.ViewObject.Transparency = 0
        doc.removeObject(ro.Name)           # (the reopened document's figures are compared below for the others)
    # what the panel wrote follows the object's own fit (issue 55): its report's fit figure is the object's
    with open(os.path.join(OUT, "panel_wire.json")) as fh:
        res["export_fit"] = {"report": json.load(fh)["fit"]["error_bound"], "object": value(mfit.ErrorBound),
                             "ends": mfit.EndsUsed}
    res["remembered"] = exportpanel.load_settings()
    page = exportpanel.PreferencesPage()
    page.loadSettings()
    page.form.resize(520, 640)
    res["prefs"] = {"shot": grab(page.form, "ruled_preferences.png"),
                    "values": {k: exportpanel._get(w) for k, w in page.widgets.items()},
                    "fit": {k: w.value() for k, w in page.fit.items()}}
    page.fit["Samples"].setValue(30)
    page.saveSettings()
    late = make_ruled_fit(doc, imp, "Face8")
    res["fit_default_after_prefs"] = late.Samples
    doc.removeObject(late.Name)           # never computed: the reopened document recomputes what was
    # save, close, reopen in the GUI: nothing in the report view, every Ruled object valid, the same results
    report = [w for w in mw.findChildren(QtGui.QTextEdit) if "Report" in w.objectName()]
    ruled = [o for o in doc.Objects if hasattr(o, "ErrorBound") and o.isValid() and o.Status == "ok"]
    before = {o.Name: value(o.ErrorBound) for o in ruled}
    path = os.path.join(OUT, "commands.FCStd")
    imp.ViewObject.Visibility = False        # as Replace in part left it (issue 59: visible again after reopen)
    shown = {o.Name: o.ViewObject.Visibility for o in doc.Objects if getattr(o, "ViewObject", None) is not None}
    doc.saveAs(path)
    FreeCAD.closeDocument(doc.Name)
    FreeCADGui.updateGui()
    if report:
        report[0].clear()
    d2 = FreeCAD.openDocument(path)
    FreeCADGui.updateGui()
    text = report[0].toPlainText() if report else ""
    objs = [d2.getObject(n) for n in before]
    reopened = {o.Name: o.ViewObject.Visibility for o in d2.Objects if getattr(o, "ViewObject", None) is not None}
    for o in objs:
        o.touch()
    d2.recompute()
    FreeCADGui.updateGui()
    res["visibility"] = {"saved": shown, "reopened": reopened, "recomputed": {
        o.Name: o.ViewObject.Visibility for o in d2.Objects if getattr(o, "ViewObject", None) is not None}}
    res["reopen"] = {"text": text[-1500:], "clean": bool(report) and "Traceback" not in text and "Error" not in text,
                     "valid": [o.isValid() for o in objs],
                     # (within 1e-5: a trimmed result's bound moves by up to 2e-6 of itself with the last digits
                     # of a saved document's shapes; see fit_face_gui.py)
                     "same": all(abs(value(o.ErrorBound) - before[o.Name]) <= 1e-5 * max(before[o.Name], 1e-12)
                                 for o in objs),
                     "bounds": {o.Label: [before[o.Name], value(o.ErrorBound)] for o in objs},
                     "kinds": sorted({type(o.Proxy).__name__ for o in objs}),
                     "view_providers": sorted({type(o.ViewObject.Proxy).__name__ for o in objs})}


def restart():
    import FreeCADGui
    FreeCADGui.activateWorkbench("RuledWorkbench")
    from ruled_workbench import exportpanel
    ep = exportpanel.ExportTaskPanel([])
    res["values"] = ep.values()
    page = exportpanel.PreferencesPage()
    page.loadSettings()
    res["fit_samples"] = page.fit["Samples"].value()


run_and_exit(main if PHASE == "main" else restart, res, "commands.json" if PHASE == "main" else "restart.json")
