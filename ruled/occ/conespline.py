"""Cone splines of faces with OCCT: the engine's cone spline of a ruled face (or of a ruled fit of any
face), as rational B-spline faces sewn into one shell, measured independently (OCCT projections onto
the patches and onto the design face; brute-force distances to the ruling segments)."""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Any, Optional

import numpy as np
from OCP.BRepBuilderAPI import BRepBuilderAPI_Sewing
from OCP.BRepCheck import BRepCheck_Analyzer

from ruled.cone.conespline import ConeSpline
from ruled.cone.surface import cone_spline_of_surface
from ruled.core.errors import positive
from ruled.core.progress import Progress
from ruled.occ.convert import container_to_face, face_surface_type, face_to_container
from ruled.occ.faceset import FaceSet, sample_faces
from ruled.occ.measure import face_points


@dataclass
class FaceCone:
    result: ConeSpline
    faces: list                    # one TopoDS_Face per patch
    shell: Any                     # the patches sewn (a shell, or a compound of shells for several pieces)
    measure: Optional[dict]        # see measure_cone
    fit: Any = None                # the ruled fit (FitResult) when the face was fitted first
    warnings: list = field(default_factory=list)
    timings: dict = field(default_factory=dict)
    fitted: Any = None             # that fit as 'ruled fit' returns it (ruled.jobs.face.FaceFit), when given

    @property
    def bound(self) -> float:
        """The certified bound against the face: the cone spline's (eq. 9), plus the fit's when it was fitted."""
        return float(self.result.bound) + (0.0 if self.fitted is None else float(self.fitted.bound))


def cone_faces(res: ConeSpline) -> list:
    return [container_to_face(p.surface) for p in res.patches]


def sew(faces, tol: float = 1e-7):
    """The faces sewn into one shape (shared edges), and whether OCCT finds it valid."""
    sw = BRepBuilderAPI_Sewing(tol)
    for f in faces:
        sw.Add(f)
    sw.Perform()
    shape = sw.SewedShape()
    return shape, bool(BRepCheck_Analyzer(shape).IsValid())


def _ruling_points(res: ConeSpline, n: int) -> np.ndarray:
    """n x n points of the ruled surface between its planes, piece by piece."""
    s = np.linspace(0.0, 1.0, n)
    pts = []
    for p in res.pieces:
        A, B = p.rulings(np.linspace(0.0, 1.0, n))
        pts.append((A[:, None, :] + s[None, :, None] * (B - A)[:, None, :]).reshape(-1, 3))
    return np.concatenate(pts)


def _to_ruled(res: ConeSpline, faces, n: int, patch_of=None):
    """Samples of the patches (OCCT) and their exact distances to the ruled surface between the planes
    (ruled.cone.report.to_ruled)."""
    from ruled.cone.report import to_ruled
    return to_ruled(res, [face_points(f, n) for f in faces], patch_of)


