"""Helpers of the GUI scripts (run inside FreeCAD's GUI; tests/gui is on their sys.path)."""


class Results(dict):
    """The script's results, each key with the seconds since the start when it was first set (written as
    "_seconds": where a GUI script spends its time)."""

    def __init__(self):
        import time
        super().__init__()
        self._t0 = time.monotonic()
        self.seconds = {}

    def __setitem__(self, key, value):
        import time
        self.seconds.setdefault(key, round(time.monotonic() - self._t0, 2))
        super().__setitem__(key, value)

    def setdefault(self, key, default=None):
        if key not in self:
            self[key] = default
        return self[key]


def run_and_exit(main, res: dict, name: str) -> None:
    """Run main(), write res as JSON to $RULED_GUI_OUT/name and end the process: exit 0 when main returned,
    1 when it raised (os._exit: FreeCAD exits 0 even when a script raises)."""
    import json
    import os
    import sys
    import traceback
    code = 1
    try:
        main()
        code = 0
    except Exception:
        traceback.print_exc()
    out = dict(res)
    if isinstance(res, Results):
        out["_seconds"] = res.seconds
    json.dump(out, open(os.path.join(os.environ["RULED_GUI_OUT"], name), "w"), indent=1, default=str)
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)


def part_document(doc_name: str, part_name: str = "Impeller", step_env: str = "RULED_STEP"):
    """(a new document, its Part::Feature part_name holding the STEP file $step_env), the workbench activated."""
    import os

    import FreeCAD
    import FreeCADGui
    import Part
    # no camera animations (FreeCAD 1.0 animates a change of view direction: a click right after one can land on
    # the scene half turned)
    FreeCAD.ParamGet("User parameter:BaseApp/Preferences/View").SetBool("UseNavigationAnimations", False)
    FreeCADGui.activateWorkbench("RuledWorkbench")
    doc = FreeCAD.newDocument(doc_name)
    part = doc.addObject("Part::Feature", part_name)
    part.Shape = Part.read(os.environ[step_env])
    doc.recompute()
    return doc, part


def toolbar_actions() -> list:
    """The buttons of the Ruled toolbar (its named actions), in their order."""
    return [a for b in _bars() for a in b.actions() if a.objectName()]


def toolbar_run(name):
    """Trigger the command's button in the Ruled toolbar, as a click does (True), or run it (False)."""
    import FreeCADGui
    for a in toolbar_actions():
        if a.objectName() == name:
            return _click(a)
    FreeCADGui.runCommand(name)
    return False


def _enabled(action, wait: float = 3.0) -> bool:
    """Whether the action is enabled once FreeCAD has updated the commands' state (on a timer, after the
    selection or the document changes), waiting up to wait seconds for it."""
    import time

    from PySide import QtGui
    end = time.time() + wait
    while not action.isEnabled() and time.time() < end:
        QtGui.QApplication.processEvents()
        time.sleep(0.05)
    return action.isEnabled()


def _click(action) -> bool:
    """Click the action's toolbar button (a real click; its action triggered where the button is out of sight)
    once FreeCAD has enabled it; False when it stays disabled."""
    if not _enabled(action):
        return False
    button = next((b.widgetForAction(action) for b in _bars() if b.widgetForAction(action) is not None), None)
    if button is not None and button.isVisible():        # a real click on the toolbar's button (QTest)
        click(button)
    else:
        action.trigger()
    return True


def _bars() -> list:
    """The Ruled toolbar(s) (the workbench's own list of its menu and toolbars)."""
    from PySide import QtGui
    from ruled_workbench.greyed import ruled_bars
    return [b for b in ruled_bars() if isinstance(b, QtGui.QToolBar)]


def shortcut(command: str) -> str:
    """The FreeCAD command's own keyboard shortcut pressed for real (QTest) where the keyboard's focus is (e.g.
    Std_Undo: Ctrl+Z), once FreeCAD has enabled it; the shortcut, as text."""
    import FreeCADGui
    from PySide2.QtTest import QTest
    from PySide2.QtWidgets import QAction, QApplication
    mw = FreeCADGui.getMainWindow()
    action = next(a for a in mw.findChildren(QAction) if a.objectName() == command)
    _enabled(action)
    seq = action.shortcut()
    QTest.keySequence(QApplication.focusWidget() or mw, seq)
    for _ in range(3):
        FreeCADGui.updateGui()
    return seq.toString()


# ------------------------------------------------------------------------------ real input (QTest events)
def click(widget, pos=None) -> None:
    """A left click on the widget (at pos, its centre by default): mouse press and release events through
    the application, as a user's click (PySide2's QTest)."""
    from PySide2.QtCore import Qt
    from PySide2.QtTest import QTest
    if pos is None:
        QTest.mouseClick(widget, Qt.LeftButton)
    else:
        QTest.mouseClick(widget, Qt.LeftButton, Qt.NoModifier, pos)


def choose(combo, text: str) -> bool:
    """A real choice in a combo box, as a user makes it: a click on it (its list opens), the arrow keys to the entry
    named text, Return; whether the combo shows it then.  (Qt ignores a click on the list's entry that comes right
    after the click that opened it, and QTest's mouse moves do not hover.)"""
    import FreeCADGui
    from PySide2.QtCore import Qt
    from PySide2.QtTest import QTest
    click(combo)
    for _ in range(3):
        FreeCADGui.updateGui()
    view = combo.view()
    steps = combo.findText(text) - combo.currentIndex()
    for _ in range(abs(steps)):
        QTest.keyClick(view, Qt.Key_Down if steps > 0 else Qt.Key_Up)
    QTest.keyClick(view, Qt.Key_Return)
    for _ in range(3):
        FreeCADGui.updateGui()
    return combo.currentText() == text


