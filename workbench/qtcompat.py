"""What Qt 5 (PySide2: FreeCAD 0.20 to 1.0) and Qt 6 (PySide6: FreeCAD 1.1) spell differently, in one place.
FreeCAD's own ``PySide`` module is either's, its QtGui holding the widgets too.

* A task dialog's standard buttons go to FreeCAD as an int: PySide2's flags are ints, PySide6's are Python
  enum flags, which int() refuses (their .value is the int).
* The task panel's dock: the Combo View's on 0.20 and 0.21, the task view's own ('Tasks') from 1.0 on; found
  from the panel's own widget, whatever the dock's name.
"""

from __future__ import annotations

from PySide import QtCore, QtGui


def standard_buttons(*names: str) -> int:
    """The int of QDialogButtonBox's standard buttons by name ('Ok', 'Cancel', 'Close'), on Qt 5 and Qt 6."""
    box = QtGui.QDialogButtonBox
    kind = getattr(box, "StandardButton", box)
    flags = getattr(kind, names[0])
    for name in names[1:]:
        flags = flags | getattr(kind, name)
    return int(getattr(flags, "value", flags))


def task_dock(widget, main_window):
    """The dock widget a task panel's widget is shown in (its nearest QDockWidget ancestor), or the main window's
    visible task dock by name ('Tasks' from FreeCAD 1.0 on, the Combo View before), or None."""
    w = widget
    while w is not None:
        if isinstance(w, QtGui.QDockWidget):
            return w
        w = w.parentWidget()
    docks = [d for d in main_window.findChildren(QtGui.QDockWidget)
             if d.isVisible() and (d.objectName() == "Tasks" or "Combo" in d.objectName())]
    return docks[0] if docks else None


def horizontal():
    """Qt's horizontal orientation (Qt.Orientation.Horizontal; Qt 5 also names it Qt.Horizontal)."""
    return getattr(QtCore.Qt, "Orientation", QtCore.Qt).Horizontal


__all__ = ["standard_buttons", "task_dock", "horizontal"]
