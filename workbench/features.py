"""Parametric objects of the Ruled workbench (no GUI imports: they recompute in freecadcmd too).

RuledFit: a ruled surface fitted to one face of another object (Source, a LinkSub), its fit
parameters as properties, its results (certified bound, measured Hausdorff distance, rulings, time)
as read-only properties, the ruled face as its Shape.  It recomputes when the source changes; bad
input leaves it invalid with a one-line message in the report view and in its Status property.

RuledSplit: the same face split for ruling (Wang & Elber §4): the optimal, best iso-parametric and
middle split curves, each side fitted; its Shape holds the two ruled fits of the best split and the
split edge on the face (the preview of the split curve).

Saved documents refer to the proxies as ``ruled_workbench.features.RuledFit`` / ``.RuledSplit``: keep
the names.
"""

from __future__ import annotations

import time

import FreeCAD

from . import quiet
from .measure import measure_into  # noqa: F401  (objects and walls import it from here)
from .names import element, is_face, short_name
from .progress import _Progress
from .state import LISTENERS, RUNNING, request_cancel  # noqa: F401  (the workbench's names for them)
from .units import length, lengths_in

RESULT_GROUP = "Result"
FIT_GROUP = "Fit"
LIMITS = ("no limit", "at most Max Error")       # RuledFit's ErrorLimit


# the data behind the view's colours and lines, not figures to read (a list of 0.00 mm): out of the property editor
HIDDEN = ("Deviation", "RulingLines")


# the links to the source faces and objects: global in scope (the source may lie in a part container or a
# PartDesign body while the result lies at the document's root: a local link there is out of its scope, which
# FreeCAD 1.0 warns about at every recompute)
LINK_SUB, LINK = "App::PropertyLinkSubGlobal", "App::PropertyLinkGlobal"


def _add(obj, kind, name, group, doc, value=None, readonly=False):
    if name not in obj.PropertiesList:
        obj.addProperty(kind, name, group, doc)
        if value is not None:
            setattr(obj, name, value)
    if readonly:
        obj.setEditorMode(name, 2 if name in HIDDEN else 1)


def _enum(obj, name, group, doc, values, default):
    if name not in obj.PropertiesList:
        obj.addProperty("App::PropertyEnumeration", name, group, doc)
        setattr(obj, name, values)
        setattr(obj, name, default)


def value(x) -> float:
    """A length property's number in mm: a Quantity's value, or the plain float of a document saved
    before the properties had units."""
    return float(getattr(x, "Value", x))


def source_face(obj):
    """The one face obj.Source names, or a BadInputError saying what is wrong."""
    from ruled.core.errors import BadInputError
    link = obj.Source
    if link is None or link[0] is None:
        raise BadInputError("no source face: select one face of a part and run the command again")
    src, subs = link
    subs = [s for s in (subs or []) if s]
    if len(subs) != 1 or not is_face(subs[0]):
        what = ", ".join(map(short_name, subs)) if subs else "the whole object"
        raise BadInputError(f"the source must be exactly one face, not {what}: select one face of {src.Label}")
    try:
        return element(src.Shape, subs[0])
    except Exception:  # Part raises IndexError / OCCError for stale names
        raise BadInputError(f"{src.Label} has no {short_name(subs[0])} any more (its shape changed); pick the face "
                            f"again") from None


_KERNELS_SAID = False


def say_kernels() -> None:
    """Once per session, in the report view: whether the engine runs its numba kernels in FreeCAD's
    Python or the NumPy code (the same results, about ten times slower)."""
    global _KERNELS_SAID
    if _KERNELS_SAID:
        return
    _KERNELS_SAID = True
    from ruled.core import jit
    if jit.enabled():
        FreeCAD.Console.PrintLog("Ruled: the numba kernels are in use\n")
    else:
        FreeCAD.Console.PrintWarning("Ruled: numba is not installed in FreeCAD's Python, so the fits run the "
                                     "NumPy code (the same results, about ten times slower); on Debian or "
                                     "Ubuntu: sudo apt-get install python3-numba\n")


