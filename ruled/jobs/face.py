"""A face's whole job: read, fit, build, measure, write (``ruled fit``, ``ruled.cq.fit_face``, the batch).

fit_job is the result every door shows and everything made from a face's fit starts from: the fit whose own
figures agree (ruled.fit.face.verdict.first_consistent: the best candidate, or the next one whose built face,
certified bound and measure do not contradict each other), built as a face (trimmed by the face's edges
where its rails run past the face) and measured against the face as bounded by its edges.  run_fit adds
reading the face and writing the STEP, report and plot.
"""

from __future__ import annotations

import os
import sys
import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Callable, Optional

from ruled import __version__
from ruled.core.errors import FiguresError, positive
from ruled.core.outputs import check_measure_samples, check_outputs

if TYPE_CHECKING:
    from ruled.fit.fit2d import FitResult
    from ruled.fit.options import FitOptions


@dataclass(frozen=True)
class FaceFit:
    """The result of a face's fit as ``ruled fit`` returns it."""

    fit: FitResult              # the fit whose figures agree (its .best: the candidate built)
    source: Any                 # the face fitted (TopoDS_Face), as bounded by its edges
    face: Any                   # the result as a face (TopoDS_Face): trimmed by the face's edges where it is
    bound: float                # certified, against the bounded face: the fit's + conversion + building slack
    slack: float                # the conversion and building part of the bound
    hausdorff: Optional[Any] = None   # ruled.occ.measure.Hausdorff (OCCT, both ways), None when not measured
    area: Optional[dict] = None       # {"face", "result", "ratio"}: OCCT's areas, when measured
    warnings: tuple = ()        # the face's patch's and the measure's (engine Text: a door words them)
    timings: dict = field(default_factory=dict)

    @property
    def measured(self) -> Optional[float]:
        return None if self.hausdorff is None else float(self.hausdorff.max)

    @property
    def trimmed(self) -> bool:
        return self.fit.best.trim is not None

    def figure(self) -> str:
        """The fit in a few words, for warnings that compare it with another (ruled.machine.trimmed.figure)."""
        from ruled.machine.trimmed import figure
        return figure(self.bound, self.measured)


def fit_job(face, options: Optional[FitOptions] = None, progress=None, rails=None,
            measure_samples: Optional[int] = 40, fitted: Optional[tuple] = None) -> FaceFit:
    """The face (a TopoDS_Face) fitted as bounded by its edges, built and measured (measure_samples n: n x n
    OCCT samples each way; None: not measured); fitted: (FitResult, conversion slack) when the fit is made
    already.  A result whose own figures disagree is replaced by the next candidate whose figures agree
    (FiguresError, naming them, when none do)."""
    from ruled.fit.face.verdict import first_consistent
    from ruled.fit.options import Ends, FitOptions
    from ruled.occ.io import face_area
    from ruled.occ.region import fit_face
    options = FitOptions(ends=Ends.AUTO) if options is None else options     # as 'ruled fit' fits
    t0 = time.perf_counter()
    if fitted is None:
        fitted = fit_face(face, options.checked(), progress, rails)
    res, slack = fitted
    t_fit = time.perf_counter() - t0
    area = face_area(face, 1e-6) if measure_samples else None     # once: each candidate is compared with it
    res, ff = first_consistent(res, lambda r: (_built(r, face, slack, area, measure_samples, progress),))
    ff.timings["fit"] = t_fit
    return ff


def face_fit_of(face, fit, fit_options, progress=None, rails=None, measure_samples: Optional[int] = 30):
    """The FaceFit that machine data, a cone spline and a split start from: fit itself (a FaceFit), a RuledFit's
    (ruled.cq), a bare FitResult built and measured, or, with fit None (or True), the face fitted as ``ruled fit``
    fits it."""
    from ruled.occ.convert import conversion_slack, face_to_container
    if isinstance(fit, FaceFit):
        return fit
    if getattr(fit, "job", None) is not None:
        return fit.job
    if fit is not None and fit is not True:
        res = getattr(fit, "result", fit)
        return fit_job(face, fit_options, progress, measure_samples=measure_samples,
                       fitted=(res, conversion_slack(face, face_to_container(face))))
    return fit_job(face, fit_options, progress, rails, measure_samples)


def _built(res: FitResult, source, slack: float, area: Optional[float], measure_samples: Optional[int],
           progress) -> FaceFit:
    """One candidate built as a face and measured; FiguresError where its figures contradict each other."""
    from ruled.fit.face.verdict import area_ratio, measured_warnings
    from ruled.occ.io import face_area
    from ruled.occ.measure import hausdorff
    from ruled.occ.trimmed import built_slack, result_face
    t1 = time.perf_counter()
    out = result_face(res)
    slack = slack + built_slack(out, res)
    bound = res.error_bound + slack
    t_build = time.perf_counter() - t1
    warnings = tuple(res.patch.warnings) if res.patch is not None else ()
    h, areas, t_meas = None, None, 0.0
    if measure_samples:
        t2 = time.perf_counter()
        if progress is not None:
            progress(f"the measure (OCCT, {measure_samples}x{measure_samples} samples each way)", 0.0)
        h = hausdorff(source, out, measure_samples)
        result_area = face_area(out, 1e-6)
        ratio = area_ratio(res, area, result_area)
        areas = {"face": area, "result": result_area, "ratio": ratio}
        size = res.patch.face_size if res.patch is not None else res.surface.diagonal()
        warnings += tuple(measured_warnings(res, bound, h.max, size, ratio))
        t_meas = time.perf_counter() - t2
    return FaceFit(res, source, out, bound, slack, h, areas, warnings, {"build": t_build, "measure": t_meas})


