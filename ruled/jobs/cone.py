"""A face's cone spline job (``ruled cone``, ``ruled.cq.cone_spline_face``): the cone spline of a ruled face, or,
asked to fit first, of the face's fit as ``ruled fit`` returns it (ruled.jobs.face.FaceFit: given, or made here),
trimmed by the face's edges where that fit is (ruled.occ.conespline.cone_of_fit); its bound is the cone
spline's plus the fit's."""

from __future__ import annotations

from typing import Any, Optional


def cone_job(face, tol: float, step: float = 0.1, *, direction: str = "auto", fit: Any = False, fit_options=None,
             progress=None, measure_samples: Optional[int] = 24, **kw):
    """The cone spline of the face (a TopoDS_Face) within tol (ruled.occ.conespline.FaceCone): of the face itself
    (fit False: a ruled face), or of its fit (fit True: fitted here with fit_options, 'ruled fit''s defaults;
    or the fit itself: a FaceFit, a RuledFit of ruled.cq, a FitResult)."""
    from ruled.occ.conespline import check_tolerance, cone_of_face, cone_of_fit
    tol = check_tolerance(tol)
    if fit is False or fit is None:
        return cone_of_face(face, tol, step, direction=direction, progress=progress,
                            measure_samples=measure_samples, **kw)
    from ruled.jobs.face import face_fit_of
    fitted = face_fit_of(face, fit, fit_options, progress, measure_samples=measure_samples)
    return cone_of_fit(face, fitted, tol, step, direction=direction, progress=progress,
                       measure_samples=measure_samples, **kw)


__all__ = ["cone_job"]
