"""Cone splines of ruled surfaces in space (Yang & Yang 2006, §§3–6), on top of the planar fat conic
fitting of fatarc.py.

A ruled surface r(u, v) = (1 - u) c0(v) + u c1(v) is cut by two parallel planes crossed by every
ruling: when both boundaries already lie in parallel planes those are the planes; otherwise the
planes are perpendicular to the rulings' mean direction at the surface's lowest and highest points,
and every ruling line is extended to meet them (the original surface is part of the extended one).
If no single direction is crossed by every ruling at a usable angle, the surface is divided along v
into pieces that each have one (§6).  The planar fat curve is the projection of the extended
boundaries; it is fitted by a fat conic spline on planes a further third of the height outside
(§5, the paper's h0 -> 4/3 h0 - 1/3 h1), and the cone patches are trimmed back to the surface's own
planes, which keeps them tangent continuous across collapsed joints.

Curves are callables v -> (N, 3) with their derivatives, v in [0, 1].  Nothing here knows a CAD host.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Callable, Optional

import numpy as np

from ruled.cone.fatarc import FatArc, fit_fat_conic, generators_concurrent, patch_surface, trim_arc
from ruled.core.errors import BadInputError, ToleranceError, positive
from ruled.core.nurbs import Curve, Surface
from ruled.core.progress import Progress

MAX_TILT_DEG = 60.0          # a ruling may lean at most this much from the planes' normal
G1_DEG = float(np.degrees(1e-6))   # neighbouring patches' normals agree to 1e-6 rad
MAX_PIECES = 16             # §6 splits beyond this many pieces are refused
EXTEND = 1.0 / 3.0           # §5: the fit runs on planes this fraction of the height outside


@dataclass
class ConePatch:
    """One cone (or cylinder) patch in space, between the surface's two planes."""

    surface: Surface             # rational, linear in u (c0 side -> c1 side), quadratic in v
    weight: float
    kind: str                    # "cone" or "cylinder"
    apex: Optional[np.ndarray]   # the cone's apex (world coordinates)
    direction: Optional[np.ndarray]  # the cylinder's generator direction (unit)
    development: float           # cone: the developed angle (degrees); cylinder: the developed width
    developable: bool            # Theorem 1: the three generator lines meet at one point or are parallel
    bound: float                 # eq. 9 for the fat arc it comes from
    v: tuple                     # boundary parameters covered on c0 (of its piece)
    vb: tuple                    # on c1
    piece: int = 0


@dataclass
class Piece:
    """One part of the surface between one pair of parallel planes."""

    v_range: tuple               # the part of the surface's v (0..1)
    origin: np.ndarray
    axes: np.ndarray             # rows: x, y, z of the frame (z: the planes' normal)
    heights: tuple               # the surface's own planes (z in the frame)
    fit_heights: tuple           # the planes of the fit (extended, §5)
    planar_boundaries: bool      # both boundaries lay in the planes already
    arcs: list                   # FatArc, planar, on the fit planes
    c0: Callable = None          # the piece's (extended) boundaries in the frame's plane, for plots
    c1: Callable = None
    orig0: Callable = None       # the surface's own boundaries, projected
    orig1: Callable = None
    line_ends: Callable = None   # v (0..1 of the piece) -> (N, 3), (N, 3): the rulings between the planes

    def rulings(self, v):
        """The surface's rulings between its two planes, in space: (ends on h0, ends on h1)."""
        return self.line_ends(v)


@dataclass
class ConeSpline:
    patches: list
    pieces: list
    tol: float
    step: float
    bound: float                 # the largest eq. 9 bound
    max_g1_deg: float            # the largest angle between the normals of neighbouring patches of a piece
    max_crease_deg: float = 0.0  # the largest angle where neighbouring pieces (§6) meet
    timings: dict = field(default_factory=dict)
    notes: list = field(default_factory=list)

    def surfaces(self) -> list:
        return [p.surface for p in self.patches]


# ---------------------------------------------------------------------------------------- curves
def curve_callables(c: Curve):
    """(f, df, breaks) of a B-spline curve on v in [0, 1]."""
    a, b = c.domain
    span = b - a

    def f(v):
        return c.evaluate(a + span * np.clip(np.atleast_1d(v), 0, 1), 0)[0]

    def df(v):
        return span * c.evaluate(a + span * np.clip(np.atleast_1d(v), 0, 1), 1)[1]
    kk = np.unique(c.knots)
    return f, df, (kk[(kk > a) & (kk < b)] - a) / span


