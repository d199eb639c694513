"""A cone spline trimmed by the face's edges: the cone spline of a ruled result that runs past the face
(its rails beyond the face's end edges, the result trimmed by the face's edges: ruled.fit.face.trim.Trim), with
each patch bounded by the face's boundary carried onto it.

The face's boundary lies on the ruled surface R as the trim's loops in R's (s, t).  For each piece of the
cone spline (its own pair of planes, §6) the loops are cut to the piece's rulings (a strip in s), carried
to the piece's chart (u, V): u the height between its planes, V = k + v on its k-th patch (the patches of
a piece follow one another along v and share their planes, so (u, V) is one chart of the piece), each point
the closest point of the patches to its point of R (Gauss-Newton from the patch that covers its ruling);
then cut to each patch's strip k <= V <= k + 1.  What is left of the face on a patch is a list of regions,
each an outer loop and its holes, as polylines in the patch's (u, v) with corner flags (the face's corners,
where a loop meets a strip's line): the host builds faces from them (one edge per run between corners).

Every point of a trimmed patch is the closest patch point to a point of R inside the trim (the chart is that
map's image), so it lies within the cone spline's bound of the fitted result, which lies within the fit's
bound of the face: the trimmed cone spline is within the sum of the two of the face.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np

from ruled.core.errors import RuledError
from ruled.core.nurbs import Curve, Surface
from ruled.core.region import crossings_odd

PER_CURVE = 96        # samples of each trim curve (the boundary's corners kept)
PER_LINE = 24         # samples of a ruling where a piece's strip cuts the face
NEWTON = 12           # Newton steps of the nearest point on a patch's section
SECTION = 33          # samples of each patch's section the nearest point starts from
CANDIDATES = 3        # patches tried for each nearest point
REFINE, FAST = 8, 0.05   # a boundary's chart refined this often where a step moves more than FAST in u or V


class TrimError(RuledError):
    """The face's boundary could not be carried onto the cone spline."""


@dataclass(frozen=True)
class PatchRegion:
    """What is left of the face on one cone patch: loops (P (M, 2) in the patch's (u, v), corner (M,) bool),
    the outer loop first (counter-clockwise), then its holes (clockwise)."""

    patch: int
    loops: tuple

    def trim(self):
        """The region as a ruled.fit.face.trim.Trim of the patch: its loops as 2D curves (loop_curves), what a host
        builds the trimmed patch from."""
        from ruled.fit.face.trim import Trim
        curves = [loop_curves(P, c) for P, c in self.loops]
        return Trim(curves[0], tuple(curves[1:]))


