"""RuledWall (no GUI imports: it recomputes in freecadcmd too): a part's wall (a ring of its faces between two
closed contours, Source naming them) as one closed ruled surface (ruled.fit.wall.fit, as ``ruled fit
--wall``): the faces read and joined by the adapter (workbench.adapter.Wall), its certified bound and its
measure against the wall's faces, both ways.  Saved documents refer to the proxy as
``ruled_workbench.walls.RuledWall``: keep the name."""

from __future__ import annotations

import FreeCAD

from .features import (
    LINK_SUB,
    RESULT_GROUP,
    _add,
    _enum,
    _Feature,
    _Progress,
    add_results,
    in_our_terms,
    measure_into,
    ruling_lines,
    say_kernels,
)
from .names import element, is_face, short_name


def wall_source(obj) -> tuple:
    """(the faces obj.Source names, their names), or a BadInputError saying what is wrong."""
    from ruled.core.errors import BadInputError
    link = obj.Source
    if link is None or link[0] is None:
        raise BadInputError("no wall: select the faces of a part's wall (the ring between its bottom and top "
                            "contours) and run Fit wall again")
    src, subs = link
    subs = list(dict.fromkeys(s for s in (subs or []) if s))
    bad = [short_name(s) for s in subs if not is_face(s)]
    if bad or not subs:
        raise BadInputError(f"a wall is made of faces, not {', '.join(bad) or 'the whole object'}: select the faces "
                            f"of {src.Label}'s wall")
    try:
        return [element(src.Shape, s) for s in subs], [short_name(s) for s in subs]
    except Exception:  # Part raises IndexError / OCCError for stale names
        raise BadInputError(f"{src.Label} does not have all of {', '.join(map(short_name, subs))} any more (its shape "
                            f"changed); select the wall's faces again") from None


class RuledWall(_Feature):
    """Proxy of a RuledWall object (Part::FeaturePython)."""

    @staticmethod
    def add_properties(obj):
        group = "Wall"
        _add(obj, LINK_SUB, "Source", "Ruled", "the wall's faces (of one part): a ring of faces "
             "between the part's bottom and top contours")
        _enum(obj, "Method", group, "2d: rulings between the contours' samples (Elber); 4d: their ends also lifted "
              "along the normal (Wang & Elber)", ["2d", "4d"], "2d")
        _add(obj, "App::PropertyInteger", "Samples", group, "samples per face along each contour", 40)
        _enum(obj, "Objective", group, "sum of the ruling distances (Elber) or the largest one", ["sum", "max"],
              "sum")
        _add(obj, "App::PropertyInteger", "MeasureSamples", group, "n x n samples per face for the measured "
             "Hausdorff distance and the colours (0: do not measure)", 16)
        _add(obj, "App::PropertyBool", "PerFace", group, "the closed ruled surface in one piece per face of the wall "
             "(cut along the faces' joints), sewn into one shell", False)
        _add(obj, "App::PropertyStringList", "Faces", RESULT_GROUP, "the wall's faces round the ring", None, True)
        _add(obj, "App::PropertyInteger", "Pieces", RESULT_GROUP, "pieces fitted between the corners both contours "
             "have (1: one periodic fit)", 0, True)
        add_results(obj, "the closed ruled surface (to the wall's faces, both ways)")

    def options(self, obj):
        from ruled import FitOptions
        return FitOptions(samples=int(obj.Samples), objective=str(obj.Objective), method=str(obj.Method)).checked()

    def compute(self, obj):
        from dataclasses import replace

        import Part

        from ruled.fit.face.verdict import measured_warnings
        from ruled.fit.wall.fit import fit_ring, smooth_parts

        from .adapter import Wall, built_slack, result_face, surface_to_face
        say_kernels()
        faces, names = wall_source(obj)
        wall = Wall(faces, names)
        opts = replace(self.options(obj), samples=int(obj.Samples) * len(wall.faces)).checked()
        progress = _Progress(f"Ruled: fitting the wall {obj.Label}", capability="wall")
        try:
            ring = progress.run(fit_ring, wall.surface, wall.breaks, wall.corners, opts, wall.size, progress)
            out = result_face(ring.results[0]) if ring.periodic else surface_to_face(ring.surface)
            bound = ring.bound + wall.slack + (built_slack(out, ring.results[0]) if ring.periodic else 0.0)
            design = Part.Compound(wall.faces)
            parts = ([surface_to_face(p) for p in smooth_parts(ring.surface)] if int(obj.MeasureSamples) >= 2
                     else None)
            measure_into(obj, [out], design, lambda f: progress("measuring (distances to the wall)", f), parts,
                         wall=True)
        finally:
            progress.stop()
        if obj.PerFace and len(wall.kept) > 1:
            from ruled.core.errors import RuledError
            try:
                shell = Part.Shell(wall.pieces(ring.surface))
                shell.sewShape()
            except RuledError as exc:
                raise type(exc)(f"the wall's pieces per face could not be built ({exc.problem}); write the wall "
                                f"whole (PerFace = False)") from None
            out = shell
        obj.Shape = out
        obj.ErrorBound, obj.Faces, obj.Pieces = float(bound), wall.names, len(ring.results)
        obj.RulingLines = ruling_lines(ring.results)
        if int(obj.MeasureSamples) >= 2:
            ratio = float(out.Area) / sum(float(f.Area) for f in wall.faces)
            for w in measured_warnings(ring.results[0], bound, float(obj.Hausdorff), wall.size, ratio):
                FreeCAD.Console.PrintWarning(f"{obj.Label}: {in_our_terms(w)}\n")


def make_ruled_wall(doc, source, subnames: list, **properties):
    """A RuledWall on source's faces subnames (e.g. ["Face2", "Face3", ...]), not recomputed."""
    obj = doc.addObject("Part::FeaturePython", "RuledWall")
    RuledWall(obj)
    obj.Source = (source, list(subnames))
    for k, v in properties.items():
        setattr(obj, k, v)
    obj.Label = f"Ruled wall of {source.Label}"
    if FreeCAD.GuiUp:
        from .viewproviders import attach_view_provider
        attach_view_provider(obj)
    return obj
