"""Task panels of "Fit ruled surface" (the fit parameters, Preview: recompute and show the rulings and
the coloured deviation), "Split for ruling" (the split DP's parameters, Preview: the split curve on
the face and the two ruled fits), "Fit to tolerance", "Cone spline" and "Curve on face" (with picking
points on the face), OK / Cancel inside one undo transaction.  The same panels edit an
existing object (double-click it in the tree).  While a computation runs the window stays responsive:
Cancel stops it (and closes the panel, the document as it was), OK and Preview wait for it."""

from __future__ import annotations

import FreeCAD
import FreeCADGui
from PySide import QtGui

from . import state
from .features import make_ruled_fit, make_ruled_split, value
from .qtcompat import standard_buttons
from .state import LISTENERS
from .units import length


class _Panel:
    """One parametric object made (or, editing, opened) inside an undo transaction: Preview recomputes
    it, OK keeps it (or stays open with the message), Cancel removes it (or restores its properties),
    and stops a computation that is running."""

    title = ""
    busy = False
    closing = False

    def _open(self, source, make, subname, obj=None):
        self.doc = source.Document if obj is None else obj.Document
        self.editing = obj is not None
        self.doc.openTransaction(("Edit " if self.editing else "") + self.title)
        self.obj = make(self.doc, source, subname) if obj is None else obj
        self._done = self.editing and self.obj.isValid() and "Touched" not in self.obj.State
        self.form = QtGui.QWidget()
        self.form.setWindowTitle(self.title)
        state.set_active(self)
        lay = QtGui.QFormLayout(self.form)
        lay.setFieldGrowthPolicy(QtGui.QFormLayout.AllNonFixedFieldsGrow)
        return lay

    def _progress(self, stage: str, frac: float) -> None:
        """The running computation's stage (its own line: a long one wraps) and the whole computation's
        percentage, the status bar's own (Cancel stops it)."""
        pct = int(round(100 * frac))
        self.progress_seen.append((stage, pct))
        self.stage_label.setText(stage)
        self.stage_label.show()
        self.bar.setValue(pct)

    def _progress_bar(self, lay) -> None:
        self.progress_seen = []
        self.stage_label = QtGui.QLabel()
        self.stage_label.setWordWrap(True)
        self.stage_label.hide()
        lay.addRow(self.stage_label)
        self.bar = QtGui.QProgressBar()        # (0 to 100, "%p%": Qt's defaults)
        self.bar.setToolTip("the running computation's progress, its stage above; Cancel stops it")
        self.bar.hide()
        lay.addRow(self.bar)

    def _rows(self, lay, rows, *extra) -> None:
        """The parameter rows (label, widget), the extra rows (check boxes), Preview, the progress bar and the
        outcome."""
        for label, w in rows:
            lay.addRow(label, w)
        for w in extra + (self.preview_button,):
            lay.addRow(w)
        self._progress_bar(lay)
        lay.addRow(self.result)

    @staticmethod
    def _tip(widget, text: str):
        widget.setToolTip(text)
        return widget

    def _recompute(self) -> bool:
        """Recompute with the panel's values, unless nothing changed since the last recompute (OK right
        after Preview keeps what Preview computed)."""
        self._apply()
        if getattr(self, "_done", False) and "Touched" not in self.obj.State:
            return True
        self.obj.touch()
        self.busy = True
        self.preview_button.setEnabled(False)
        self.bar.setValue(0)
        self.bar.show()
        LISTENERS.append(self._progress)
        try:
            # the object alone: the document's recompute runs FreeCAD's progress indicator (workbench.busy)
            if self.obj.recompute():
                self.obj.purgeTouched()      # (the document's recompute does that; OK keeps what Preview made)
        finally:
            LISTENERS.remove(self._progress)
            self.busy = False
            self.bar.hide()
            self.stage_label.hide()
            self.preview_button.setEnabled(True)
        self._done = self.obj.isValid() and self.obj.Status == "ok"
        if self.closing:                 # Cancel was pressed while it ran: close now, as it was
            self._close_cancelled()
            return False
        return self._done

    @staticmethod
    def _set(obj, **values):
        """Set the properties that differ (setting one touches the object, even to the same value)."""
        for name, new in values.items():
            if getattr(obj, name) != new:      # a length property compares with a number in mm
                setattr(obj, name, new)

    def preview(self) -> bool:
        """Recompute with the panel's values; the outcome (describe) or the error in the panel."""
        if self.busy:
            return False
        if self._recompute():
            self.result.setText(self.describe(self.obj))
            return True
        if not self.closing:
            self.result.setText(f"Cannot {self.verb}: {self.obj.Status}")
        return False

    def accept(self):
        if self.busy or not self.preview():
            return False                 # the panel stays open (with the message)
        self.doc.commitTransaction()
        self._leave()
        return True

    def reject(self):
        if self.busy:
            self.closing = True
            state.request_cancel()             # the engine stops at its next progress report; then the panel closes
            return False
        self._close_cancelled()
        return True

    def _close_cancelled(self):
        from .viewproviders import hide_legend
        obj = getattr(self, "obj", None)
        try:                      # undoing the object does not delete it: its colour legend would stay in the view
            hide_legend(self.doc.Name, obj.Name)
        except Exception:         # no object, or gone already
            pass
        self.doc.abortTransaction()
        self._leave()
        self.doc.recompute()

    def _leave(self):
        if self.editing:
            FreeCADGui.ActiveDocument.resetEdit()
        FreeCADGui.Control.closeDialog()
        state.set_active(None)

    def getStandardButtons(self):
        return standard_buttons("Ok", "Cancel")