def key(widget, k) -> None:
    from PySide2.QtTest import QTest
    QTest.keyClick(widget, k)


def widgets(class_name: str) -> list:
    """The main window's visible widgets of a Qt class (by its C++ name, e.g. 'Gui::TreeWidget')."""
    import FreeCADGui
    from PySide import QtGui
    return [w for w in FreeCADGui.getMainWindow().findChildren(QtGui.QWidget)
            if w.metaObject().className() == class_name and w.isVisible()]


def settle(rounds: int = 10) -> None:
    """Let the GUI finish what a view change started (events, redraws), a few 20 ms rounds."""
    import time

    import FreeCADGui
    for _ in range(rounds):
        FreeCADGui.updateGui()
        time.sleep(0.02)


def view3d():
    """The 3D view's viewer widget (Coin's Quarter widget: its own class on 0.20, Gui::View3DInventorViewer, a
    subclass of it, on 1.0)."""
    import FreeCADGui
    from PySide import QtGui
    return [w for w in FreeCADGui.getMainWindow().findChildren(QtGui.QWidget)
            if w.inherits("SIM::Coin3D::Quarter::QuarterWidget") and w.isVisible()][0]


def task_width(panel):
    """The width of the dock a task panel is shown in (the combo view's on 0.20, the task view's own from 1.0 on),
    or None."""
    import FreeCADGui
    from ruled_workbench.qtcompat import task_dock
    dock = task_dock(panel.form, FreeCADGui.getMainWindow())
    return dock.width() if dock is not None else None


def combo_tab(label: str):
    """(the combo view's tab bar, the position of its tab named label)."""
    import FreeCADGui
    from PySide import QtGui
    for bar in FreeCADGui.getMainWindow().findChildren(QtGui.QTabBar):
        for i in range(bar.count()):
            if bar.tabText(i) == label and bar.isVisible():
                return bar, bar.tabRect(i).center()
    return None, None


def task_button(which: str):
    """The task panel's standard button ('Cancel' or 'OK') as FreeCAD shows it."""
    from PySide import QtGui
    kind = {"Cancel": QtGui.QDialogButtonBox.Cancel, "OK": QtGui.QDialogButtonBox.Ok}[which]
    for box in widgets("QDialogButtonBox"):
        b = box.button(kind)
        if b is not None and b.isVisible():
            return b
    return None


def tree_item(label: str):
    """(the tree's viewport, the position of the item labelled label)."""
    from PySide import QtCore
    for tree in widgets("Gui::TreeWidget"):
        items = tree.findItems(label, QtCore.Qt.MatchExactly | QtCore.Qt.MatchRecursive, 0)
        if items:
            tree.scrollToItem(items[0])
            return tree.viewport(), tree.visualItemRect(items[0]).center()
    return None, None


def grab_window(path: str) -> str:
    """The main window as the user sees it, saved to path: the screen's pixels where the window is (the 3D
    view's OpenGL content and the navigation cube included, which a widget's grab leaves blank)."""
    import FreeCADGui
    from PySide import QtGui
    mw = FreeCADGui.getMainWindow()
    for _ in range(5):
        FreeCADGui.updateGui()
    g = mw.frameGeometry()
    QtGui.QGuiApplication.primaryScreen().grabWindow(0, g.x(), g.y(), g.width(), g.height()).save(path)
    return path


def click_view(view, xy) -> None:
    """A real mouse click (QTest: move, press, release) on the 3D view's viewport at xy, in Coin's pixels from the
    lower left (as view.getPointOnScreen gives them; the viewport's Qt pixels may be fewer)."""
    import FreeCADGui
    from PySide2 import QtCore
    from PySide2.QtTest import QTest
    port = view3d().viewport()
    width, height = view.getSize()
    pos = QtCore.QPoint(round(xy[0] * port.width() / width), round((height - xy[1]) * port.height() / height))
    QTest.mouseMove(port, pos)
    click(port, pos)
    for _ in range(3):
        FreeCADGui.updateGui()


def click_greyed(name: str, where: str = "toolbar") -> dict:
    """A real click (QTest) on the Ruled command name's entry in the Ruled toolbar or menu, once FreeCAD has
    updated its state: {"enabled": its state, "status": the status bar's message after the click}."""
    import FreeCADGui
    from PySide2 import QtCore, QtWidgets
    from ruled_workbench.greyed import ruled_bars
    mw = FreeCADGui.getMainWindow()
    _enabled([a for b in ruled_bars() for a in b.actions() if a.objectName() == name][0], 0.5)   # (its state now)
    mw.statusBar().clearMessage()
    bars = [b for b in ruled_bars() if isinstance(b, QtWidgets.QMenu) == (where == "menu")]
    bar = bars[0]
    action = [a for a in bar.actions() if a.objectName() == name][0]
    if where == "menu":
        bar.popup(mw.mapToGlobal(QtCore.QPoint(200, 200)))
        QtWidgets.QApplication.processEvents()
        widget, pos = bar, bar.actionGeometry(action).center()
    else:
        widget = bar.widgetForAction(action)
        pos = widget.rect().center()
    click(widget, pos)
    QtWidgets.QApplication.processEvents()
    out = {"enabled": action.isEnabled(), "status": mw.statusBar().currentMessage()}
    if where == "menu":
        bar.hide()
    return out


def click_preview(panel) -> bool:
    """The panel's Preview clicked for real (QTest; its computation runs meanwhile, the click returns when it is
    done): True when its object came out valid (as panel.preview() says)."""
    click(panel.preview_button)
    return bool(getattr(panel, "_done", False))
