"""Commands of the Ruled workbench: "Fit ruled surface", "Fit several faces", "Split for ruling", "Fit
to tolerance", "Cone spline", "Curve on face", "Replace in part", "Export for machining..." and "Replay a machine
file...".  Registered when the
workbench is activated (InitGui.py)."""

from __future__ import annotations

import os

import FreeCAD
import FreeCADGui

from . import icon
from .names import is_face, short_name

LAST_MESSAGE = ""        # the last refusal, also in the report view (for scripts and tests)


def resources(pixmap: str, menu: str, tip: str, select: str) -> dict:
    """A command's resources; what to select is said in its tooltip, which FreeCAD also shows in the status bar
    (the status tip), over a greyed button too."""
    return {"Pixmap": icon(pixmap), "MenuText": menu, "ToolTip": f"{tip}. Select {select}."}


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
        what = ", ".join([short_name(n) for _, n in subs] + [o.Label for o in whole])
        return None, f"select exactly one face (the selection is {what})"
    obj, name = subs[0]
    if not is_face(name):
        return None, f"{short_name(name)} of {obj.Label} is not a face: select one face"
    return obj, name


class _Command:
    """A command active when why_not() has nothing to say: what it says is the reason it is greyed (shown in the
    status bar when its greyed menu entry or button is clicked, workbench.greyed)."""

    def why_not(self) -> str:
        return ""

    def IsActive(self):
        return FreeCAD.ActiveDocument is not None and not self.why_not()


class FitCommand(_Command):
    """A face selected, a task panel opened on it (the subclasses name their panel and their selection)."""

    panel = "FitTaskPanel"
    select = staticmethod(lambda: selected_face())

    def GetResources(self):
        return resources("fit.svg", "Fit ruled surface", "Fit the best ruled surface to the selected face, with a "
                         "certified error", "one face of a part (click it in the 3D view)")

    def why_not(self) -> str:
        obj, why = self.select()
        return why if obj is None else ""

    def Activated(self):
        obj, sub = self.select()
        if obj is None:
            _say(sub)
            return
        from . import taskpanels
        from .busy import show_panel
        show_panel(getattr(taskpanels, self.panel)(obj, sub))


class SplitCommand(FitCommand):
    panel = "SplitTaskPanel"

    def GetResources(self):
        return resources("split.svg", "Split for ruling", "Find the curve that cuts the selected face in two so that "
                         "each side rules best, and fit both sides", "one face of a part")


class PartitionCommand(FitCommand):
    panel = "PartitionTaskPanel"

    def GetResources(self):
        return resources("partition.svg", "Fit to tolerance", "Split the selected face into strips until each "
                         "strip's ruled fit is within a tolerance", "one face of a part")


def _is_fit(obj) -> bool:
    return type(getattr(obj, "Proxy", None)).__name__ == "RuledFit"


def selected_fit_or_face():
    """(a RuledFit, "") when one Ruled fit is selected, else selected_face()."""
    sel = FreeCADGui.Selection.getSelectionEx()
    if len(sel) == 1 and _is_fit(sel[0].Object):
        return sel[0].Object, ""
    return selected_face()


class ConeCommand(FitCommand):
    panel = "ConeTaskPanel"
    select = staticmethod(lambda: selected_fit_or_face())

    def GetResources(self):
        return resources("cone.svg", "Cone spline", "Approximate a Ruled fit (or a ruled face) by tangent-continuous "
                         "developable cone and cylinder patches", "a Ruled fit in the tree, or one ruled face")


def selected_face_and_sketch():
    """(object, "FaceN", sketch or None) of one selected face and at most one selected sketch, or
    (None, what is wrong, None)."""
    sel = FreeCADGui.Selection.getSelectionEx()
    sketches = [s.Object for s in sel if not s.SubElementNames and hasattr(s.Object, "Geometry")]
    faces = [(s.Object, n) for s in sel for n in (s.SubElementNames or []) if is_face(n)]
    other = [short_name(n) for s in sel for n in (s.SubElementNames or []) if not is_face(n)] + \
        [s.Object.Label for s in sel if not s.SubElementNames and s.Object not in sketches]
    if len(faces) != 1 or len(sketches) > 1 or other:
        what = ", ".join([short_name(n) for _, n in faces] + [k.Label for k in sketches] + other) or "nothing"
        return None, f"select one face, and at most one sketch (the selection is {what})", None
    return faces[0][0], faces[0][1], (sketches[0] if sketches else None)


class CurveCommand(_Command):
    def GetResources(self):
        return resources("curve.svg", "Curve on face", "A curve lying on the selected face: through points you pick "
                         "on it, or from a sketch mapped onto its (u, v)", "one face, and a sketch if you drew one")

    def why_not(self) -> str:
        obj, why, _ = selected_face_and_sketch()
        return why if obj is None else ""

    def Activated(self):
        obj, sub, sketch = selected_face_and_sketch()
        if obj is None:
            _say(sub)
            return
        from .busy import show_panel
        from .curvepanel import CurveTaskPanel
        show_panel(CurveTaskPanel(obj, sub, sketch=sketch))


