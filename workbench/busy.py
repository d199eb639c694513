"""The GUI while Ruled computes (GUI only; workbench.progress._Progress uses it when FreeCAD.GuiUp): the
progress in FreeCAD's status bar (a bar and the stage, saying that Esc or Cancel stops it), and an event
filter that keeps the window usable and the document safe.

FreeCAD's own progress indicator, started from the main thread (a document's recompute starts one), grabs
the keyboard and refuses every mouse press while it runs (the task panel's Cancel and the tree included),
asking about Esc only when the computation next reports: the task panels recompute their object alone,
which runs none.  The engine runs in a worker thread (_Progress.run) and the main thread keeps processing
events; the filter lets through clicks in the 3D view (navigation, selection), the tree
and the combo view's tabs, and the task panel (its Cancel), and holds back what could change the document
under the running computation: key presses (Esc cancels), double clicks and context menus, the menus and
toolbars, the property editor, closing the window.
"""

from __future__ import annotations

import FreeCADGui
from PySide import QtCore, QtGui

# widgets (by Qt class name, the widget or one of its parents) whose clicks go through while Ruled computes
ALLOWED = ("SIM::Coin3D::Quarter::QuarterWidget", "Gui::View3DInventor", "Gui::TreeWidget", "Gui::TaskView::TaskView",
           "QTabBar")
HELD = ("Gui::PropertyEditor::PropertyEditor", "QMenu", "QMenuBar", "QToolBar")
MOUSE = (QtCore.QEvent.MouseButtonPress, QtCore.QEvent.MouseButtonRelease)
HOLD = (QtCore.QEvent.MouseButtonDblClick, QtCore.QEvent.ContextMenu, QtCore.QEvent.KeyRelease,
        QtCore.QEvent.ShortcutOverride, QtCore.QEvent.Shortcut)


def _classes(widget) -> list:
    out = []
    while widget is not None:
        out.append(widget.metaObject().className())
        widget = widget.parentWidget() if isinstance(widget, QtGui.QWidget) else None
    return out


def cancel_by_user() -> None:
    """Esc while Ruled computes: what Cancel does (the open Ruled panel closes as it was; without one, the
    computation stops and its object is left invalid, 'cancelled by the user')."""
    from . import state
    panel = state.ACTIVE
    if panel is not None and getattr(panel, "busy", False):
        panel.reject()
    else:
        state.request_cancel()


class BusyFilter(QtCore.QObject):
    def eventFilter(self, obj, event):
        t = event.type()
        if t == QtCore.QEvent.KeyPress:
            if event.key() == QtCore.Qt.Key_Escape:
                cancel_by_user()
            return True
        if t in HOLD:
            return True
        if t in MOUSE:
            if not isinstance(obj, QtGui.QWidget):
                return False       # (the window's own handling; the widget under the mouse gets it next)
            names = _classes(obj)
            if any(n in HELD for n in names):
                return True
            return not any(n in ALLOWED for n in names)
        if t == QtCore.QEvent.Close and obj is FreeCADGui.getMainWindow():
            event.ignore()
            return True
        return False


class StatusDisplay:
    """The computation's progress in FreeCAD's status bar: a bar (0-100) and the stage, while the filter
    holds the input that must wait."""

    def __init__(self, text: str):
        self.text = text
        self.mw = FreeCADGui.getMainWindow()
        self.bar = QtGui.QProgressBar()
        self.bar.setRange(0, 100)
        self.bar.setFixedWidth(160)
        self.bar.setToolTip("Ruled is computing; Esc or the panel's Cancel stops it")
        self.mw.statusBar().addPermanentWidget(self.bar)
        self.bar.show()
        self.filter = BusyFilter()
        QtGui.QApplication.instance().installEventFilter(self.filter)
        QtGui.QApplication.setOverrideCursor(QtCore.Qt.BusyCursor)
        self.mw.statusBar().showMessage(f"{text} (Esc stops)")

    def show(self, stage: str, pct: int) -> None:
        """The whole computation's percentage (workbench.progress._Progress.percent), the same the panel shows."""
        self.bar.setValue(pct)
        self.mw.statusBar().showMessage(f"{self.text}: {stage}, {pct} % (Esc stops)")

    def close(self) -> None:
        QtGui.QApplication.instance().removeEventFilter(self.filter)
        QtGui.QApplication.restoreOverrideCursor()
        self.mw.statusBar().removeWidget(self.bar)
        self.bar.deleteLater()
        self.mw.statusBar().clearMessage()


def show_panel(panel):
    """A task panel in FreeCAD's task view (the combo view's on 0.20, its own dock from 1.0 on), the view widened
    (once, as a user drags its edge) so that the panel is whole on first open: its widest row, the buttons and the
    panel's frame."""
    FreeCADGui.Control.showDialog(panel)
    from .qtcompat import horizontal, task_dock
    mw = FreeCADGui.getMainWindow()
    dock = task_dock(panel.form, mw)
    if dock is not None:
        need = panel.form.sizeHint().width() + 60          # (the task box's frame and the dock's margins)
        if dock.width() < need:
            mw.resizeDocks([dock], [need], horizontal())
    return panel