def _row_curve(S: Surface, i: int) -> Curve:
    w = None if S.weights is None else S.weights[i]
    return Curve(S.poles[i], S.knots_v, S.degree_v, w, S.periodic_v)


def iso_deviation(S: Surface, n: int = 25) -> float:
    """The largest distance (sampled) between S and the ruled surface between its u-boundaries
    joining equal v: how far S is from being ruled that way."""
    u0, u1, v0, v1 = S.domain
    u, v = np.meshgrid(np.linspace(u0, u1, n), np.linspace(v0, v1, n), indexing="ij")
    X = S(u.ravel(), v.ravel()).reshape(n, n, 3)
    s = ((u - u0) / (u1 - u0))[..., None]
    R = (1 - s) * X[:1] + s * X[-1:]
    return float(np.linalg.norm(X - R, axis=2).max())


def ruled_boundaries(S: Surface, direction: str = "auto", rel: float = 1e-9):
    """The boundary pairs (c0, c1) of the ruled strips of S, as curves: S linear in u (or v) with k + 1
    rows of poles is k ruled strips.  A face that is not ruled is refused with its distance from the
    ruled surface between its boundaries."""
    opts = []
    if direction in ("auto", "u"):
        opts.append(("u", S))
    if direction in ("auto", "v"):
        opts.append(("v", S.transposed()))
    lin = sorted(((T.poles.shape[0], name, T) for name, T in opts if T.degree_u == 1), key=lambda x: x[0])
    if lin:                                           # the fewest strips (bilinear faces: the single one)
        _, name, T = lin[0]
        return name, [(_row_curve(T, i), _row_curve(T, i + 1)) for i in range(T.poles.shape[0] - 1)]
    devs = [(iso_deviation(T), name) for name, T in opts]
    dev, name = min(devs)
    size = S.diagonal()
    if dev <= rel * size:
        T = S if name == "u" else S.transposed()
        u0, u1, _, _ = T.domain
        return name, [(T.iso_curve("v", u0), T.iso_curve("v", u1))]
    raise BadInputError(f"the face is not ruled: it is {dev:.4g} from the ruled surface between its {name}-boundaries "
                        f"({dev / size:.2%} of its size); «fit_first»")


# boundaries within this fraction of the size of two parallel planes lie in them (the model's tolerance)
PLANAR = 1e-6


# ---------------------------------------------------------------------------------------- frames
def _dirs(c0, c1, v):
    D = c1(v) - c0(v)
    n = np.linalg.norm(D, axis=1)
    if np.any(n <= 1e-12 * max(n.max(), 1e-300)):
        raise BadInputError("a ruling has zero length (the two boundaries touch); the surface has no pair of "
                            "parallel planes across it there - fit the part away from the touching point")
    return D / n[:, None]


def _plane_normal(c0, c1, v):
    """Normal of the parallel planes holding both boundaries, and the largest out-of-plane distance."""
    P0, P1 = c0(v), c1(v)
    C = np.cov((P0 - P0.mean(axis=0)).T) + np.cov((P1 - P1.mean(axis=0)).T)
    _, vecs = np.linalg.eigh(C)
    n = vecs[:, 0]
    dev = max(np.abs((P0 - P0.mean(axis=0)) @ n).max(), np.abs((P1 - P1.mean(axis=0)) @ n).max())
    return n, float(dev)


def _frame(z: np.ndarray):
    """Rows x, y, z: z the planes' normal, x the world x axis projected onto the planes (the world y
    axis when z is near x), so plots keep the model's orientation."""
    z = z / np.linalg.norm(z)
    a = np.eye(3)[0] if abs(z[0]) < 0.9 else np.eye(3)[1]
    x = a - (a @ z) * z
    x /= np.linalg.norm(x)
    return np.array([x, np.cross(z, x), z])


def split_by_tilt(c0, c1, max_tilt_deg: float = MAX_TILT_DEG, n: int = 257) -> list:
    """§6: the v ranges (0..1) of pieces that each have a direction all their rulings lean from by at
    most max_tilt_deg (greedy, longest first piece); one range when the whole surface has one."""
    v = np.linspace(0.0, 1.0, n)
    U = _dirs(c0, c1, v)
    cmin = np.cos(np.radians(max_tilt_deg))
    out, i = [], 0
    while i < n - 1:
        j = i + 1
        while j < n - 1:
            m = U[i:j + 2].sum(axis=0)
            m /= np.linalg.norm(m)
            if (U[i:j + 2] @ m).min() < cmin:
                break
            j += 1
        out.append((v[i], v[j]))
        i = j
    return out


