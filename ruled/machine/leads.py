"""The lead-in and lead-out of an XYUV path: each guide leaves its contour square to it, on the wire's side;
on a closed loop no farther than half the way across it (a hole's opening), so that a lead never runs into
the material."""

from __future__ import annotations

import numpy as np

from ruled.core.nurbs import Surface


def _direction(C3: np.ndarray, k: int, sign: float, fr, ruling: np.ndarray) -> np.ndarray:
    """The unit in-plane direction a guide's lead leaves its contour C3 by at its first (k = 0) or last point:
    square to it, on the wire's side (sign (d contour / du) x the ruling); zero where that has no length."""
    i, j = (0, 1) if k == 0 else (-1, -2)
    tan = (C3[j] - C3[i]) * (1.0 if k == 0 else -1.0)    # along increasing u
    m = fr.xy(sign * np.cross(tan, ruling))
    ln = float(np.linalg.norm(m))
    return m / ln if ln > 0 else np.zeros(2)


def with_leads(lower: np.ndarray, upper: np.ndarray, lines, us: np.ndarray, sign: float, fr,
               opts, R: Surface):
    """The moves (X, Y, U, V) with a lead-in to the first pair and a lead-out from the last: each guide
    leaves its contour square to it, on the outside, i.e. along the in-plane part of the normal of the
    line surface at that guide (_direction); both together."""
    xy, uv = fr.xy(lower), fr.xy(upper)
    lead = opts.lead if opts.lead is not None else 0.05 * R.diagonal()
    body = np.concatenate([xy, uv], axis=1)
    if lead <= 0:
        return body, ("cut",) * len(body)
    a, b, _ = lines.ends(us[[0, -1]])
    ends = [(C3, k, _direction(C3, k, sign, fr, b[k] - a[k])) for k in (0, 1) for C3 in (lower, upper)]
    if R.periodic_u:        # a closed loop: the leads stay on their side of it (in a hole's opening, not across it)
        lead = min([lead] + [0.5 * _room(fr.xy(C3), k, m) for C3, k, m in ends])
    pts = [fr.xy(C3[0 if k == 0 else -1]) + lead * m for C3, k, m in ends]
    moves = np.concatenate([np.concatenate(pts[:2])[None], body, np.concatenate(pts[2:])[None]])
    return moves, ("lead-in",) + ("cut",) * len(body) + ("lead-out",)


def _room(xy: np.ndarray, k: int, m: np.ndarray) -> float:
    """How far a lead can run from the closed contour xy's first (k = 0) or last point along the unit direction
    m before it meets the contour again (inf: never, or no direction)."""
    if not np.any(m):
        return np.inf
    o = xy[0 if k == 0 else -1]
    xy = np.vstack([xy, xy[:1]])
    p, d = xy[:-1] - o, np.diff(xy, axis=0)
    den = d[:, 0] * m[1] - d[:, 1] * m[0]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (d[:, 0] * p[:, 1] - d[:, 1] * p[:, 0]) / den        # along the lead
        s = (m[0] * p[:, 1] - m[1] * p[:, 0]) / den               # along the segment
    hit = (np.abs(den) > 0) & (s >= 0) & (s <= 1) & (t > 1e-9 * float(np.ptp(xy, axis=0).max()))
    return float(t[hit].min()) if hit.any() else np.inf


__all__ = ["with_leads"]
