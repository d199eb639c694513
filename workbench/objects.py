"""Parametric objects beside RuledFit and RuledSplit (no GUI imports: they recompute in freecadcmd too).

RuledPartition: a face split into strips until every strip's ruled fit is within a tolerance (the
command line's ``ruled fit --tol``): the strips' fits and the split curves on the face, each strip's
certified bound, and which splitting was kept (optimal or uniform iso-parametric, the fewer strips).

RuledConeSpline: the cone spline (tangent-continuous developable patches, Yang & Yang) of a RuledFit
or of a ruled face (optionally fitted first): the patches sewn, their kinds, the eq. 9 bound, the
largest angle between neighbouring patches, measured against the design face.

RuledCurveOnFace: a curve lying on a face (Wang & Elber's curves on surfaces) from a (u, v) domain
curve given by a sketch (its x, y mapped onto the face's parameters) or by points picked on the face:
the edge within the tolerance of the exact image, its certified bound and its measured distances.

Saved documents refer to the proxies as ``ruled_workbench.objects.<Name>``: keep the names.
"""

from __future__ import annotations

import FreeCAD

from .features import (
    LINK,
    LINK_SUB,
    RESULT_GROUP,
    _add,
    _enum,
    _Feature,
    _make,
    _Progress,
    add_results,
    in_our_terms,
    measure_into,
    ruling_lines,
    say_kernels,
    source_face,
    value,
)
from .units import length


class RuledPartition(_Feature):
    """Proxy of a RuledPartition object (Part::FeaturePython)."""

    capability = "partition"

    @staticmethod
    def add_properties(obj):
        group = "Partition"
        _add(obj, LINK_SUB, "Source", "Ruled", "the face to partition (one face of a part)")
        _add(obj, "App::PropertyLength", "Tolerance", group, "every strip's certified bound within this (against the "
             "face as bounded by its edges)", 0.05)
        _add(obj, "App::PropertyInteger", "MaxStrips", group, "refuse beyond this many strips", 16)
        _add(obj, "App::PropertyInteger", "Samples", group, "split DP: P-, Q- and M-columns", 30)
        _add(obj, "App::PropertyInteger", "Interior", group, "split DP: interior M-rows", 10)
        _add(obj, "App::PropertyInteger", "FitSamples", group, "samples per boundary of each strip's fit", 40)
        _add(obj, "App::PropertyInteger", "MeasureSamples", group, "n x n samples per strip for the measured "
             "Hausdorff distance and the colours (0: do not measure)", 16)
        _add(obj, "App::PropertyInteger", "Strips", RESULT_GROUP, "strips of the kept splitting", 0, True)
        _add(obj, "App::PropertyString", "Used", RESULT_GROUP, "the splitting kept: optimal (recursive optimal "
             "splits) or uniform (equal iso-parametric strips), whichever needs fewer strips", "", True)
        _add(obj, "App::PropertyStringList", "StripBounds", RESULT_GROUP, "each strip's certified bound", None, True)
        _add(obj, "App::PropertyInteger", "UniformStrips", RESULT_GROUP, "strips that uniform iso-parametric "
             "splitting needs (0: more than MaxStrips)", 0, True)
        add_results(obj, "the strips' ruled fits (together)")

    def options(self, obj):
        from ruled import FitOptions
        from ruled.split.partition import SplitOptions
        return SplitOptions(samples=int(obj.Samples), interior=int(obj.Interior), max_strips=int(obj.MaxStrips),
                            fit=FitOptions(samples=int(obj.FitSamples)).checked()).checked()

    def compute(self, obj):
        import Part

        from ruled.core.errors import BadInputError
        from ruled.curves.curve_on_surface import approximate
        from ruled.fit.face.fit import face_patch
        from ruled.split.partition import partition
        from ruled.split.strips import EDGE_TOL, input_curve

        from .adapter import curve_to_edge, face_region, surface_to_face
        tol = value(obj.Tolerance)
        if not tol > 0:
            raise BadInputError("the Tolerance must be a positive length: set it to the largest distance each "
                                "strip's ruled surface may have from the face")
        face, opts, S, progress = self.inputs(obj, "partitioning")
        try:
            patch = face_patch(face_region(face, S))
            for w in patch.warnings:
                FreeCAD.Console.PrintWarning(f"{obj.Label}: {in_our_terms(w)}\n")
            S, dev = patch.surface, float(patch.deviation)
            if dev >= 0.5 * tol:
                raise BadInputError(f"the Tolerance {length(tol)} is too tight for this trimmed face: its own "
                                    f"four-sided patch, which the strips split, is {length(dev)} from it; raise the "
                                    f"Tolerance above {length(2 * dev)}")
            p = progress.run(partition, S, tol - dev, opts, progress)     # the strips within tol of the face as bounded
            fits = [surface_to_face(s.fit.surface) for s in p.strips]
            measure_into(obj, fits, face, lambda f: progress("measuring (distances to the source)", f))
        finally:
            progress.stop()
        curves = [approximate(S, input_curve(s.strip.hi, p.transposed), EDGE_TOL * S.diagonal(), 10.0).curve
                  for s in p.strips[:-1]]
        obj.Shape = Part.makeCompound(fits + [curve_to_edge(c) for c in curves])
        obj.Strips, obj.Used, obj.UniformStrips = len(p.strips), p.used, int(p.uniform_count or 0)
        obj.StripBounds = [f"strip {k + 1}: {b + dev:.6g}" for k, b in enumerate(p.bounds)]
        obj.ErrorBound = float(max(p.bounds) + dev)
        obj.RulingLines = ruling_lines(s.fit for s in p.strips)


