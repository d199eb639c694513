"""The task panel of "Fit wall": the wall fit's parameters (method, samples per face, objective, one piece per
face, measure samples), Preview and OK / Cancel inside one undo transaction, as the Fit panel; and, where the
selected faces are not one side wall, the panel that says so in one line and makes no object."""

from __future__ import annotations

import FreeCAD
import FreeCADGui
from PySide import QtGui

from . import state
from .names import element, short_name
from .qtcompat import standard_buttons
from .taskpanels import _Panel
from .units import length


class WallTaskPanel(_Panel):
    title = "Fit wall"
    verb = "fit the wall"

    def __init__(self, source, subnames: list, obj=None):
        from .walls import make_ruled_wall
        lay = self._open(source, make_ruled_wall, list(subnames), obj)
        tip = self._tip
        self.method = tip(QtGui.QComboBox(), "2d: rulings between samples of the bottom and top contours (Elber); "
                          "4d: their ends also lifted along the normal (Wang & Elber)")
        self.method.addItems(["2d", "4d"])
        self.samples = tip(QtGui.QSpinBox(), "samples per face along each contour (more: a finer optimum, slower)")
        self.samples.setRange(3, 2000)
        self.samples.setValue(40)
        self.objective = tip(QtGui.QComboBox(), "sum: the least total distance of the rulings to the wall "
                             "(Elber); max: the least largest one")
        self.objective.addItems(["sum", "max"])
        self.per_face = tip(QtGui.QCheckBox("one piece per face"), "the closed ruled surface cut along the faces' "
                            "joints into one piece per face of the wall, sewn into one shell")
        self.measure = tip(QtGui.QSpinBox(), "n x n samples per face for the measured Hausdorff distance and the "
                           "colours (0: do not measure)")
        self.measure.setRange(0, 400)
        self.measure.setValue(16)
        self.preview_button = tip(QtGui.QPushButton("Preview"), "fit the wall with these parameters and show the "
                                  "result (Cancel stops a fit that runs)")
        self.result = QtGui.QLabel(f"{len(subnames)} faces of {source.Label}: Preview fits them as one closed ruled "
                                   f"surface.")
        self.result.setWordWrap(True)
        self._rows(lay, (("Method", self.method), ("Samples per face", self.samples), ("Objective", self.objective),
                         ("Measure samples", self.measure)), self.per_face)
        if self.editing:
            o = self.obj
            self.method.setCurrentIndex(self.method.findText(o.Method))
            self.samples.setValue(o.Samples)
            self.objective.setCurrentIndex(self.objective.findText(o.Objective))
            self.measure.setValue(o.MeasureSamples)
            self.per_face.setChecked(bool(o.PerFace))
        self.preview_button.clicked.connect(self.preview)

    def _apply(self):
        self._set(self.obj, Method=self.method.currentText(), Samples=self.samples.value(),
                  Objective=self.objective.currentText(), MeasureSamples=self.measure.value(),
                  PerFace=self.per_face.isChecked())

    def describe(self, o) -> str:
        pieces = "one periodic fit" if o.Pieces == 1 else f"{o.Pieces} pieces between its corners"
        each = ", one piece per face" if o.PerFace else ""
        return (f"{len(o.Faces)} faces as one closed ruled surface ({pieces}{each}): certified bound "
                f"{length(o.ErrorBound)}, measured Hausdorff {length(o.Hausdorff)}.")


class WallRefusal:
    """The Fit wall panel where the selection is no side wall: the reason in one line, no object, Close."""

    def __init__(self, why: str):
        global REFUSED
        self.form = QtGui.QWidget()
        self.form.setWindowTitle("Fit wall")
        lay = QtGui.QVBoxLayout(self.form)
        self.message = QtGui.QLabel(f"Cannot fit a wall: {why}")
        self.message.setWordWrap(True)
        lay.addWidget(self.message)
        REFUSED = self
        FreeCAD.Console.PrintWarning(f"Ruled: Fit wall: {why}\n")

    def getStandardButtons(self):
        return standard_buttons("Close")

    def reject(self):
        global REFUSED
        FreeCADGui.Control.closeDialog()
        REFUSED = None
        return True

    accept = reject


REFUSED = None      # the open refusal (for scripts and tests)


def _edit_wall(obj):
    source, subs = obj.Source
    return WallTaskPanel(source, list(subs or []), obj=obj)


state.PANELS["RuledWall"] = _edit_wall


def wall_refusal(part, subnames: list):
    """Why the faces subnames of part are no side wall (their ring: the topology, read at once), in this
    workbench's words (None: they are one)."""
    from ruled.core.errors import BadInputError

    from .adapter import ring_order
    from .features import in_our_terms
    try:
        ring_order([element(part.Shape, s) for s in subnames], [short_name(s) for s in subnames])
    except BadInputError as exc:
        return in_our_terms(exc)
    return None


__all__ = ["WallTaskPanel", "WallRefusal", "wall_refusal"]