def add_results(obj, what: str) -> None:
    """The result properties every Ruled object has: the certified bound, the measured Hausdorff distance
    with the deviations that colour it, the rulings, the time and the status."""
    _add(obj, "App::PropertyLength", "ErrorBound", RESULT_GROUP, f"certified upper bound of the distance of "
         f"{what} to the source face", 0.0, True)
    _add(obj, "App::PropertyLength", "Hausdorff", RESULT_GROUP, f"measured Hausdorff distance between {what} and "
         f"the source face (FreeCAD's BRepExtrema, independent of the fit)", 0.0, True)
    _add(obj, "App::PropertyFloatList", "Deviation", RESULT_GROUP, "measured distance of each sample of each result "
         "face to the source face (MeasureSamples x MeasureSamples per face, for colouring)", None, True)
    _add(obj, "App::PropertyVectorList", "RulingLines", RESULT_GROUP, "end points of the rulings, two per ruling",
         None, True)
    _add(obj, "App::PropertyFloat", "Seconds", RESULT_GROUP, "time of the last recompute", 0.0, True)
    _add(obj, "App::PropertyString", "Status", RESULT_GROUP, "ok, or what went wrong", "", True)


def ruling_lines(fits) -> list:
    """The DP rulings of the fits (FitResult) as end points, two per ruling."""
    return [FreeCAD.Vector(*map(float, p)) for f in fits for p in f.best.rulings.reshape(-1, 3)]


# the engine's options as this workbench's properties (the engine names them by key: ruled.core.errors)
PROPERTIES = {"samples": "Samples", "max_error": "MaxError", "tol": "Tolerance", "elevations": "Elevations",
              "lift_step": "Step", "arc_step": "Step", "split_elevations": "Elevations", "interior": "Interior",
              "max_strips": "MaxStrips",
              "fit_samples": "FitSamples", "dims": "Dims", "direction": "Direction", "objective": "Objective",
              "method": "Method", "metric": "Metric", "rails": "Rails", "allow_creases": "AllowCreases",
              "fit_first": "cone-spline a Ruled fit of it, or set FitFirst",
              "keep_creases": "set AllowCreases to keep the creases", "fit_help": "the object's properties",
              "edges_listing": "the face's outer-wire edges in order", "partition": "a Ruled split with a Tolerance",
              "walls_listing": "select the faces of one side wall (the ring of faces between the part's bottom and "
                               "top contours)", "one_face": "Fit ruled surface on it"}


def _camel(key: str) -> str:
    return "".join(w.capitalize() for w in key.split("_"))


def in_our_terms(message, shown: dict | None = None) -> str:
    """An engine error, warning or note as FreeCAD says it: the options it names are this object's
    properties, its lengths in the user's unit (workbench.units.lengths_in: shown, {the engine's figure: the one
    the object shows})."""
    from ruled.core.errors import in_terms, names_from
    return lengths_in(in_terms(message, names_from(PROPERTIES, _camel, " = ")), shown)


class _Feature:
    """What the proxies share: properties added on restore, and a recompute that leaves the object
    invalid with a one-line message (report view and Status) when the engine refuses."""

    capability = ""          # what its first use compiles (ruled.warm.NEEDS)

    def __init__(self, obj):
        self.add_properties(obj)
        obj.Proxy = self

    def onDocumentRestored(self, obj):
        self.add_properties(obj)            # properties added by later versions

    def inputs(self, obj, verb: str):
        """(source face, options, its surface as arrays, a progress indicator)."""
        from .adapter import face_to_arrays
        say_kernels()
        face = source_face(obj)
        opts = self.options(obj)
        return face, opts, face_to_arrays(face), _Progress(f"Ruled: {verb} {obj.Label}", capability=self.capability)

    def execute(self, obj):
        from ruled.core.errors import CancelledError, RuledError
        quiet.RESTORER.restore()      # (the report's error output, off while FreeCAD reported an earlier refusal)
        t0 = time.perf_counter()
        RUNNING.append(obj.Name)
        try:
            self.compute(obj)
            obj.Status = "ok"
        except RuledError as exc:
            obj.Status = in_our_terms(exc)
            obj.Seconds = time.perf_counter() - t0
            # the user's own cancel is no error: said as a message, not in the report's red
            say = FreeCAD.Console.PrintMessage if isinstance(exc, CancelledError) else FreeCAD.Console.PrintError
            say(f"{obj.Label}: {obj.Status}\n")
            quiet.RESTORER.arm()
            raise RuntimeError(obj.Status) from None        # FreeCAD marks the object invalid with this message
        finally:
            RUNNING.remove(obj.Name)
        obj.Seconds = time.perf_counter() - t0

    def __getstate__(self):
        return None

    def __setstate__(self, state):
        return None

    dumps, loads = __getstate__, __setstate__