def split_fans(c0, dc0, c1, dc1, ranges, n: int = 513, rel: float = 0.1) -> list:
    """Cut the v ranges where one boundary nearly stands still while the other moves (a fan of
    rulings through one point: a cone with its apex on that boundary, which planes below or above
    the apex would cross) from the rest, so each gets its own planes."""
    v = np.linspace(0.0, 1.0, n)
    s0, s1 = np.linalg.norm(dc0(v), axis=1), np.linalg.norm(dc1(v), axis=1)
    fan = (s0 <= rel * (s0 + s1)) | (s1 <= rel * (s0 + s1))
    cuts = [0.5 * (v[i - 1] + v[i]) for i in range(1, n) if fan[i] != fan[i - 1]]
    out = []
    for a, b in ranges:
        inner = [c for c in cuts if a + 2.0 / n < c < b - 2.0 / n]
        edges = [a] + inner + [b]
        out += list(zip(edges[:-1], edges[1:]))
    return out


# ---------------------------------------------------------------------------------------- fitting
def _sub(f, a, b, scale=False):
    if scale:
        return lambda v: (b - a) * f(a + (b - a) * np.clip(np.atleast_1d(v), 0, 1))
    return lambda v: f(a + (b - a) * np.clip(np.atleast_1d(v), 0, 1))


def _on_plane(c0, dc0, c1, dc1, origin, E, H):
    """Where the ruling lines of the surface meet the plane z = H (frame E), and the derivative:
    P + s D with s = (H - z(P)) / z(D), relative to origin, in space."""
    def parts(v):
        v = np.atleast_1d(v)
        P, Q = c0(v) - origin, c1(v) - origin
        dP, dQ = dc0(v), dc1(v)
        D, dD = Q - P, dQ - dP
        zP, zD, zdP, zdD = P @ E[2], D @ E[2], dP @ E[2], dD @ E[2]
        s = (H - zP) / zD
        ds = (-zdP * zD - (H - zP) * zdD) / zD ** 2
        return P + s[:, None] * D, dP + ds[:, None] * D + s[:, None] * dD
    return parts


def _extended(c0, dc0, c1, dc1, origin, E, H):
    """The boundary of the extended ruled surface in the plane z = H, as a planar curve (frame
    coordinates) with its derivative."""
    parts = _on_plane(c0, dc0, c1, dc1, origin, E, H)
    return (lambda v: parts(v)[0] @ E[:2].T), (lambda v: parts(v)[1] @ E[:2].T)


def _to_world(P, origin, E):
    return origin + P @ E


def _patch_info(arc: FatArc, h0, h1, origin, E, piece: int) -> ConePatch:
    S = patch_surface(arc, h0, h1)
    poles = _to_world(S.poles.reshape(-1, 3), origin, E).reshape(S.poles.shape)
    W = S.weights
    S = Surface(poles, S.knots_u, S.knots_v, 1, 2, W)
    P, Q = poles[0], poles[1]
    dev = generators_concurrent(P, Q)
    # the ratio of the similar triangles: Q - X = k (P - X) about the apex X
    a = P[2] - P[0] if np.linalg.norm(P[2] - P[0]) >= np.linalg.norm(P[1] - P[0]) else P[1] - P[0]
    b = Q[2] - Q[0] if np.linalg.norm(P[2] - P[0]) >= np.linalg.norm(P[1] - P[0]) else Q[1] - Q[0]
    la = float(a @ a)
    k = float(b @ a) / la if la > 0 else np.inf
    t = np.linspace(0.0, 1.0, 401)
    side = S(np.zeros_like(t), t) if np.isfinite(k) and la > 0 else S(np.ones_like(t), t)
    if np.isfinite(k) and abs(1.0 - k) <= 1e-9:
        d = Q[0] - P[0]
        d /= np.linalg.norm(d)
        flat = side - np.outer(side @ d, d)
        return ConePatch(S, arc.w, "cylinder", None, d, float(np.linalg.norm(np.diff(flat, axis=0), axis=1).sum()),
                         dev, arc.err, arc.v, arc.vb, piece)
    apex = P[0] if not np.isfinite(k) else (Q[0] - k * P[0]) / (1.0 - k)
    U = side - apex
    U /= np.maximum(np.linalg.norm(U, axis=1), 1e-300)[:, None]
    ang = np.arctan2(np.linalg.norm(np.cross(U[:-1], U[1:]), axis=1), (U[:-1] * U[1:]).sum(axis=1)).sum()
    return ConePatch(S, arc.w, "cone", apex, None, float(np.degrees(ang)), dev, arc.err, arc.v, arc.vb, piece)