def cone_source(obj):
    """(the ruled surface as arrays, the face's boundary on it as a ruled.fit.face.trim.Trim or None, the design face
    to measure against, the ruled fit's bound or None when the source is a face) of a RuledConeSpline's Source:
    a RuledFit (its result as it is: trimmed by the face's edges where it is), or a face of a part."""
    from ruled.core.errors import BadInputError

    from .adapter import face_to_arrays, surface_to_arrays, trim_of
    link = obj.Source
    if link is None or link[0] is None:
        raise BadInputError("no source: select a Ruled fit, or one ruled face of a part, and run the command again")
    src, subs = link
    subs = [s for s in (subs or []) if s]
    if not subs and type(getattr(src, "Proxy", None)).__name__ == "RuledFit":
        from .measure import trimmed
        if not src.Shape.Faces:
            raise BadInputError(f"{src.Label} has no result yet (see its Status); recompute it first")
        result = src.Shape.Faces[0]
        if not trimmed(result):
            return face_to_arrays(result), None, source_face(src), value(src.ErrorBound)
        A = surface_to_arrays(result.Surface)        # the whole ruled surface, rail to rail, as 'ruled cone' takes it
        return A, trim_of(result, A), source_face(src), value(src.ErrorBound)
    face = source_face(obj)
    return face_to_arrays(face), None, face, None


def fitted(region, face, options, progress) -> tuple:
    """(the ruled surface, the face's boundary on it or None, its certified bound against the face as bounded by
    its edges) of the face's fit as 'ruled fit' fits it (the smaller bound of the fit pinned to its corners and
    the one trimmed by its edges)."""
    from dataclasses import replace

    from ruled.core.hostform import bounds_slack
    from ruled.fit.face.fit import fit_region
    res = progress.run(fit_region, region, replace(options, ends="auto").checked(), progress)
    return res.surface, res.best.trim, float(res.error_bound + bounds_slack(region.surface, face.ParameterRange))