class RuledFit(_Feature):
    """Proxy of a RuledFit object (Part::FeaturePython)."""

    capability = "fit"

    @staticmethod
    def add_properties(obj):
        _add(obj, LINK_SUB, "Source", "Ruled", "the face to fit (one face of a part)")
        _enum(obj, "Method", FIT_GROUP, "2d: rulings between boundary samples (Elber); 4d: their ends also "
              "lifted along the normal (Wang & Elber), never worse than 2d", ["2d", "4d"], "2d")
        _add(obj, "App::PropertyInteger", "Samples", FIT_GROUP, "samples per boundary", 40)
        _enum(obj, "Objective", FIT_GROUP, "sum of the ruling distances (Elber) or the largest one",
              ["sum", "max"], "sum")
        _add(obj, "App::PropertyLength", "MaxError", FIT_GROUP, "forbid rulings farther than this from the face "
             "(0: no limit)", 0.0)
        _enum(obj, "ErrorLimit", FIT_GROUP, "no limit, or forbid rulings farther than Max Error from the face (shown "
              "then)", list(LIMITS), LIMITS[value(obj.MaxError) > 0])
        obj.setEditorMode("MaxError", 0 if obj.ErrorLimit == LIMITS[1] else 2)
        _enum(obj, "Direction", FIT_GROUP, "which pair of opposite sides of the face the rulings join: v, its "
              "sides 0 and 2 (the v-min and v-max edges of an untrimmed face); u, sides 1 and 3; auto: the better",
              ["auto", "u", "v"], "auto")
        _add(obj, "App::PropertyInteger", "Elevations", FIT_GROUP, "4d: elevation levels on each side", 10)
        _add(obj, "App::PropertyLength", "Step", FIT_GROUP, "4d: elevation step in model units (0: the 2d result's "
             "distance / elevations)", 0.0)
        _enum(obj, "Metric", FIT_GROUP, "4d cost: lsad (each ruling's distance to the face) or sshb (certified "
              "bound of each bilinear patch)", ["lsad", "sshb"], "lsad")
        _add(obj, "App::PropertyBool", "Refine", FIT_GROUP, "refine the pairing beyond the samples", True)
        _add(obj, "App::PropertyInteger", "MeasureSamples", FIT_GROUP, "n x n samples per face for the measured "
             "Hausdorff distance (0: do not measure)", 40)
        _enum(obj, "Ends", FIT_GROUP, "trimmed: the rails run past the face and the result is trimmed by its "
              "edges, so rulings may cross its end edges; pinned: the end rulings at the face's corners; auto: the "
              "one with the smaller certified bound", ["auto", "pinned", "trimmed"], "auto")
        _add(obj, "App::PropertyString", "EndsUsed", RESULT_GROUP, "which result the fit returned (trimmed by "
             "the face's edges, or pinned at its corners) and why", "", True)
        _add(obj, "App::PropertyLength", "ErrorBound", RESULT_GROUP, "certified upper bound of the distance to the "
             "source face", 0.0, True)
        _add(obj, "App::PropertyLength", "Hausdorff", RESULT_GROUP, "measured Hausdorff distance (OCCT, "
             "independent of the fit)", 0.0, True)
        _add(obj, "App::PropertyInteger", "Rulings", RESULT_GROUP, "rulings of the DP path", 0, True)
        _add(obj, "App::PropertyFloat", "Seconds", RESULT_GROUP, "time of the last recompute", 0.0, True)
        _add(obj, "App::PropertyString", "Status", RESULT_GROUP, "ok, or what went wrong", "", True)
        _add(obj, "App::PropertyFloatList", "Deviation", RESULT_GROUP, "measured distance of each sample of the "
             "result to the source face (MeasureSamples x MeasureSamples over its parameters, for colouring)",
             None, True)
        _add(obj, "App::PropertyVectorList", "RulingLines", RESULT_GROUP, "end points of the DP rulings on the "
             "source face, two per ruling", None, True)
        _add(obj, "App::PropertyStringList", "Rails", RESULT_GROUP, "the source's edges the rulings join (two "
             "opposite sides of the face)", None, True)
        _add(obj, "App::PropertyBool", "Trimmed", RESULT_GROUP, "the face is trimmed: it is fitted as bounded by "
             "its edges (its own four-sided patch), not as its surface's rectangle", False, True)
        _add(obj, "App::PropertyLength", "PatchDeviation", RESULT_GROUP, "the face's four-sided patch's distance to "
             "the face (included in ErrorBound)", 0.0, True)

    def options(self, obj):
        from ruled import FitOptions
        return FitOptions(samples=int(obj.Samples), objective=str(obj.Objective),
                          max_error=value(obj.MaxError) if obj.ErrorLimit == LIMITS[1] and value(obj.MaxError) > 0
                          else None,
                          direction=str(obj.Direction), refine=bool(obj.Refine), method=str(obj.Method),
                          elevations=int(obj.Elevations) if obj.Method == "4d" else None,
                          step=value(obj.Step) if obj.Method == "4d" and value(obj.Step) > 0 else None,
                          metric=str(obj.Metric), ends=str(obj.Ends)).checked()

    def onChanged(self, obj, prop):
        """'no limit' says so (Max Error hidden); a Max Error set (by the panel, by Python) sets the limit with it."""
        if "ErrorLimit" not in obj.PropertiesList or "Restore" in obj.State:
            return
        if prop == "MaxError" and obj.ErrorLimit != LIMITS[value(obj.MaxError) > 0]:
            obj.ErrorLimit = LIMITS[value(obj.MaxError) > 0]
        elif prop == "ErrorLimit":
            obj.setEditorMode("MaxError", 0 if obj.ErrorLimit == LIMITS[1] else 2)

    def onDocumentRestored(self, obj):
        before = "Ends" not in obj.PropertiesList
        super().onDocumentRestored(obj)
        if before:          # saved before issue 35: its result was pinned at the face's corners, and stays so
            obj.Ends = "pinned"

    def compute(self, obj):
        from ruled.core.hostform import bounds_slack
        from ruled.fit.face.fit import fit_region
        from ruled.fit.face.verdict import area_ratio, first_consistent, measured_warnings

        from .adapter import built_slack, face_region, outer_edges, result_face
        face, opts, S, progress = self.inputs(obj, "fitting")
        names = source_edge_names(obj, outer_edges(face))

        def built(res):
            """The result face, its figures on obj, and what only the measure says (FiguresError where its
            figures disagree: the next candidate is tried)."""
            result = result_face(res)
            obj.ErrorBound = float(res.error_bound + bounds_slack(S, face.ParameterRange) + built_slack(result, res))
            p = res.patch
            obj.Rails = [" + ".join(names[k] for k in rail) or "a point" for rail in p.rails(res.direction)]
            obj.Trimmed = not p.identity
            obj.PatchDeviation = float(p.deviation)
            obj.Rulings = int(len(res.best.rulings))
            obj.RulingLines = ruling_lines([res])
            measure_into(obj, [result], face, lambda f: progress("measuring (distances to the source)", f))
            if int(obj.MeasureSamples) < 2:
                return result, ()
            return result, measured_warnings(res, float(obj.ErrorBound), float(obj.Hausdorff), p.face_size,
                                             area_ratio(res, float(face.Area), float(result.Area)))
        try:
            res, result, more = first_consistent(progress.run(fit_region, face_region(face, S), opts, progress), built)
            p = res.patch      # (the fit's bound read as the object's: the same figure in the panel and here)
            figures = [p.edge_gap, p.deviation, p.face_size, value(obj.Hausdorff)] + \
                [c.error_bound for c in res.candidates.values() if hasattr(c, "error_bound")]
            shown = {(res.error_bound, value(obj.ErrorBound)): obj.ErrorBound, **{f: f for f in figures}}
            for w in tuple(p.warnings) + tuple(more):
                FreeCAD.Console.PrintWarning(f"{obj.Label}: {in_our_terms(w, shown)}\n")
            for note in res.notes:          # what the fit decided (the iso surface, the next candidate)
                FreeCAD.Console.PrintMessage(f"{obj.Label}: {in_our_terms(note, shown)}\n")
            obj.EndsUsed = next((in_our_terms(n, shown) for n in reversed(res.notes) if "rail" in n or "corners" in n),
                                "trimmed by the face's edges" if res.best.trim is not None else
                                "pinned at the face's corners")
        finally:
            progress.stop()
        obj.Shape = result


