""""Replace in part" (issue 35, point 6): a parametric Part feature, the part of a RuledFit's source with
the fitted face replaced by the fit's ruled surface bounded by the face's own edges (which its neighbours
share, so nothing needs sewing; FreeCAD 0.20's sewShape has no tolerance), the edges' tolerances raised to
how far they lie from the ruled surface; refused as an invalid object with a one-line Status where the
face's solid does not come out a valid closed solid.  The part's other solids are kept as they are."""

from __future__ import annotations

import FreeCAD

from .features import LINK, RESULT_GROUP, _add, _Feature, value
from .names import element

MARGIN = 1.1      # the edges' largest tolerance: this many times the fit's bound (as ruled.occ.replace)


class RuledReplace(_Feature):
    """Proxy of a RuledReplace object (Part::FeaturePython)."""

    @staticmethod
    def add_properties(obj):
        _add(obj, LINK, "Fit", "Ruled", "the RuledFit whose result replaces its face in its part")
        _add(obj, "App::PropertyLength", "EdgeTolerance", RESULT_GROUP, "the largest tolerance of the replaced "
             "face's edges: how far the part's edges there lie from the ruled surface (at most 1.1 x its bound)",
             0.0, True)
        _add(obj, "App::PropertyBool", "ClosedSolid", RESULT_GROUP, "the face's solid is a valid closed solid",
             False, True)
        _add(obj, "App::PropertyInteger", "Faces", RESULT_GROUP, "faces of the part", 0, True)
        _add(obj, "App::PropertyFloat", "Seconds", RESULT_GROUP, "time of the last recompute", 0.0, True)
        _add(obj, "App::PropertyString", "Status", RESULT_GROUP, "ok, or what went wrong", "", True)

    def compute(self, obj):
        from ruled.core.errors import BadInputError, RuledError
        fit = obj.Fit
        if fit is None or type(getattr(fit, "Proxy", None)).__name__ != "RuledFit":
            raise BadInputError("no Ruled fit to put back: set Fit to a RuledFit")
        if not fit.isValid() or fit.Shape.isNull() or len(fit.Shape.Faces) != 1:
            raise RuledError(f"{fit.Label} has no result to put back; recompute it first")
        part, subs = fit.Source
        old = element(part.Shape, subs[0])
        tol = max([MARGIN * value(fit.ErrorBound), 1e-7] + [e.Tolerance for e in old.Edges])
        owner = next((s for s in part.Shape.Solids if any(f.isSame(old) for f in s.Faces)), None)
        whole = (owner if owner is not None else part.Shape).copy()      # (the fix below must not touch the source)
        k = next(i for i, f in enumerate((owner if owner is not None else part.Shape).Faces) if f.isSame(old))
        old2 = whole.Faces[k]
        import Part
        try:
            # the ruled surface bounded by the face's own edges, which its neighbours share: no gap to sew, the
            # edges' tolerances raised to how far they lie from the ruled surface (at most tol)
            face = Part.Face(fit.Shape.Faces[0].Surface, old2.OuterWire)
            inner = [w for w in old2.Wires if not w.isSame(old2.OuterWire)]
            if inner:
                face = face.cutHoles(inner)
            face.fix(1e-7, 1e-7, tol)
            built = whole.replaceShape([(old2, face)])
        except Exception as exc:      # Part.OCCError and friends
            raise RuledError(f"{fit.Label}'s result could not be put into {part.Label} ({exc}); export the face "
                             "alone") from None
        edge_tol = max(e.Tolerance for e in face.Edges)
        if owner is not None:
            if built.ShapeType != "Solid" or not (built.isValid() and built.isClosed()) or _free(built):
                raise RuledError(f"{fit.Label}'s result put into {part.Label} does not give a valid closed solid "
                                 f"(FreeCAD's check; its edges lie up to {edge_tol:.3g} from the ruled surface); "
                                 "export the face alone, or fit it closer (Samples)")
            others = [s for s in part.Shape.Solids if not s.isSame(owner)]
            built = Part.makeCompound([built] + others) if others else built
        elif not built.isValid() or _free(built) > _free(part.Shape):
            raise RuledError(f"{fit.Label}'s result put into {part.Label} leaves it open where it was not; export "
                             "the face alone")
        obj.EdgeTolerance, obj.ClosedSolid, obj.Faces = edge_tol, owner is not None, len(built.Faces)
        obj.Shape = built


def _free(shape) -> int:
    """Edges of shape that bound one face only (where it is open)."""
    import Part
    return sum(1 for e in shape.Edges if not e.Degenerated and len(shape.ancestorsOfType(e, Part.Face)) == 1)


def make_ruled_replace(doc, fit):
    """A RuledReplace of a RuledFit (not recomputed); the source part hidden in the GUI."""
    obj = doc.addObject("Part::FeaturePython", "RuledReplace")
    RuledReplace(obj)
    obj.Fit = fit
    obj.Label = f"{fit.Source[0].Label} ruled"
    if FreeCAD.GuiUp:
        from .viewproviders import attach_view_provider
        attach_view_provider(obj)
        fit.Source[0].ViewObject.Visibility = False
        fit.ViewObject.Visibility = False
    return obj
