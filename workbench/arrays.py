"""A Part.BSplineSurface as the engine's plain arrays (ruled.core.nurbs.Surface) and back (FreeCAD only): what the
adapter (workbench.adapter) and the measure (workbench.measure) share, importing no other module of the
workbench."""

from __future__ import annotations

import FreeCAD
import numpy as np
import Part

from ruled.core.hostform import from_kernel_form, kernel_form
from ruled.core.nurbs import Surface


def surface_to_arrays(bs) -> Surface:
    """A Part.BSplineSurface as a container (periodic ones unrolled by the kernel, the flags kept)."""
    per_u, per_v = bool(bs.isUPeriodic()), bool(bs.isVPeriodic())
    if per_u or per_v:
        bs = bs.copy()
        if per_u:
            bs.setUNotPeriodic()
        if per_v:
            bs.setVNotPeriodic()
    poles = np.array([[(p.x, p.y, p.z) for p in row] for row in bs.getPoles()], float)
    weights = np.array(bs.getWeights(), float)
    return from_kernel_form(poles, weights, bs.getUKnots(), bs.getUMultiplicities(), bs.getVKnots(),
                            bs.getVMultiplicities(), bs.UDegree, bs.VDegree,
                            bool(bs.isURational() or bs.isVRational()), per_u, per_v)


def arrays_to_surface(S: Surface):
    """A container as a Part.BSplineSurface (periodic ones become kernel-periodic)."""
    f = kernel_form(S)
    poles = [[FreeCAD.Vector(*map(float, p)) for p in row] for row in f["poles"]]
    w = f["weights"]
    weights = np.ones(f["poles"].shape[:2]) if w is None else w
    bs = Part.BSplineSurface()
    bs.buildFromPolesMultsKnots(poles, [int(m) for m in f["umults"]], [int(m) for m in f["vmults"]],
                                [float(k) for k in f["uknots"]], [float(k) for k in f["vknots"]],
                                bool(f["uperiodic"]), bool(f["vperiodic"]), int(f["udegree"]), int(f["vdegree"]),
                                [[float(x) for x in row] for row in weights])
    # the kernel's own non-periodic form of a periodic surface comes back periodic, as it was
    for flag, done, make in ((S.periodic_u, f["uperiodic"], bs.setUPeriodic),
                             (S.periodic_v, f["vperiodic"], bs.setVPeriodic)):
        if flag and not done:
            try:
                make()
            except Exception:  # Part.OCCError: not closed after all; keep the non-periodic form
                pass
    return bs


__all__ = ["surface_to_arrays", "arrays_to_surface"]