def cone_measure(obj, cone, faces, design, progress, patch_of=None) -> None:
    """What the cone spline's ErrorBound bounds, measured (as ``ruled cone`` measures it): the design face's
    points to the patches (FreeCAD's BRepExtrema) and the patches' points, an n x n grid over each (also
    their colours), to the ruled surface between the planes of its end curves (exact distances to its
    ruling segments).  The patches span that surface: where the face's end curves are not planar they run
    past the face, as far as those planes, so their distance to the face itself is not what is bounded.
    Patches trimmed by the face's edges (patch_of: each face's patch) are measured against the face both
    ways: their points to the face too."""
    import numpy as np
    import Part

    from ruled.cone.report import to_ruled

    from .measure import distances, face_points, grid
    n = int(obj.MeasureSamples)
    if n < 2:
        obj.Hausdorff, obj.Deviation = 0.0, []
        return
    _, to_surface = to_ruled(cone, [grid(f, n) for f in faces], patch_of)
    pts = np.concatenate([face_points(f, n) for f in design.Faces])
    to_cone = distances(pts, Part.Compound(faces), lambda f: progress("measuring (the face to the patches)", f))
    back = 0.0
    if patch_of is not None:
        mine = np.concatenate([face_points(f, n) for f in faces])
        back = float(distances(mine, design, lambda f: progress("measuring (the patches to the face)", f)).max())
    obj.Hausdorff, obj.Deviation = float(max(to_surface.max(), to_cone.max(), back)), list(to_surface)


class RuledConeSpline(_Feature):
    """Proxy of a RuledConeSpline object (Part::FeaturePython)."""

    @staticmethod
    def add_properties(obj):
        group = "Cone spline"
        _add(obj, LINK_SUB, "Source", "Ruled", "a Ruled fit (the whole object), or one ruled face of "
             "a part")
        _add(obj, "App::PropertyLength", "Tolerance", group, "largest distance of the patches from the ruled surface "
             "(eq. 9)", 0.05)
        _add(obj, "App::PropertyFloat", "Step", group, "first arc step along the boundaries (a fraction of the "
             "parameter range, 0 < step <= 1)", 0.1)
        _enum(obj, "Direction", group, "the rulings of a ruled face: along u, v, or auto", ["auto", "u", "v"], "auto")
        _add(obj, "App::PropertyBool", "FitFirst", group, "a face that is not ruled is fitted first (2d, 40 samples) "
             "and the fit is cone-splined", False)
        _add(obj, "App::PropertyBool", "AllowCreases", group, "keep a cone spline whose neighbouring patches meet at "
             "creases (not tangent continuous) instead of refusing it", False)
        _add(obj, "App::PropertyInteger", "MeasureSamples", group, "n x n samples per patch for the measured "
             "Hausdorff distance to the design face and the colours (0: do not measure)", 12)
        _add(obj, "App::PropertyInteger", "Patches", RESULT_GROUP, "cone and cylinder patches", 0, True)
        _add(obj, "App::PropertyInteger", "Pieces", RESULT_GROUP, "pieces between parallel planes (patches within a "
             "piece are tangent continuous)", 0, True)
        _add(obj, "App::PropertyLength", "ConeBound", RESULT_GROUP, "the largest eq. 9 bound: patches to the ruled "
             "surface", 0.0, True)
        _add(obj, "App::PropertyLength", "FitBound", RESULT_GROUP, "the ruled fit's certified bound to the design "
             "face (0: the face is ruled itself)", 0.0, True)
        _add(obj, "App::PropertyFloat", "MaxG1Angle", RESULT_GROUP, "largest angle between the normals of "
             "neighbouring patches along their common ruling (degrees)", 0.0, True)
        _add(obj, "App::PropertyBool", "Developable", RESULT_GROUP, "every patch is developable (Theorem 1)", False,
             True)
        add_results(obj, "the patches (ConeBound + FitBound)")
        for name, text in (("Hausdorff", "measured (cone_measure): the design face to the patches, and the patches "
                                         "to the ruled surface between the planes of its end curves, which they span "
                                         "(where those curves are not planar the patches run past the face)"),
                           ("Deviation", "measured distance of each patch sample to the ruled surface between the "
                                         "planes (MeasureSamples x MeasureSamples per patch, for colouring)")):
            if hasattr(obj, "setDocumentation"):
                obj.setDocumentation(name, text)

    def compute(self, obj):
        import Part

        from ruled import FitOptions
        from ruled.cone.surface import cone_spline_of_surface
        from ruled.core.errors import BadInputError
        from ruled.fit.face.fit import face_patch

        from .adapter import face_region, surface_to_face
        tol = value(obj.Tolerance)
        if not tol > 0:
            raise BadInputError("the Tolerance must be a positive length: the largest distance of the cone patches "
                                "from the ruled surface")
        if not 0 < float(obj.Step) <= 1:
            raise BadInputError(f"the Step {obj.Step:g} must be a fraction of the parameter range, 0 < step <= 1")
        say_kernels()
        S, trim, design, fit_bound = cone_source(obj)
        progress = _Progress(f"Ruled: cone spline of {obj.Label}", capability="cone")
        try:
            if fit_bound is None:
                region = face_region(design, S)
                if obj.FitFirst:
                    S, trim, fit_bound = fitted(region, design, FitOptions(direction=str(obj.Direction)).checked(),
                                                progress)
                else:
                    patch = face_patch(region)       # the face as bounded by its edges
                    S, fit_bound = patch.surface, (None if patch.identity else float(patch.deviation))
            patch_of, direction = None, str(obj.Direction)
            if trim is not None:
                # a fit trimmed by the face's edges: the rulings that cross the face, their patches trimmed like it
                from ruled.cone.trim import trimmed_patches
                from ruled.machine.trimmed import trimmed_lines

                from .adapter import trimmed_face
                S, direction = trimmed_lines(S, (trim.outer,) + tuple(trim.holes))[0], "v"
            cone = progress.run(cone_spline_of_surface, S, tol, float(obj.Step), direction=direction,
                                progress=progress, allow_creases=bool(obj.AllowCreases))
            if trim is None:
                faces = [surface_to_face(p.surface) for p in cone.patches]
            else:
                regions = trimmed_patches(cone, S, trim)
                faces = [trimmed_face(cone.patches[r.patch].surface, r.trim()) for r in regions]
                patch_of = [r.patch for r in regions]
            cone_measure(obj, cone, faces, design, progress, patch_of)
        finally:
            progress.stop()
        for note in cone.notes:
            FreeCAD.Console.PrintWarning(f"{obj.Label}: {note}\n")
        shell = Part.makeShell(faces)
        try:
            shell.sewShape()
        except Exception:  # Part.OCCError: kept unsewn, the patches as they are
            FreeCAD.Console.PrintWarning(f"{obj.Label}: the patches could not be sewn; they are kept as they are\n")
        obj.Shape = shell
        obj.Patches, obj.Pieces = len(cone.patches), len(cone.pieces)
        obj.ConeBound, obj.FitBound = float(cone.bound), float(fit_bound or 0.0)
        obj.ErrorBound = float(cone.bound + (fit_bound or 0.0))
        obj.MaxG1Angle, obj.Developable = float(cone.max_g1_deg), all(p.developable for p in cone.patches)
        obj.RulingLines = []


