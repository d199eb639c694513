"""A wall's faces as one B-spline surface closed round the ring, on plain arrays: each face a four-sided
patch (its surface turned so that v runs from the bottom contour to the top and u round the ring, or the
ruled patch between its contour curves on a plane), the patches made compatible along v (common degrees
and knots: exact) and joined with full-multiplicity knots at the joints (C0: the contours' corners stay
corners), the faces' shares of u their contours' lengths.  Hosts give the faces' surfaces, their contour
curves and the points of their edges (ruled.occ.wall for OCCT)."""

from __future__ import annotations

import numpy as np

from ruled.core.errors import BadInputError
from ruled.core.knots import elevate, insert_knot
from ruled.core.nurbs import Curve, Surface

CORNER_DEG = 1.0     # contours turning by more than this at a joint have a corner there


def turn(before: np.ndarray, after: np.ndarray) -> float:
    """The angle (degrees) a curve turns at the joint of two clamped control polygons (the last pole of before
    is the first of after): between their end legs; 0 where a leg has no length (a contour collapsed to a
    point there)."""
    a = before[-1] - next((p for p in before[-2::-1] if np.linalg.norm(before[-1] - p) > 0), before[-1])
    b = next((p for p in after[1:] if np.linalg.norm(p - after[0]) > 0), after[0]) - after[0]
    na, nb = float(np.linalg.norm(a)), float(np.linalg.norm(b))
    if na == 0.0 or nb == 0.0:
        return 0.0
    return float(np.degrees(np.arccos(np.clip(a @ b / (na * nb), -1.0, 1.0))))


def _w(S: Surface) -> np.ndarray:
    return S.weights if S.weights is not None else np.ones(S.poles.shape[:2])


def _rows(S: Surface) -> list:
    """S's rows along u (one curve per v-index)."""
    w = _w(S)
    return [Curve(S.poles[:, j], S.knots_u, S.degree_u, w[:, j] if S.weights is not None else None)
            for j in range(S.poles.shape[1])]


def _from_rows(rows: list, S: Surface) -> Surface:
    P = np.stack([c.poles for c in rows], axis=1)
    W = np.stack([c.weights if c.weights is not None else np.ones(len(c.poles)) for c in rows], axis=1)
    return Surface(P, rows[0].knots, S.knots_v, rows[0].degree, S.degree_v, W if S.weights is not None else None)


def along_u(S: Surface, op) -> Surface:
    return _from_rows([op(c) for c in _rows(S)], S)


def _along_v(S: Surface, op) -> Surface:
    return along_u(S.transposed(), op).transposed()


def elevated_u(S: Surface, p: int) -> Surface:
    """S with its u degree raised to p (exactly)."""
    return along_u(S, lambda c: elevate(c, p))


def reversed_u(S: Surface) -> Surface:
    k = S.knots_u
    return Surface(S.poles[::-1].copy(), (k[0] + k[-1]) - k[::-1], S.knots_v, S.degree_u, S.degree_v,
                   None if S.weights is None else S.weights[::-1].copy())


def remapped(S: Surface, a: float, b: float, c: float = 0.0, d: float = 1.0) -> Surface:
    """S with its u knots mapped affinely onto [a, b] and its v knots onto [c, d]."""
    def m(k, x, y):
        out = x + (y - x) * (k - k[0]) / (k[-1] - k[0])
        out[k == k[0]], out[k == k[-1]] = x, y
        return out
    return Surface(S.poles, m(S.knots_u, a, b), m(S.knots_v, c, d), S.degree_u, S.degree_v, S.weights)


def with_knots(C: Curve, wanted: dict) -> Curve:
    """C with each knot x of wanted (inside its domain) of multiplicity at least wanted[x]."""
    for x, m in sorted(wanted.items()):
        have = int(np.sum(np.abs(C.knots - x) <= 1e-12))
        if have < m:
            C = insert_knot(C, x, m - have)
    return C


def _knot_mults(k: np.ndarray) -> dict:
    x, m = np.unique(np.round(k, 12), return_counts=True)
    return dict(zip(x.tolist(), m.tolist()))


def side_distance(S: Surface, side: int, cloud: np.ndarray) -> float:
    """The largest distance from the points cloud to side (0: v-min, 1: u-max, 2: v-max, 3: u-min) of S, as a
    polyline of 129 of its points: small when cloud lies along that side."""
    u0, u1, v0, v1 = S.domain
    t = np.linspace(0.0, 1.0, 129)
    u, v = {0: (u0 + (u1 - u0) * t, np.full(t.size, v0)), 1: (np.full(t.size, u1), v0 + (v1 - v0) * t),
            2: (u0 + (u1 - u0) * t, np.full(t.size, v1)), 3: (np.full(t.size, u0), v0 + (v1 - v0) * t)}[side]
    P = S(u, v)
    A, D = P[:-1], np.diff(P, axis=0)
    x = cloud[:, None, :] - A[None]
    f = np.clip((x * D[None]).sum(-1) / np.maximum((D * D).sum(-1), 1e-300)[None], 0.0, 1.0)
    return float(np.max(np.min(np.linalg.norm(x - f[..., None] * D[None], axis=2), axis=1)))