def _length_box(special: str) -> QtGui.QDoubleSpinBox:
    """A length in model units (mm): 0 shows ``special``."""
    box = QtGui.QDoubleSpinBox()
    box.setDecimals(4)
    box.setRange(0.0, 10000.0)
    box.setSuffix(" mm")
    box.setSpecialValueText(special)
    return box


class FitTaskPanel(_Panel):
    title = "Fit ruled surface"

    def __init__(self, source, subname: str, obj=None):
        lay = self._open(source, make_ruled_fit, subname, obj)
        tip = self._tip
        self.method = tip(QtGui.QComboBox(), "2d: rulings between samples of two opposite sides (Elber); 4d: "
                          "their ends also lifted along the normal (Wang & Elber), never worse than 2d")
        self.method.addItems(["2d", "4d"])
        self.samples = tip(QtGui.QSpinBox(), "samples per side; the rulings join samples of the two sides "
                           "(more: a finer optimum, slower)")
        self.samples.setRange(3, 2000)
        self.samples.setValue(40)
        self.objective = tip(QtGui.QComboBox(), "sum: the least total distance of the rulings to the face "
                             "(Elber); max: the least largest one")
        self.objective.addItems(["sum", "max"])
        self.max_error = tip(_length_box("no limit"), "forbid rulings farther than this from the face")
        self.direction = tip(QtGui.QComboBox(), "which pair of opposite sides the rulings join; auto: the "
                             "pair with the smaller certified bound")
        self.direction.addItems(["auto", "u", "v"])
        self.elevations = tip(QtGui.QSpinBox(), "4d: elevation levels of each ruling end along the normal")
        self.elevations.setRange(1, 200)
        self.elevations.setValue(10)
        self.step = tip(_length_box("auto"), "4d: the elevation step (auto: the 2d result's distance / "
                        "elevations)")
        self.metric = tip(QtGui.QComboBox(), "4d cost: lsad, each ruling's distance to the face; sshb, the "
                          "certified bound of each patch between consecutive rulings")
        self.metric.addItems(["lsad", "sshb"])
        self.measure = tip(QtGui.QSpinBox(), "n x n samples of the result for the measured Hausdorff distance "
                           "and the colours (0: do not measure)")
        self.measure.setRange(0, 400)
        self.measure.setValue(40)
        self.rulings = tip(QtGui.QCheckBox("show the rulings"), "draw the rulings of the optimal path as lines")
        self.rulings.setChecked(True)
        self.preview_button = tip(QtGui.QPushButton("Preview"), "fit with these parameters and show the result "
                                  "(Cancel stops a fit that runs)")
        self.result = QtGui.QLabel("Preview fits the face with these parameters.")
        self.result.setWordWrap(True)
        self._rows(lay, (("Method", self.method), ("Samples per side", self.samples),
                         ("Objective", self.objective), ("Max error", self.max_error), ("Direction", self.direction),
                         ("4d elevations", self.elevations), ("4d step", self.step), ("4d metric", self.metric),
                         ("Measure samples", self.measure)), self.rulings)
        if self.editing:
            o = self.obj
            self.method.setCurrentIndex(self.method.findText(o.Method))
            self.samples.setValue(o.Samples)
            self.objective.setCurrentIndex(self.objective.findText(o.Objective))
            self.max_error.setValue(value(o.MaxError))
            self.direction.setCurrentIndex(self.direction.findText(o.Direction))
            self.elevations.setValue(o.Elevations)
            self.step.setValue(value(o.Step))
            self.metric.setCurrentIndex(self.metric.findText(o.Metric))
            self.measure.setValue(o.MeasureSamples)
        self.preview_button.clicked.connect(self.preview)
        self.rulings.toggled.connect(self._show_rulings)
        self.method.currentIndexChanged.connect(self._method_changed)
        self._method_changed()

    def _method_changed(self, *_):
        """The 4d options apply to the 4d method only."""
        on = self.method.currentText() == "4d"
        for w in (self.elevations, self.step, self.metric):
            w.setEnabled(on)

    def _apply(self):
        self._set(self.obj, Method=self.method.currentText(), Samples=self.samples.value(),
                  Objective=self.objective.currentText(), MaxError=self.max_error.value(),
                  Direction=self.direction.currentText(), Elevations=self.elevations.value(),
                  MeasureSamples=self.measure.value(), Step=self.step.value(), Metric=self.metric.currentText())

    def _show_rulings(self, on):
        if FreeCAD.GuiUp and hasattr(self.obj.ViewObject, "ShowRulings"):
            self.obj.ViewObject.ShowRulings = bool(on)

    verb = "fit"

    def describe(self, o) -> str:
        from .legend import exact_bound
        if exact_bound(o) is not None:       # (a plane, a face that is ruled: its figures are round-off's)
            return (f"Exact: the face is ruled. {o.Rulings} rulings, certified within {length(o.ErrorBound)}, "
                    f"measured Hausdorff {length(o.Hausdorff)} ({o.Seconds:.2f} s).\nColours: one, exact (the "
                    f"legend in the view).")
        return (f"{o.Rulings} rulings, certified bound {length(o.ErrorBound)}, measured Hausdorff "
                f"{length(o.Hausdorff)} ({o.Seconds:.2f} s).\nColours: distance to the face, blue 0 ... red "
                f"{length(o.Hausdorff)} (the legend in the view).")


