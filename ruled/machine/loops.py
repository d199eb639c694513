"""The wire's offset lines where the surface turns tighter than the kerf towards the wire: in a concave corner
(a crease, or a small fan cone a draft puts at a sharp concave corner of a profile) the offsets of the two
sides cross before the corner and loop back behind it (a swallowtail).  A wire of radius k cannot follow
them there: on each guide's plane the loop is cut at the crossing, and the guide stays at the crossing point
while the other guide goes on (a pivot of the wire, the corner's mitre at a sharp corner).  Found on dense
samples of each smooth piece of the result between its creases (evaluated from its own side), the contour
joined across the creases."""

from __future__ import annotations

import numpy as np

DENSE = 8192          # samples of the whole loop to find the crossings on (at least MIN_PIECE per smooth piece)
MIN_PIECE = 65


def smooth_pieces(R, u0: float, u1: float) -> list:
    """The ranges of u between R's creases (C0 rulings), in order."""
    c = [float(x) for x in R.creases(0) if u0 < x < u1]
    edges = [u0, *c, u1]
    return list(zip(edges[:-1], edges[1:]))


def one_sided(u: np.ndarray, a: float, b: float, L: float) -> np.ndarray:
    """u kept inside [a, b] by a hair, so that evaluating a piece's ends takes that piece's own side of a
    crease."""
    eps = 1e-12 * L
    return np.clip(u, a + eps, b - eps)


def dense_params(pieces: list, L: float) -> np.ndarray:
    """Samples of every piece (one-sided at its ends), in order."""
    out = []
    for a, b in pieces:
        n = max(MIN_PIECE, int(DENSE * (b - a) / L))
        out.append(one_sided(np.linspace(a, b, n), a, b, L))
    return np.concatenate(out)


def crossings(P: np.ndarray, closed: bool) -> list:
    """(i, j, s, t) for each crossing of the polyline P ((n, 2)) with itself: segment i (P[i] to P[i+1]) at s
    meets segment j > i + 1 at t (the closing segment n - 1 to 0 included when closed)."""
    from scipy.spatial import cKDTree
    Q = np.vstack([P, P[:1]]) if closed else P
    A, D = Q[:-1], np.diff(Q, axis=0)
    m = A.shape[0]
    if m < 3:
        return []
    lengths = np.linalg.norm(D, axis=1)
    mid = A + 0.5 * D
    pairs = np.array(sorted(cKDTree(mid).query_pairs(float(lengths.max()) + 1e-300)), int).reshape(-1, 2)
    i, j = pairs[:, 0], pairs[:, 1]
    keep = (j > i + 1) & ~(closed & (i == 0) & (j == m - 1))
    i, j = i[keep], j[keep]
    den = D[i, 0] * D[j, 1] - D[i, 1] * D[j, 0]
    w = A[j] - A[i]
    with np.errstate(divide="ignore", invalid="ignore"):
        s = (w[:, 0] * D[j, 1] - w[:, 1] * D[j, 0]) / den
        t = (w[:, 0] * D[i, 1] - w[:, 1] * D[i, 0]) / den
    ok = (np.abs(den) > 0) & (s >= 0) & (s < 1) & (t >= 0) & (t < 1)
    return [(int(a), int(b), float(x), float(y)) for a, b, x, y in zip(i[ok], j[ok], s[ok], t[ok])]