def run_fit(input_path: str, face_index: int, output: str, *, samples=40, objective="sum", max_error=None,
            direction="auto", refine=True, report=None, plot=None, measure_samples=40, quiet=False, method="2d",
            elevations=None, step=None, metric="lsad", memory_cap_mb=None, rails=None, face=None, say=True,
            text: Callable = str, face_timeout=None, ends="auto", replace=False,
            after: Optional[Callable] = None) -> dict:
    """The whole job: read, fit, build, measure, write. Returns the report dict.  face: the face, read
    already (the batch's workers keep the files they have read); say: print the warnings and notes
    (the batch keeps them in the reports); text: how the warnings name options (the door's terms);
    face_timeout: seconds the fit and the measure may take (None: no limit; the batch has its own);
    replace: output holds the whole part, the face replaced by its result (ruled.occ.replace); after(FaceFit):
    more work on the fit (its machine file: the demo's, the batch's --post), its dict added to the report."""
    from ruled.fit.options import FitOptions
    opts = FitOptions(samples=samples, objective=objective, max_error=max_error, direction=direction,
                      refine=refine, method=method, elevations=elevations, step=step, metric=metric,
                      memory_cap=None if memory_cap_mb is None else memory_cap_mb * 2.0 ** 20, ends=ends).checked()
    check_outputs(output, report, plot, inputs=(input_path,))
    check_measure_samples(measure_samples)
    if face_timeout is not None:
        positive("face_timeout", face_timeout, "seconds")
    # the face before the engine: a wrong face index is answered without loading it
    from ruled.occ.io import get_face, read_shape
    t0 = time.perf_counter()
    part = read_shape(input_path) if replace else None      # (read once: the face from it, then the part)
    face = get_face(input_path, face_index, part) if face is None else face
    t_read = time.perf_counter() - t0
    from ruled.core.progress import Bar, TimeLimit
    from ruled.fit.report import plot as make_plot
    from ruled.fit.report import report_dict, write_report
    from ruled.occ.io import write_step
    bar = Bar(enabled=not quiet and sys.stderr.isatty())
    limit = TimeLimit(face_timeout, bar, f"face {face_index}",
                      "; give it more time («face_timeout»), or fewer «samples»")
    with limit:
        try:
            ff = fit_job(face, opts, limit, rails, measure_samples)
        except FiguresError as exc:
            raise FiguresError(f"face {face_index}: {exc.template}") from None
        finally:
            bar.done()
    res, h = ff.fit, ff.hausdorff
    t1 = time.perf_counter()
    write_step(ff.face, output)
    rep = report_dict(res, input_path=input_path, face=face_index, method=method,
                      hausdorff={"max": h.max, "mean": h.mean, "input_to_result": h.max_a_to_b,
                                 "result_to_input": h.max_b_to_a, "samples": h.samples,
                                 "resolution": h.resolution},
                      timings={"read": t_read, "fit": ff.timings["fit"],
                               "build_and_write": ff.timings["build"] + time.perf_counter() - t1,
                               "measure": ff.timings["measure"]},
                      version=__version__, conversion_slack=ff.slack)
    rep["area"] = ff.area
    if res.best.trim is not None:
        rep["trim"] = {"ends": "trimmed", "trim_eps": res.best.trim.eps, "trim_bound": res.best.trim.added,
                       **(res.patch.extension or {})}
    if replace:
        rep["replace"] = _replaced(part if part is not None else read_shape(input_path), face_index, ff.face,
                                   rep["error_bound"], output)
    rep["warnings"] = [text(w) for w in ff.warnings]
    if after is not None:
        rep.update(after(ff))
    for w in rep["warnings"] if say else ():
        print(f"ruled: warning: face {face_index}: {w}", file=sys.stderr)
    for note in res.notes if say else ():
        print(f"ruled: {note}", file=sys.stderr)
    if report:
        write_report(rep, report)
    if plot:
        make_plot(res, plot, rep["hausdorff"]["max"])
    return rep


def _replaced(shape, index: int, face, bound: float, output: str) -> dict:
    """The whole part (shape, as read) written to output, its face ``index`` replaced by the result face and
    sewn; returns the report's ``replace`` section.  A part that cannot be sewn is refused (output removed)."""
    from ruled.core.errors import RuledError
    from ruled.occ.io import faces_of, write_step
    from ruled.occ.replace import replaced_part, sewing_tolerance
    t0 = time.perf_counter()
    try:
        part = replaced_part(shape, index, face, sewing_tolerance(bound, faces_of(shape)[index], face))
    except RuledError:
        os.unlink(output)              # the face alone is not what was asked for
        raise
    write_step(part.shape, output)
    return {**part.report(), "seconds": time.perf_counter() - t0}


__all__ = ["FaceFit", "face_fit_of", "fit_job", "run_fit"]
