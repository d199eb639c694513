"""A face's machine job (``ruled machine --face``, ``ruled.cq.xyuv_face`` / ``flank_face``): the machine data of
the fit ``ruled fit`` returns for the face.

The path is made from the face's FaceFit (ruled.jobs.face): given (a fit the user has seen), or made here with
the same options.  Where that result cannot be machined (a result trimmed by the face's edges whose rulings
cannot be carried from plane to plane, say), the path follows the fit pinned to the face's corners instead,
and a warning gives both figures: never a silent change of the surface that is cut.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any, Optional

from ruled.core.errors import BadInputError
from ruled.jobs.face import face_fit_of
from ruled.machine.trimmed import fallback_warning


def machine_job(face, opts, fit_options=None, progress=None, measure_samples: Optional[int] = 30,
                side: float = 1.0, fit: Any = None, rails=None, given: bool = False):
    """The face's machine data (ruled.occ.machine.FaceMachine) made from its fit as ``ruled fit`` returns it
    (fit: that fit, when the user has it; see face_fit_of); given: the face is a ruled result already.  A
    fit whose path cannot be made falls back to the fit pinned to the face's corners, with a warning (in
    the report's "warnings" and "fallback") that names both fits' figures."""
    from ruled.fit.options import Ends, FitOptions
    from ruled.occ.machine import machine_of_face
    if given:
        return machine_of_face(face, opts, progress=progress, measure_samples=measure_samples, side=side,
                               given=True)
    fit_options = (fit_options or FitOptions(ends=Ends.AUTO)).checked()
    ff = face_fit_of(face, fit, fit_options, progress, rails, measure_samples)
    try:
        return machine_of_face(face, opts, progress=progress, measure_samples=measure_samples, side=side, job=ff)
    except BadInputError as exc:
        if not ff.trimmed:
            raise
        why = exc
    pinned = face_fit_of(face, None, replace(fit_options, ends="pinned"), progress, rails, measure_samples)
    fm = machine_of_face(face, opts, progress=progress, measure_samples=measure_samples, side=side, job=pinned)
    fm.warnings.insert(0, fallback_warning(opts.mode, pinned.figure(), why, ff.figure()))
    fm.report["warnings"] = list(fm.warnings)
    fm.report["fallback"] = {"followed": "pinned", "pinned_bound": pinned.bound, "pinned_measured": pinned.measured,
                             "trimmed_bound": ff.bound, "trimmed_measured": ff.measured, "why": str(why)}
    return fm


def machine_file(fm, output: str, settings=None, units: str = "mm") -> dict:
    """The machine data's file by its post and its CSV (ruled.machine.output.write_checked: LinuxCNC's interpreter
    checks a LinuxCNC file where it is installed), with the machine figures and what it cuts: the report section
    the demo and the batch keep beside a fit ({"machine": ...})."""
    from ruled.machine.output import write_checked
    program = write_checked(fm.path, output, settings, units, fm.report.get("side"))
    out = {**fm.report["machine"], "program": program}
    for key in ("cut", "swept_tool", "fallback"):
        if key in fm.report:
            out[key] = fm.report[key]
    return {"machine": out}


def post_extension(settings) -> str:
    """The file name ending of the post the settings name (a wire's)."""
    return settings.resolved("xyuv")[0].extension


__all__ = ["machine_job", "machine_file", "post_extension"]
