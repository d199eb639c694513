"""Curves on surfaces (Yang et al. 2008): low-degree curves that lie exactly on a B-spline surface,
within a distance tolerance of the exact image of a domain curve and G1 within an angle tolerance.

The domain curve D(t) (a polynomial or rational B-spline in (u, v), or a polyline) is cut into
Bézier pieces at its knots, where it crosses a knot line of S, and where it crosses its own chord
(§3), so every piece lies in one Bézier patch of S and on one side of its chord.  A piece whose
chord distance (§4, eqs. 13–17, from the real roots of the candidate polynomials) is too large for
the tolerance is split at its farthest point (§4); then, at every joint whose mapped tangents (the
chain rule of eqs. 18–22) differ by more than the angle tolerance, the piece with the larger
deviation is split at its farthest point (§5; Theorem 1 keeps the distance bound).  Each final
chord is composed with its Bézier patch (ruled.curves.compose): a Bézier curve of degree p + q on S exactly.

The 2D tolerance.  The paper's d = eps / (max|S_u| + max|S_v|) over the whole patch (eq. 12) is
kept as ``bound="span"``.  The default ``bound="local"`` is the same argument made tighter: a
piece, its chord and the segments between them lie in the bounding box of the piece's control
points, so the derivative bounds are taken over that box only (the patch restricted to it by
blossoming), and |S(P) - S(Q)| <= |P - Q| sqrt(Mu^2 + Mv^2) (Cauchy–Schwarz) replaces Mu + Mv.
The reported bound is the largest (chord distance x gradient bound) over the final pieces:
certified, and at most the tolerance.

Pieces are homogeneous Bézier control points (w u, w v, w); every piece of one domain curve has
the curve's degree, so the work is done on stacks of pieces at once.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ruled.core import jit
from ruled.core.basis import find_spans
from ruled.core.distance import to_polyline
from ruled.core.errors import BadInputError, TooBigError, positive
from ruled.core.nurbs import Curve, Surface
from ruled.core.progress import Progress
from ruled.curves import kernels as kernels_cos
from ruled.curves.bezier import (
    Piece,
    _add,
    _b2p,
    _der,
    _hom,
    _mul,
    _polyval,
    _roots01,
    _single_sided_stack,
    _split_stack,
    bezier_eval,
    bezier_split,
    domain_pieces,
    single_sided,
)
from ruled.curves.compose import SpanPatches, compose_stack
from ruled.curves.domain import domain_curve_from_json, parse_uv, polyline_curve

# ---------------------------------------------------------------------------------------------
# Bézier and power-basis helpers (stacks: axis 0 runs over pieces)
# ---------------------------------------------------------------------------------------------




# ---------------------------------------------------------------------------------------------
# §4: chord distance
# ---------------------------------------------------------------------------------------------

def _farthest(H: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """H(C, chord) for a stack of single-sided (rational) planar Bézier pieces (N, d + 1, 3) (§4):
    the largest distance to the chord over the candidate points: the ends, tangent parallel to
    the chord (eq. 15), the crossings of the end perpendiculars, tangent perpendicular to the line
    to an end (eqs. 16–17), all real roots of polynomials.  Returns (distances, parameters)."""
    N, n1, _ = H.shape
    n = n1 - 1
    if n == 1:
        return np.zeros(N), np.full(N, 0.5)
    poly = bool(np.all(H[:, :, 2] == H[:, :1, 2]))
    if jit.enabled():
        h, t = np.empty(N), np.empty(N)
        kernels_cos.farthest(np.ascontiguousarray(H), _b2p(n), poly, h, t)
        return h, t
    M = _b2p(n)
    A = np.zeros((N, n1, 3))                         # power coefficients, summed in order (as the twin)
    for j in range(n1):
        A += M[None, :, j, None] * H[:, None, j, :]
    Au, Av, w = A[:, :, 0], A[:, :, 1], A[:, :, 2]
    P0 = H[:, 0, :2] / H[:, 0, 2:]
    Pn = H[:, -1, :2] / H[:, -1, 2:]
    d = Pn - P0
    du, dv = d[:, :1], d[:, 1:]
    if poly:                                         # polynomial: w constant, C' = A' / w
        w0 = H[:, :1, 2]
        Cu, Cv, one = Au / w0, Av / w0, np.ones((1, 1))
        Nu, Nv = _der(Cu), _der(Cv)
    else:
        dw = _der(w)
        Nu = _add(_mul(_der(Au), w), -_mul(Au, dw))
        Nv = _add(_mul(_der(Av), w), -_mul(Av, dw))
        Cu, Cv, one = Au, Av, w
    cand = [np.zeros((N, 1)), np.ones((N, 1)), np.full((N, 1), 0.5), _roots01(_add(-Nu * dv, Nv * du))]  # eq. 15
    # the end regions (beyond the perpendiculars at the chord's ends) only matter for pieces whose
    # control points (hence the piece) reach beyond them
    L2 = (d * d).sum(axis=1)
    sc = (H[:, :, 0] / H[:, :, 2] - P0[:, :1]) * du + (H[:, :, 1] / H[:, :, 2] - P0[:, 1:]) * dv
    out = np.nonzero(~((sc >= 0).all(axis=1) & (sc <= L2[:, None]).all(axis=1)))[0]
    if out.size:
        perp, crit = [], []
        for E in (P0[out], Pn[out]):
            o1 = one if one.shape[0] == 1 else one[out]
            eu, ev = _add(Cu[out], -E[:, :1] * o1), _add(Cv[out], -E[:, 1:] * o1)
            perp.append(_add(eu * du[out], ev * dv[out]))                                # end perpendicular
            crit.append(_add(_mul(Nu[out], eu), _mul(Nv[out], ev)))                        # eqs. 16-17
        extra = np.full((N, 2 * (perp[0].shape[1] - 1) + 2 * (crit[0].shape[1] - 1)), np.nan)
        rp = _roots01(np.concatenate(perp))
        rc = _roots01(np.concatenate(crit))
        m = out.size
        extra[out] = np.concatenate([rp[:m], rp[m:], rc[:m], rc[m:]], axis=1)
        cand.append(extra)
    t = np.concatenate(cand, axis=1)
    tt = np.nan_to_num(t, nan=0.0)
    W = _polyval(w, tt)
    X = np.stack([_polyval(Au, tt) / W, _polyval(Av, tt) / W], axis=2)          # (N, m, 2)
    s = np.clip(((X[:, :, 0] - P0[:, :1]) * du + (X[:, :, 1] - P0[:, 1:]) * dv) / np.where(L2 > 0, L2, 1.0)[:, None],
                0.0, 1.0)
    s[L2 == 0] = 0.0
    dist = np.linalg.norm(X - (P0[:, None] + s[:, :, None] * d[:, None]), axis=2)
    dist[np.isnan(t)] = -1.0
    k = np.argmax(dist, axis=1)
    r = np.arange(N)
    return dist[r, k], tt[r, k]


def chord_distance(ctrl: np.ndarray, weights=None) -> tuple[float, float]:
    """H(C, chord) of a single-sided planar Bézier curve with Euclidean control points ctrl (and
    optional weights) and its chord (§4).  Returns (distance, parameter of the farthest point)."""
    h, t = _farthest(_hom(np.asarray(ctrl, float), weights)[None])
    return float(h[0]), float(t[0])


# ---------------------------------------------------------------------------------------------
# eq. 12 and its local form: gradient bounds; eqs. 21-22: the patch's derivatives
# ---------------------------------------------------------------------------------------------

def span_tolerance(S: Surface, eps: float, u: float, v: float, bounds: dict | None = None) -> float:
    """Eq. 12: the domain tolerance d of the knot span containing (u, v) so that a domain polyline
    within d of the domain curve maps within eps of its exact image: d = eps / (max|S_u| + max|S_v|)
    over the span (rigorous control-net bounds, rational surfaces included)."""
    b = bounds if bounds is not None else S.derivative_bounds()
    iu = int(find_spans(S.knots_u, S.degree_u, S.poles.shape[0], np.array([u]))[0]) - S.degree_u
    iv = int(find_spans(S.knots_v, S.degree_v, S.poles.shape[1], np.array([v]))[0]) - S.degree_v
    return float(eps / (b["Su"][iu, iv] + b["Sv"][iu, iv]))


# ---------------------------------------------------------------------------------------------
# the algorithm
# ---------------------------------------------------------------------------------------------

@dataclass
class CurveOnSurface:
    """A curve lying exactly on S that approximates the image of a domain curve."""

    curve: Curve               # 3D B-spline, degree p + q, knots of multiplicity p + q at the joints
    pcurve: Curve              # the domain polyline, degree 1 on the same knots: curve(t) = S(pcurve(t))
    degree: int
    segments: int
    control_points: int
    error_bound: float         # certified bound of the Hausdorff distance to the exact image
    max_joint_angle_deg: float  # largest tangent discrepancy at the joints (corners of the image excluded)
    corners: list              # [(t, angle_deg)] where the exact image itself turns by >= the angle tolerance
    closed: bool
    tol: float
    angle_deg: float
    bound_rule: str
    distance_segments: int     # segments after the distance phase (§4), before the angle phase (§5)
    notes: list = field(default_factory=list)


class _Stack:
    """Pieces as arrays: homogeneous control points, parameter intervals, span, chord distance,
    farthest parameter and gradient bound."""

    def __init__(self, H, t0, t1, sid, h, tf, G):
        self.H, self.t0, self.t1, self.sid, self.h, self.tf, self.G = H, t0, t1, sid, h, tf, G

    def take(self, m) -> "_Stack":
        return _Stack(*(x[m] for x in (self.H, self.t0, self.t1, self.sid, self.h, self.tf, self.G)))

    @staticmethod
    def join(parts) -> "_Stack":
        return _Stack(*(np.concatenate([getattr(p, a) for p in parts])
                        for a in ("H", "t0", "t1", "sid", "h", "tf", "G")))

    @property
    def n(self) -> int:
        return self.H.shape[0]


def _angles(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    na, nb = np.linalg.norm(a, axis=1), np.linalg.norm(b, axis=1)
    c = np.einsum("nc,nc->n", a, b) / np.where(na * nb > 0, na * nb, 1.0)
    out = np.degrees(np.arccos(np.clip(c, -1.0, 1.0)))
    out[(na == 0) | (nb == 0)] = np.nan
    return out


def _end_legs(P: np.ndarray, start: bool) -> np.ndarray:
    """Tangent directions (N, 2) of Bézier curves (N, d + 1, 2) at their start (or end): the first
    leg of non-zero length."""
    seq = P if start else P[:, ::-1]
    out = np.zeros((P.shape[0], 2))
    found = np.zeros(P.shape[0], bool)
    scale = np.abs(P).max(axis=(1, 2)) + 1e-300
    for k in range(1, P.shape[1]):
        leg = seq[:, k] - seq[:, 0]
        ok = ~found & (np.linalg.norm(leg, axis=1) > 1e-14 * scale)
        out[ok] = leg[ok]
        found |= ok
    return out if start else -out


def approximate(S: Surface, D: Curve, tol: float, angle_deg: float = 10.0, *, bound: str = "local",
                progress: Progress = None, max_segments: int = 200_000) -> CurveOnSurface:
    """Approximate the image S(D(t)) of the domain curve D by a curve of degree p + q lying on S
    exactly, within tol of it (Hausdorff, certified) and with joint tangents within angle_deg."""
    positive("tol", tol)
    if not (np.isfinite(angle_deg) and 0 < angle_deg < 180):
        raise BadInputError(f"the angle tolerance must be between 0 and 180 degrees, got {angle_deg}")
    if bound not in ("local", "span"):
        raise BadInputError(f"unknown bound rule {bound!r}; use 'local' or 'span'")
    diag = S.diagonal()
    if tol < 1e-11 * diag:
        raise BadInputError(f"the tolerance {tol:.3g} is below round-off for this surface (diagonal "
                            f"{diag:.3g}); give at least {1e-11 * diag:.3g}")
    ext = float(np.ptp(D.poles, axis=0).max())
    if ext <= 1e-12 * max(1.0, float(np.abs(D.poles).max())):
        raise BadInputError("the domain curve has zero length (all its points coincide); give distinct points")
    spans = SpanPatches(S)
    sb = S.derivative_bounds() if bound == "span" else None

    def analyse(H, t0, t1, sid=None) -> _Stack:
        P = H[:, :, :2] / H[:, :, 2:]
        if sid is None:
            mid = _split_stack(H, np.full(H.shape[0], 0.5))[1][:, 0]
            sid = spans.of(mid[:, :2] / mid[:, 2:])
        h, tf = _farthest(H)
        if bound == "span":
            _, _, _, slo, _ = spans.arrays()
            iu = find_spans(S.knots_u, S.degree_u, S.poles.shape[0], slo[sid, 0]) - S.degree_u
            iv = find_spans(S.knots_v, S.degree_v, S.poles.shape[1], slo[sid, 1]) - S.degree_v
            G = sb["Su"][iu, iv] + sb["Sv"][iu, iv]
        else:
            G = spans.local_bounds(sid, P.min(axis=1), P.max(axis=1))
        return _Stack(H, t0, t1, sid, h, tf, G)

    def split(st: _Stack) -> _Stack:
        """Split at the farthest points, then into single-sided parts (which stay in their span)."""
        t = np.where(st.h > 0, st.tf, 0.5)
        L, R = _split_stack(st.H, t)
        tm = st.t0 + (st.t1 - st.t0) * t
        H, t0, t1, sid = _single_sided_stack(np.concatenate([L, R]), np.concatenate([st.t0, tm]),
                                             np.concatenate([tm, st.t1]), np.concatenate([st.sid, st.sid]))
        return analyse(H, t0, t1, sid)

    t_lo, t_hi = D.domain
    init = domain_pieces(D, S)
    active = analyse(np.array([p.hom for p in init]), np.array([p.t0 for p in init]),
                     np.array([p.t1 for p in init]))
    # §4: split at the farthest point until every piece's certified bound meets the tolerance
    done = []
    covered = 0.0
    while active.n:
        ok = active.h * active.G <= tol
        done.append(active.take(ok))
        covered += float((active.t1[ok] - active.t0[ok]).sum())
        if progress is not None:
            progress("distance", covered / (t_hi - t_lo))
        if ok.all():
            break
        if sum(x.n for x in done) + 2 * int((~ok).sum()) > max_segments:
            raise TooBigError(f"more than {max_segments} segments would be needed for the tolerance {tol:.3g}; "
                              f"raise the tolerance")
        active = split(active.take(~ok))
    pieces = _Stack.join(done)
    pieces = pieces.take(np.argsort(pieces.t0, kind="stable"))
    n_dist = pieces.n
    D01 = D(np.array([t_lo, t_hi]))
    closed = bool(np.linalg.norm(D01[1] - D01[0]) <= 1e-10 * max(1.0, ext))

    def joints(st: _Stack):
        """Joint pairs (i, j), chord-image angles and exact-image angles (eqs. 20–22)."""
        k = st.n
        i = np.arange(k - 1)
        if closed and k > 1:
            i = np.append(i, k - 1)
        j = (i + 1) % k
        P = st.H[:, :, :2] / st.H[:, :, 2:]
        J = spans.jacobian(np.concatenate([st.sid[i], st.sid[j]]), np.concatenate([P[i, -1], P[j, 0]]))
        Ja, Jb = J[:i.size], J[i.size:]
        chord = _angles(np.einsum("nc,ncx->nx", P[i, -1] - P[i, 0], Ja),
                        np.einsum("nc,ncx->nx", P[j, -1] - P[j, 0], Jb))
        exact = _angles(np.einsum("nc,ncx->nx", _end_legs(P[i], False), Ja),
                        np.einsum("nc,ncx->nx", _end_legs(P[j], True), Jb))
        return i, j, chord, exact

    # §5: split the piece with the larger deviation at every joint over the angle tolerance; joints
    # where the exact image itself turns by the tolerance or more are corners and stay
    rounds = 0
    i, j, chord, exact = joints(pieces)
    while True:
        corner = np.isnan(chord) | np.isnan(exact) | (exact >= angle_deg * (1 - 1e-9))
        bad = ~corner & (chord > angle_deg)
        pick = np.where(pieces.h[i] >= pieces.h[j], i, j)[bad]
        stuck = pieces.h[pick] <= 1e-15 * ext
        pick = np.unique(pick[~stuck])
        if pick.size == 0:
            break
        rounds += 1
        if pieces.n + pick.size > max_segments:
            raise TooBigError(f"more than {max_segments} segments would be needed for the angle tolerance "
                              f"{angle_deg:g} degrees; raise it")
        keep = np.ones(pieces.n, bool)
        keep[pick] = False
        pieces = _Stack.join([pieces.take(keep), split(pieces.take(pick))])
        pieces = pieces.take(np.argsort(pieces.t0, kind="stable"))
        if progress is not None:
            progress("angle", min(1.0, rounds / 20))
        i, j, chord, exact = joints(pieces)
    corner = np.isnan(chord) | np.isnan(exact) | (exact >= angle_deg * (1 - 1e-9))
    made = chord[~corner]
    corners = [(float(pieces.t0[jj]) if jj else float(pieces.t1[ii]), float(e))
               for ii, jj, e in zip(i[corner], j[corner], exact[corner])]
    notes = []
    if corners:
        notes.append(f"{len(corners)} joint(s) where the exact image itself has a corner of at least the angle "
                     f"tolerance (a polyline vertex, a kink of the domain curve or of the surface) are kept")
    curve, pcurve = _assemble(S, spans, pieces, closed)
    return CurveOnSurface(
        curve=curve, pcurve=pcurve, degree=S.degree_u + S.degree_v, segments=pieces.n,
        control_points=int(curve.poles.shape[0]), error_bound=float((pieces.h * pieces.G).max()),
        max_joint_angle_deg=float(made.max()) if made.size else 0.0, corners=corners, closed=closed,
        tol=float(tol), angle_deg=float(angle_deg), bound_rule=bound, distance_segments=n_dist, notes=notes)


def _assemble(S: Surface, spans: SpanPatches, st: _Stack, closed: bool) -> tuple[Curve, Curve]:
    """Compose every chord with its patch and join the Bézier segments into one B-spline (C0 knots of
    multiplicity p + q at the joints, parameters those of the domain curve); the pcurve is the polyline."""
    p, q = S.degree_u, S.degree_v
    deg = p + q
    nets, _, _, slo, shi = spans.arrays()
    P = st.H[:, :, :2] / st.H[:, :, 2:]
    segs = compose_stack(nets[st.sid], slo[st.sid], shi[st.sid], P[:, 0], P[:, -1])
    Hc = np.concatenate([segs[0]] + list(segs[1:, 1:]), axis=0)
    Hc[deg:-1:deg] = 0.5 * (segs[:-1, -1] + segs[1:, 0])   # the joints: both sides agree to round-off
    verts = np.concatenate([P[:, 0], P[-1:, -1]])
    if closed:
        Hc[-1] = Hc[0]
        verts[-1] = verts[0]
    ts = np.concatenate([st.t0, st.t1[-1:]])
    knots = np.concatenate([[ts[0]] * (deg + 1), np.repeat(ts[1:-1], deg), [ts[-1]] * (deg + 1)])
    w = Hc[:, 3]
    curve = Curve(Hc[:, :3] / w[:, None], knots, deg, None if S.weights is None else w)
    pcurve = Curve(verts, np.concatenate([[ts[0]], ts, [ts[-1]]]), 1)
    return curve, pcurve


def sampled_error(S: Surface, D: Curve, res: CurveOnSurface, per_segment: int = 64) -> dict:
    """The engine's own measure of a result (no OCCT): the Hausdorff distance between the result
    and the exact image S(D(t)) by dense sampling of both (distance to the other's dense polyline),
    and the largest |curve(t) - S(pcurve(t))|."""
    knots = np.unique(res.curve.knots)
    per_segment = max(per_segment, -(-4000 // (knots.size - 1)))
    s = np.linspace(0.0, 1.0, per_segment + 1)[:-1]
    t = np.concatenate([a + s * (b - a) for a, b in zip(knots[:-1], knots[1:])] + [knots[-1:]])
    C = res.curve(t)
    uv = res.pcurve(t)
    on = float(np.linalg.norm(C - S(uv[:, 0], uv[:, 1]), axis=1).max())
    lo, hi = D.domain
    kd = D.knots[(D.knots > lo) & (D.knots < hi)]
    duv = D(np.unique(np.concatenate([np.linspace(lo, hi, max(4 * t.size, 2001)), kd])))   # corners included
    E = S(duv[:, 0], duv[:, 1])
    return {"hausdorff": max(to_polyline(C, E), to_polyline(E, C)), "on_surface": on}


__all__ = ["Piece", "CurveOnSurface", "approximate", "domain_pieces", "polyline_curve", "parse_uv",
           "domain_curve_from_json", "chord_distance",
           "span_tolerance", "sampled_error", "bezier_eval", "bezier_split", "single_sided"]
