"""Independent error measure inside FreeCAD: the two-sided Hausdorff distance between two faces by
n x n samples of each over its parameter rectangle, each sample's exact distance to the other face's
rectangle by OCCT's BRepExtrema (Part's distToShape).  The same samples and the same surfaces as the
command line's measure (ruled.occ.measure), so both agree."""

from __future__ import annotations

import numpy as np

import FreeCAD
import Part
from ruled.hostform import Hausdorff


def face_bounds(face):
    """The face's parameter range, clipped to its surface's own range where not periodic."""
    u0, u1, v0, v1 = face.ParameterRange
    s = face.Surface
    a0, a1, b0, b1 = s.bounds()
    if not s.isUPeriodic():
        u0, u1 = max(u0, a0), min(u1, a1)
    if not s.isVPeriodic():
        v0, v1 = max(v0, b0), min(v1, b1)
    return u0, u1, v0, v1


def grid(face, n: int) -> np.ndarray:
    u0, u1, v0, v1 = face_bounds(face)
    s = face.Surface
    return np.array([tuple(s.value(float(u), float(v))) for u in np.linspace(u0, u1, n)
                     for v in np.linspace(v0, v1, n)])


def distances(points: np.ndarray, face, progress=None) -> np.ndarray:
    out = np.empty(len(points))
    for i, p in enumerate(points):
        out[i] = face.distToShape(Part.Vertex(FreeCAD.Vector(*map(float, p))))[0]
        if progress is not None and i % 64 == 0:
            progress(i / len(points))
    return out


def rectangle(face):
    """The face's surface over its whole parameter rectangle (the measure, like the fit, ignores trims)."""
    return face.Surface.toShape(*face_bounds(face))


def hausdorff(face_a, face_b, n: int = 40, progress=None) -> Hausdorff:
    pa, pb = grid(face_a, n), grid(face_b, n)
    dab = distances(pa, rectangle(face_b), None if progress is None else (lambda f: progress(0.5 * f)))
    dba = distances(pb, rectangle(face_a), None if progress is None else (lambda f: progress(0.5 + 0.5 * f)))
    alld = np.concatenate([dab, dba])
    return Hausdorff(float(alld.max()), float(alld.mean()), float(dab.max()), float(dba.max()), int(alld.size),
                     tuple(dab))