def measure_cone(res: ConeSpline, faces, design_face=None, n: int = 24, exact_face: bool = False,
                 patch_of=None) -> dict:
    """Independent distances (no fitting code is used):
    design_to_cone: samples of the design face (OCCT; the ruled surface's rulings when no face is
    given) to the nearest patch by OCCT projection; cone_to_ruled: samples of the patches to the ruled
    surface between the planes, by exact distances to its ruling segments; cone_to_design: samples of
    the patches projected onto the design face (only when exact_face: the cone spans the face exactly,
    i.e. the face is the ruled surface and its boundaries lie in the planes)."""
    t0 = time.perf_counter()
    fs = FaceSet(faces)
    design = sample_faces([design_face], n) if design_face is not None else _ruling_points(res, n)
    d_dc = fs.distances(design)
    cone_pts, d_cr = _to_ruled(res, faces, max(8, n // 2), patch_of)
    out = {"design_to_cone": float(d_dc.max()), "cone_to_ruled": float(d_cr.max()), "cone_to_design": None,
           "samples": int(design.shape[0] + cone_pts.shape[0])}
    if exact_face and design_face is not None:
        fd = FaceSet([design_face])
        out["cone_to_design"] = float(fd.distances(cone_pts).max())
    out["hausdorff"] = max(out["design_to_cone"], out["cone_to_design"] if out["cone_to_design"] is not None
                           else out["cone_to_ruled"])
    out["seconds"] = time.perf_counter() - t0
    return out


def cone_of_face(face, tol: float, step: float = 0.1, *, direction: str = "auto", progress: Progress = None,
                 measure_samples: Optional[int] = 24, **kw) -> FaceCone:
    """The cone spline of a ruled face within tol (a face that is not ruled: fit it first, and cone-spline the
    fit: ruled.jobs.cone.cone_job, or cone_of_fit)."""
    t0 = time.perf_counter()
    S = face_to_container(face)
    warnings = []
    kind = face_surface_type(face)
    if kind != "bspline":
        warnings.append(f"the face is a {kind}; it is taken as its exact B-spline conversion")
    from ruled.fit.face.fit import face_patch
    from ruled.occ.region import face_region
    patch = face_patch(face_region(face, S))
    if not patch.identity:
        warnings.append(f"the face is trimmed: its own four-sided patch (within {patch.deviation:.3g} of it) "
                        f"is cone-splined")
        S = patch.surface
    res = cone_spline_of_surface(S, tol, step, direction=direction, progress=progress, **kw)
    return _built(face, res, cone_faces(res), None, warnings, progress, measure_samples, t0,
                  all(p.planar_boundaries for p in res.pieces))


def _built(face, res: ConeSpline, faces: list, patch_of, warnings: list, progress, measure_samples, t0: float,
           exact: bool, fitted=None) -> FaceCone:
    """The patches sewn and measured against the face (exact: they span it, so both ways) as a FaceCone."""
    t1 = time.perf_counter()
    shell, valid = sew(faces)
    if not valid:
        warnings.append("OCCT reports the sewn shell as not valid; the faces are exported as they are")
    meas = None
    if measure_samples:
        if progress is not None:
            progress("measuring (OCCT)", 0.0)
        meas = measure_cone(res, faces, face, measure_samples, exact_face=exact, patch_of=patch_of)
    return FaceCone(res, faces, shell, meas, None if fitted is None else fitted.fit, warnings + _notes(res),
                    {"fit": res.timings["fit"], "build": time.perf_counter() - t1,
                     "measure": meas["seconds"] if meas else 0.0, "total": time.perf_counter() - t0}, fitted)


def _notes(res: ConeSpline) -> list:
    """What the cone spline itself says (its notes; patches that are not tangent continuous)."""
    out = list(res.notes)
    if res.max_g1_deg > 1.0:
        out.append(f"neighbouring patches meet at up to {res.max_g1_deg:.3g} deg (not tangent continuous): the "
                   f"surface twists so much that patches collapse to triangles without the §5 extension")
    return out


def trimmed_cone_faces(res: ConeSpline, R, trim) -> tuple:
    """The cone spline res of a result R trimmed by the face's edges (trim: ruled.fit.face.trim.Trim), each patch
    bounded by the face's boundary carried onto it (ruled.cone.trim): (one face per region of a patch, the
    patch of each)."""
    from ruled.cone.trim import trimmed_patches
    from ruled.occ.trimmed import trimmed_face
    regions = trimmed_patches(res, R, trim)
    return [trimmed_face(res.patches[r.patch].surface, r.trim()) for r in regions], [r.patch for r in regions]


def cone_of_fit(face, fitted, tol: float, step: float = 0.1, *, direction: str = "auto", progress: Progress = None,
                measure_samples: Optional[int] = 24, **kw) -> FaceCone:
    """The cone spline of a face's fit as 'ruled fit' returns it (fitted: ruled.jobs.face.FaceFit): a result
    trimmed by the face's edges is cone-splined between its rails over the rulings that cross the face and
    each patch trimmed by the face's edges like the fit (trimmed_cone_faces), measured against the face
    as bounded by its edges, both ways; an untrimmed one as it is (its patches against its rulings)."""
    t0 = time.perf_counter()
    res_fit = fitted.fit
    warnings = list(fitted.warnings)
    trim = res_fit.best.trim
    R = res_fit.surface
    if trim is not None:
        from ruled.machine.trimmed import trimmed_lines
        direction = "v"                      # a trimmed result's rulings run along v
        R = trimmed_lines(R, (trim.outer,) + tuple(trim.holes))[0]
    res = cone_spline_of_surface(R, tol, step, direction=direction, progress=progress, **kw)
    faces, patch_of = (cone_faces(res), None) if trim is None else trimmed_cone_faces(res, R, trim)
    return _built(face, res, faces, patch_of, warnings, progress, measure_samples, t0, trim is not None, fitted)


def check_tolerance(tol) -> float:
    return positive("tol", tol)
