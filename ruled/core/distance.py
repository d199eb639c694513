"""Line–surface distance (Elber 2011 §2.1; Wang & Elber §2.1, eq. 5).

For a ruling segment L from P = S(uP, v0) to Q = S(uQ, v1) the composition
curve c(t) = S(l(t)) of the parameter line l(t) = (1-t)(uP, v0) + t(uQ, v1)
runs on S from P to Q.  Its largest radial deviation from L is an upper bound
of the one-sided Hausdorff distance D_H(L, S) (eq. 1): every point of L lies
at the height of some point of c(t) (intermediate values), at most that
radial distance away.

The antipodal refinement (eq. 2) looks for the surface point where the
connecting line is orthogonal to S: the foot X of c(t) on L is projected
onto S by Gauss–Newton steps started from l(t), and the smaller of the
radial and the projected distance is kept.  The cost of a ruling is the
largest of these distances over the samples.  All of it is vectorized over
many rulings at once.
"""

from __future__ import annotations

import numpy as np

from ruled.core import jit, kernels
from ruled.core.nurbs import Surface

_POINTS_PER_CHUNK = 120000


def wrap_u(surface_domain, u, closed_u: bool):
    """Map u into the domain: wrap when closed, clamp otherwise."""
    u0, u1 = surface_domain
    if closed_u:
        return u0 + np.mod(u - u0, u1 - u0)
    return np.clip(u, u0, u1)