class RuledSplit(_Feature):
    """Proxy of a RuledSplit object (Part::FeaturePython)."""

    capability = "split"

    @staticmethod
    def add_properties(obj):
        group = "Split"
        _add(obj, LINK_SUB, "Source", "Ruled", "the face to split (one face of a part)")
        _add(obj, "App::PropertyInteger", "Samples", group, "P-, Q- and M-columns of the split DP", 30)
        _add(obj, "App::PropertyInteger", "Interior", group, "interior M-rows of the split DP", 10)
        _enum(obj, "Dims", group, "split DP: 4 (nothing elevated), 5 (M-points lifted along the normal), 7 (P, Q "
              "and M lifted)", ["4", "5", "7"], "4")
        _enum(obj, "Objective", group, "the largest line metric along the M-curve (the paper's) or their sum",
              ["max", "sum"], "max")
        _add(obj, "App::PropertyInteger", "FitSamples", group, "samples per boundary of each side's fit", 40)
        _add(obj, "App::PropertyString", "Chosen", RESULT_GROUP, "the split kept: optimal, best-iso or iso-0.5 (none: "
             "the face needs no split, its own fit is better, and is the result)", "", True)
        _add(obj, "App::PropertyLength", "WholeBound", RESULT_GROUP, "certified bound of one ruled fit of the whole "
             "face", 0.0, True)
        _add(obj, "App::PropertyStringList", "Candidates", RESULT_GROUP, "each split's certified bound", None, True)
        _add(obj, "App::PropertyVectorList", "SplitCurve", RESULT_GROUP, "points of the kept split curve on the face",
             None, True)
        _add(obj, "App::PropertyInteger", "MeasureSamples", group, "n x n samples per fitted side for the measured "
             "Hausdorff distance and the colours (0: do not measure)", 16)
        add_results(obj, "the kept split's two fitted sides (together)")

    def options(self, obj):
        from ruled import FitOptions
        from ruled.split.partition import SplitOptions
        return SplitOptions(samples=int(obj.Samples), interior=int(obj.Interior), objective=str(obj.Objective),
                            dims=int(obj.Dims), fit=FitOptions(samples=int(obj.FitSamples)).checked()).checked()

    def compute(self, obj):
        from ruled.fit.face.fit import face_patch
        from ruled.split.partition import split_face

        from .adapter import face_region
        face, opts, S, progress = self.inputs(obj, "splitting")
        try:
            region = face_region(face, S)
            patch = face_patch(region)     # the face as bounded by its edges
            for w in patch.warnings:
                FreeCAD.Console.PrintWarning(f"{obj.Label}: {in_our_terms(w)}\n")
            res = progress.run(split_face, patch.surface, opts, progress)
            whole = unsplit_fit(region, face, opts.fit, progress)
            self.finish(obj, face, patch.surface, res, progress, float(patch.deviation), whole)
        finally:
            progress.stop()

    def finish(self, obj, face, S, res, progress, dev: float, whole=None):
        """The kept split's faces, measure and rulings; the bounds against the face as bounded by its edges
        (the split's, against the face's four-sided patch, plus the patch's deviation dev).  whole: (the face's
        fit unsplit as a Part.Face, its bound, its rulings' fit); where the split is not better than it, the
        object is that fit (the face needs no split), and says so."""
        import numpy as np
        import Part

        from ruled.curves.curve_on_surface import approximate
        from ruled.split.strips import EDGE_TOL, input_curve

        from .adapter import curve_to_edge, surface_to_face
        best = res.best()
        obj.Candidates = [f"{k}: {c.bound + dev:.6g}" for k, c in res.candidates.items()]
        if whole is not None and not best.bound + dev < whole[1]:
            result, bound, fit = whole
            measure_into(obj, [result], face, lambda f: progress("measuring (distances to the source)", f))
            obj.RulingLines = ruling_lines([fit])
            obj.Shape, obj.Chosen, obj.ErrorBound, obj.WholeBound = result, "none", bound, bound
            obj.SplitCurve = []
            FreeCAD.Console.PrintMessage(f"{obj.Label}: the face needs no split: its fit is {length(bound)} (the best "
                                         f"split's worse side is {length(best.bound + dev)})\n")
            return
        cos = approximate(S, input_curve(best.curve, res.transposed), EDGE_TOL * S.diagonal(), 10.0)
        fits = [surface_to_face(side.fit.surface) for side in best.sides]
        measure_into(obj, fits, face, lambda f: progress("measuring (distances to the source)", f))
        obj.RulingLines = ruling_lines(side.fit for side in best.sides)
        obj.Shape = Part.makeCompound(fits + [curve_to_edge(cos.curve)])
        obj.Chosen, obj.ErrorBound = best.name, best.bound + dev
        obj.WholeBound = res.whole.bound + dev if whole is None else min(res.whole.bound + dev, whole[1])
        t = np.linspace(*cos.curve.domain, 101)
        obj.SplitCurve = [FreeCAD.Vector(*map(float, p)) for p in cos.curve(t)]