PICK_TOL = 1e-2          # a picked point this far from the face (a fraction of its size) is not on it


class RuledCurveOnFace(_Feature):
    """Proxy of a RuledCurveOnFace object (Part::FeaturePython)."""

    @staticmethod
    def add_properties(obj):
        group = "Curve"
        _add(obj, LINK_SUB, "Source", "Ruled", "the face the curve lies on (one face of a part)")
        _add(obj, LINK, "Sketch", group, "a sketch whose edges (x, y) are mapped onto the face's "
             "(u, v) (see Mapping); each edge becomes a curve on the face")
        _add(obj, "App::PropertyVectorList", "Points", group, "points on the face (picked in the 3D view): the "
             "curve runs through them (used without a Sketch)")
        _add(obj, "App::PropertyBool", "Smooth", group, "through the points: a smooth cubic spline in the face's "
             "(u, v), no corner at a point (true), or straight between them in (u, v) (false)", True)
        _enum(obj, "Mapping", group, "how a sketch's x, y become (u, v): unit square, x and y from 0 to 1 across the "
              "face's parameter range; parameters, x = u and y = v", ["unit square", "parameters"], "unit square")
        _add(obj, "App::PropertyLength", "Tolerance", group, "largest distance of the curve from the exact image of "
             "the (u, v) curve on the face (0: 1e-5 of the face's size)", 0.0)
        _add(obj, "App::PropertyAngle", "Angle", group, "largest angle between the curve's pieces at their joints",
             1.0)
        _add(obj, "App::PropertyInteger", "MeasureSamples", group, "samples along each curve for the measured "
             "distances (0: do not measure)", 400)
        _add(obj, "App::PropertyInteger", "Segments", RESULT_GROUP, "pieces of the curves (together)", 0, True)
        _add(obj, "App::PropertyLength", "OnFace", RESULT_GROUP, "measured largest distance of the curves from the "
             "face (FreeCAD's BRepExtrema)", 0.0, True)
        add_results(obj, "the curves (to the exact images of the (u, v) curves)")
        obj.setEditorMode("Deviation", 2)
        obj.setEditorMode("RulingLines", 2)

    def onDocumentRestored(self, obj):
        before = "Smooth" not in obj.PropertiesList
        super().onDocumentRestored(obj)
        if before:          # saved before issue 38: its curve ran straight between the points, and stays so
            obj.Smooth = False

    def domain_curves(self, obj, face, S) -> list:
        """The (u, v) curves: the sketch's edges mapped onto the face, or a polyline through the points."""
        from ruled.core.errors import BadInputError
        from ruled.curves.domain import domain_curve_from_json, polyline_curve, smooth_curve
        u0, u1, v0, v1 = S.domain
        if obj.Sketch is not None:
            unit = obj.Mapping == "unit square"
            curves = []
            for e in obj.Sketch.Shape.Edges:
                bc = e.Curve.toBSpline(*e.ParameterRange)
                local = [obj.Sketch.Placement.inverse().multVec(p) for p in bc.getPoles()]
                pts = [[u0 + p.x * (u1 - u0), v0 + p.y * (v1 - v0)] if unit else [p.x, p.y] for p in local]
                knots = [k for k, m in zip(bc.getKnots(), bc.getMultiplicities()) for _ in range(m)]
                curves.append(domain_curve_from_json({"degree": bc.Degree, "knots": knots, "points": pts,
                                                      "weights": bc.getWeights() if bc.isRational() else None}))
            if not curves:
                raise BadInputError(f"the sketch {obj.Sketch.Label} has no edges: draw the curve in it")
            return curves
        if len(obj.Points) < 2:
            raise BadInputError("no curve: pick at least two points on the face, or give a Sketch")
        import Part
        uv, size = [], face.BoundBox.DiagonalLength
        for k, p in enumerate(obj.Points):
            d = face.distToShape(Part.Vertex(p))[0]
            if d > PICK_TOL * size:     # picks land on the face's tessellation, close to it
                raise BadInputError(f"point {k + 1} ({p.x:.4g}, {p.y:.4g}, {p.z:.4g}) is {length(d)} from the face: "
                                    f"pick the points on the face")
            u, v = face.Surface.parameter(p)
            uv.append([u, v])
        return [smooth_curve(uv) if getattr(obj, "Smooth", True) else polyline_curve(uv)]

    def compute(self, obj):
        import numpy as np
        import Part

        from ruled.curves.curve_on_surface import approximate
        from ruled.curves.domain import check_inside

        from .adapter import curve_to_edge, face_region, face_to_arrays
        from .measure import distances
        say_kernels()
        face = source_face(obj)
        if not isinstance(face.Surface, Part.BSplineSurface):   # (u, v) of the B-spline the engine sees
            face = face.toNurbs().Faces[0]
        S = face_to_arrays(face)
        region = face_region(face, S)
        tol = value(obj.Tolerance) or 1e-5 * S.diagonal()
        curves = self.domain_curves(obj, face, S)
        progress = _Progress(f"Ruled: curve on {obj.Label}", capability="curve")
        results = []
        try:
            for k, D in enumerate(curves):
                check_inside(region, D)
                results.append(progress.run(approximate, S, D, tol, float(getattr(obj.Angle, "Value", obj.Angle)),
                                            progress=lambda st, f, k=k: progress(st, (k + f) / len(curves))))
        finally:
            progress.stop()
        edges = [curve_to_edge(r.curve) for r in results]
        obj.Shape = edges[0] if len(edges) == 1 else Part.makeCompound(edges)
        # (a piece composed exactly is certified 0 off; its poles are computed in floating point: ROUND)
        obj.ErrorBound = float(max(r.error_bound for r in results) + ROUND * S.diagonal())
        obj.Segments = int(sum(r.segments for r in results))
        n = int(obj.MeasureSamples)
        if n >= 2:
            on, far = [], []
            for D, e in zip(curves, edges):
                exact = _image(face, D, n)
                pts = np.array([tuple(e.valueAt(float(x))) for x in np.linspace(*e.ParameterRange, n)])
                on.append(distances(pts, face).max())
                # both ways: the exact image's samples to the edge and the edge's samples to the exact image,
                # each the nearest of 8 n samples refined by a golden-section search between its neighbours
                # (OCCT's point-to-curve extrema miss the nearest point on curves with C0 joints)
                def on_edge(t, e=e):
                    return np.array([tuple(e.valueAt(float(x))) for x in np.atleast_1d(t)])
                far.append(max(_to_curve(exact, on_edge, *e.ParameterRange, 8 * n),
                               _to_curve(pts, lambda t, D=D: _image_at(face, D, t), *D.domain, 8 * n)))
            obj.OnFace, obj.Hausdorff = float(max(on)), float(max(far))
        else:
            obj.OnFace, obj.Hausdorff = 0.0, 0.0


