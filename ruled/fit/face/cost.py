"""The rulings' costs on a face's extended patch (ruled.fit.face.extend: the patch carries the face's mask), and
how the pairing is held past the face: a ruling counts only over the face (and a little past its edges),
the rulings past it follow the line of the last ones over it, and the smooth pairing ends where the rails
reach the patch's ends (its end rulings free).  On a patch with no mask every function is the plain one."""

from __future__ import annotations

from typing import Any, Optional

import numpy as np

from ruled.core.distance import ruling_distances
from ruled.core.nurbs import Surface
from ruled.fit.face.extend import face_mask


def ruling_cost(S: Surface, uP: np.ndarray, uQ: np.ndarray, m: int, iters: int, closed: bool,
                outside=0.0) -> np.ndarray:
    """(K,) the distances to S of the rulings from S(uP, v0) to S(uQ, v1) (ruled.core.distance.ruling_distances).
    On a face's extended patch (ruled.fit.face.extend.masked) only a ruling's points over the face, or a little
    past its edges (FaceMask.inside), count: the result is trimmed by the face's edges, so the part of a
    ruling past them is not part of it, and the surface far past them (the natural extension past the
    face's own surface) is nothing the ruling must follow.  A ruling with no sample there costs
    ``outside`` (a number, or one per ruling)."""
    mask = face_mask(S)
    if mask is None:
        return ruling_distances(S, uP, uQ, m, iters, closed)[1]
    uP, uQ = np.asarray(uP, float), np.asarray(uQ, float)
    _, _, tau, foot = ruling_distances(S, uP, uQ, m, iters, closed, feet=True)
    v0, v1 = S.domain[2:]
    K = uP.size
    ends = S(np.concatenate([uP, uQ]), np.concatenate([np.full(K, v0), np.full(K, v1)]))
    P, Q = ends[:K], ends[K:]
    X = P[:, None, :] + tau[..., None] * (Q - P)[:, None, :]
    d = np.linalg.norm(X - S(foot[..., 0].ravel(), foot[..., 1].ravel()).reshape(X.shape), axis=2)
    inside = _inside(S, uP, uQ, m)
    return np.where(inside.any(axis=1), np.where(inside, d, 0.0).max(axis=1), outside)


def _inside(S: Surface, uP: np.ndarray, uQ: np.ndarray, k: int) -> np.ndarray:
    """(K, k) whether the rulings' parameter lines from (uP, v0) to (uQ, v1), at the k samples the rulings'
    distances are taken at (ruled.core.distance), lie in the face the masked patch S carries."""
    t = (np.arange(k) + 0.5) / k
    v0, v1 = S.domain[2:]
    st = np.stack([uP[:, None] * (1 - t) + uQ[:, None] * t, np.broadcast_to(v0 + (v1 - v0) * t, (uP.size, k))],
                  axis=2)
    return np.asarray(face_mask(S).inside(st.reshape(-1, 2)).reshape(uP.size, k))


# the samples per ruling by which it is over the face or not (the refinement's)
OVER_SAMPLES = 11


def over_face(S: Surface, uP: np.ndarray, uQ: np.ndarray, k: int = OVER_SAMPLES, every: bool = False) -> np.ndarray:
    """(K,) whether a ruling from (uP, v0) to (uQ, v1) has a sample over the face a masked patch S carries
    (k samples, as ruling_cost takes them: one that only grazes the face between its samples counts as
    past it); every: whether all its samples are (it crosses the face from rail to rail, its pairing held
    by the face all along).  All True on a patch with no mask."""
    uP, uQ = np.asarray(uP, float), np.asarray(uQ, float)
    if face_mask(S) is None:
        return np.ones(uP.size, bool)
    inside = _inside(S, uP, uQ, k)
    return np.asarray(inside.all(axis=1) if every else inside.any(axis=1))



def _past_face(S: Surface, sig: np.ndarray, d: np.ndarray) -> np.ndarray:
    """delta at rulings with no point over the face (ruling_cost: they cost 0 whatever their pairing, so
    the search leaves them anywhere): before the first and after the last ruling over the face, the
    line the rulings there follow (_end_lines; a held value would kink the rails at the face's end
    edge), within the bounds that keep a and b in [0, 1]; between rulings over the face, the nearest
    one's.  The smooth pairing through them then bends only where the face does."""
    over = over_face(S, sig - d, sig + d)
    if over.all() or not over.any():
        return d
    n = np.arange(sig.size)
    idx = np.nonzero(over)[0]
    j = np.searchsorted(idx, n)
    after, before = idx[np.clip(j, 0, idx.size - 1)], idx[np.clip(j - 1, 0, idx.size - 1)]
    near = np.where(np.abs(before - n) < np.abs(after - n), before, after)
    out = d[near].copy()
    (s0, d0, m0), (s1, d1, m1) = _end_lines(sig, d, idx)
    lo, hi = n < idx[0], n > idx[-1]
    out[lo] = d0 + m0 * (sig[lo] - s0)
    out[hi] = d1 + m1 * (sig[hi] - s1)
    lim = np.minimum(sig, 1.0 - sig)
    return np.where(over, d, np.clip(out, -lim, lim))


