"""The B-spline form CAD kernels exchange (OCCT's, which FreeCAD's Part module wraps too): distinct
knots with multiplicities, and periodic surfaces stored with their unique poles over one period.
Both host adapters (ruled/occ and FreeCAD's workbench) convert through these plain-array functions,
so the two agree exactly.  No CAD host is imported here.

The engine's containers (ruled.nurbs.Surface) keep full knot vectors; a periodic container is
stored unwrapped (the first p poles repeated at the end) with its flag set, or clamped as a kernel's
own non-periodic form of a periodic surface delivers it (then it is evaluated as it is).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .nurbs import Curve, Surface


def full_knots(knots, mults) -> np.ndarray:
    return np.repeat(np.asarray(knots, float), np.asarray(mults, int))


def compress(full: np.ndarray):
    """Distinct knots (the exact value of each first occurrence) and their multiplicities."""
    full = np.asarray(full, float)
    _, m = np.unique(np.round(full, 15), return_counts=True)
    vals = []
    i = 0
    for c in m:
        vals.append(full[i])
        i += c
    return np.array(vals), m


def is_unwrapped_periodic(knots: np.ndarray, p: int) -> bool:
    """Clamped containers (read from a kernel) are evaluated as they are."""
    return not (np.all(knots[: p + 1] == knots[0]) and np.all(knots[-p - 1:] == knots[-1]))


def wraps(poles, weights, p, axis) -> bool:
    """Our unwrapped periodic storage repeats the first p poles at the end.  A kernel's own
    non-periodic form of a periodic surface (also unclamped) does not: it is kept as it is."""
    n = poles.shape[axis]
    if p == 0 or n <= p:
        return False
    head, tail = np.take(poles, np.arange(p), axis=axis), np.take(poles, np.arange(n - p, n), axis=axis)
    if weights is not None:
        hw, tw = np.take(weights, np.arange(p), axis=axis), np.take(weights, np.arange(n - p, n), axis=axis)
        if not np.array_equal(hw, tw):
            return False
    return bool(np.array_equal(head, tail))


def to_kernel_periodic(poles, weights, knots, p, axis):
    """Unwrapped periodic storage -> the kernel's periodic form (unique poles, one period of knots)."""
    n = poles.shape[axis] - p  # unique poles
    a, b = knots[p], knots[n + p]
    inner = knots[p: n + p + 1]
    kk, mm = compress(inner)
    mm = mm.copy()
    mm[-1] = mm[0]
    uniq = np.take(poles, np.arange(n), axis=axis)
    w = None if weights is None else np.take(weights, np.arange(n), axis=axis)
    # the kernel's pole 1 is our pole (m0 - 1), m0 the multiplicity of the first knot (checked in tests)
    uniq = np.roll(uniq, -(int(mm[0]) - 1), axis=axis)
    if w is not None:
        w = np.roll(w, -(int(mm[0]) - 1), axis=axis)
    assert abs(kk[0] - a) < 1e-15 * max(1, abs(a)) + 1e-300 and abs(kk[-1] - b) <= 1e-12 * max(1, abs(b))
    return uniq, w, kk, mm


def kernel_form(s: Surface) -> dict:
    """The arrays a kernel builds a B-spline surface from: poles (nu, nv, 3), weights (nu, nv) or None,
    distinct knots and multiplicities in u and v, degrees, periodic flags."""
    poles, weights = s.poles, s.weights
    pu, pv = s.degree_u, s.degree_v
    ku, mu = compress(s.knots_u)
    kv, mv = compress(s.knots_v)
    per_u = bool(s.periodic_u and is_unwrapped_periodic(s.knots_u, pu) and wraps(poles, weights, pu, 0))
    per_v = bool(s.periodic_v and is_unwrapped_periodic(s.knots_v, pv) and wraps(poles, weights, pv, 1))
    if per_u:
        poles, weights, ku, mu = to_kernel_periodic(poles, weights, s.knots_u, pu, axis=0)
    if per_v:
        poles, weights, kv, mv = to_kernel_periodic(poles, weights, s.knots_v, pv, axis=1)
    return {"poles": poles, "weights": weights, "uknots": ku, "umults": mu, "vknots": kv, "vmults": mv,
            "udegree": pu, "vdegree": pv, "uperiodic": per_u, "vperiodic": per_v}


def from_kernel_form(poles, weights, uknots, umults, vknots, vmults, udegree, vdegree, rational: bool,
                     uperiodic: bool = False, vperiodic: bool = False) -> Surface:
    """A container from a kernel's non-periodic form (the caller unrolls periodic surfaces with the
    kernel's own SetNotPeriodic first and passes the flags it had)."""
    return Surface(np.asarray(poles, float), full_knots(uknots, umults), full_knots(vknots, vmults), int(udegree),
                   int(vdegree), np.asarray(weights, float) if rational else None, bool(uperiodic), bool(vperiodic))


def curve_from_kernel_form(poles, weights, knots, mults, degree: int, reversed_: bool = False,
                           onto=None) -> Curve:
    """A (2D or 3D) curve container from a kernel's non-periodic form (distinct knots, multiplicities),
    reversed when the edge runs against its curve in its wire, and, with onto = (a, b), its parameter
    mapped affinely onto [a, b] (an edge's 3D curve onto its pcurve's range)."""
    poles = np.asarray(poles, float)
    w = None if weights is None else np.asarray(weights, float)
    full = full_knots(knots, mults)
    if reversed_:
        poles = poles[::-1].copy()
        w = None if w is None else w[::-1].copy()
        full = (full[0] + full[-1]) - full[::-1]
    if onto is not None:
        k0, k1 = full[degree], full[-degree - 1]
        full = onto[0] + (full - k0) * (onto[1] - onto[0]) / (k1 - k0)
    if w is not None and np.all(w == w[0]):
        w = None
    return Curve(poles, full, int(degree), w)


def bounds_slack(S: Surface, face_bounds) -> float:
    """Upper bound of the distance from the container to the face, where the face's UV bounds
    (u0, u1, v0, v1) lie inside the container's domain by less than the segmentation tolerance (a
    round-off strip): the strip width times the largest |S_u| or |S_v| there."""
    fu0, fu1, fv0, fv1 = face_bounds
    u0, u1, v0, v1 = S.domain
    if S.periodic_u:
        fu0, fu1 = u0, u1
    if S.periodic_v:
        fv0, fv1 = v0, v1
    du = max(0.0, fu0 - u0) + max(0.0, u1 - fu1)
    dv = max(0.0, fv0 - v0) + max(0.0, v1 - fv1)
    if du == 0.0 and dv == 0.0:
        return 0.0
    b = S.derivative_bounds()
    return float(du * b["Su"].max() + dv * b["Sv"].max())


@dataclass(frozen=True)
class Hausdorff:
    """Both hosts' independent measure between two faces: the largest and mean sampled distance, each
    side's largest, the sample count, and the distance of each sample of the first face."""

    max: float
    mean: float
    max_a_to_b: float
    max_b_to_a: float
    samples: int
    a_to_b: tuple = ()
