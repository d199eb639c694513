"""Why a command is greyed (GUI): a click on a greyed entry of the Ruled menu or toolbar shows the command's reason in
the status bar (what to select), as its tooltip says what it needs.  Installed when the workbench is activated."""

from __future__ import annotations

import FreeCADGui
from PySide import QtCore, QtGui

from .commands import COMMANDS, why_greyed

SHOWN_FOR_MS = 8000


class _Reasons(QtCore.QObject):
    """On the Ruled menu and the toolbar's buttons: a mouse release over a greyed Ruled command says why it is
    greyed (the menu and the toolbar go on as before: the event is theirs)."""

    def eventFilter(self, watched, event):
        if event.type() == QtCore.QEvent.MouseButtonRelease:
            action = watched.actionAt(event.pos()) if hasattr(watched, "actionAt") else watched.defaultAction()
            if action is not None and not action.isEnabled() and action.objectName() in COMMANDS:
                why = why_greyed(action.objectName())
                if why:
                    FreeCADGui.getMainWindow().statusBar().showMessage(why, SHOWN_FOR_MS)
        return False


_FILTER = None


def ruled_bars() -> list:
    """The Ruled menu and toolbar(s) of the main window (FreeCAD builds them when the workbench is activated)."""
    mw = FreeCADGui.getMainWindow()
    menus = [m for m in mw.findChildren(QtGui.QMenu) if m.objectName() == "Ruled"]
    bars = [b for b in mw.findChildren(QtGui.QToolBar) if b.objectName() == "Ruled" or b.windowTitle() == "Ruled"]
    return menus + bars


def install() -> None:
    """The filter on the Ruled menu and toolbar, once each (the workbench may be activated many times), after
    FreeCAD has built them (the next turn of its event loop)."""
    QtCore.QTimer.singleShot(0, _install)


def _install() -> None:
    global _FILTER
    if _FILTER is None:
        _FILTER = _Reasons()
    bars = ruled_bars()
    buttons = [b.widgetForAction(a) for b in bars if isinstance(b, QtGui.QToolBar) for a in b.actions()]
    for widget in bars + [w for w in buttons if hasattr(w, "defaultAction")]:   # (a greyed button's own events)
        try:
            if not widget.property("ruledReasons"):
                widget.installEventFilter(_FILTER)
                widget.setProperty("ruledReasons", True)
        except RuntimeError:     # (a menu FreeCAD replaced meanwhile)
            continue


__all__ = ["install", "ruled_bars"]
