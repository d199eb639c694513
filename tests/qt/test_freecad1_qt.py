"""Issue 73, what FreeCAD 1.0 and 1.1 change, checked in the project's own Python: the panels' Qt code under Qt 6
(PySide6 from PyPI, offscreen: FreeCAD 1.1's Qt; FreeCAD's own PySide module, whose QtGui holds the widgets too,
stood in for), and the sub-element names of FreeCAD 1.0's topological naming."""

import ast
import importlib
import pathlib
import sys
import types

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture
def qt6(monkeypatch):
    """workbench.qtcompat imported over PySide6 (FreeCAD 1.1's PySide module: QtCore, and QtGui with QtWidgets)."""
    PySide6 = pytest.importorskip("PySide6", reason="PySide6 (the test extras) is not installed")
    monkeypatch.setenv("QT_QPA_PLATFORM", "offscreen")
    from PySide6 import QtCore, QtGui, QtWidgets
    gui = types.ModuleType("PySide.QtGui")

    def either(name):               # (PySide6 loads its classes lazily: looked up on use)
        return getattr(QtWidgets, name) if hasattr(QtWidgets, name) else getattr(QtGui, name)
    gui.__getattr__ = either
    pkg = types.ModuleType("PySide")
    pkg.QtCore, pkg.QtGui = QtCore, gui
    for name, mod in (("PySide", pkg), ("PySide.QtCore", QtCore), ("PySide.QtGui", gui)):
        monkeypatch.setitem(sys.modules, name, mod)
    monkeypatch.syspath_prepend(str(ROOT))
    monkeypatch.delitem(sys.modules, "workbench.qtcompat", raising=False)
    app = QtWidgets.QApplication.instance() or QtWidgets.QApplication([])
    yield importlib.import_module("workbench.qtcompat"), QtWidgets, app
    sys.modules.pop("workbench.qtcompat", None)
    assert PySide6.__version__.startswith("6.")


def test_the_task_panels_standard_buttons_are_the_ints_qt6_defines_and_make_those_buttons(qt6):
    compat, QtWidgets, _ = qt6
    B = QtWidgets.QDialogButtonBox.StandardButton
    with pytest.raises(TypeError):               # (the premise: what the panels returned fails on Qt 6)
        int(B.Ok | B.Cancel)
    got = compat.standard_buttons("Ok", "Cancel")
    assert type(got) is int and got == B.Ok.value | B.Cancel.value == 0x00400400
    assert compat.standard_buttons("Close") == B.Close.value == 0x00200000
    box = QtWidgets.QDialogButtonBox(B(got))      # as FreeCAD's task view makes them from the int
    assert box.button(B.Ok) is not None and box.button(B.Cancel) is not None and box.button(B.Close) is None


def test_the_task_dock_is_found_from_the_panel_by_any_name_and_widened_on_qt6(qt6):
    compat, QtWidgets, app = qt6
    mw = QtWidgets.QMainWindow()
    mw.setCentralWidget(QtWidgets.QWidget())
    dock = QtWidgets.QDockWidget("Tasks")
    dock.setObjectName("Tasks")                   # FreeCAD 1.0's task view: its own dock
    form = QtWidgets.QLabel("a panel " * 20)
    dock.setWidget(form)
    mw.addDockWidget(compat.QtCore.Qt.DockWidgetArea.LeftDockWidgetArea, dock)
    mw.resize(1200, 800)
    mw.show()
    app.processEvents()
    assert compat.task_dock(form, mw) is dock
    assert compat.task_dock(QtWidgets.QLabel("elsewhere"), mw) is dock        # (by its name)
    mw.resizeDocks([dock], [500], compat.horizontal())
    app.processEvents()
    assert dock.width() >= 450, dock.width()
    mw.close()


def test_every_panel_hands_freecad_its_buttons_through_the_compat_helper_and_no_qt_enum_is_made_an_int():
    """The workbench's source: each getStandardButtons returns standard_buttons(...); no int() of a Qt name, no
    exec_() (gone in PySide6)."""
    found = 0
    for path in sorted((ROOT / "workbench").glob("*.py")):
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree):
            if isinstance(node, ast.FunctionDef) and node.name == "getStandardButtons":
                found += 1
                ret = node.body[-1]
                assert isinstance(ret, ast.Return) and isinstance(ret.value, ast.Call) and \
                    getattr(ret.value.func, "id", "") == "standard_buttons", (path.name, ast.dump(ret))
            if isinstance(node, ast.Call) and getattr(node.func, "id", "") == "int" and node.args:
                text = ast.unparse(node.args[0])
                assert "QtGui." not in text and "QtCore." not in text, (path.name, text)
            if isinstance(node, ast.Attribute) and node.attr == "exec_":
                raise AssertionError(f"{path.name}: exec_() is gone in PySide6 (use exec())")
    assert found >= 3


@pytest.mark.parametrize("sub,short,face", [("Face6", "Face6", True), ("Edge12", "Edge12", False),
                                            (";#11f;:H4d1,F.Face6", "Face6", True),
                                            (";#7:1;:G0;XTR;:H4d1:8,E.Edge3", "Edge3", False),
                                            ("Body.Pad.Face2", "Face2", True), ("Face", "Face", True),
                                            ("Surface3x", "Surface3x", False), ("", "", False)])
def test_a_mapped_sub_element_name_reads_as_its_indexed_name(sub, short, face):
    sys.path.insert(0, str(ROOT))
    try:
        from workbench.names import is_face, short_name
    finally:
        sys.path.remove(str(ROOT))
    assert short_name(sub) == short and is_face(sub) == face


def test_a_face_selected_by_its_mapped_name_is_a_face_to_the_commands(monkeypatch):
    """FreeCAD 1.0's selection of a PartDesign body's face (its mapped name): the commands' selection checks take
    it as the face it is and keep the name FreeCAD gave (a stand-in FreeCAD and FreeCADGui: the checks are plain
    Python over the selection)."""
    class Obj:
        Label = "Fillet"

    class Sel:
        def __init__(self, names):
            self.Object, self.SubElementNames = Obj(), names
    picked = []
    gui = types.ModuleType("FreeCADGui")
    gui.Selection = types.SimpleNamespace(getSelectionEx=lambda *a: picked)
    monkeypatch.setitem(sys.modules, "FreeCAD", types.ModuleType("FreeCAD"))
    monkeypatch.setitem(sys.modules, "FreeCADGui", gui)
    monkeypatch.syspath_prepend(str(ROOT))
    monkeypatch.delitem(sys.modules, "workbench.commands", raising=False)
    commands = importlib.import_module("workbench.commands")
    mapped = ";#1a:2;:G;FLT;:H1054:7,F.Face3"
    picked[:] = [Sel([mapped])]
    obj, name = commands.selected_face()
    assert obj is picked[0].Object and name == mapped
    assert commands.selected_faces()[0] == [(picked[0].Object, mapped)]
    assert commands.selected_face_and_sketch()[1] == mapped
    picked[:] = [Sel([";#7:1;:G0;XTR;:H4d1:8,E.Edge3"])]
    assert commands.selected_face() == (None, "Edge3 of Fillet is not a face: select one face")
    sys.modules.pop("workbench.commands", None)