def selected_faces():
    """[(object, "FaceN")] of every selected face, or (None, what is wrong)."""
    sel = FreeCADGui.Selection.getSelectionEx()
    if not sel:
        return None, "nothing is selected: select faces of a part in the 3D view"
    out, other = [], []
    for s in sel:
        if not s.SubElementNames:
            other.append(s.Object.Label)
        for n in s.SubElementNames:
            (out if is_face(n) else other).append((s.Object, n) if is_face(n) else short_name(n))
    if other or not out:
        return None, f"select faces only (the selection has {', '.join(other) or 'no face'})"
    return out, ""


class FitManyCommand(_Command):
    """One RuledFit per selected face, with the default parameters, in one undo step; a face the engine
    refuses becomes an invalid object with its reason (the others are kept)."""

    def GetResources(self):
        return resources("fitmany.svg", "Fit several faces", "Fit a ruled surface to each selected face (default "
                         "parameters, one RuledFit each; edit any of them afterwards by double-click)",
                         "the faces (Ctrl+click adds one)")

    def why_not(self) -> str:
        faces, why = selected_faces()
        return why if faces is None else ""

    def Activated(self):
        faces, why = selected_faces()
        if faces is None:
            _say(why)
            return
        from .features import make_ruled_fit
        doc = faces[0][0].Document
        doc.openTransaction("Fit several faces")
        made = []
        try:
            for k, (obj, sub) in enumerate(faces):
                FreeCADGui.getMainWindow().statusBar().showMessage(f"Ruled: fitting {obj.Label} {sub} "
                                                                   f"({k + 1} of {len(faces)})")
                made.append(_recomputed(make_ruled_fit(doc, obj, sub)))
        finally:
            doc.commitTransaction()
            FreeCADGui.getMainWindow().statusBar().clearMessage()
        bad = [f.Label for f in made if not f.isValid() or f.Status != "ok"]
        FreeCAD.Console.PrintMessage(f"Ruled: {len(made) - len(bad)} of {len(made)} faces fitted"
                                     + (f"; not fitted: {', '.join(bad)} (see their Status)" if bad else "") + "\n")
        return made


def faces_of_one_part(what: str):
    """(object, ["FaceN", ...]) of the selected faces of one part, or (None, what is wrong); what: the faces' use, in
    words ("the faces of a part's wall")."""
    faces, why = selected_faces()
    if faces is None:
        return None, why.replace("select faces", f"select {what}")
    parts = list(dict.fromkeys(o for o, _ in faces))
    if len(parts) != 1:
        return None, f"select faces of one part (the selection has faces of {', '.join(o.Label for o in parts)})"
    return parts[0], [n for _, n in faces]


def selected_wall():
    """(object, ["FaceN", ...]) of the selected faces of one part, at least two, or (None, what is wrong)."""
    part, subs = faces_of_one_part("the faces of a part's wall")
    if part is not None and len(subs) < 2:
        return None, ("select every face of the wall (the ring of faces between the part's bottom and top contours; "
                      "Ctrl+click adds a face), not one")
    return part, subs


class WallCommand(_Command):
    """The selected faces (a part's wall) as one closed ruled surface: the Fit wall panel (a parametric RuledWall
    made in one undo step), or the panel saying why the faces are no side wall."""

    def GetResources(self):
        return resources("wall.svg", "Fit wall", "Fit the selected faces of a part's wall (the ring between its "
                         "bottom and top contours) as one closed ruled surface, for one wire path round the part",
                         "every face of the wall (Ctrl+click adds one)")

    def why_not(self) -> str:
        """Greyed unless the selection is a ring of faces of one part."""
        part, subs = selected_wall()
        if part is None:
            return subs
        return (_ring_refusal(part, subs) or "").replace("Cannot fit a wall: ", "", 1)

    def Activated(self):
        part, subs = selected_wall()
        if part is None:
            _say(subs)
            return None
        from .busy import show_panel
        from .wallpanel import WallRefusal, WallTaskPanel
        why = _ring_refusal(part, subs)       # (faces that are no side wall: said in the panel, no object made)
        show_panel(WallRefusal(why) if why else WallTaskPanel(part, subs))
        return None


def _ring_refusal(part, subs: list):
    """wallpanel.wall_refusal of the faces subs of part, kept for the selection it was asked of (FreeCAD asks
    whether Fit wall is active after every change)."""
    key = (part.Document.Name, part.Name, tuple(subs), part.Shape.hashCode())
    if key not in _RINGS:
        from .wallpanel import wall_refusal
        _RINGS.clear()
        _RINGS[key] = wall_refusal(part, subs)
    return _RINGS[key]