def oriented(S: Surface, bottom, top, before, after, name, size: float, tol: float) -> Surface:
    """The face's surface S turned so that v runs from its bottom contour edges' points (bottom, or None where
    it meets the contour at a point) to its top ones and u from its joint with the previous face (before's
    points; after's where before is None).  Refused when the edges are no opposite sides of S within tol."""
    score = [[side_distance(S, s, c) if c is not None else np.inf for s in range(4)] for c in (bottom, top)]
    sb = (int(np.argmin(score[1])) + 2) % 4 if bottom is None else int(np.argmin(score[0]))
    st = (sb + 2) % 4
    worst = max(score[0][sb] if bottom is not None else 0.0, score[1][st] if top is not None else 0.0)
    if worst > tol:
        raise BadInputError(f"face {name} of the wall: its contour edges are not opposite sides of its surface "
                            f"(a trimmed face; {worst:.3g} off); walls of such faces are not supported yet")
    if sb in (1, 3):
        S = S.transposed()
        sb = 0 if sb == 3 else 2
    if sb == 2:
        S = S.transposed()
        S = reversed_u(S).transposed()
    if before is not None and side_distance(S, 3, before) > side_distance(S, 1, before):
        S = reversed_u(S)
    elif before is None and after is not None and side_distance(S, 1, after) > side_distance(S, 3, after):
        S = reversed_u(S)
    return S


def ruled_patch(bottom: Curve, top: Curve) -> Surface:
    """The ruled surface between two curves at equal fractions of their parameters (both running from the
    face's joint with the previous one): a planar face between straight joints, exactly."""
    p = max(bottom.degree, top.degree)
    cs = [elevate(Curve(c.poles, (c.knots - c.knots[0]) / (c.knots[-1] - c.knots[0]), c.degree, c.weights), p)
          for c in (bottom, top)]
    inner: dict = {}
    for c in cs:
        for x, m in _knot_mults(c.knots).items():
            if 0.0 < x < 1.0:
                inner[x] = max(inner.get(x, 0), m)
    cs = [with_knots(c, inner) for c in cs]
    W = np.stack([c.weights if c.weights is not None else np.ones(len(c.poles)) for c in cs], axis=1)
    rational = any(c.weights is not None for c in cs)
    return Surface(np.stack([c.poles for c in cs], axis=1), cs[0].knots, np.array([0.0, 0.0, 1.0, 1.0]), p, 1,
                   W if rational else None)


def _reversed_curve(c: Curve) -> Curve:
    k = c.knots
    return Curve(c.poles[::-1].copy(), (k[0] + k[-1]) - k[::-1], c.degree,
                 None if c.weights is None else c.weights[::-1].copy())


def chained(curves: list, start: np.ndarray, tol: float) -> Curve:
    """Curves (in any order and direction) chained end to end into one from the point start: each turned to
    run on from the last's end, raised to the largest degree (exactly), given its share of the parameter by
    its control polygon's length, and joined with a full-multiplicity knot (C0; a rational one's weights
    scaled to agree at the joint, which keeps it)."""
    left, cur, parts = list(curves), np.asarray(start, float), []
    while left:
        ends = [(c(np.array(c.domain[:1]))[0], c(np.array(c.domain[1:]))[0]) for c in left]
        k, flip = min(((i, j) for i in range(len(left)) for j in (0, 1)),
                      key=lambda ij: float(np.linalg.norm(ends[ij[0]][ij[1]] - cur)))
        if np.linalg.norm(ends[k][flip] - cur) > tol:
            raise BadInputError("a face's contour edges do not chain end to end; repair the part")
        c = left.pop(k)
        parts.append(_reversed_curve(c) if flip else c)
        cur = ends[k][1 - flip]
    p = max(c.degree for c in parts)
    parts = [elevate(c, p) for c in parts]
    lengths = np.array([max(float(np.linalg.norm(np.diff(c.poles, axis=0), axis=1).sum()), 1e-300) for c in parts])
    edges = np.concatenate([[0.0], np.cumsum(lengths) / lengths.sum()])
    P, W = parts[0].poles, _cw(parts[0])
    knots: list = [edges[0]] * (p + 1)
    for i, c in enumerate(parts):
        kn = c.knots
        inner = edges[i] + (edges[i + 1] - edges[i]) * (kn[p + 1:-p - 1] - kn[0]) / (kn[-1] - kn[0])
        knots += list(inner) + [edges[i + 1]] * p
        if i:
            w = _cw(c) * (W[-1] / _cw(c)[0])
            P, W = np.concatenate([P, c.poles[1:]]), np.concatenate([W, w[1:]])
    knots.append(edges[-1])
    rational = bool(np.ptp(W) > 1e-12 * float(np.max(W)))
    return Curve(P, np.asarray(knots), p, W if rational else None)


