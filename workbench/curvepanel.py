"""The Curve on face task panel (GUI): a curve lying on the face, from a sketch or through points picked on the face
in the 3D view, each pick marked there and numbered; while picking, a click off the face changes nothing."""

from __future__ import annotations

import FreeCAD
import FreeCADGui
from PySide import QtGui

from . import state
from .features import value
from .names import element, is_edge, short_name
from .taskpanels import _editor, _length_box, _Panel
from .units import length


class CurveTaskPanel(_Panel):
    """A curve on the face from a sketch or from points picked on the face: with Pick points on, each
    click on the face adds a point."""

    title = "Curve on face"

    def __init__(self, source, subname: str, obj=None, sketch=None):
        from .objects import make_ruled_curve
        lay = self._open(source, lambda d, s, n: make_ruled_curve(d, s, n, sketch=sketch), subname, obj)
        o = self.obj
        self.source, self.subname = o.Source[0], (o.Source[1] or [""])[0]
        self.mapping = self._tip(QtGui.QComboBox(), "how the sketch's x, y become the face's (u, v): unit square, "
                                 "0..1 across its parameter range; parameters, x = u and y = v")
        self.mapping.addItems(["unit square", "parameters"])
        self.mapping.setCurrentIndex(self.mapping.findText(o.Mapping))
        self.mapping.setEnabled(o.Sketch is not None)
        self.tol = self._tip(_length_box("auto"), "largest distance from the exact image of the (u, v) curve (auto: "
                             "1e-5 of the face's size)")
        self.tol.setValue(value(o.Tolerance))
        self.angle = self._tip(QtGui.QDoubleSpinBox(), "largest angle between the curve's pieces at their joints")
        self.angle.setRange(0.01, 45.0)
        self.angle.setSuffix(" deg")
        self.angle.setValue(float(getattr(o.Angle, "Value", o.Angle)))
        self.pick_button = self._tip(QtGui.QPushButton("Pick points on the face"), "then click on the face in the 3D "
                                     "view: the curve runs through the points in order")
        self.pick_button.setCheckable(True)
        self.pick_button.setEnabled(o.Sketch is None)
        self.clear_button = self._tip(QtGui.QPushButton("Clear points"), "forget the picked points")
        self.points_label = QtGui.QLabel()
        self.points = [FreeCAD.Vector(p) for p in o.Points]
        self.preview_button = self._tip(QtGui.QPushButton("Preview"), "build the curve on the face")
        self.result = QtGui.QLabel("Preview builds the curve." if o.Sketch is not None else
                                   "Pick points on the face, then Preview.")
        self.result.setWordWrap(True)
        lay.addRow("Sketch mapping", self.mapping)
        lay.addRow("Tolerance", self.tol)
        lay.addRow("Joint angle", self.angle)
        lay.addRow(self.pick_button)
        lay.addRow(self.clear_button, self.points_label)
        lay.addRow(self.preview_button)
        self._progress_bar(lay)
        lay.addRow(self.result)
        self.callback = self.marks = self.role = None
        self._show_points()
        self.pick_button.toggled.connect(self._picking)
        self.clear_button.clicked.connect(self._clear)
        self.preview_button.clicked.connect(self.preview)

    def _show_points(self):
        self.points_label.setText(f"{len(self.points)} points" if self.obj.Sketch is None else "from the sketch")
        if FreeCAD.GuiUp:
            self._marks()

    def _clear(self):
        self.points = []
        self._show_points()

    def _picking(self, on: bool):
        """Picking on: every left click in the 3D view comes to _clicked, and the view's selection is off (its
        selection node would take the button's release, an edge's or another face's included)."""
        from pivy import coin
        view = FreeCADGui.ActiveDocument.ActiveView
        role = view.getSceneGraph().getField("selectionRole")
        if on and self.callback is None:
            self.callback = view.addEventCallbackPivy(coin.SoMouseButtonEvent.getClassTypeId(), self._clicked)
            self.role = str(role.get()).strip() if role is not None else None
            if role is not None:
                role.set("FALSE")
        elif not on and self.callback is not None:
            view.removeEventCallbackPivy(coin.SoMouseButtonEvent.getClassTypeId(), self.callback)
            self.callback = None
            if role is not None and self.role is not None:
                role.set(self.role)

    def _clicked(self, cb):
        """While picking, every left click is the panel's (the selection never changes): on the face, a point;
        elsewhere (an edge alone, another face, the background), nothing but a word in the status bar."""
        from pivy import coin
        ev = cb.getEvent()
        if ev.getButton() != coin.SoMouseButtonEvent.BUTTON1:
            return
        cb.setHandled()
        if ev.getState() == coin.SoMouseButtonEvent.DOWN and not self.pick(tuple(ev.getPosition().getValue())):
            FreeCADGui.getMainWindow().statusBar().showMessage(
                f"Curve on face: not on {self.source.Label}'s {self.subname}; click on the face itself", 4000)

    def pick(self, pos) -> bool:
        """Add the point of the source face under the view position pos (pixels, from the lower left), also
        where its edges are drawn over it (a thin face shows little but its edges until zoomed in); a click on
        one of the face's own edges alone snaps onto the face (its nearest point)."""
        hits = FreeCADGui.ActiveDocument.ActiveView.getObjectsInfo((int(pos[0]), int(pos[1]))) or []
        mine = [h for h in hits if h.get("Object") == self.source.Name]
        info = next((h for h in mine if short_name(h.get("Component", "")) == short_name(self.subname)), None)
        face = element(self.source.Shape, self.subname)
        if info is not None:
            point = FreeCAD.Vector(info["x"], info["y"], info["z"])
        else:
            edges = [h for h in mine if is_edge(h.get("Component", ""))
                     and any(e.isSame(element(self.source.Shape, h["Component"])) for e in face.Edges)]
            if not edges:
                return False
            import Part
            point = face.distToShape(Part.Vertex(edges[0]["x"], edges[0]["y"], edges[0]["z"]))[1][0][0]
        self.points.append(point)
        self._show_points()
        return True

    def _marks(self, keep: bool = True) -> None:
        """A marker at each picked point in the 3D view, numbered in order (replaced whenever the points change,
        removed with the panel)."""
        from pivy import coin
        view = FreeCADGui.ActiveDocument.ActiveView
        if self.marks is not None:
            view.getSceneGraph().removeChild(self.marks)
            self.marks = None
        if not keep or not self.points or self.obj.Sketch is not None:
            return
        self.marks = coin.SoAnnotation()        # (over the face: no depth test)
        col = coin.SoBaseColor()
        col.rgb = (0.9, 0.1, 0.1)
        coords = coin.SoCoordinate3()
        coords.point.setValues(0, len(self.points), [tuple(p) for p in self.points])
        marker = coin.SoMarkerSet()
        marker.markerIndex = getattr(coin.SoMarkerSet, "CIRCLE_FILLED_9_9", 0)
        for node in (col, coords, marker):
            self.marks.addChild(node)
        for k, p in enumerate(self.points):
            sep, tr, text = coin.SoSeparator(), coin.SoTranslation(), coin.SoText2()
            tr.translation = tuple(p)
            text.string = f"  {k + 1}"
            for node in (tr, text):
                sep.addChild(node)
            self.marks.addChild(sep)
        view.getSceneGraph().addChild(self.marks)

    def _apply(self):
        self._set(self.obj, Mapping=self.mapping.currentText(), Tolerance=self.tol.value(),
                  Angle=self.angle.value())
        if [tuple(p) for p in self.obj.Points] != [tuple(p) for p in self.points]:
            self.obj.Points = self.points

    def _leave(self):
        self._picking(False)
        self._marks(keep=False)         # (the markers go with the panel)
        super()._leave()

    def describe(self, o) -> str:
        return (f"{o.Segments} pieces, certified within {length(o.ErrorBound)} of the exact image; measured: "
                f"{length(o.Hausdorff)} from it, {length(o.OnFace)} from the face.")

    verb = "build the curve"


state.PANELS["RuledCurveOnFace"] = _editor(CurveTaskPanel)

__all__ = ["CurveTaskPanel"]
