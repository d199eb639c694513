"""Commands of the Ruled workbench: "Fit ruled surface", "Split for ruling" and "Export for
machining...".  Registered when the workbench is activated (InitGui.py)."""

from __future__ import annotations

import FreeCAD
import FreeCADGui

from . import icon

LAST_MESSAGE = ""        # the last refusal, also in the report view (for scripts and tests)


def _say(msg: str) -> None:
    global LAST_MESSAGE
    LAST_MESSAGE = msg
    FreeCAD.Console.PrintError("Ruled: " + msg + "\n")


def selected_face():
    """(object, "FaceN") of the one selected face, or (None, what is wrong)."""
    sel = FreeCADGui.Selection.getSelectionEx()
    subs = [(s.Object, n) for s in sel for n in (s.SubElementNames or [])]
    whole = [s.Object for s in sel if not s.SubElementNames]
    if not sel:
        return None, "nothing is selected: select one face of a part in the 3D view"
    if whole or len(subs) != 1:
        what = ", ".join([n for _, n in subs] + [o.Label for o in whole])
        return None, f"select exactly one face (the selection is {what})"
    obj, name = subs[0]
    if not name.startswith("Face"):
        return None, f"{name} of {obj.Label} is not a face: select one face"
    return obj, name


class FitCommand:
    panel = "FitTaskPanel"

    def GetResources(self):
        return {"Pixmap": icon("fit.svg"), "MenuText": "Fit ruled surface",
                "ToolTip": "Fit the best ruled surface to the selected face, with a certified error (select one face)"}

    def IsActive(self):
        return FreeCAD.ActiveDocument is not None and selected_face()[0] is not None

    def Activated(self):
        obj, sub = selected_face()
        if obj is None:
            _say(sub)
            return
        from . import taskpanels
        FreeCADGui.Control.showDialog(getattr(taskpanels, self.panel)(obj, sub))


class SplitCommand(FitCommand):
    panel = "SplitTaskPanel"

    def GetResources(self):
        return {"Pixmap": icon("split.svg"), "MenuText": "Split for ruling",
                "ToolTip": "Find the curve that cuts the selected face in two so that each side rules best, and "
                           "fit both sides (select one face)"}


def export_step(objects, path: str) -> None:
    """The objects' shapes (ruled results) as one STEP file."""
    import Part
    shapes = [o.Shape for o in objects if hasattr(o, "Shape") and not o.Shape.isNull()]
    if not shapes:
        raise ValueError("nothing to export: select a ruled result")
    Part.makeCompound(shapes).exportStep(path)


class ExportCommand:
    def GetResources(self):
        return {"Pixmap": icon("export.svg"), "MenuText": "Export for machining...",
                "ToolTip": "Write the selected ruled results as STEP (select one or more results)"}

    def IsActive(self):
        return any(hasattr(o, "Shape") for o in FreeCADGui.Selection.getSelection())

    def Activated(self):
        from PySide import QtGui
        objs = FreeCADGui.Selection.getSelection()
        path, _ = QtGui.QFileDialog.getSaveFileName(None, "Export for machining", "ruled.step", "STEP (*.step *.stp)")
        if not path:
            return
        try:
            export_step(objs, path)
        except Exception as exc:  # Part raises OCCError on write failures
            _say(f"cannot write {path}: {exc}")
            return
        FreeCAD.Console.PrintMessage(f"Ruled: wrote {path}\n")


NAMES = ["Ruled_Fit", "Ruled_Split", "Ruled_Export"]


def register() -> None:
    FreeCADGui.addCommand("Ruled_Fit", FitCommand())
    FreeCADGui.addCommand("Ruled_Split", SplitCommand())
    FreeCADGui.addCommand("Ruled_Export", ExportCommand())
