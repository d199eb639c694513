"""The (u, v) curve a user gives: a polyline (--uv), a JSON B-spline (--uv-curve), and the check that it
lies inside the face's domain."""

from __future__ import annotations

import numpy as np

from ruled.core.errors import BadInputError
from ruled.core.nurbs import Curve


def smooth_curve(points) -> Curve:
    """A smooth (u, v) curve through the points: the cubic B-spline interpolating them at chord-length
    parameters (quadratic through three, a line through two; repeated points dropped), so that its image
    on a face has no corner at a point, as a polyline's has."""
    from scipy.interpolate import make_interp_spline
    P = polyline_curve(points).poles
    chords = np.linalg.norm(np.diff(P, axis=0), axis=1)
    t = np.concatenate([[0.0], np.cumsum(chords)]) / chords.sum()
    k = min(3, len(P) - 1)
    spline = make_interp_spline(t, P, k=k)
    return Curve(np.asarray(spline.c, float), np.asarray(spline.t, float), k)


def polyline_curve(points) -> Curve:
    """A polyline of (u, v) points as a degree-1 domain curve, parameter t = i at point i (repeated
    points are dropped)."""
    P = np.asarray(points, float)
    if P.ndim != 2 or P.shape[1] != 2 or P.shape[0] < 2:
        raise BadInputError("a domain polyline needs at least two (u, v) points")
    if not np.all(np.isfinite(P)):
        raise BadInputError("the domain polyline has non-finite coordinates")
    keep = np.concatenate([[True], np.linalg.norm(np.diff(P, axis=0), axis=1) > 0])
    P = P[keep]
    if P.shape[0] < 2:
        raise BadInputError("the domain curve has zero length (all its points coincide); give distinct points")
    n = P.shape[0]
    return Curve(P, np.concatenate([[0.0], np.arange(n, dtype=float), [n - 1.0]]), 1)


def check_inside(region, D: Curve, n: int = 2001) -> None:
    """Refuse a domain curve that leaves a trimmed face (ruled.core.region.Region) as bounded by its edges
    (n samples); outside the surface's rectangle, approximate's own test names the bound it crosses."""
    if region.is_rectangle():
        return
    t = np.linspace(*D.domain, n)
    uv = D(t)[:, :2]
    u0, u1, v0, v1 = region.surface.domain
    inbox = (uv[:, 0] >= u0) & (uv[:, 0] <= u1) & (uv[:, 1] >= v0) & (uv[:, 1] <= v1)
    ok = region.contains(uv) | ~inbox
    if not ok.all():
        k = int(np.argmin(ok))
        raise BadInputError(f"the domain curve leaves the face: at t = {t[k]:.6g} it reaches (u, v) = "
                            f"({uv[k, 0]:.6g}, {uv[k, 1]:.6g}), outside the face's edges (the face is trimmed); "
                            f"keep the curve inside the face's boundary")


def parse_uv(text: str) -> Curve:
    """A polyline from "u0,v0;u1,v1;..." (the command line's --uv)."""
    try:
        pts = [[float(x) for x in item.split(",")] for item in text.replace(" ", "").strip(";").split(";")]
    except ValueError:
        raise BadInputError(f"cannot read «uv={text!r}»; write points as \"u0,v0;u1,v1;...\"") from None
    if any(len(p) != 2 for p in pts):
        raise BadInputError(f"cannot read «uv={text!r}»: every point needs two numbers, as \"u0,v0;u1,v1;...\"")
    return polyline_curve(pts)


def domain_curve_from_json(d) -> Curve:
    """A domain curve from {"degree": p, "knots": [full knot vector], "points": [[u, v], ...],
    "weights": [optional]} (the command line's --uv-curve)."""
    if not isinstance(d, dict) or not {"degree", "knots", "points"} <= set(d):
        raise BadInputError('the curve file needs "degree", "knots" (the full knot vector) and "points" '
                            '([[u, v], ...]); "weights" is optional')
    try:
        P = np.asarray(d["points"], float)
        K = np.asarray(d["knots"], float)
        W = None if d.get("weights") is None else np.asarray(d["weights"], float)
        p = int(d["degree"])
    except (TypeError, ValueError):
        raise BadInputError("the curve file's degree, knots, points or weights are not numbers") from None
    if P.ndim != 2 or P.shape[1] != 2:
        raise BadInputError('the curve file\'s "points" must be a list of [u, v] pairs')
    if p < 1:
        raise BadInputError(f"the curve's degree must be at least 1, got {p}")
    if W is not None and W.shape != (P.shape[0],):
        raise BadInputError(f"the curve needs one weight per point ({P.shape[0]}), got {W.size}")
    if not (np.all(np.isfinite(P)) and np.all(np.isfinite(K)) and (W is None or np.all(np.isfinite(W)))):
        raise BadInputError("the curve file holds non-finite numbers")
    if W is not None and np.any(W <= 0):
        raise BadInputError("the curve's weights must be positive")
    return Curve(P, K, p, W)
