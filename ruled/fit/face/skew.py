"""The face over a parallelogram of its surface's domain whose sides run along the face's straightest direction.

An exactly ruled surface whose rulings are not its iso lines (a ruled loft written in skewed parameters, a
hyperbolic paraboloid or a hyperboloid piece) has, across a face trimmed by curved edges, rulings that enter
and leave through the face's edges anywhere: no grouping of its edges into four sides, nor its surface's own
rectangle, has rails that those rulings join.  A straight direction d of the surface's (u, v) is found by
search (the one along which the face's points lie straightest in space: `straightest`), and the face is
covered by the parallelogram

    Omega(s, t) = o + s a e + t b d,     e perpendicular to d in the domain scaled to the unit square,

whose rails (t = 0 and 1) cross the rulings and lie past the face (the surface's natural extension where
they leave its domain).  S o Omega is sampled like a Coons patch (ruled.fit.face.sampled), the face is its
mask (ruled.fit.face.extend.FaceMask), and the fit is trimmed by the face's edges (ruled.fit.face.trim)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np

from ruled.core.edgegap import off_face
from ruled.core.nurbs import Surface
from ruled.core.region import Region

ANGLES = 48          # directions tried over half a turn, then refined round the best
LINES = 9            # parallel lines across the face per direction
PER_LINE = 33        # points per line
REFINE = 24          # golden-section steps round the best direction
# the parallelogram runs past the face by these fractions of its extent each way: along the rails (a ruling
# that curves in the domain, a hyperboloid's, stays between them) and along the rulings
MARGIN_S, MARGIN_T = 0.25, 0.03
# the rulings' costs count their points this far past the face (fractions of the patch in s and in t): a ruling
# that only grazes the face is held by its own line's run past it (the surface is ruled there too, or nothing
# is won); farther in s would count rulings that miss the face, which may leave the parallelogram's sides
GROW = (0.05, 0.3)
WORTH = 0.25         # tried where the straightest direction is this much straighter than both iso directions
ISO_ANGLE = np.radians(5.0)   # ... and this far from them


def _inside(poly: np.ndarray, pts: np.ndarray) -> np.ndarray:
    """Whether the points (N, 2) lie inside the closed polyline (M, 2), by the even-odd rule."""
    a, b = poly, np.roll(poly, -1, axis=0)
    y = pts[:, 1]
    i, j = np.nonzero((a[None, :, 1] > y[:, None]) != (b[None, :, 1] > y[:, None]))    # the edges each row crosses
    with np.errstate(divide="ignore", invalid="ignore"):
        xi = a[j, 0] + (y[i] - a[j, 1]) * (b[j, 0] - a[j, 0]) / (b[j, 1] - a[j, 1])
    return (np.bincount(i[pts[i, 0] < xi], minlength=len(pts)) % 2).astype(bool)


class _Face:
    """The face's outer loop in the surface's domain scaled to the unit square, and the surface there."""

    def __init__(self, region: Region):
        S = region.surface
        self.S = S
        u0, u1, v0, v1 = S.domain
        self.lo, self.span = np.array([u0, v0]), np.array([max(u1 - u0, 1e-300), max(v1 - v0, 1e-300)])
        pts = [c(np.linspace(c.domain[0], c.domain[1], 65)) for c in region.loop]
        self.poly = (np.concatenate(pts) - self.lo) / self.span

    def scores(self, thetas: np.ndarray) -> np.ndarray:
        """Per direction (angle in the scaled domain), the largest distance of the face's points on LINES lines
        along it from the chord of each line's points in the face."""
        d = np.stack([np.cos(thetas), np.sin(thetas)], axis=1)          # (A, 2)
        n = np.stack([-d[:, 1], d[:, 0]], axis=1)
        pa, pn = self.poly @ d.T, self.poly @ n.T                         # (M, A)
        c = pn.min(axis=0)[:, None] + (np.arange(LINES) + 0.5)[None, :] / LINES * np.ptp(pn, axis=0)[:, None]
        a = pa.min(axis=0)[:, None] + np.linspace(0.0, 1.0, PER_LINE)[None, :] * np.ptp(pa, axis=0)[:, None]
        # points (A, LINES, PER_LINE, 2)
        P = (a[:, None, :, None] * d[:, None, None, :] + c[:, :, None, None] * n[:, None, None, :])
        flat = P.reshape(-1, 2)
        ins = _inside(self.poly, flat).reshape(P.shape[:3])
        uv = self.lo + flat * self.span
        X = self.S(uv[:, 0], uv[:, 1]).reshape(P.shape[:3] + (3,))
        # per line, the chord between its first and last point in the face, and its points in the face from it
        first = np.argmax(ins, axis=2)
        last = PER_LINE - 1 - np.argmax(ins[:, :, ::-1], axis=2)
        Y0 = np.take_along_axis(X, first[:, :, None, None], axis=2)
        chord = np.take_along_axis(X, last[:, :, None, None], axis=2) - Y0
        L2 = np.sum(chord * chord, axis=3, keepdims=True)
        w = X - Y0
        along = np.sum(w * chord, axis=3, keepdims=True) / np.where(L2 > 0, L2, 1.0)
        dist = np.linalg.norm(w - along * chord, axis=3)
        ok = (ins.sum(axis=2) >= 3) & (L2[:, :, 0, 0] > 0)
        return np.where(ok, np.where(ins, dist, 0.0).max(axis=2), 0.0).max(axis=1)