def _cw(c: Curve) -> np.ndarray:
    return c.weights if c.weights is not None else np.ones(len(c.poles))


def wall_patch(name, S, bottom: list, top: list, before, after, size: float, edge_tol: float,
               loose=None) -> tuple:
    """(a wall's face as a four-sided patch: u along the ring, from its joint ``before`` to ``after``, v from its
    bottom contour edges to its top ones; its contours' mean length; its deviation from the face, 0 where
    exact).  S: the face's surface (clamped, not periodic), or None for a planar face, whose patch is the ruled
    surface between its chained contour curves (exact where its joints are straight).  bottom, top, before,
    after: ruled.fit.wall.ring.RingEdge (with their curves where S is None); edge_tol: the face's contour edges'
    tolerance (an edge that close to the surface lies on it).  loose: where the face is no exact patch (its
    contour edges are not opposite sides of its surface; a plane with curved joints), a callable giving its
    Coons patch (ruled.fit.wall.patch.contour_patch), whose deviation is then the third figure; without it
    such a face is refused."""
    length = max(0.5 * (sum(e.length for e in bottom) + sum(e.length for e in top)), 1e-12 * size)
    b, t = (np.concatenate([e.points for e in c]) if c else None for c in (bottom, top))
    jb, ja = (None if e is None else e.points for e in (before, after))
    try:
        return _exact_patch(name, S, bottom, top, (before, after), (b, t, jb, ja), size, edge_tol), length, 0.0
    except BadInputError:
        if loose is None or b is None or t is None:
            raise
    fp = loose()
    dev = float(fp.deviation)
    return oriented(fp.surface, b, t, jb, ja, name, size, max(1e-3 * size, 1.5 * edge_tol + dev)), length, dev


def _covers(S: Surface, side: int, cloud: np.ndarray, tol: float) -> bool:
    """Side ``side`` of S lies along the points cloud (its edges' samples), end to end within tol."""
    from ruled.core.distance import to_polyline
    u0, u1, v0, v1 = S.domain
    x = np.linspace(0.0, 1.0, 65)
    v = v0 if side == 0 else v1
    return to_polyline(S(u0 + (u1 - u0) * x, np.full(x.size, v)), cloud) <= tol


def _dense(edges: list) -> np.ndarray:
    """Points along the edges, dense enough for a polyline through them to follow them (their curves at 257
    points each, where known; else their samples)."""
    out = []
    for e in edges:
        if e.curve is None:
            out.append(e.points)
        else:
            a, b = e.curve.domain
            out.append(e.curve(np.linspace(a, b, 257)))
    return np.concatenate(out)


def _exact_patch(name, S, bottom: list, top: list, joints: tuple, points: tuple, size: float,
                 edge_tol: float) -> Surface:
    """wall_patch's exact patch, or BadInputError; joints: (before, after); points: the bottom, top, before and
    after edges' samples."""
    before, after = joints
    b, t, jb, ja = points
    if S is None:
        sides = [e for e in (before, after) if e is not None]
        if before is None or not bottom or not top or not all(e.straight for e in sides):
            raise BadInputError(f"face {name} of the wall is planar but not bounded by its contour edges and two "
                                f"straight joints; walls of such faces are not supported yet")
        near = [float(np.min(np.linalg.norm(b - q, axis=1))) for q in (before.start, before.end)]
        start_b, start_t = (before.start, before.end) if near[0] <= near[1] else (before.end, before.start)
        tol = 1e-6 * size
        return ruled_patch(chained([e.curve for e in bottom], start_b, tol),
                           chained([e.curve for e in top], start_t, tol))
    tol = max(1e-3 * size, 1.5 * edge_tol)
    P = oriented(S, b, t, jb, ja, name, size, tol)
    # the contour edges cover the sides end to end (a face trimmed by curved joints has sides longer than them)
    for side, c in ((0, bottom), (1, top)):
        if c and not _covers(P, 2 * side, _dense(c), tol):
            raise BadInputError(f"face {name} of the wall: its contour edges are only part of its surface's sides "
                                f"(a face trimmed by its joints); walls of such faces are not supported yet")
    return P