def _image(face, D, n: int):
    """n points of the exact image S(D(t)) of a domain curve on the face (FreeCAD's evaluation)."""
    import numpy as np
    return _image_at(face, D, np.linspace(*D.domain, n))


def _image_at(face, D, t):
    """The exact image S(D(t)) at the parameters t (FreeCAD's evaluation of the face's surface)."""
    import numpy as np
    uv = D(np.clip(np.atleast_1d(np.asarray(t, float)), *D.domain))[:, :2]
    return np.array([tuple(face.Surface.value(float(u), float(v))) for u, v in uv])


ROUND = 1e-12            # a result composed exactly: its poles' round-off, a fraction of the face's size


def _to_curve(X, curve, t0: float, t1: float, m: int):
    """The largest distance from the points X to the curve t -> curve(t) on [t0, t1] (arrays of parameters to
    (N, 3) points): the nearest of m samples, refined by a golden-section search between its neighbours."""
    import numpy as np

    from ruled.core.distance import _golden_min
    ts = np.linspace(t0, t1, m)
    C = curve(ts)
    k = np.argmin(np.linalg.norm(X[:, None, :] - C[None], axis=2), axis=1)
    best = np.linalg.norm(C[k] - X, axis=1)
    refined = _golden_min(lambda t: np.linalg.norm(curve(t) - X, axis=1), ts[np.maximum(k - 1, 0)],
                          ts[np.minimum(k + 1, m - 1)], 40)
    return float(np.minimum(best, refined).max())


def make_ruled_partition(doc, source, subname: str, **properties):
    """A RuledPartition on source's face subname (not recomputed)."""
    return _with_view(_make(doc, RuledPartition, source, subname, properties))


def make_ruled_cone_spline(doc, source, subname: str = "", **properties):
    """A RuledConeSpline of a RuledFit (subname "") or of source's face subname (not recomputed)."""
    return _with_view(_make(doc, RuledConeSpline, source, subname, properties))


def make_ruled_curve(doc, source, subname: str, sketch=None, points=(), **properties):
    """A RuledCurveOnFace on source's face subname, from a sketch or from points on the face."""
    obj = _make(doc, RuledCurveOnFace, source, subname, properties)
    if sketch is not None:
        obj.Sketch = sketch
    if points:
        obj.Points = [FreeCAD.Vector(*p) for p in points]
    return _with_view(obj)


def _with_view(obj):
    if FreeCAD.GuiUp:
        from .viewproviders import attach_view_provider
        attach_view_provider(obj)
    return obj