def project_points(S: Surface, X: np.ndarray, uv: np.ndarray, iters: int = 3, closed_u: bool = False,
                   closed_v: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Closest points on S to X (N, 3) by damped Gauss–Newton from uv (N, 2).

    Returns (uv_best (N, 2), distance (N,)): the best iterate seen, so the
    distance never exceeds the distance from the starting point.
    """
    a0, a1, b0, b1 = S.domain
    u = wrap_u((a0, a1), uv[:, 0].copy(), closed_u)
    v = wrap_u((b0, b1), uv[:, 1].copy(), closed_v)
    best_uv = np.stack([u, v], axis=1)
    best_d = np.full(X.shape[0], np.inf)
    still = 1e-14 * ((a1 - a0) + (b1 - b0))       # a step below this leaves the point where it is
    act = np.arange(X.shape[0])                    # the points still moving
    for it in range(iters + 1):
        need_d = it < iters
        ua, va = u[act], v[act]
        D = S.evaluate(ua, va, 1 if need_d else 0)
        r = D.P - X[act]
        d = np.sqrt(np.einsum("ij,ij->i", r, r))
        better = d < best_d[act]
        idx = act[better]
        best_d[idx] = d[better]
        best_uv[idx, 0] = ua[better]
        best_uv[idx, 1] = va[better]
        if not need_d:
            break
        Su, Sv = D.Su, D.Sv
        a = np.einsum("ij,ij->i", Su, Su)
        b = np.einsum("ij,ij->i", Su, Sv)
        c = np.einsum("ij,ij->i", Sv, Sv)
        g1 = np.einsum("ij,ij->i", Su, r)
        g2 = np.einsum("ij,ij->i", Sv, r)
        lam = 1e-12 * (a + c) + 1e-300
        a = a + lam
        c = c + lam
        det = a * c - b * b
        det = np.where(np.abs(det) > 0, det, 1e-300)
        un = wrap_u((a0, a1), ua - (c * g1 - b * g2) / det, closed_u)
        vn = wrap_u((b0, b1), va - (a * g2 - b * g1) / det, closed_v)
        moving = np.abs(un - ua) + np.abs(vn - va) > still
        u[act], v[act] = un, vn
        act = act[moving]
        if act.size == 0:
            break
    return best_uv, best_d


def ruling_distances(S: Surface, uP: np.ndarray, uQ: np.ndarray, m: int = 9, iters: int = 3,
                     closed_u: bool = False, feet: bool = False):
    """Distances of K rulings from S(uP, v0) to S(uQ, v1) to the surface S.

    uP, uQ: (K,) parameters on the v0 and v1 boundaries (any unwrapped values
    for closed u: the parameter line then takes the shorter way around).
    Returns (upper_bound (K,), distance (K,)): the sampled composition bound
    of eq. (1) and the antipodally refined one-sided distance (<= the bound).
    With feet=True also (tau (K, m), foot (K, m, 2)): each sample's parameter
    on the segment and the (u, v) of the surface point its distance was measured to.
    """
    u0, u1, v0, v1 = S.domain
    if closed_u:  # the parameter line takes the shorter way around
        L = u1 - u0
        uQ = uP + (np.mod(uQ - uP + 0.5 * L, L) - 0.5 * L)
    K = uP.shape[0]
    ub = np.empty(K)
    dist = np.empty(K)
    tau_all = np.empty((K, m)) if feet else None
    foot_all = np.empty((K, m, 2)) if feet else None
    if jit.enabled():
        kernels.ruling_distances(S._hom, S.knots_u, S.knots_v, S._tabs[0], S._tabs[1], S.degree_u, S.degree_v,
                                 np.array(S.domain, float), bool(closed_u), np.ascontiguousarray(uP, float),
                                 np.ascontiguousarray(uQ, float), int(m), int(iters), ub, dist, tau_all, foot_all)
        return (ub, dist, tau_all, foot_all) if feet else (ub, dist)
    out = segment_distances(S, np.stack([uP, np.full(K, v0)], axis=1), np.stack([uQ, np.full(K, v1)], axis=1), m,
                            iters, closed_u, feet)
    return out if feet else out[:2]


def segment_distances(S: Surface, uvA: np.ndarray, uvB: np.ndarray, m: int = 9, iters: int = 3,
                      closed_u: bool = False, feet: bool = False):
    """Distances to S of the K segments between the surface points S(uvA) and S(uvB) ((K, 2) each):
    m samples of the parameter line between them, each sample's foot on the segment, refined by
    projecting the foot onto S.  Returns (upper_bound, distance, tau, foot) as ruling_distances."""
    u0, u1, v0, v1 = S.domain
    K = uvA.shape[0]
    ub = np.empty(K)
    dist = np.empty(K)
    tau_all = np.empty((K, m)) if feet else None
    foot_all = np.empty((K, m, 2)) if feet else None
    t = (np.arange(m) + 0.5) / m
    step = max(1, _POINTS_PER_CHUNK // m)
    for s in range(0, K, step):
        e = min(K, s + step)
        a, b = uvA[s:e, 0], uvB[s:e, 0]
        va, vb = uvA[s:e, 1], uvB[s:e, 1]
        k = e - s
        ends = S.evaluate(wrap_u((u0, u1), np.concatenate([a, b]), closed_u), np.concatenate([va, vb])).P
        P, Q = ends[:k], ends[k:]
        uu = a[:, None] * (1 - t)[None, :] + b[:, None] * t[None, :]
        vv = va[:, None] * (1 - t)[None, :] + vb[:, None] * t[None, :]
        uu_w = wrap_u((u0, u1), uu, closed_u)
        C = S.evaluate(uu_w.ravel(), vv.ravel()).P.reshape(k, m, 3)
        d = Q - P
        dd = np.einsum("ij,ij->i", d, d)
        dd = np.where(dd > 0, dd, 1.0)
        tau = np.clip(np.einsum("kmj,kj->km", C - P[:, None, :], d) / dd[:, None], 0.0, 1.0)
        X = P[:, None, :] + tau[..., None] * d[:, None, :]
        r0 = np.linalg.norm(C - X, axis=2)
        uv0 = np.stack([uu_w.ravel(), vv.ravel()], axis=1)
        uvb, dproj = project_points(S, X.reshape(-1, 3), uv0, iters, closed_u)
        dproj = dproj.reshape(k, m)
        dref = np.minimum(r0, dproj)
        ub[s:e] = r0.max(axis=1)
        dist[s:e] = dref.max(axis=1)
        if feet:
            tau_all[s:e] = tau
            foot_all[s:e] = np.where((dproj < r0)[..., None], uvb.reshape(k, m, 2), uv0.reshape(k, m, 2))
    return ub, dist, tau_all, foot_all


def lifted_segment_distances(S: Surface, uvA: np.ndarray, hA: np.ndarray, uvB: np.ndarray, hB: np.ndarray,
                             m: int = 9, iters: int = 3) -> np.ndarray:
    """Distances to S of the K segments between S(uvA) + hA N(uvA) and S(uvB) + hB N(uvB) (ends lifted
    along the unit normal; (K, 2) and (K,) each): m points of each segment projected onto S by
    Gauss–Newton steps started from the parameter line between uvA and uvB; the largest."""
    K = uvA.shape[0]
    out = np.empty(K)
    t = (np.arange(m) + 0.5) / m
    step = max(1, _POINTS_PER_CHUNK // m)
    for s in range(0, K, step):
        e = min(K, s + step)
        k = e - s
        uv = np.concatenate([uvA[s:e], uvB[s:e]])
        D = S.evaluate(uv[:, 0], uv[:, 1], 1)
        ends = D.P + np.concatenate([hA[s:e], hB[s:e]])[:, None] * D.normals()
        P, Q = ends[:k], ends[k:]
        X = P[:, None, :] * (1 - t)[None, :, None] + Q[:, None, :] * t[None, :, None]
        uv0 = uvA[s:e, None, :] * (1 - t)[None, :, None] + uvB[s:e, None, :] * t[None, :, None]
        _, dist = project_points(S, X.reshape(-1, 3), uv0.reshape(-1, 2), iters)
        out[s:e] = dist.reshape(k, m).max(axis=1)
    return out


def to_polyline(A: np.ndarray, B: np.ndarray, k: int = 4) -> float:
    """max over the points A of their distance to the polyline through the points B (every edge for
    small inputs, else the edges at each point's k nearest vertices): a dense-sampling measure
    between two curves."""
    if B.shape[0] < 2:
        return float(np.linalg.norm(A - B[:1], axis=1).max())
    if A.shape[0] * B.shape[0] <= 200_000:           # small: every edge, exactly
        P, d = B[:-1], B[1:] - B[:-1]
        s = np.clip(((A[:, None] - P[None]) * d[None]).sum(axis=2) / np.maximum((d * d).sum(axis=1), 1e-300),
                    0, 1)
        return float(np.linalg.norm(A[:, None] - (P[None] + s[..., None] * d[None]), axis=2).min(axis=1).max())
    from scipy.spatial import cKDTree

    _, near = cKDTree(B).query(A, k=min(k, B.shape[0]))
    near = near.reshape(A.shape[0], -1)
    best = np.full(A.shape[0], np.inf)
    for c in range(near.shape[1]):
        for off in (-1, 0):
            i = np.clip(near[:, c] + off, 0, B.shape[0] - 2)
            P, d = B[i], B[i + 1] - B[i]
            s = np.clip(((A - P) * d).sum(axis=1) / np.maximum((d * d).sum(axis=1), 1e-300), 0, 1)
            best = np.minimum(best, np.linalg.norm(A - (P + s[:, None] * d), axis=1))
    return float(best.max())


def _golden_min(f, a, b, iters: int):
    """The smallest value golden-section search finds for f on [a, b]; elementwise when a, b are arrays
    (f then maps arrays of parameters to arrays of values)."""
    g = 0.5 * (np.sqrt(5) - 1)
    if np.ndim(a) == 0 and np.ndim(b) == 0:
        return _golden_min_scalar(f, float(a), float(b), iters, g)
    a, b = np.asarray(a, float), np.asarray(b, float)
    c, d = b - g * (b - a), a + g * (b - a)
    fc, fd = np.asarray(f(c), float), np.asarray(f(d), float)
    for _ in range(iters):
        left = fc < fd
        a, b = np.where(left, a, c), np.where(left, d, b)
        c, d = np.where(left, b - g * (b - a), d), np.where(left, c, a + g * (b - a))
        fn = np.asarray(f(np.where(left, c, d)), float)
        fc, fd = np.where(left, fn, fd), np.where(left, fc, fn)
    m = np.minimum(fc, fd)
    return float(m) if m.ndim == 0 else m


def _golden_min_scalar(f, a: float, b: float, iters: int, g: float) -> float:
    """_golden_min for one interval, in plain floats (the array form's numpy calls cost 20x the search)."""
    c, d = b - g * (b - a), a + g * (b - a)
    fc, fd = float(f(c)), float(f(d))
    for _ in range(iters):
        if fc < fd:
            b, d, fd = d, c, fc
            c = b - g * (b - a)
            fc = float(f(c))
        else:
            a, c, fc = c, d, fd
            d = a + g * (b - a)
            fd = float(f(d))
    return min(fc, fd)


def to_lines(points: np.ndarray, ends, m: int = 2049, iters: int = 40) -> np.ndarray:
    """Distances from points to the ruled surface swept by the segments ends(v) = (A(v), B(v)), v in
    [0, 1] (each (N, 3)): the nearest of m segments, then a golden-section search over v between its
    neighbours, exact segment distances throughout."""
    def seg(X, A, B):
        D = B - A
        s = np.clip(((X - A) * D).sum(axis=-1) / np.maximum((D * D).sum(axis=-1), 1e-300), 0, 1)
        return np.linalg.norm(X - (A + s[..., None] * D), axis=-1)
    vs = np.linspace(0.0, 1.0, m)
    A, B = ends(vs)
    size = float(np.ptp(np.vstack([A, B]), axis=0).max())
    closed = max(np.linalg.norm(A[0] - A[-1]), np.linalg.norm(B[0] - B[-1])) <= 1e-12 * max(size, 1e-300)
    out = np.empty(len(points))
    for i in range(0, len(points), 256):
        X = points[i:i + 256]
        d = seg(X[:, None, :], A[None], B[None])
        k = np.argmin(d, axis=1)

        def f(v, X=X):
            a, b = ends(v)
            return seg(X, a, b)
        best = np.minimum(d[np.arange(len(X)), k],
                          _golden_min(f, vs[np.maximum(k - 1, 0)], vs[np.minimum(k + 1, m - 1)], iters))
        if closed:            # v = 0 and v = 1 are one ruling: search the other side of the seam too
            k2 = np.where(k == 0, m - 1, np.where(k == m - 1, 0, k))
            best = np.minimum(best, _golden_min(f, vs[np.maximum(k2 - 1, 0)], vs[np.minimum(k2 + 1, m - 1)], iters))
        out[i:i + 256] = best
    return out