class ReplaceCommand(_Command):
    """The selected RuledFit's result put back into its part in place of its face: a parametric RuledReplace."""

    def GetResources(self):
        return resources("replace.svg", "Replace in part", "Put the selected Ruled fit's result back into its part in "
                         "place of its face, bounded by the face's own edges: a parametric copy of the part",
                         "one Ruled fit in the tree")

    def why_not(self) -> str:
        sel = FreeCADGui.Selection.getSelection()
        return "" if len(sel) == 1 and _is_fit(sel[0]) else \
            "select one Ruled fit (a RuledFit object in the tree) to put back into its part"

    def Activated(self):
        sel, why = FreeCADGui.Selection.getSelection(), self.why_not()
        if why:
            _say(why)
            return
        from .replace import make_ruled_replace
        doc = sel[0].Document
        doc.openTransaction("Replace in part")
        try:
            return _recomputed(make_ruled_replace(doc, sel[0]))
        finally:
            doc.commitTransaction()


def _recomputed(obj):
    """obj recomputed alone, and left up to date (not Touched, as a document's recompute leaves it)."""
    try:
        if obj.recompute():
            obj.purgeTouched()
    except Exception:  # refused: the object is invalid, its Status says why
        pass
    return obj


class ExportCommand(_Command):
    def GetResources(self):
        return resources("export.svg", "Export for machining...", "Write the selected ruled results for machining: "
                         "STEP (with or without rulings), XYUV G-code for a 4-axis wire, or flank-milling CL data "
                         "(APT)", "Ruled results in the tree (a Ruled fit or wall for machine data)")

    def why_not(self) -> str:
        return "" if any(hasattr(o, "Shape") for o in FreeCADGui.Selection.getSelection()) else \
            "select the Ruled results to write in the tree (a Ruled fit or wall for machine data)"

    def Activated(self):
        from .busy import show_panel
        from .exportpanel import ExportTaskPanel
        show_panel(ExportTaskPanel(FreeCADGui.Selection.getSelection()))


def selected_design():
    """(part, ["FaceN", ...]) of the selected face(s) of one part, or of a selected Ruled fit's or wall's source, or
    (None, what is wrong)."""
    sel = FreeCADGui.Selection.getSelectionEx()
    if len(sel) == 1 and not sel[0].SubElementNames and type(getattr(sel[0].Object, "Proxy", None)).__name__ in (
            "RuledFit", "RuledWall"):
        part, subs = sel[0].Object.Source
        return part, list(subs)
    return faces_of_one_part("the face (or a wall's faces) the file cuts")


CHOOSE_FILE = None      # (tests: a function giving the file to replay instead of the file dialog)


class ReplayCommand(_Command):
    """A machine file replayed against the selected face (or wall): a parametric RuledReplay drawn beside it."""

    def GetResources(self):
        return resources("replay.svg", "Replay a machine file...", "Read a G-code or APT file back (LinuxCNC's own "
                         "interpreter where it is installed) and draw the wire it moves beside the part, coloured by "
                         "how far its cut lies from the design", "the face (or a wall's faces, or a Ruled fit) the "
                         "file cuts")

    def why_not(self) -> str:
        part, why = selected_design()
        return why if part is None else ""

    def Activated(self):
        part, subs = selected_design()
        if part is None:
            _say(subs)
            return None
        if CHOOSE_FILE is not None:
            path = CHOOSE_FILE()
        else:
            from PySide import QtGui
            path, _ = QtGui.QFileDialog.getOpenFileName(None, "Replay a machine file", os.path.expanduser("~"),
                                                        "Machine files (*.ngc *.nc *.gcode *.tap *.apt *.cls);;"
                                                        "All files (*)")
        if not path:
            return None
        from .replay import make_ruled_replay
        doc = part.Document
        doc.openTransaction("Replay a machine file")
        try:
            return _recomputed(make_ruled_replay(doc, part, subs, path))
        finally:
            doc.commitTransaction()


COMMANDS = {"Ruled_Fit": FitCommand, "Ruled_FitMany": FitManyCommand, "Ruled_Split": SplitCommand,
            "Ruled_Partition": PartitionCommand, "Ruled_Cone": ConeCommand, "Ruled_Curve": CurveCommand,
            "Ruled_Wall": WallCommand, "Ruled_Replace": ReplaceCommand, "Ruled_Export": ExportCommand,
            "Ruled_Replay": ReplayCommand}
NAMES = list(COMMANDS)
_RINGS: dict = {}          # {the wall selection: why its faces are no ring, None when they are one}


def register() -> None:
    """The commands added to FreeCAD, and the task panels loaded (each registers the objects it edits)."""
    from . import curvepanel, taskpanels, wallpanel  # noqa: F401
    for name, kind in COMMANDS.items():
        INSTANCES[name] = kind()
        FreeCADGui.addCommand(name, INSTANCES[name])


INSTANCES: dict = {}      # {name: the command FreeCAD runs}


def why_greyed(name: str) -> str:
    """Why the command name is greyed now, in words for the status bar ("" when it is active)."""
    cmd = INSTANCES.get(name) or COMMANDS[name]()
    why = "open a document and select in it" if FreeCAD.ActiveDocument is None else cmd.why_not()
    return f"{cmd.GetResources()['MenuText']}: {why}" if why else ""
