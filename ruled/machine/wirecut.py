"""What a wire cuts, from its lines alone: the surface the wire sweeps between two guides moving straight and
together (XYUV: between two consecutive lines the wire at the fraction s of the move joins the two guides' points
at s, a bilinear patch), measured against the design faces both ways, signed, less the kerf.  It needs nothing of
the fit or of how the path was made: ``ruled machine`` measures its own lines with it and ``ruled replay`` the
lines a file makes the machine move, so the two report the same figures for the same file.

The faces come from a host (``Target``: OCCT's ruled.occ.wirecut or FreeCAD's): points of the faces as bounded
by their edges with their normals on the wire's side, and the feet of points on the faces' surfaces, whether each
foot lies inside its face and is a true (orthogonal) foot.

* design to cut: each design point's nearest point on the swept surface (exact on the patches: the nearest lines
  found by brute force, then golden sections across the two patches beside each); signed along the design's
  normal on the wire's side (+: the wire passes outside the design: material left; -: inside it, a gouge);
* cut to design: points of the swept lines (every move's start line, and more per move for about ``3 n^2`` in
  all) whose foot on a design surface lies inside its face: the signed distance to the foot;
* each less the kerf (the wire's radius plus its spark gap: the cut lies that far from the wire's axis, towards
  the design); overcut = the largest depth past the design, undercut = the largest material left.
"""

from __future__ import annotations

from typing import Protocol

import numpy as np

from ruled.core.nearest import golden

ALONG = 41          # points along each sampled line (plane to plane)