def _g1(patches, across: bool = False) -> float:
    """The largest angle (degrees) between the normals of neighbouring patches of one piece along their
    common ruling; across=True: of the last and first patches of neighbouring pieces (the §6 creases)."""
    worst = 0.0
    u = np.linspace(0.0, 1.0, 9)
    for a, b in zip(patches[:-1], patches[1:]):
        if (a.piece != b.piece) != across:
            continue
        na = a.surface.normals(u, np.ones_like(u))
        nb = b.surface.normals(u, np.zeros_like(u))
        ang = np.arctan2(np.linalg.norm(np.cross(na, nb), axis=1), (na * nb).sum(axis=1))
        worst = max(worst, float(np.degrees(ang).max()))
    return worst


def _heights(P0, P1, origin, z, planar: bool, extend: float):
    """The surface's planes (its boundaries' planes, or its lowest and highest points) and the fit's
    planes, extend x the height further out."""
    if planar:
        h0, h1 = float(((P0 - origin) @ z).mean()), float(((P1 - origin) @ z).mean())
    else:
        zs = np.concatenate([(P0 - origin) @ z, (P1 - origin) @ z])
        h0, h1 = float(zs.min()), float(zs.max())
    return h0, h1, h0 - extend * (h1 - h0), h1 + extend * (h1 - h0)


def _fold_score(f0, g0, f1, g1, z, extend: float, planar: bool = False, n: int = 65):
    """How far the fat curve on the fit's planes (normal z) is from folding: the smallest cosine
    between the two extended boundaries' tangents, and where (v)."""
    v = np.linspace(0.0, 1.0, n)
    P0, P1 = f0(v), f1(v)
    origin = P0.mean(axis=0)
    E = _frame(z)
    _, _, H0, H1 = _heights(P0, P1, origin, E[2], planar, extend)
    t0 = _on_plane(f0, g0, f1, g1, origin, E, H0)(v)[1] @ E[:2].T
    t1 = _on_plane(f0, g0, f1, g1, origin, E, H1)(v)[1] @ E[:2].T
    n0, n1 = np.linalg.norm(t0, axis=1), np.linalg.norm(t1, axis=1)
    c = (t0 * t1).sum(axis=1) / np.maximum(n0 * n1, 1e-300)
    c[(n0 <= 1e-9 * n0.max()) | (n1 <= 1e-9 * n1.max())] = 1.0      # a boundary at rest (a cone's apex) is no fold
    k = int(np.argmin(c))
    return float(c[k]), float(v[k])


def _best_direction(f0, g0, f1, g1, extend: float, max_tilt_deg: float):
    """The planes' normal for boundaries that are not planar: of the rulings' mean direction and
    directions tilted from it (up to 50 deg, every 30 deg around), the one whose fat curve is furthest
    from folding (_fold_score), among those every ruling crosses at most max_tilt_deg from the
    normal.  (normal, score, where)."""
    U = _dirs(f0, f1, np.linspace(0.0, 1.0, 65))
    z0 = U.sum(axis=0)
    z0 /= np.linalg.norm(z0)
    F = _frame(z0)
    cands = [z0]
    for tilt in np.radians([10.0, 20.0, 30.0, 40.0, 50.0]):
        for az in np.radians(np.arange(0.0, 360.0, 30.0)):
            cands.append(np.cos(tilt) * z0 + np.sin(tilt) * (np.cos(az) * F[0] + np.sin(az) * F[1]))
    cmin = np.cos(np.radians(max_tilt_deg))
    best = (-np.inf, z0, 0.0)
    for z in cands:
        if (U @ z).min() < cmin:
            continue
        score, at = _fold_score(f0, g0, f1, g1, z, extend)
        if score > best[0] + 1e-9:
            best = (score, z, at)
    return best[1], best[0], best[2]