class SplitTaskPanel(_Panel):
    title = "Split for ruling"

    def __init__(self, source, subname: str, obj=None):
        lay = self._open(source, make_ruled_split, subname, obj)
        tip = self._tip
        self.samples = _spin(4, 200, 30, "samples of the split DP along each side (P, Q and M columns)")
        self.interior = _spin(1, 100, 10, "interior rows where the split curve may cross (M-rows)")
        self.dims = tip(QtGui.QComboBox(), "4: nothing lifted; 5: the split points lifted along the normal; "
                        "7: the rulings' ends lifted too")
        self.dims.addItems(["4", "5", "7"])
        self.objective = tip(QtGui.QComboBox(), "max: the least largest line metric along the split curve (the "
                             "paper's); sum: their least total")
        self.objective.addItems(["max", "sum"])
        self.fit_samples = _spin(3, 2000, 40, "samples per side of each half's ruled fit")
        self.preview_button = tip(QtGui.QPushButton("Preview"), "split with these parameters and show both halves "
                                  "(Cancel stops a split that runs)")
        self.result = QtGui.QLabel("Preview finds the split curve and fits both sides.")
        self.result.setWordWrap(True)
        self._rows(lay, (("Samples (P, Q, M columns)", self.samples), ("Interior M-rows", self.interior),
                         ("Split DP dimension", self.dims), ("Objective", self.objective),
                         ("Samples per side fit", self.fit_samples)))
        if self.editing:
            o = self.obj
            self.samples.setValue(o.Samples)
            self.interior.setValue(o.Interior)
            self.dims.setCurrentIndex(self.dims.findText(o.Dims))
            self.objective.setCurrentIndex(self.objective.findText(o.Objective))
            self.fit_samples.setValue(o.FitSamples)
        self.preview_button.clicked.connect(self.preview)

    def _apply(self):
        self._set(self.obj, Samples=self.samples.value(), Interior=self.interior.value(), Dims=self.dims.currentText(),
                  Objective=self.objective.currentText(), FitSamples=self.fit_samples.value())

    verb = "split"

    def describe(self, o) -> str:
        what = "the face needs no split: its fit is" if o.Chosen == "none" else f"kept the {o.Chosen} split: bound"
        return (f"{what} {length(o.ErrorBound)} (one strip: {length(o.WholeBound)}; " + ", ".join(
            o.Candidates) + f"), measured Hausdorff {length(o.Hausdorff)}, in {o.Seconds:.1f} s.")