class Target(Protocol):
    """The design faces as a host gives them."""

    size: float
    against: str

    def design(self, n: int) -> tuple[np.ndarray, np.ndarray]:
        """(points (N, 3) of the faces as bounded by their edges, about n x n a face and n along every edge;
        unit normals (N, 3) there on the wire's side)."""
        ...

    def feet(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(feet (K, 3): the nearest point of the faces' surfaces to each point; unit normals there on the wire's
        side; (K,) True where the foot is an orthogonal foot inside its face)."""
        ...


def _segment(X, a, b):
    """Distances from X (..., 3) to the segments a-b (broadcast), and the fraction t of the nearest point."""
    d = b - a
    L2 = np.einsum("...k,...k->...", d, d)
    t = np.clip(np.einsum("...k,...k->...", X - a, d) / np.where(L2 > 0, L2, 1.0), 0.0, 1.0)
    r = X - (a + t[..., None] * d)
    return np.sqrt(np.einsum("...k,...k->...", r, r)), t


def swept_nearest(lower: np.ndarray, upper: np.ndarray, moves: np.ndarray, X: np.ndarray, near: int = 4,
                  rounds: int = 40, spacing: float = 0.01) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(distances (N,), nearest points (N, 3), the move (N,) each lies on, the fraction (N,) of that move) of the
    points X to the surface swept by the lines lower[i]-upper[i] over the moves (indices i: the move from line
    i - 1 to line i): lines sampled across every move no farther apart than `spacing` of the path's size (a long
    straight move gets many), the `near` nearest of them by brute force (in chunks), then a golden-section search
    across each one's move between its neighbouring samples.  Then every stretch between two sampled lines of a
    move that could hold a nearer point is searched too: the stretch's points lie within its step h (the most a
    guide moves over it) of either line, so none is nearer than (d0 + d1 - h) / 2, d0 and d1 the lines'
    distances (where the path twists, the nearest lines need not bracket the nearest point)."""
    X = np.asarray(X, float).reshape(-1, 3)
    moves = np.asarray(moves, np.int64)
    ends = np.concatenate([lower, upper])
    h = spacing * max(float(np.linalg.norm(np.ptp(ends, axis=0))), 1e-300)
    step = np.maximum(np.linalg.norm(lower[moves] - lower[moves - 1], axis=1),
                      np.linalg.norm(upper[moves] - upper[moves - 1], axis=1))
    per = np.maximum(1, np.ceil(step / h)).astype(np.int64)
    M = np.repeat(moves, per + 1)                                  # the sampled lines: move, fraction, spacing
    S = np.concatenate([np.arange(k + 1) / k for k in per])
    W = np.repeat(1.0 / per, per + 1)
    H = np.repeat(step / per, per + 1)                             # the step from each sampled line to the next
    a = lower[M - 1] + S[:, None] * (lower[M] - lower[M - 1])
    b = upper[M - 1] + S[:, None] * (upper[M] - upper[M - 1])
    k = min(near, len(M))
    chunk = max(1, 2_000_000 // len(M))

    def lines_to(c):
        return _segment(X[c:c + chunk, None, :], a[None], b[None])[0]
    nearest = np.empty((len(X), k), np.int64)
    for c in range(0, len(X), chunk):
        d = lines_to(c)
        nearest[c:c + chunk] = np.argpartition(d, k - 1, axis=1)[:, :k] if k < len(M) else np.arange(len(M))[None]
    rows = np.repeat(np.arange(len(X)), k)
    j = nearest.ravel()
    got = _searched(lower, upper, X, rows, M[j], np.maximum(S[j] - W[j], 0.0), np.minimum(S[j] + W[j], 1.0),
                    S[j], rounds)
    fs = _best(rows, got[1], len(X))[1]
    # the stretches (sampled line i to i + 1 of one move) whose bound is below the best found
    inner = np.flatnonzero(M[:-1] == M[1:])
    more_r, more_i = [], []
    for c in range(0, len(X), chunk):
        d = lines_to(c)
        lb = 0.5 * (d[:, inner] + d[:, inner + 1] - H[inner][None])
        r, i = np.nonzero(lb < fs[c:c + chunk, None] * (1.0 - 1e-9))
        more_r.append(r + c)
        more_i.append(inner[i])
    r, i = np.concatenate(more_r), np.concatenate(more_i)
    if r.size:
        more = _searched(lower, upper, X, r, M[i], S[i], S[i + 1], S[i], rounds)
        rows = np.concatenate([rows, r])
        got = tuple(np.concatenate([g, m]) for g, m in zip(got, more))
    m, fs, s = got
    sel = _best(rows, fs, len(X))[0]
    a0, a1, b0, b1 = lower[m[sel] - 1], lower[m[sel]], upper[m[sel] - 1], upper[m[sel]]
    ss = s[sel][:, None]
    A, B = a0 + ss * (a1 - a0), b0 + ss * (b1 - b0)
    _, t = _segment(X, A, B)
    return fs[sel], A + t[:, None] * (B - A), m[sel], s[sel]


def _searched(lower, upper, X, rows, m, lo, hi, at, rounds) -> tuple:
    """(moves, distances, fractions): golden sections of the distance from X[rows] to the line across the move m
    over the fractions [lo, hi] (its ends and the sample `at` tried too: a search ends a hair inside)."""
    P = X[rows]
    a0, a1, b0, b1 = lower[m - 1], lower[m], upper[m - 1], upper[m]

    def f(s):
        s = s[:, None]
        return _segment(P, a0 + s * (a1 - a0), b0 + s * (b1 - b0))[0]
    s, fs = golden(f, lo, hi, rounds)
    for edge in (lo, hi, at):
        fe = f(edge)
        s, fs = np.where(fe < fs, edge, s), np.minimum(fe, fs)
    return m, fs, s


def _best(rows: np.ndarray, fs: np.ndarray, n: int) -> tuple:
    """(the index of each point's smallest candidate, ordered by point; those smallest values)."""
    order = np.lexsort((fs, rows))
    first = np.ones(order.size, bool)
    first[1:] = rows[order][1:] != rows[order][:-1]
    sel = order[first]
    sel = sel[np.argsort(rows[sel])]
    return sel, fs[sel]


def swept_normals(lower: np.ndarray, upper: np.ndarray, move: np.ndarray, s: np.ndarray) -> np.ndarray:
    """(N, 3) unit normals of the swept surface on the moves at the fractions s, half way up the wire: the move's
    direction there crossed with the wire (one orientation along the whole path, the path running on)."""
    a0, a1, b0, b1 = lower[move - 1], lower[move], upper[move - 1], upper[move]
    along = 0.5 * ((a1 - a0) + (b1 - b0))
    wire = (b0 - a0) + s[:, None] * ((b1 - b0) - (a1 - a0))
    n = np.cross(along, wire)
    return n / np.maximum(np.linalg.norm(n, axis=1), 1e-300)[:, None]


def loop_sides(lower: np.ndarray, upper: np.ndarray, moves: np.ndarray, leads: tuple, X: np.ndarray):
    """(N,) +1 where a point of X lies on the side of a closed XYUV loop that most of them lie on (the material's:
    the design lies a kerf from the wire, on its material side), -1 on the other, or None where the moves (past
    the leads) are not one closed loop.  The guides lie on two parallel planes, so the surface the wire sweeps
    meets each plane between them exactly in the polygon through the lines' points there: the side is the
    winding number of that polygon, at each point's own height, about it (where the path twists at a corner its
    swept surface folds, and no normal of it tells the sides apart)."""
    body = moves[leads[0]:len(moves) - leads[1]] if len(moves) > sum(leads) else moves
    if body.size < 3 or np.any(np.diff(body) != 1):
        return None
    lo, up = lower[body[0] - 1:body[-1] + 1], upper[body[0] - 1:body[-1] + 1]
    size = float(np.linalg.norm(np.ptp(np.concatenate([lo, up]), axis=0)))
    if max(np.linalg.norm(lo[-1] - lo[0]), np.linalg.norm(up[-1] - up[0])) > 1e-9 * size:
        return None
    frame = np.linalg.svd(lo - lo.mean(axis=0))[2]
    d = frame[2]                                   # the planes' normal
    h0, h1 = lo @ d, up @ d
    if np.any(np.abs(h1 - h1[0]) > 1e-9 * size) or np.any(np.abs(h0 - h0[0]) > 1e-9 * size):
        return None
    e1 = frame[0]
    e2 = np.cross(d, e1)
    f = ((np.asarray(X, float) @ d) - h0[0]) / (h1[0] - h0[0])
    w = np.empty(len(f))
    chunk = max(1, 2_000_000 // len(lo))
    for k in range(0, len(f), chunk):
        Q = lo[None] + f[k:k + chunk, None, None] * (up - lo)[None]      # the polygon at each point's height
        V = Q - X[k:k + chunk, None, :]
        x, y = V @ e1, V @ e2
        x1, y1 = np.roll(x, -1, axis=1), np.roll(y, -1, axis=1)
        w[k:k + chunk] = np.arctan2(x * y1 - y * x1, x * x1 + y * y1).sum(axis=1)
    turns = np.rint(w / (2.0 * np.pi)).astype(np.int64)
    values, counts = np.unique(turns, return_counts=True)
    return np.where(turns == values[np.argmax(counts)], 1.0, -1.0)


def line_points(lower: np.ndarray, upper: np.ndarray, moves: np.ndarray, count: int, along: int = ALONG,
                spans=None) -> tuple[np.ndarray, np.ndarray]:
    """(points (K, 3), the move (K,) each is on) of the swept lines: `along` points from the lower to the upper
    guide (or between the fractions spans[k] of the way, for the k-th move), on lines evenly inside every move (its
    start line first, the last move's end line too), about count / along lines in all, shared among the moves
    by their lengths (a long straight move gets many)."""
    moves = np.asarray(moves, np.int64)
    step = np.maximum(np.linalg.norm(lower[moves] - lower[moves - 1], axis=1),
                      np.linalg.norm(upper[moves] - upper[moves - 1], axis=1))
    lines = count / along
    per = np.maximum(1, np.round(lines * step / max(float(step.sum()), 1e-300))).astype(np.int64)
    spans = np.tile([0.0, 1.0], (moves.size, 1)) if spans is None else np.asarray(spans, float)
    S = np.concatenate([np.arange(k) / k for k in per] + [[1.0]])
    k = np.concatenate([np.repeat(np.arange(moves.size), per), [moves.size - 1]])
    M = moves[k]
    a = lower[M - 1] + S[:, None] * (lower[M] - lower[M - 1])
    b = upper[M - 1] + S[:, None] * (upper[M] - upper[M - 1])
    t = spans[k, :1] + np.linspace(0.0, 1.0, along)[None, :] * (spans[k, 1:] - spans[k, :1])
    pts = a[:, None] + t[..., None] * (b - a)[:, None]
    return pts.reshape(-1, 3), np.repeat(M, along)


def cut_points(target: Target, lower: np.ndarray, upper: np.ndarray, moves: np.ndarray, count: int):
    """(points, their moves, feet, normals) of the swept lines over the faces, about `count` of them: on each line
    the unbroken stretch of points with a foot inside a face round its point nearest a face (past the faces' edges
    a line runs through the air, or past the part; farther on, a curved face can have feet again that the line
    never cuts).  A first pass along the whole of each move's start line finds its stretch, a second samples the
    stretches of each move's two lines."""
    def over(C):
        F, N, ok = target.feet(C)
        d = np.where(ok, np.linalg.norm(C - np.where(ok[:, None], F, C), axis=1), np.inf).reshape(-1, ALONG)
        okr = ok.reshape(-1, ALONG)
        rows = np.arange(len(okr))
        j = np.argmin(d, axis=1)
        breaks = np.cumsum(~okr, axis=1)        # the run of ok points through j: no break between
        run = okr & (breaks == breaks[rows, j][:, None]) & np.isfinite(d[rows, j])[:, None]
        return F, N, run
    moves = np.asarray(moves, np.int64)
    C, cm = line_points(lower, upper, moves, 0, ALONG)
    F, N, run = over(C)
    if run.any():
        t = np.linspace(0.0, 1.0, ALONG)
        lo = np.where(run.any(axis=1), t[np.argmax(run, axis=1)], np.inf)
        hi = np.where(run.any(axis=1), t[ALONG - 1 - np.argmax(run[:, ::-1], axis=1)], -np.inf)
        step = 1.0 / (ALONG - 1)
        a = np.maximum(np.minimum(lo[:-1], lo[1:]) - step, 0.0)       # each move: its two lines' stretches
        b = np.minimum(np.maximum(hi[:-1], hi[1:]) + step, 1.0)
        has = b > a
        if has.any():
            C, cm = line_points(lower, upper, moves[has], count, ALONG, np.stack([a[has], b[has]], axis=1))
            F, N, run = over(C)
    ok = run.ravel()
    return C[ok], cm[ok], F[ok], N[ok]


def wire_cut(target: Target, lower: np.ndarray, upper: np.ndarray, moves: np.ndarray, n: int = 30,
             kerf: float = 0.0, leads: tuple = (0, 0)) -> dict:
    """The cut of the wire swept along the moves against the target's faces (see the module): the report's
    "cut" figures and, per move, the largest over- and undercut ("per_move", indexed like lower).  leads: how
    many of the first and of the last moves bring the wire to the path and take it away (a lead-in and lead-out,
    a wire EDM's tilt from upright): they count from the design's side (a lead that cut into the design would
    show there), not as points of the cut (a lead runs square to the face, off it)."""
    lower, upper = np.asarray(lower, float), np.asarray(upper, float)
    P, N = target.design(n)
    d, q, mv, sq = swept_nearest(lower, upper, moves, P)
    # which side of the swept surface a design point lies on: by the surface's own normal (one orientation for
    # the whole path, turned to the wire's side by the design's normals, by a majority: a design normal alone is
    # not to be trusted at a sharp corner, where the point is on two faces, nor at a cone's apex)
    moves = np.asarray(moves, np.int64)
    side = loop_sides(lower, upper, moves, leads, P)
    if side is None:
        nw = swept_normals(lower, upper, mv, sq)
        nw *= 1.0 if float(np.sum(np.sign(np.einsum("ij,ij->i", nw, N)))) >= 0 else -1.0
        side = np.einsum("ij,ij->i", q - P, nw)
    dev_design = np.where(side >= 0, d, -d) - kerf
    body = moves[leads[0]:len(moves) - leads[1]] if len(moves) > sum(leads) else moves
    C, cm, F, NF = cut_points(target, lower, upper, body, 3 * n * n)
    dev_cut = np.einsum("ij,ij->i", C - F, NF) - kerf
    over, under = np.zeros(len(lower)), np.zeros(len(lower))
    for dev, at in ((dev_design, mv), (dev_cut, cm)):
        good = at >= 0
        np.maximum.at(over, at[good], np.maximum(-dev[good], 0.0))
        np.maximum.at(under, at[good], np.maximum(dev[good], 0.0))
    every = np.concatenate([dev_design, dev_cut])
    pts = np.concatenate([P, C])
    i, j = int(np.argmin(every)), int(np.argmax(every))
    out = {"against": target.against, "max": float(np.abs(every).max()),
           "design_to_cut": float(np.abs(dev_design).max()),
           "design_to_cut_median": float(np.median(np.abs(dev_design))),
           "cut_to_design": float(np.abs(dev_cut).max()) if dev_cut.size else 0.0,
           "overcut": float(max(0.0, -every[i])), "undercut": float(max(0.0, every[j])),
           "overcut_at": pts[i].tolist() if every[i] < 0 else None,
           "undercut_at": pts[j].tolist() if every[j] > 0 else None,
           "samples": int(every.size), "line_points_over_the_faces": int(len(C)), "measure_samples": int(n),
           "per_move": {"overcut": over.tolist(), "undercut": under.tolist()}}
    if kerf:
        out["kerf"] = kerf
    return out


__all__ = ["Target", "swept_nearest", "loop_sides", "swept_normals", "line_points", "cut_points", "wire_cut", "ALONG"]