def end_to_end(ps: list) -> tuple:
    """(Surface, offsets, spreads): surfaces of one u degree and one v knot vector, on consecutive u ranges,
    joined end to end with full-multiplicity knots (C0) and closed round: at each joint (and the closing one,
    last) the two end columns replaced by their mean, and each row of the later surface's weights scaled to
    agree with the earlier's there.  offsets: per joint the largest distance between the two columns;
    spreads: per joint the relative spread of the rows' weight ratios (0 where one factor scales them all,
    which keeps any surface; a ruled surface, v of degree 1, is kept as a point set by any)."""
    p = ps[0].degree_u
    P, W = ps[0].poles.copy(), _w(ps[0])
    knots = list(ps[0].knots_u[:-1])
    offs, spreads = [], []
    for S in ps[1:]:
        Pk, Wk = S.poles, _w(S)
        r = W[-1] / Wk[0]
        offs.append(float(np.max(np.linalg.norm(P[-1] - Pk[0], axis=1))))
        spreads.append(float(np.ptp(r) / np.max(r)))
        P[-1] = 0.5 * (P[-1] + Pk[0])
        P = np.concatenate([P, Pk[1:]])
        W = np.concatenate([W, Wk[1:] * r[None, :]])
        knots += list(S.knots_u[p + 1:-1])          # the joint's knot: p copies (one was the last surface's end)
    knots += [ps[-1].knots_u[-1]]
    offs.append(float(np.max(np.linalg.norm(P[0] - P[-1], axis=1))))
    P[0] = P[-1] = 0.5 * (P[0] + P[-1])
    rational = bool(np.ptp(W) > 1e-12 * float(np.max(W)))
    return Surface(P, np.asarray(knots), ps[0].knots_v, p, ps[0].degree_v, W if rational else None), offs, spreads


def joined(patches: list, lengths, names: list, size: float, deviations=None) -> tuple:
    """(Surface, breaks, corners, slack): the patches (u round the ring, v bottom to top) joined (see the module);
    breaks: the faces' joints in u; corners: the joints (indices into breaks, 0 the seam) where both
    contours turn by more than CORNER_DEG; slack: how far the joined surface can be from the faces beyond
    their edges' tolerances: the sampled patches' deviations (deviations, per patch; 0 for an exact one) and
    half the distance between the two end columns at a joint of a sampled patch, which are replaced by their
    mean (a pole moved moves the surface by at most as much)."""
    lengths = np.asarray(lengths, float)
    deviations = [0.0] * len(patches) if deviations is None else [float(d) for d in deviations]
    breaks = np.concatenate([[0.0], np.cumsum(lengths) / lengths.sum()])
    du = max(S.degree_u for S in patches)
    dv = max(S.degree_v for S in patches)
    ps = []
    for k, S in enumerate(patches):
        S = remapped(S, breaks[k], breaks[k + 1])
        S = elevated_u(S, du)
        S = _along_v(S, lambda c: elevate(c, dv))
        ps.append(S)
    inner: dict = {}
    for S in ps:
        for x, m in _knot_mults(S.knots_v).items():
            if 0.0 < x < 1.0:
                inner[x] = max(inner.get(x, 0), m)
    ps = [_along_v(S, lambda c: with_knots(c, inner)) for S in ps]
    S, offs, spreads = end_to_end(ps)
    tol = 1e-6 * size
    n, moved = len(ps), 0.0
    for k in range(n if n > 1 else 0):
        a, b = (k - 1) % n, k                    # joint k: between patch k - 1 and k (0: the closing one)
        off, spread = offs[k - 1], spreads[k - 1] if k else 0.0
        if off <= tol and spread <= 1e-9:
            continue
        if (deviations[a] > 0 or deviations[b] > 0) and spread <= 1e-9:
            moved = max(moved, 0.5 * off)
            continue
        raise BadInputError(f"faces {names[a]} and {names[b]} of the wall parametrize the edge they share "
                            f"differently ({off:.3g} apart); walls of such faces are not supported yet")
    corners = [k for k in range(len(ps)) if all(turn(ps[k - 1].poles[:, row], ps[k].poles[:, row]) > CORNER_DEG
                                                for row in (0, -1))]
    return S, breaks, corners, max(deviations) + moved


__all__ = ["CORNER_DEG", "turn", "joined", "chained", "wall_patch", "end_to_end", "elevated_u", "along_u",
           "with_knots", "oriented", "ruled_patch", "side_distance", "reversed_u", "remapped"]
