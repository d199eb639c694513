"""Replay (issue 71): a machine file read back (LinuxCNC's own interpreter for a LinuxCNC file where Debian's
linuxcnc-uspace is installed, else the project's reader for its post: ruled.machine.replay.read_file) and what
its moves cut measured against a face or a wall of the part, both ways (ruled.machine.replay.measure_program over
FreeCAD's faces, workbench.wirecut: the command line's ``ruled replay``), drawn beside the part: the wire's line at
every point of the file (a flank file: the tool's axis), coloured by how far the cut lies from the design there
(blue: on it, red: the largest over- or undercut), with the figures as properties.  A parametric Part feature:
change File (a file written again) and recompute."""

from __future__ import annotations

import os

import FreeCAD
import numpy as np

from .features import LINK_SUB, RESULT_GROUP, _add, _enum, _Feature

POSTS = ["auto", "linuxcnc", "grbl", "iso-wedm", "apt-sync", "apt"]     # (ruled.machine.posts.SHIPPED)


class RuledReplay(_Feature):
    """Proxy of a RuledReplay object (Part::FeaturePython)."""

    @staticmethod
    def add_properties(obj):
        _add(obj, "App::PropertyFile", "File", "Ruled", "the machine file to replay: G-code or APT ('ruled machine' "
             "and Export for machining write them; a file edited by hand too)")
        _add(obj, LINK_SUB, "Source", "Ruled", "the face, or the faces of a wall, that the file cuts")
        _enum(obj, "Post", "Ruled", "the post the file was written for (auto: the one its Ruled comments name, else "
              "guessed from it)", POSTS, "auto")
        _enum(obj, "Side", "Ruled", "the side the wire runs on (file's: as the file says; outside: the faces' "
              "normals' side, off the material)", ["file's", "outside", "inside"], "file's")
        _add(obj, "App::PropertyInteger", "MeasureSamples", "Ruled", "n x n points of each face for the measure", 20)
        _add(obj, "App::PropertyLength", "Overcut", RESULT_GROUP, "the largest depth the cut goes past the design (a "
             "gouge)", 0.0, True)
        _add(obj, "App::PropertyLength", "Undercut", RESULT_GROUP, "the largest material the cut leaves on the design",
             0.0, True)
        _add(obj, "App::PropertyAngle", "MaxTaper", RESULT_GROUP, "the wire's largest angle from the machine axis",
             0.0, True)
        _add(obj, "App::PropertyInteger", "Moves", RESULT_GROUP, "points of the file (its moves' ends)", 0, True)
        _add(obj, "App::PropertyString", "Reader", RESULT_GROUP, "what read the file", "", True)
        _add(obj, "App::PropertyFloatList", "Deviation", RESULT_GROUP, "per line drawn: the cut's largest "
             "deviation from the design there (negative: an overcut)", [], True)
        _add(obj, "App::PropertyFloat", "Seconds", RESULT_GROUP, "time of the last recompute", 0.0, True)
        _add(obj, "App::PropertyString", "Status", RESULT_GROUP, "ok, or what went wrong", "", True)

    def compute(self, obj):
        import Part

        from ruled.core.errors import BadInputError
        from ruled.machine.replay import measure_program, read_file

        from .walls import wall_source
        from .wirecut import FreeCADFaces
        if not obj.File:
            raise BadInputError("no file to replay: set File to a G-code or APT file")
        faces, names = wall_source(obj) if obj.Source and obj.Source[0] is not None else (None, None)
        if not faces:
            raise BadInputError("no face to replay against: set Source to the face (or a wall's faces) the file cuts")
        post, prog, warnings = read_file(obj.File, None if obj.Post == "auto" else obj.Post)
        side = int(prog.meta.get("side", "+1") or 1) if obj.Side == "file's" else (1 if obj.Side == "outside"
                                                                                  else -1)
        what = f"{obj.Source[0].Label} {', '.join(names)}"
        target = FreeCADFaces(faces, side, "the face" if len(faces) == 1 else "the wall's faces")
        rep, plot = measure_program(prog, target, max(4, int(obj.MeasureSamples)), what=what,
                                    name=os.path.basename(obj.File))
        cut = rep["cut"]
        if prog.machine == "flank":         # (the tool's axis, tip to its length up)
            lo, hi = prog.points[:, :3], prog.points[:, :3] + prog.cutter[6] * prog.points[:, 3:]
        else:
            lo, hi = plot["lines"]
        over, under = np.asarray(plot["per"]["overcut"]), np.asarray(plot["per"]["undercut"])
        dev = np.where(over > under, -over, under)
        keep = np.linalg.norm(hi - lo, axis=1) > 0
        obj.Shape = Part.makeCompound([Part.LineSegment(FreeCAD.Vector(*map(float, a)),
                                                        FreeCAD.Vector(*map(float, b))).toShape()
                                       for a, b in zip(lo[keep], hi[keep])])
        obj.Deviation = [float(x) for x in dev[keep]]
        obj.Overcut, obj.Undercut = cut["overcut"], cut["undercut"]
        obj.MaxTaper = float(rep["machine"].get("max_taper_deg", rep["machine"].get("taper_deg", 0.0)))
        obj.Moves = int(rep["moves"]["points"])
        obj.Reader = f"{'LinuxCNC interpreter' if prog.reader == 'linuxcnc' else 'Ruled reader'} ({post.name})"
        for w in warnings:
            FreeCAD.Console.PrintWarning(f"Ruled: {obj.Label}: {w}\n")


class ViewProviderRuledReplay:
    """The replay's lines coloured by the cut's deviation there (blue: none, red: the largest), thicker than
    Part's default; the legend shows the range."""

    def __init__(self, vobj):
        vobj.Proxy = self

    def attach(self, vobj):
        self.Object = vobj.Object

    def updateData(self, fp, prop):
        if prop == "Deviation" and FreeCAD.GuiUp:
            colour_lines(fp)

    def onChanged(self, vobj, prop):
        pass

    def __getstate__(self):
        return None

    def __setstate__(self, state):
        return None

    dumps, loads = __getstate__, __setstate__


def colour_lines(obj) -> None:
    """Each line of the replay its colour (the legend's ramp over the largest |deviation|), the legend shown."""
    from .legend import colour_ramp, show_legend
    dev = np.abs(np.asarray(obj.Deviation, float))
    if not dev.size or len(obj.Shape.Edges) != dev.size:
        return
    top = max(float(dev.max()), 1e-12)
    cols = colour_ramp(dev / top)
    vo = obj.ViewObject
    vo.LineWidth = 2.0
    vo.LineColorArray = [tuple(float(c) for c in col) + (0.0,) for col in cols]
    show_legend(obj, top)


def make_ruled_replay(doc, part, subs: list, path: str, **properties):
    """A RuledReplay of the machine file path against the faces subs of part (not recomputed)."""
    obj = doc.addObject("Part::FeaturePython", "RuledReplay")
    RuledReplay(obj)
    obj.Source = (part, list(subs))
    obj.File = path
    obj.Label = f"Replay {os.path.basename(path)}"
    for k, v in properties.items():
        setattr(obj, k, v)
    if FreeCAD.GuiUp:
        ViewProviderRuledReplay(obj.ViewObject)
    return obj


__all__ = ["RuledReplay", "ViewProviderRuledReplay", "make_ruled_replay", "colour_lines"]