# ------------------------------------------------------------------------------------------------ loops
def _area(P: np.ndarray) -> float:
    x, y = P[:, 0], P[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def oriented(loops: list) -> list:
    """The loops with the first counter-clockwise and the others clockwise (the even-odd region's boundary
    with its inside on the left)."""
    out = []
    for i, (P, c) in enumerate(loops):
        ccw = _area(P) > 0
        out.append((P, c) if ccw == (i == 0) else (P[::-1].copy(), c[::-1].copy()))
    return out


def _chains(P: np.ndarray, c: np.ndarray, a: float, b: float, axis: int):
    """A closed loop cut to a <= x <= b (x = P[:, axis]): (chains, whole), chains: lists of (point, corner)
    entering and leaving through the lines (their first and last points on a line, flagged as corners, with
    the line: 0 for a, 1 for b); whole: the loop when it lies inside without crossing, else None."""
    x = P[:, axis]
    inside = (x >= a) & (x <= b)
    if inside.all():
        return [], (P, c)
    start = int(np.argmin(inside))            # an outside vertex: no chain wraps round the loop's start
    n = len(P)
    chains: list = []
    cur: Optional[list] = None
    for i in range(start, start + n):
        p, q = P[i % n], P[(i + 1) % n]
        if cur is not None:
            cur.append((p, bool(c[i % n])))
        # the segment's crossings of the two lines, in order along it
        ev = []
        da0, da1, db0, db1 = p[axis] - a, q[axis] - a, p[axis] - b, q[axis] - b
        if (da0 < 0) != (da1 < 0):              # inside is x >= a ...
            ev.append((da0 / (da0 - da1), 0))
        if (db0 > 0) != (db1 > 0):              # ... and x <= b
            ev.append((db0 / (db0 - db1), 1))
        for t, line in sorted(ev):
            X = p + t * (q - p)
            X[axis] = a if line == 0 else b
            if cur is None:
                cur = [(X, True, line)]
            else:
                cur.append((X, True, line))
                chains.append(cur)
                cur = None
    if cur is not None:
        raise TrimError("the face's boundary could not be cut to a patch of the cone spline (a loop that does not "
                        "close); try another tolerance")
    return chains, None


def strip_regions(loops: list, a: float, b: float, axis: int = 0) -> list:
    """The part of the region the loops bound (outer counter-clockwise, holes clockwise: see oriented) with
    a <= x <= b, x the coordinate `axis`: regions, each a list of loops (P (M, 2), corner (M,)), outer
    first.  Where the region meets a line x = a or b its boundary runs straight along it (corners at both
    ends)."""
    chains, whole = [], []
    for P, c in loops:
        ch, w = _chains(P, c, a, b, axis)
        chains += ch
        if w is not None:
            whole.append(w)
    # on each line, the crossings sorted along it bound the region's intervals there: (exit, entry) pairs
    other = 1 - axis
    follow = {}
    for line in (0, 1):
        ends = [(ch[-1][0][other], k, "exit") for k, ch in enumerate(chains) if ch[-1][2] == line] + \
               [(ch[0][0][other], k, "entry") for k, ch in enumerate(chains) if ch[0][2] == line]
        ends.sort(key=lambda e: e[0])
        if len(ends) % 2:
            raise TrimError("the face's boundary crosses a patch's edge an odd number of times; try another tolerance")
        for e, f in zip(ends[0::2], ends[1::2]):
            if {e[2], f[2]} != {"exit", "entry"}:
                raise TrimError("the face's boundary could not be cut to a patch of the cone spline (crossings "
                                "that do not pair); try another tolerance")
            ex, en = (e, f) if e[2] == "exit" else (f, e)
            follow[ex[1]] = en[1]
    out_loops, used = list(whole), set()
    for k in range(len(chains)):
        if k in used:
            continue
        pts, cs, j = [], [], k
        while j not in used:
            used.add(j)
            pts += [p[0] for p in chains[j]]
            cs += [p[1] for p in chains[j]]
            j = follow[j]
        if j != k:
            raise TrimError("the face's boundary could not be cut to a patch of the cone spline; try another "
                            "tolerance")
        out_loops.append((np.array(pts), np.array(cs, bool)))
    outers = [lp for lp in out_loops if _area(lp[0]) > 0]
    holes = [lp for lp in out_loops if _area(lp[0]) <= 0]
    regions = [[o] for o in sorted(outers, key=lambda lp: abs(_area(lp[0])))]
    for h in holes:
        for reg in regions:       # the smallest outer loop round it
            if crossings_odd(reg[0][0], h[0][:1])[0]:
                reg.append(h)
                break
    return regions


def _densify(P: np.ndarray, c: np.ndarray, n: int) -> tuple:
    """Runs along a strip's line (two corners in a row) sampled at n points: a ruling carried to a chart is
    curved there."""
    outP, outc = [], []
    m = len(P)
    for i in range(m):
        outP.append(P[i])
        outc.append(c[i])
        j = (i + 1) % m
        if c[i] and c[j]:
            t = np.linspace(0.0, 1.0, n + 1)[1:-1, None]
            outP += list(P[i] + t * (P[j] - P[i]))
            outc += [False] * (n - 1)
    return np.array(outP), np.array(outc, bool)


# ------------------------------------------------------------------------------------------------ chart
def _along(S: Surface, X: np.ndarray, u: np.ndarray, v: np.ndarray) -> tuple:
    """Damped Newton for the points of S's sections u (fixed) nearest to X (N, 3), from v, held in [0, 1] (a
    step that does not bring a point nearer is halved): (v, distance)."""
    dist = np.linalg.norm(X - S(u, v), axis=1)
    lam = np.ones(len(X))
    for _ in range(NEWTON):
        d = S.evaluate(u, v, 1)
        r = X - d.P
        g, h = (d.Sv * r).sum(1), (d.Sv * d.Sv).sum(1)
        vn = np.clip(v + lam * g / np.maximum(h, 1e-300), 0.0, 1.0)
        dn = np.linalg.norm(X - S(u, vn), axis=1)
        ok = dn <= dist
        v, dist = np.where(ok, vn, v), np.where(ok, dn, dist)
        lam = np.where(ok, np.minimum(1.0, 2 * lam), 0.5 * lam)
    return v, dist


def _to_chart(piece, patches: list, X: np.ndarray) -> np.ndarray:
    """Points X (N, 3) between the piece's planes as its chart (u, V), V = k + v: u the height's fraction
    between the planes, and the point of the patches' section at that height nearest to X (the section is
    a tangent-smooth chain of conics, R's section at that height a nearby smooth curve, so the nearest
    point moves continuously along it; eq. 9 bounds the distance between the two sections).  Newton on
    the CANDIDATES patches whose samples are nearest, from their nearest sample; the nearest kept."""
    h0, h1 = piece.heights
    u = np.clip(((X - piece.origin) @ piece.axes[2] - h0) / (h1 - h0), 0.0, 1.0)
    vs = np.linspace(0.0, 1.0, SECTION)
    near = np.empty((len(X), len(patches)))
    at = np.empty((len(X), len(patches)))
    for k, S in enumerate(patches):
        G = S(np.repeat(u, SECTION), np.tile(vs, len(X))).reshape(len(X), SECTION, 3)
        D = np.linalg.norm(G - X[:, None, :], axis=2)
        j = np.argmin(D, axis=1)
        at[:, k], near[:, k] = vs[j], D[np.arange(len(X)), j]
    best = np.full(len(X), np.inf)
    V = np.zeros(len(X))
    for rank in np.argsort(near, axis=1)[:, :CANDIDATES].T:
        for k in np.unique(rank):
            m = rank == k
            v, d = _along(patches[k], X[m], u[m], at[m, k])
            better = d < best[m]
            idx = np.flatnonzero(m)[better]
            best[idx], V[idx] = d[better], k + v[better]
    return np.stack([u, V], axis=1)


def _charted(R: Surface, piece, patches: list, P: np.ndarray, c: np.ndarray) -> tuple:
    """A closed loop P (M, 2) in R's normalized (x, t) carried to the piece's chart (_to_chart), its segments
    refined where the chart moves fast along them (across a patch's fan, where a patch collapses to a
    triangle, the chart runs over a whole patch in a short way): (the chart's points, their corner flags)."""
    s0, s1 = R.domain[:2]

    def chart(Q):
        X = R(np.clip(s0 + Q[:, 0] * (s1 - s0), s0, s1), np.clip(Q[:, 1], *R.domain[2:]))
        return _to_chart(piece, patches, X)
    C = chart(P)
    for _ in range(REFINE):
        step = np.abs(np.roll(C, -1, axis=0) - C).max(axis=1)
        fast = np.flatnonzero(step > FAST)
        if not fast.size:
            break
        mid = 0.5 * (P[fast] + np.roll(P, -1, axis=0)[fast])
        Cm = chart(mid)
        at = fast + 1
        P, C = np.insert(P, at, mid, axis=0), np.insert(C, at, Cm, axis=0)
        c = np.insert(c, at, False)
    return C, c


def _sampled(loops, per_curve: int) -> list:
    """Loops of 2D curves as closed polylines with a corner flag at each curve's start."""
    out = []
    for loop in loops:
        P = np.concatenate([cv(np.linspace(cv.domain[0], cv.domain[1], per_curve))[:-1] for cv in loop])
        c = np.zeros(len(P), bool)
        c[np.arange(len(loop)) * (per_curve - 1)] = True
        out.append((P, c))
    return out


def trimmed_patches(cone, R: Surface, trim) -> list:
    """The face (trim: its boundary on R as ruled.fit.face.trim.Trim, in R's (u, v)) on each patch of cone, the
    cone spline of R between its rails (R's rulings along v: ruled.cone.surface.cone_spline_of_surface with
    direction 'v'): PatchRegion list, patches the face does not reach left out."""
    s0, s1 = R.domain[:2]
    # the loops in (x, t): x along the rails, normalized as the cone spline's boundaries are; t across
    loops = oriented([(np.stack([(P[:, 0] - s0) / (s1 - s0), P[:, 1]], axis=1), c)
                      for P, c in _sampled((trim.outer,) + tuple(trim.holes), PER_CURVE)])
    out = []
    for p, piece in enumerate(cone.pieces):
        idx = [i for i, pt in enumerate(cone.patches) if pt.piece == p]
        patches = [cone.patches[i].surface for i in idx]
        a, b = piece.v_range
        for region in strip_regions(loops, a, b, 0):
            charted = []
            for P, c in region:
                P, c = _densify(P, c, PER_LINE)
                charted.append(_charted(R, piece, patches, P, c))
            if _area(charted[0][0]) < 0:             # the chart turns (x, t) over: the loops turned back
                charted = [(P[::-1].copy(), c[::-1].copy()) for P, c in charted]
            for k in range(len(patches)):
                for reg in strip_regions(charted, float(k), float(k + 1), 1):
                    out.append(PatchRegion(idx[k], tuple((np.stack([P[:, 0], P[:, 1] - k], axis=1), c)
                                                         for P, c in reg)))
    return out


def loop_curves(P: np.ndarray, corner: np.ndarray) -> tuple:
    """A closed loop of points as 2D curves, one per run between corners: a line where the run has two
    points, else the cubic (quadratic) interpolating it at chord-length parameters."""
    from scipy.interpolate import make_interp_spline
    n = len(P)
    cuts = np.flatnonzero(corner)
    if cuts.size == 0:
        cuts = np.array([0])
    out = []
    for i, j in zip(cuts, np.append(cuts[1:], cuts[0] + n)):
        Q = P[np.arange(i, j + 1) % n]
        keep = np.concatenate([[True], np.linalg.norm(np.diff(Q, axis=0), axis=1) > 1e-14])
        Q = Q[keep]
        if len(Q) < 2:
            continue
        if len(Q) == 2:
            out.append(Curve(Q, np.array([0.0, 0.0, 1.0, 1.0]), 1))
            continue
        t = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(Q, axis=0), axis=1))])
        k = min(3, len(Q) - 1)
        sp = make_interp_spline(t / t[-1], Q, k=k)
        out.append(Curve(np.asarray(sp.c, float), np.asarray(sp.t, float), k))
    return tuple(out)


__all__ = ["PatchRegion", "TrimError", "loop_curves", "oriented", "strip_regions", "trimmed_patches"]