def _spin(low: int, high: int, value: int, tip: str) -> QtGui.QSpinBox:
    box = QtGui.QSpinBox()
    box.setRange(low, high)
    box.setValue(value)
    box.setToolTip(tip)
    return box


class PartitionTaskPanel(_Panel):
    title = "Fit to tolerance"

    def __init__(self, source, subname: str, obj=None):
        from .objects import make_ruled_partition
        lay = self._open(source, make_ruled_partition, subname, obj)
        o = self.obj
        self.tol = self._tip(_length_box(""), "every strip's certified bound within this distance from the face")
        self.tol.setMinimum(0.0001)
        self.tol.setValue(value(o.Tolerance))
        self.max_strips = _spin(1, 200, o.MaxStrips, "refuse beyond this many strips")
        self.samples = _spin(4, 200, o.Samples, "split DP: samples along each side (P, Q and M columns)")
        self.interior = _spin(1, 100, o.Interior, "split DP: interior rows where a split curve may cross")
        self.fit_samples = _spin(3, 2000, o.FitSamples, "samples per side of each strip's ruled fit")
        self.measure = _spin(0, 200, o.MeasureSamples, "n x n samples per strip for the measured Hausdorff "
                             "distance and the colours (0: do not measure)")
        self.preview_button = self._tip(QtGui.QPushButton("Preview"), "partition with these parameters and show "
                                        "the strips (Cancel stops a partition that runs)")
        self.result = QtGui.QLabel("Preview splits the face into strips until each strip's ruled fit is within the "
                                   "tolerance.")
        self.result.setWordWrap(True)
        self._rows(lay, (("Tolerance", self.tol), ("Max strips", self.max_strips), ("Split samples", self.samples),
                         ("Split rows", self.interior), ("Fit samples", self.fit_samples),
                         ("Measure samples", self.measure)))
        self.preview_button.clicked.connect(self.preview)

    def _apply(self):
        self._set(self.obj, Tolerance=self.tol.value(), MaxStrips=self.max_strips.value(),
                  Samples=self.samples.value(), Interior=self.interior.value(), FitSamples=self.fit_samples.value(),
                  MeasureSamples=self.measure.value())

    def describe(self, o) -> str:
        return (f"{o.Strips} strips ({o.Used} splitting; uniform iso-parametric needs "
                f"{o.UniformStrips or 'more than ' + str(o.MaxStrips)}), largest certified bound "
                f"{length(o.ErrorBound)}, measured Hausdorff {length(o.Hausdorff)} ({o.Seconds:.1f} s).")

    verb = "partition"