def unsplit_fit(region, face, options, progress) -> tuple:
    """(the face's fit as 'ruled fit' fits it, built as a Part.Face; its certified bound against the face as
    bounded by its edges; the fit): what a split must beat to be kept."""
    from dataclasses import replace

    from ruled.core.hostform import bounds_slack
    from ruled.fit.face.fit import fit_region

    from .adapter import built_slack, result_face
    res = progress.run(fit_region, region, replace(options, ends="auto").checked(), progress)
    result = result_face(res)
    return result, float(res.error_bound + bounds_slack(region.surface, face.ParameterRange)
                         + built_slack(result, res)), res


def source_edge_names(obj, edges) -> list:
    """The source object's names ("Edge7") of the given edges of its face."""
    all_edges = obj.Source[0].Shape.Edges
    out = []
    for e in edges:
        k = next((i for i, x in enumerate(all_edges) if x.isSame(e)), None)
        out.append("?" if k is None else f"Edge{k + 1}")
    return out


# the label of a new object, after its source face ("Ruled Face7"; FreeCAD numbers repeats)
LABELS = {"RuledFit": "Ruled {}", "RuledSplit": "Split {}", "RuledPartition": "Strips {}",
          "RuledConeSpline": "Cone spline {}", "RuledCurveOnFace": "Curve on {}"}