END_FIT = 6        # the rulings over the face whose line continues the pairing past each end


def _end_lines(sig: np.ndarray, d: np.ndarray, idx: np.ndarray) -> tuple:
    """((sigma, delta, slope) at the first ruling over the face, the same at the last): the least-squares
    line of the END_FIT rulings over the face next to each end, its slope within the monotone range."""
    out = []
    for k in (idx[:END_FIT], idx[-END_FIT:]):
        x, y = sig[k], d[k]
        m = float(np.polyfit(x, y, 1)[0]) if k.size >= 2 and np.ptp(x) > 0 else 0.0
        e = k[0] if k is idx[:END_FIT] else k[-1]
        out.append((float(sig[e]), float(d[e]), float(np.clip(m, -0.9, 0.9))))
    return tuple(out)


def face_span(S: Surface, pairing: Any, margin: float = 0.01, k: int = 1001) -> Optional[tuple]:
    """(s0, s1): the range of the pairing's s (a ruled.fit.dp.pairing.Pairing) whose rulings meet the face a
    masked patch S carries, widened by margin; None on a patch with no mask (or no ruling over the face)."""
    if face_mask(S) is None or pairing.closed:
        return None
    s = np.linspace(0.0, 1.0, k)
    a, b = pairing.ab(s)
    u0, u1 = S.domain[:2]
    over = over_face(S, u0 + (u1 - u0) * a, u0 + (u1 - u0) * b)
    if not over.any():
        return None
    return float(s[over].min()) - margin, float(s[over].max()) + margin


def face_weights(S: Surface, sig: np.ndarray, d: np.ndarray) -> Optional[np.ndarray]:
    """fit_delta's weights for refined rulings (sigma, delta): a ruling with no point over the face a
    masked patch carries weighs PAST_FACE (its pairing is free, and at the patch's ends it is clipped
    into a kink the smooth pairing need not follow); None where every ruling is over the face."""
    over = over_face(S, sig - d, sig + d)
    return None if over.all() else np.where(over, 1.0, PAST_FACE)


PAST_FACE = 1e-2



# the free end rulings stay this far (in the patch's s) from the face's rulings, so that the certificate's
# cells next to the face lie under the result
END_MARGIN = 0.008


def face_ends(S: Surface, sig: np.ndarray, delta: np.ndarray) -> Optional[tuple]:
    """(sigma_a, delta_a, sigma_b, delta_b): the smooth pairing's range and its end values: at each end
    the line of the rulings over the face there (_end_lines) continued until a or b reaches the patch's
    end, where that leaves END_MARGIN past the rulings over the face, else the patch's corner (sigma 0 or
    1, delta 0: the pairing turns to it); None where both ends are the corners."""
    over = over_face(S, sig - delta, sig + delta)
    idx = np.nonzero(over)[0]
    if idx.size < 4:
        return None
    (s0, d0, m0), (s1, d1, m1) = _end_lines(sig, delta, idx)

    def root(f, a, b):          # f(a) < 0 <= f(b): the bracket bisected to round-off
        for _ in range(60):
            c = 0.5 * (a + b)
            a, b = (c, b) if f(c) < 0 else (a, c)
        return a, b

    lo_end = hi_end = None
    if s0 - abs(d0) > 0:        # a or b = sigma - |delta| falls to 0 at sigma_a (the side where it is >= 0)
        sa = root(lambda x: x - abs(d0 + m0 * (x - s0)), 0.0, s0)[1]
        if s0 - END_MARGIN >= sa:
            lo_end = (sa, d0 + m0 * (sa - s0))
    if s1 + abs(d1) < 1:        # sigma + |delta| rises to 1 at sigma_b (the side where it is < 1)
        sb = root(lambda x: x + abs(d1 + m1 * (x - s1)) - 1.0, s1, 1.0)[0]
        if s1 + END_MARGIN <= sb:
            hi_end = (sb, d1 + m1 * (sb - s1))
    if lo_end is None and hi_end is None:
        return None
    return (lo_end or (0.0, 0.0)) + (hi_end or (1.0, 0.0))