def guide_loops(u: np.ndarray, xy: np.ndarray, P3: np.ndarray, closed: bool) -> list:
    """The swallowtails of one guide's contour: (u_start, u_end, X) per loop, X the crossing point (3D, on the
    guide's plane) the guide stays at from u_start to u_end.  u: the samples' parameters; xy: the contour in
    the plane's coordinates; P3: the same points in 3D.  Each loop is the shorter way round between its
    crossing's two segments; loops inside an outer one are left to it; a loop through the closing point of a
    closed contour (the start of a wall's loop, never at a corner) is left as it is."""
    seg = np.linalg.norm(np.diff(np.vstack([xy, xy[:1]]) if closed else xy, axis=0), axis=1)
    total = float(seg.sum())
    cum = np.concatenate([[0.0], np.cumsum(seg)])
    found = []
    for i, j, s, t in crossings(xy, closed):
        inner = cum[j] + t * seg[j] - cum[i] - s * seg[i]
        if closed and inner > 0.5 * total or j + 1 >= len(u):
            continue
        ua = u[i] + s * (u[i + 1] - u[i])
        ub = u[j] + t * (u[j + 1] - u[j])
        found.append((inner, ua, ub, P3[i] + s * (P3[i + 1] - P3[i])))
    out: list = []
    for _, ua, ub, X in sorted(found, key=lambda f: -f[0]):
        if all(ub < a or ua > b for a, b, _ in out):
            out.append((ua, ub, X))
    return sorted(out, key=lambda x: x[0])


class TrimmedGuides:
    """A contour function u -> (n, 2, 3) (the lines met with the two planes) with each guide held at its
    loops' crossing points (guide_loops) over their ranges."""

    def __init__(self, f, loops: tuple):
        self.f, self.loops = f, loops

    def __call__(self, u) -> np.ndarray:
        u = np.asarray(u, float)
        E = self.f(u)
        for g, lp in enumerate(self.loops):
            for a, b, X in lp:
                E[(u >= a) & (u <= b), g] = X
        return E

    def held(self, u) -> np.ndarray:
        """(n,) where either guide is held."""
        u = np.asarray(u, float)
        m = np.zeros(u.shape, bool)
        for lp in self.loops:
            for a, b, _ in lp:
                m |= (u >= a) & (u <= b)
        return m


def trimmed_guides(f, pieces: list, L: float, xy, closed: bool) -> tuple:
    """(TrimmedGuides of f, its dense samples' parameters): f's contours with their swallowtails cut (see the
    module); xy: the planes' coordinates of 3D points (ruled.machine.paths.Frame.xy)."""
    u = dense_params(pieces, L)
    E = f(u)
    loops = tuple(guide_loops(u, xy(E[:, g]), E[:, g], closed) for g in (0, 1))
    return TrimmedGuides(f, loops), u


def held_ends(f, us: np.ndarray, a: np.ndarray, b: np.ndarray, d: np.ndarray) -> tuple:
    """The lines' ends (a, b) where a guide is held at a loop's crossing (ruled.machine.loops): the held line,
    through f's two plane points, at the heights of the offset line's ends."""
    m = f.held(us)
    if not m.any():
        return a, b
    E = f(us[m])
    H0, H1 = E[:, 0] @ d, E[:, 1] @ d
    a, b = a.copy(), b.copy()
    for P, h in ((a, a[m] @ d), (b, b[m] @ d)):
        P[m] = E[:, 0] + ((h - H0) / (H1 - H0))[:, None] * (E[:, 1] - E[:, 0])
    return a, b


def held_fillet(f, u: np.ndarray, lines, kerf: float) -> float:
    """How far the surface's rulings are from the wire beyond the kerf where a guide is held (the round the
    wire leaves in a corner tighter than itself): the largest, at the dense samples u."""
    m = f.held(u)
    if not m.any():
        return 0.0
    E = f(u[m])
    A, B = lines.rulings(u[m])
    e = E[:, 1] - E[:, 0]
    e = e / np.linalg.norm(e, axis=1)[:, None]
    worst = 0.0
    for P in (A, B):
        w = P - E[:, 0]
        worst = max(worst, float(np.linalg.norm(w - (w * e).sum(axis=1)[:, None] * e, axis=1).max()) - kerf)
    return max(worst, 0.0)


__all__ = ["held_ends", "held_fillet", "smooth_pieces", "one_sided", "dense_params", "crossings", "guide_loops",
           "TrimmedGuides", "trimmed_guides"]