def _make(doc, proxy, source, subname: str, properties: dict):
    obj = doc.addObject("Part::FeaturePython", proxy.__name__)
    proxy(obj)
    obj.Source = (source, [subname] if subname else [])
    obj.Label = LABELS.get(proxy.__name__, "{}").format(short_name(subname) if subname else f"of {source.Label}")
    for k, v in properties.items():
        setattr(obj, k, v)
    return obj


def make_ruled_split(doc, source, subname: str, **properties):
    """A RuledSplit on source's face subname with the given properties (not recomputed)."""
    obj = _make(doc, RuledSplit, source, subname, properties)
    if FreeCAD.GuiUp:
        from .viewproviders import attach_view_provider
        attach_view_provider(obj)
    return obj


def fit_defaults() -> dict:
    """The defaults of new fits from the preferences (Edit > Preferences > Ruled)."""
    g = FreeCAD.ParamGet("User parameter:BaseApp/Preferences/Mod/Ruled/Fit")
    return {"Samples": g.GetInt("Samples", 40), "MeasureSamples": g.GetInt("MeasureSamples", 40)}


def make_ruled_fit(doc, source, subname: str, **properties):
    """A RuledFit on source's face subname (e.g. "Face3") with the given fit properties (not recomputed);
    the others from the preferences."""
    obj = _make(doc, RuledFit, source, subname, {**fit_defaults(), **properties})
    if FreeCAD.GuiUp:
        from .viewproviders import attach_view_provider
        attach_view_provider(obj)
    return obj