def cone_spline(c0, dc0, c1, dc1, tol: float, step: float = 0.1, *, breaks=(), extend: float = EXTEND,
                max_tilt_deg: float = MAX_TILT_DEG, allow_creases: bool = False, progress: Progress = None,
                **fit_kw) -> ConeSpline:
    """Cone spline of the ruled surface between the space curves c0 and c1 (callables v -> (N, 3), with
    derivatives, v in [0, 1], rulings joining equal v) within tol (eq. 9 on every patch).  Neighbouring
    patches of one piece are tangent continuous (to 1e-6 rad) or the surface is refused, unless
    allow_creases (pieces of §6 meet at creases in any case)."""
    positive("tol", tol)
    if not (np.isfinite(step) and 0 < step <= 1):
        raise BadInputError(f"the step must be in (0, 1] (got {step}); it is a fraction of the boundary's parameter")
    t0 = time.perf_counter()
    vs = np.linspace(0.0, 1.0, 257)
    n, dev = _plane_normal(c0, c1, vs)
    size = float(np.ptp(np.vstack([c0(vs), c1(vs)]), axis=0).max())
    # boundaries within the model's tolerance of two parallel planes are in them (a CAD file holds no
    # better: a blade's boundaries at z = 0 and 36 to 1.2e-5); the sliver between a boundary and its
    # plane, along the rulings, is added to the bound
    planar = dev <= PLANAR * max(size, 1e-300)
    Q = np.vstack([c0(vs), c1(vs)])
    Q = Q - Q.mean(axis=0)
    flat = float(np.abs(Q @ np.linalg.svd(Q, full_matrices=False)[2][-1]).max())
    if flat <= PLANAR * max(size, 1e-300):
        raise BadInputError(f"the face is flat (all of it within {flat:.2g} of one plane): a plane is developable as "
                            f"it is and needs no cone spline; cut or machine the face itself")
    U = _dirs(c0, c1, vs)
    ranges = [(0.0, 1.0)]
    slack = 0.0
    if planar:
        cos = float(np.abs(U @ n).min())
        if cos <= 1e-9:
            raise BadInputError("a ruling lies in the planes of the boundaries; the surface cannot be cut by them")
        slack = dev / cos
    else:
        ranges = split_fans(c0, dc0, c1, dc1, split_by_tilt(c0, c1, max_tilt_deg))
        if len(ranges) > MAX_PIECES:
            raise BadInputError(f"the rulings turn too far to split the surface into pieces between parallel planes: "
                                f"{len(ranges)} pieces would be needed (at most {MAX_PIECES}); fit a part of it")
    notes = []
    if len(ranges) > 1:
        notes.append(f"the surface is divided into {len(ranges)} pieces, each between its own pair of parallel planes "
                     f"(§6): its rulings turn by more than {2 * max_tilt_deg:.0f} degrees, or fan out from one point "
                     f"of a boundary (a cone whose apex the planes must not cross)")
    plan: list = []
    queue, folds = list(ranges), 0
    while queue:                                   # planes per piece; a piece whose fat curve folds is cut there
        a, b = queue.pop(0)
        f0, g0, f1, g1 = _sub(c0, a, b), _sub(dc0, a, b, True), _sub(c1, a, b), _sub(dc1, a, b, True)
        # a piece whose fat curve folds on the fit's planes (§5) is cut where it folds (§6) while it can be,
        # rather than fitted with less extension: without the full extension the patches of a twisted
        # surface collapse to triangles and meet at creases inside the piece; only a piece that cannot be
        # cut further (planar boundaries, too short, too many pieces) tries less (a fan's apex)
        splittable = not planar and b - a >= 1.0 / 128 and len(plan) + len(queue) + 2 <= MAX_PIECES
        for ext in ((extend,) if splittable else (extend, extend / 3, 0.0)):
            if planar:
                z = n if (U @ n).mean() > 0 else -n
                score, at = _fold_score(f0, g0, f1, g1, z, ext, True)
            else:
                z, score, at = _best_direction(f0, g0, f1, g1, ext, max_tilt_deg)
            if score > 0.0:
                break
        if score > 0.0:
            plan.append((a, b, z, ext))
            continue
        if not splittable:
            where = (f"the two boundaries run against each other there (their tangents "
                     f"{np.degrees(np.arccos(np.clip(score, -1, 1))):.0f} deg apart near v = {a + (b - a) * at:.3g}: "
                     f"the surface twists too much, or a fan of rulings goes through one boundary point)")
            raise BadInputError(
                (f"between the boundaries' parallel planes the fat curve folds, so no cone spline follows it: {where}"
                 if planar else
                 f"the boundaries are not in parallel planes, and between every pair of parallel planes tried across "
                 f"the rulings the fat curve folds, so no cone spline follows it: {where}")
                + "; use a part of the surface between two parallel planes")
        cut = a + (b - a) * min(max(at, 0.1), 0.9)
        queue[0:0] = [(a, cut), (cut, b)]
        folds += 1
    if folds:
        notes.append(f"{folds} more cut(s) where the fat curve of a piece would fold (§6): {len(plan)} pieces")
    pieces, patches = [], []
    brk = np.asarray(breaks, float)
    ranges = [(a, b) for a, b, _, _ in plan]
    for k, (a, b, z, ext) in enumerate(plan):
        f0, g0, f1, g1 = _sub(c0, a, b), _sub(dc0, a, b, True), _sub(c1, a, b), _sub(dc1, a, b, True)
        vv = np.linspace(0.0, 1.0, 257)
        if ext < extend:
            notes.append(f"piece {k}: the extension beyond the surface's planes is {ext:.3g} of the height "
                         f"(not {extend:.3g}): further out the rulings would cross each other")
        extend_k = ext
        E = _frame(z)
        P0, P1 = f0(vv), f1(vv)
        origin = P0.mean(axis=0)
        if ((P1 - P0) @ E[2]).min() <= 0:
            raise BadInputError("the rulings do not all cross the planes in one sense; split the face (ruled split) "
                                "or fit a part of it")
        h0, h1, H0, H1 = _heights(P0, P1, origin, E[2], planar, extend_k)
        e0, de0 = _extended(f0, g0, f1, g1, origin, E, H0)
        e1, de1 = _extended(f0, g0, f1, g1, origin, E, H1)
        o0 = _extended(f0, g0, f1, g1, origin, E, h0)[0]
        o1 = _extended(f0, g0, f1, g1, origin, E, h1)[0]
        span = (k / len(ranges), (k + 1) / len(ranges))
        prog = None if progress is None else \
            (lambda stage, frac, s=span: progress(stage, s[0] + (s[1] - s[0]) * frac))
        pb = (brk[(brk > a) & (brk < b)] - a) / (b - a)
        arcs = fit_fat_conic(e0, de0, e1, de1, tol, step, h0=H0, h1=H1, breaks=pb, progress=prog, **fit_kw)
        s0, s1 = (h0 - H0) / (H1 - H0), (h1 - H0) / (H1 - H0)
        for arc in arcs:
            cut = trim_arc(arc, s0, s1)
            cut.v = tuple(a + (b - a) * x for x in arc.v)
            cut.vb = tuple(a + (b - a) * x for x in arc.vb)
            patches.append(_patch_info(cut, h0, h1, origin, E, k))
        lo_, hi_ = _on_plane(f0, g0, f1, g1, origin, E, h0), _on_plane(f0, g0, f1, g1, origin, E, h1)

        def ends(v, lo_=lo_, hi_=hi_, o=origin):
            return o + lo_(v)[0], o + hi_(v)[0]
        pieces.append(Piece((a, b), origin, E, (h0, h1), (H0, H1), planar, arcs, e0, e1, o0, o1, ends))
    if slack > 0.0:
        notes.append(f"the boundaries lie within {dev:.3g} of their parallel planes (taken as the planes): "
                     f"the bound includes the {slack:.3g} between them along the rulings")
    res = ConeSpline(patches, pieces, tol, step, max(p.bound for p in patches) + slack, _g1(patches),
                     _g1(patches, across=True), notes=notes)
    res.timings["fit"] = time.perf_counter() - t0
    if res.max_g1_deg > G1_DEG and not allow_creases:
        raise ToleranceError(f"the cone spline would not be tangent continuous: neighbouring patches meet at up to "
                             f"{res.max_g1_deg:.3g} deg (the surface twists so much that patches collapse to "
                             f"triangles and the §5 extension cannot be used)", creases_help=True)
    return res


def cone_spline_of_curves(C0: Curve, C1: Curve, tol: float, step: float = 0.1, **kw) -> ConeSpline:
    """Cone spline of the ruled surface between two B-spline curves in space (rulings join equal
    normalized parameters), the boundary curves given directly."""
    f0, df0, br0 = curve_callables(C0)
    f1, df1, br1 = curve_callables(C1)
    return cone_spline(f0, df0, f1, df1, tol, step, breaks=np.union1d(br0, br1), **kw)