def straightest(region: Region) -> Optional[tuple]:
    """(theta, score, iso_score): the direction (an angle in the surface's domain scaled to the unit square)
    along which the face is straightest, its score (the largest distance of the face's points on lines along
    it from their chords) and the better of the two iso directions'; None for a face too small to tell."""
    f = _Face(region)
    th = np.linspace(0.0, np.pi, ANGLES, endpoint=False)
    sc = f.scores(th)
    iso = float(min(sc[0], sc[ANGLES // 2]))
    k = int(np.argmin(sc))
    lo, hi = th[k] - np.pi / ANGLES, th[k] + np.pi / ANGLES
    g = (np.sqrt(5.0) - 1.0) / 2.0
    a, b = hi - g * (hi - lo), lo + g * (hi - lo)
    fa, fb = f.scores(np.array([a, b]))
    for _ in range(REFINE):
        if fa <= fb:
            hi, b, fb = b, a, fa
            a = hi - g * (hi - lo)
            fa = float(f.scores(np.array([a]))[0])
        else:
            lo, a, fa = a, b, fb
            b = lo + g * (hi - lo)
            fb = float(f.scores(np.array([b]))[0])
    best, score = (a, fa) if fa <= fb else (b, fb)
    if sc[k] < score:
        best, score = float(th[k]), float(sc[k])
    return float(np.mod(best, np.pi)), float(score), iso


def worth_trying(theta: float, score: float, iso: float) -> bool:
    """Whether the straightest direction differs from both iso directions and is straighter than both."""
    off = min(abs(theta), abs(theta - np.pi / 2), abs(theta - np.pi))
    return off > ISO_ANGLE and score < WORTH * iso


@dataclass
class SkewMap:
    """Omega of the module doc, with the interface side_surface samples (ruled.split.strips.Strip's)."""

    lo: np.ndarray          # the domain's (u0, v0)
    span: np.ndarray        # its (u1 - u0, v1 - v0)
    origin: np.ndarray      # Omega(0, 0) in the scaled domain
    M: np.ndarray           # (2, 2): Omega(s, t) = origin + M @ (s, t) in the scaled domain
    name: str = "face's parallelogram along its straightest direction"

    @property
    def whole(self) -> bool:
        return False

    @property
    def refine_hint(self) -> str:
        return "the surface past the face is too wiggly to extend it along its straightest direction"

    def raw(self, s, t) -> np.ndarray:
        st = np.stack([np.asarray(s, float).ravel(), np.asarray(t, float).ravel()], axis=1)
        return self.lo + (self.origin + st @ self.M.T) * self.span

    def omega(self, S: Surface, s, t):
        s, t = np.broadcast_arrays(np.asarray(s, float), np.asarray(t, float))
        uv = self.raw(s, t)
        return uv[:, 0].reshape(s.shape), uv[:, 1].reshape(s.shape)

    def offset(self, s, t):
        return None

    def breaks(self, S: Surface):
        return np.linspace(0.0, 1.0, 9), np.linspace(0.0, 1.0, 5)

    def invert(self, uv: np.ndarray) -> np.ndarray:
        return np.linalg.solve(self.M, ((uv - self.lo) / self.span - self.origin).T).T


def skew_map(region: Region, theta: float) -> SkewMap:
    """The parallelogram along theta (rulings along d, rails along e) covering the face with MARGIN."""
    f = _Face(region)
    d = np.array([np.cos(theta), np.sin(theta)])
    e = np.array([d[1], -d[0]])
    if np.linalg.det(np.stack([e, d], axis=1)) < 0:
        e = -e
    a, b = f.poly @ e, f.poly @ d
    ra, rb = np.ptp(a), np.ptp(b)
    a0, a1 = a.min() - MARGIN_S * ra, a.max() + MARGIN_S * ra
    b0, b1 = b.min() - MARGIN_T * rb, b.max() + MARGIN_T * rb
    M = np.stack([e * (a1 - a0), d * (b1 - b0)], axis=1)
    return SkewMap(f.lo, f.span, a0 * e + b0 * d, M)


def skew_patch(region: Region, size: float, theta: float):
    """The face's parallelogram patch along theta (a FacePatch with the face's mask, rulings along v), or None
    where S o Omega cannot be sampled (the surface's extension past its domain too wiggly, or not finite)."""
    from ruled.fit.face.extend import PER_EDGE, FaceMask, masked
    from ruled.fit.face.patch import EDGE_MARGIN, FacePatch
    from ruled.fit.face.trimfit import _extension, sampled_past
    m = skew_map(region, theta)
    side = sampled_past(region, m, size)
    if side is None:
        return None

    def st_of(curves):
        return tuple(np.clip(m.invert(c(np.linspace(c.domain[0], c.domain[1], PER_EDGE))), 0.0, 1.0)
                     for c in curves)
    outer = st_of(region.loop)
    holes = tuple(st_of(h) for h in region.holes)
    mask = FaceMask((np.concatenate(outer),) + tuple(np.concatenate(h) for h in holes), outer, holes, 0.0,
                    grow=GROW)
    E = masked(side.surface, mask)
    gap = EDGE_MARGIN * off_face(region)
    return FacePatch(region, E, float(side.deviation) + gap, False, None, "v", side.spans, size, (), gap, 0.0,
                     mask=mask, extension=_extension(E, mask, [MARGIN_S, MARGIN_S]), skew=float(np.degrees(theta)))


__all__ = ["straightest", "worth_trying", "skew_map", "skew_patch", "SkewMap"]