class ConeTaskPanel(_Panel):
    title = "Cone spline"

    def __init__(self, source, subname: str, obj=None):
        from .objects import make_ruled_cone_spline
        lay = self._open(source, make_ruled_cone_spline, subname, obj)
        o = self.obj
        self.tol = self._tip(_length_box(""), "largest distance of the cone patches from the ruled surface (eq. 9)")
        self.tol.setMinimum(0.0001)
        self.tol.setValue(value(o.Tolerance))
        self.step = self._tip(QtGui.QDoubleSpinBox(), "first arc step along the boundaries, a fraction of their "
                              "parameter range")
        self.step.setRange(0.001, 1.0)
        self.step.setDecimals(3)
        self.step.setSingleStep(0.05)
        self.step.setValue(o.Step)
        self.direction = self._tip(QtGui.QComboBox(), "a ruled face's rulings: along u, v, or auto")
        self.direction.addItems(["auto", "u", "v"])
        self.direction.setCurrentIndex(self.direction.findText(o.Direction))
        self.fit_first = self._tip(QtGui.QCheckBox("fit a face that is not ruled first"), "the face is fitted by a "
                                   "ruled surface (2d, 40 samples) and the fit is cone-splined")
        self.fit_first.setChecked(o.FitFirst)
        self.fit_first.setEnabled(bool([s for s in (o.Source[1] or []) if s]))    # a face, not a RuledFit
        self.creases = self._tip(QtGui.QCheckBox("allow creases between patches"), "keep a cone spline whose "
                                 "neighbouring patches are not tangent continuous instead of refusing it")
        self.creases.setChecked(o.AllowCreases)
        self.measure = _spin(0, 100, o.MeasureSamples, "n x n samples per patch for the measured distance to the "
                             "design face and the colours (0: do not measure)")
        self.preview_button = self._tip(QtGui.QPushButton("Preview"), "build the cone spline and show its patches")
        self.result = QtGui.QLabel("Preview approximates the ruled surface by developable cone and cylinder patches.")
        self.result.setWordWrap(True)
        self._rows(lay, (("Tolerance", self.tol), ("First arc step", self.step), ("Rulings along", self.direction),
                         ("Measure samples", self.measure)), self.fit_first, self.creases)
        self.preview_button.clicked.connect(self.preview)

    def _apply(self):
        self._set(self.obj, Tolerance=self.tol.value(), Step=self.step.value(), Direction=self.direction.currentText(),
                  FitFirst=self.fit_first.isChecked(), AllowCreases=self.creases.isChecked(),
                  MeasureSamples=self.measure.value())

    def describe(self, o) -> str:
        return (f"{o.Patches} patches in {o.Pieces} piece(s), developable: {'yes' if o.Developable else 'no'}, largest "
                f"angle between patches {o.MaxG1Angle:.2g} deg; bound {length(o.ErrorBound)} (cone "
                f"{length(o.ConeBound)} + fit {length(o.FitBound)}), measured {length(o.Hausdorff)}.")

    verb = "make the cone spline"


def _editor(panel):
    """The panel editing an existing object of its kind (its view provider's setEdit)."""
    def edit(obj):
        source, subs = obj.Source
        return panel(source, (subs or [""])[0], obj=obj)
    return edit


state.PANELS.update({name: _editor(p) for name, p in (
    ("RuledFit", FitTaskPanel), ("RuledSplit", SplitTaskPanel), ("RuledPartition", PartitionTaskPanel),
    ("RuledConeSpline", ConeTaskPanel))})
