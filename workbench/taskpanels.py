"""Task panels of "Fit ruled surface" (the fit parameters, Preview: recompute and show the rulings and
the coloured deviation) and "Split for ruling" (the split DP's parameters, Preview: the split curve on
the face and the two ruled fits), OK / Cancel inside one undo transaction."""

from __future__ import annotations

import FreeCAD
import FreeCADGui
from PySide import QtGui

from .features import make_ruled_fit, make_ruled_split

ACTIVE = None            # the open panel (for scripts and tests)


class _Panel:
    """One parametric object made inside an undo transaction: Preview recomputes it, OK keeps it (or
    stays open with the message), Cancel removes it."""

    title = ""

    def _open(self, source, make, subname):
        global ACTIVE
        self.doc = source.Document
        self.doc.openTransaction(self.title)
        self.obj = make(self.doc, source, subname)
        self.form = QtGui.QWidget()
        self.form.setWindowTitle(self.title)
        ACTIVE = self
        return QtGui.QFormLayout(self.form)

    def _recompute(self) -> bool:
        """Recompute with the panel's values, unless nothing changed since the last recompute (OK right
        after Preview keeps what Preview computed)."""
        self._apply()
        if getattr(self, "_done", False) and "Touched" not in self.obj.State:
            return True
        self.obj.touch()
        self.doc.recompute()
        self._done = self.obj.isValid() and self.obj.Status == "ok"
        return self._done

    @staticmethod
    def _set(obj, **values):
        """Set the properties that differ (setting one touches the object, even to the same value)."""
        for name, value in values.items():
            if getattr(obj, name) != value:
                setattr(obj, name, value)

    def accept(self):
        global ACTIVE
        if not self.preview():
            return False                 # the panel stays open with the message
        self.doc.commitTransaction()
        FreeCADGui.Control.closeDialog()
        ACTIVE = None
        return True

    def reject(self):
        global ACTIVE
        self.doc.abortTransaction()
        FreeCADGui.Control.closeDialog()
        self.doc.recompute()
        ACTIVE = None
        return True

    def getStandardButtons(self):
        return int(QtGui.QDialogButtonBox.Ok | QtGui.QDialogButtonBox.Cancel)


class FitTaskPanel(_Panel):
    title = "Fit ruled surface"

    def __init__(self, source, subname: str):
        lay = self._open(source, make_ruled_fit, subname)
        self.method = QtGui.QComboBox()
        self.method.addItems(["2d", "4d"])
        self.samples = QtGui.QSpinBox()
        self.samples.setRange(3, 2000)
        self.samples.setValue(40)
        self.objective = QtGui.QComboBox()
        self.objective.addItems(["sum", "max"])
        self.max_error = QtGui.QDoubleSpinBox()
        self.max_error.setDecimals(6)
        self.max_error.setRange(0.0, 1e9)
        self.max_error.setSpecialValueText("no limit")
        self.direction = QtGui.QComboBox()
        self.direction.addItems(["auto", "u", "v"])
        self.elevations = QtGui.QSpinBox()
        self.elevations.setRange(1, 200)
        self.elevations.setValue(10)
        self.step = QtGui.QDoubleSpinBox()
        self.step.setDecimals(6)
        self.step.setRange(0.0, 1e9)
        self.step.setSpecialValueText("auto")
        self.metric = QtGui.QComboBox()
        self.metric.addItems(["lsad", "sshb"])
        self.measure = QtGui.QSpinBox()
        self.measure.setRange(0, 400)
        self.measure.setValue(40)
        self.rulings = QtGui.QCheckBox("show the rulings")
        self.rulings.setChecked(True)
        self.preview_button = QtGui.QPushButton("Preview")
        self.result = QtGui.QLabel("Preview fits the face with these parameters.")
        self.result.setWordWrap(True)
        for label, w in (("Method", self.method), ("Samples per boundary", self.samples),
                         ("Objective", self.objective), ("Max error", self.max_error), ("Direction", self.direction),
                         ("4d elevations", self.elevations), ("4d step", self.step), ("4d metric", self.metric),
                         ("Measure samples", self.measure)):
            lay.addRow(label, w)
        lay.addRow(self.rulings)
        lay.addRow(self.preview_button)
        lay.addRow(self.result)
        self.preview_button.clicked.connect(self.preview)
        self.rulings.toggled.connect(self._show_rulings)

    def _apply(self):
        self._set(self.obj, Method=self.method.currentText(), Samples=self.samples.value(),
                  Objective=self.objective.currentText(), MaxError=self.max_error.value(),
                  Direction=self.direction.currentText(), Elevations=self.elevations.value(),
                  MeasureSamples=self.measure.value(), Step=self.step.value(), Metric=self.metric.currentText())

    def _show_rulings(self, on):
        if FreeCAD.GuiUp and hasattr(self.obj.ViewObject, "ShowRulings"):
            self.obj.ViewObject.ShowRulings = bool(on)

    def preview(self) -> bool:
        """Recompute with the panel's parameters; the outcome (or the error) in the panel."""
        o = self.obj
        if self._recompute():
            self.result.setText(f"{o.Rulings} rulings, certified bound {o.ErrorBound:.6g}, measured Hausdorff "
                                f"{o.Hausdorff:.6g} ({o.Seconds:.2f} s).\nColours: distance to the face, "
                                f"blue 0 ... red {o.Hausdorff:.4g}.")
            return True
        self.result.setText(f"Cannot fit: {o.Status}")
        return False


class SplitTaskPanel(_Panel):
    title = "Split for ruling"

    def __init__(self, source, subname: str):
        lay = self._open(source, make_ruled_split, subname)
        self.samples = QtGui.QSpinBox()
        self.samples.setRange(4, 200)
        self.samples.setValue(30)
        self.interior = QtGui.QSpinBox()
        self.interior.setRange(1, 100)
        self.interior.setValue(10)
        self.dims = QtGui.QComboBox()
        self.dims.addItems(["4", "5", "7"])
        self.objective = QtGui.QComboBox()
        self.objective.addItems(["max", "sum"])
        self.fit_samples = QtGui.QSpinBox()
        self.fit_samples.setRange(3, 2000)
        self.fit_samples.setValue(40)
        self.preview_button = QtGui.QPushButton("Preview")
        self.result = QtGui.QLabel("Preview finds the split curve and fits both sides.")
        self.result.setWordWrap(True)
        for label, w in (("Samples (P, Q, M columns)", self.samples), ("Interior M-rows", self.interior),
                         ("Split DP dimension", self.dims), ("Objective", self.objective),
                         ("Samples per side fit", self.fit_samples)):
            lay.addRow(label, w)
        lay.addRow(self.preview_button)
        lay.addRow(self.result)
        self.preview_button.clicked.connect(self.preview)

    def _apply(self):
        self._set(self.obj, Samples=self.samples.value(), Interior=self.interior.value(), Dims=self.dims.currentText(),
                  Objective=self.objective.currentText(), FitSamples=self.fit_samples.value())

    def preview(self) -> bool:
        o = self.obj
        if self._recompute():
            self.result.setText(f"kept the {o.Chosen} split: certified bound {o.ErrorBound:.6g} (one strip: "
                                f"{o.WholeBound:.6g}; " + ", ".join(o.Candidates) + f") in {o.Seconds:.1f} s.")
            return True
        self.result.setText(f"Cannot split: {o.Status}")
        return False
