"""Helpers of the GUI scripts (run inside FreeCAD's GUI; tests/gui is on their sys.path)."""


def toolbar_run(name):
    """Trigger the command's button in the Ruled toolbar, as a click does (True), or run it (False)."""
    import FreeCADGui
    from PySide import QtGui
    mw = FreeCADGui.getMainWindow()
    for bar in mw.findChildren(QtGui.QToolBar):
        if bar.objectName() == "Ruled" or bar.windowTitle() == "Ruled":
            for a in bar.actions():
                if a.objectName() == name:
                    return _click(a)
    FreeCADGui.runCommand(name)
    return False


def _click(action, wait: float = 3.0) -> bool:
    """Trigger the action once FreeCAD has enabled it (it updates the buttons' state on a timer after the
    selection changes); False when it stays disabled."""
    import time

    from PySide import QtGui
    end = time.time() + wait
    while not action.isEnabled() and time.time() < end:
        QtGui.QApplication.processEvents()
        time.sleep(0.05)
    if not action.isEnabled():
        return False
    action.trigger()
    return True
