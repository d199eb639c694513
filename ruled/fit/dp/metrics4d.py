"""Cost tables of the 4D-DP (Wang & Elber §2.1–2.2, §3): SSHB and LSAD, both from closest points.

Every candidate ruling (i, j) is sampled once, unelevated, like the 2D cost
(distance.ruling_distances): at the samples t_q = (q + 1/2) / ns of its
parameter line the composition point is projected onto the segment (segment
parameter tau_q, point X_q) and X_q back onto S (Gauss–Newton), giving the
node F_q = S(w_q) with w_q = (u_q, v_q), r_q = X_q - F_q and the unit normal
N_q.  Lifting the ends by k tau nP and l tau nQ moves X_q by
lift_q = k tau a_q + l tau b_q, a_q = (1 - tau_q) nP, b_q = tau_q nQ.

Node distance of the elevated ruling.  Move the node along S by
Delta_q = J^+ (tangential part of lift_q) (J = [S_u S_v] at w_q, linear in
the lifts: Delta_q = k tau A_q + l tau B_q).  Then
S(w_q + Delta_q) = F_q + J Delta_q + R_q, |R_q| <= q_M(Delta_q) / 2 with
q_M(du, dv) = Muu du^2 + 2 Muv |du dv| + Mvv dv^2 (S's second-derivative
bounds), so the elevated sample lies within

    d_q = |r_q + (lift_q . N_q) N_q| + q_M(Delta_q) / 2

of the surface point S(w_q + Delta_q).  The ruling's ends count |k| tau and
|l| tau (they stay on their samples P_i, Q_j).

SSHB, the surface–bilinear Hausdorff bound (eqs. 8–12, with eq. 14's
projected parameterization).  For consecutive rulings let b(r, s) be, on each
cell between nodes q and q + 1, the bilinear map through the four (moved)
node parameters, and sigma(r, s) the bilinear map through the nodes' segment
parameters tau_q (0 and 1 at the ends).  The map (r, s) -> (r, sigma) is onto
the unit square and maps sides to sides, so with B the bilinear patch of the
four elevated end points, H(B, S(b)) <= sup |f|, f = S o b - B(r, sigma),
and bilinear interpolation on each cell (B is linear in r and in sigma) gives

    sup |f| <= max(c, c') + max(E_s, E_s') + q_M(d_u, d_v) / 8 + 2 |B_r sigma| T / 8,

c the largest node distance of a ruling, E_s = max_q q_M(step_q) / 8 over
its node-to-node parameter steps, (d_u, d_v) the largest parameter change
between corresponding nodes of the two rulings (unelevated change plus both
rulings' largest |Delta|), T = max_q |tau_q - tau'_q| and
|B_r sigma| = |(Q - P) - (Q' - P')| bounded by the triangle inequality.  The
patches' regions tile S (the first and last rulings of an open face keep
their composition nodes, which lie on the face's edges), so the largest
patch bound bounds the whole discrete ruled surface.  M is taken over all of
S, so the bound needs no per-cell lookups.

LSAD, the line metric (§3.2): the largest node distance without the
second-order term, |r_q + (lift_q . N_q) N_q|, and the ends; with m = 0 it
is the 2D cost of the ruling.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ruled.core import jit
from ruled.core.distance import ruling_distances
from ruled.core.nurbs import Surface
from ruled.core.sampling import PATTERNS, Elevated
from ruled.fit.dp import kernels as kernels4d


def f32_up(x: np.ndarray) -> np.ndarray:
    """x rounded to float32, upwards (a stored bound never drops below its float64 value)."""
    x = np.asarray(x, dtype=np.float64)
    y = x.astype(np.float32)
    return np.where(y.astype(np.float64) < x, np.nextafter(y, np.float32(np.inf)), y).astype(np.float32)


@dataclass(frozen=True)
class RulingFeet:
    """Closest-point nodes of every unelevated ruling (see the module doc); arrays (n, n, ns)."""

    tau: np.ndarray     # segment parameters of the nodes
    u: np.ndarray       # node parameters on S
    v: np.ndarray
    rr: np.ndarray      # |r|^2
    r2n: np.ndarray     # 2 r . N
    al: np.ndarray      # a . N, per unit lift of the P end
    be: np.ndarray      # b . N, per unit lift of the Q end
    Au: np.ndarray      # parameter motion of the node per unit lift of the P end (tangential part)
    Av: np.ndarray
    Bu: np.ndarray      # ... of the Q end
    Bv: np.ndarray
    M: tuple            # (Muu, Muv, Mvv): bounds of S's second derivatives over all of S
    uB: np.ndarray      # (n, n) parameter of the Q end as seen from the P end (unwrapped when closed)
    v_ends: tuple       # (v0, v1)


def ruling_feet(S: Surface, smp: Elevated, ns: int, iters: int = 3, edges: bool = True) -> RulingFeet:
    """The nodes of every ruling (i, j) from ruling_distances' closest points; with ``edges`` the
    first and last rulings of an open face keep their composition nodes (on the face's edges)."""
    n = smp.n
    u0, u1, v0, v1 = S.domain
    L = u1 - u0
    I, J = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    uP = smp.u[I.ravel()]
    uQ = u0 + L * smp.partner_x(I.ravel(), J.ravel()) if smp.closed else smp.u[J.ravel()]
    _, _, tau, foot = ruling_distances(S, uP, uQ, ns, iters, smp.closed, feet=True)
    foot = foot.reshape(n, n, ns, 2)
    tau = tau.reshape(n, n, ns)
    uB = uQ.reshape(n, n)
    if smp.closed:  # node parameters continuous along each ruling's parameter line
        t = (np.arange(ns) + 0.5) / ns
        ref = smp.u[I][..., None] + t * (uB - smp.u[I])[..., None]
        foot[..., 0] = ref + (np.mod(foot[..., 0] - ref + 0.5 * L, L) - 0.5 * L)
    if edges and not smp.closed:
        t = (np.arange(ns) + 0.5) / ns
        for i in (0, n - 1):
            foot[i, i, :, 0] = smp.u[i]
            foot[i, i, :, 1] = v0 + (v1 - v0) * t
    fu = foot[..., 0].ravel()
    D = S.evaluate(u0 + np.mod(fu - u0, L) if smp.closed else fu, foot[..., 1].ravel(), 1)
    F = D.P.reshape(n, n, ns, 3)
    N = D.normals().reshape(n, n, ns, 3)
    Su = D.Su.reshape(n, n, ns, 3)
    Sv = D.Sv.reshape(n, n, ns, 3)
    Xbar = smp.P[I][..., None, :] + tau[..., None] * (smp.Q[J] - smp.P[I])[..., None, :]
    r = Xbar - F
    a = (1.0 - tau)[..., None] * smp.nP[I][..., None, :]
    b = tau[..., None] * smp.nQ[J][..., None, :]
    al = (a * N).sum(-1)
    be = (b * N).sum(-1)
    # J^+ of the tangential parts: solve the 2x2 normal equations
    g11, g12, g22 = (Su * Su).sum(-1), (Su * Sv).sum(-1), (Sv * Sv).sum(-1)
    det = g11 * g22 - g12 * g12
    det = np.where(np.abs(det) > 1e-300, det, np.inf)  # singular point: no tangential motion model

    def pinv(w):
        wt = w - (w * N).sum(-1)[..., None] * N
        p1, p2 = (Su * wt).sum(-1), (Sv * wt).sum(-1)
        return (g22 * p1 - g12 * p2) / det, (g11 * p2 - g12 * p1) / det
    Au, Av = pinv(a)
    Bu, Bv = pinv(b)
    bd = S.derivative_bounds()
    M = (float(bd["Suu"].max()), float(bd["Suv"].max()), float(bd["Svv"].max()))
    c = np.ascontiguousarray
    return RulingFeet(c(tau), c(foot[..., 0]), c(foot[..., 1]), c((r * r).sum(-1)), c(2.0 * (r * N).sum(-1)),
                      c(al), c(be), c(Au), c(Av), c(Bu), c(Bv), M, c(uB), (float(v0), float(v1)))


def sshb_ruling_tables(smp: Elevated, feet: RulingFeet):
    """Ruling terms of SSHB (module doc), float32 rounded up, each (n, n, K, K): c (largest node
    distance), es (largest node-to-node remainder E_s), dku, dkv (largest |Delta| per parameter)."""
    n, K = smp.n, smp.levels.shape[0]
    out = [np.empty((n, n, K, K), np.float32) for _ in range(4)]
    Muu, Muv, Mvv = feet.M
    uA = np.ascontiguousarray(smp.u)
    uB = np.ascontiguousarray(feet.uB)
    v0, v1 = feet.v_ends
    if jit.enabled():
        kernels4d.sshb_rulings(smp.levels, uA, uB, v0, v1, feet.u, feet.v, feet.rr, feet.r2n, feet.al, feet.be,
                               feet.Au, feet.Av, feet.Bu, feet.Bv, Muu, Muv, Mvv, *out)
        return tuple(out)
    e = smp.levels
    ns = feet.rr.shape[2]
    ek = e[None, :, None]
    el = e[None, None, :]
    ends = np.maximum(np.abs(e)[:, None], np.abs(e)[None, :])
    shape = (n, K, K)

    def col(a, i, q):
        return a[i, :, q][:, None, None]

    def qm(su, sv):
        return (Muu * su * su + 2.0 * Muv * su * sv) + Mvv * sv * sv

    for i in range(n):
        c = np.broadcast_to(ends, shape).copy()
        es = np.zeros(shape)
        dku = np.zeros(shape)
        dkv = np.zeros(shape)
        pu = np.full(shape, uA[i])
        pv = np.full(shape, v0)
        for q in range(ns + 1):
            if q < ns:
                lam = ek * col(feet.al, i, q) + el * col(feet.be, i, q)
                d2 = col(feet.rr, i, q) + lam * (col(feet.r2n, i, q) + lam)
                du = ek * col(feet.Au, i, q) + el * col(feet.Bu, i, q)
                dv = ek * col(feet.Av, i, q) + el * col(feet.Bv, i, q)
                adu, adv = np.abs(du), np.abs(dv)
                c = np.maximum(c, np.sqrt(np.maximum(d2, 0.0)) + 0.5 * qm(adu, adv))
                dku = np.maximum(dku, adu)
                dkv = np.maximum(dkv, adv)
                nu_ = col(feet.u, i, q) + du
                nv_ = col(feet.v, i, q) + dv
            else:
                nu_ = np.broadcast_to(uB[i][:, None, None], shape)
                nv_ = np.full(shape, v1)
            su, sv = np.abs(nu_ - pu), np.abs(nv_ - pv)
            es = np.maximum(es, 0.125 * qm(su, sv))
            pu, pv = nu_, nv_
        for k, arr in enumerate((c, es, dku, dkv)):
            out[k][i] = f32_up(arr)
    return tuple(out)


def lsad_tables(smp: Elevated, feet: RulingFeet) -> np.ndarray:
    """LSAD[i, j, k, l] (float32, rounded up): the line metric of every elevated ruling (module
    doc).  Shape (n, n, K, K)."""
    n, K = smp.n, smp.levels.shape[0]
    out = np.empty((n, n, K, K), np.float32)
    if jit.enabled():
        kernels4d.lsad(smp.levels, feet.rr, feet.r2n, feet.al, feet.be, out)
        return out
    e = smp.levels
    ends = np.maximum(np.abs(e)[:, None], np.abs(e)[None, :])
    ek = e[None, :, None]
    el = e[None, None, :]
    for i in range(n):
        best = np.broadcast_to(ends * ends, (n, K, K)).copy()
        for q in range(feet.rr.shape[2]):
            ln = ek * feet.al[i, :, q][:, None, None] + el * feet.be[i, :, q][:, None, None]
            best = np.maximum(best, feet.rr[i, :, q][:, None, None] + ln * (feet.r2n[i, :, q][:, None, None] + ln))
        out[i] = f32_up(np.sqrt(best))
    return out


@dataclass(frozen=True)
class PatchTerms:
    """Per-move terms that do not depend on the elevations, indexed [pattern, i, j]."""

    area: np.ndarray    # area of the supporting region (two triangles on the samples)
    d0u: np.ndarray     # largest |u| change between corresponding nodes of the two rulings (unelevated)
    d0v: np.ndarray
    t0: np.ndarray      # largest |tau_q - tau'_q|
    g0: np.ndarray      # |(Q_j - P_i) - (Q_j' - P_i')|
    gP: np.ndarray      # (3, n, K): |k tau nP_i - k' tau nP_i'| for dk = k - k' in (0, -1, +1)
    gQ: np.ndarray      # (3, n, K): the same on the Q side
    M: tuple


def patch_terms(S: Surface, smp: Elevated, feet: RulingFeet) -> PatchTerms:
    n = smp.n
    K = smp.levels.shape[0]
    I, J = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    u0, u1 = S.domain[:2]
    L = u1 - u0
    D = smp.Q[None, :, :] - smp.P[:, None, :]
    area, d0u, d0v, t0, g0 = (np.zeros((3, n, n)) for _ in range(5))
    # node parameters with the ends, unwrapped along each ruling's parameter line
    uA = smp.u[I]
    uB = feet.uB
    for p, (di, dj) in enumerate(PATTERNS):
        Ip, Jp = (I - di) % n, (J - dj) % n
        du = np.abs(feet.u - _shift_like(feet.u[Ip, Jp], feet.u, L, smp.closed))
        dv = np.abs(feet.v - feet.v[Ip, Jp])
        dA = np.abs(uA - _shift_like(smp.u[Ip], uA, L, smp.closed))
        dB = np.abs(uB - _shift_like(uB[Ip, Jp], uB, L, smp.closed))
        d0u[p] = np.maximum(du.max(axis=-1), np.maximum(dA, dB))
        d0v[p] = dv.max(axis=-1)
        t0[p] = np.abs(feet.tau - feet.tau[Ip, Jp]).max(axis=-1)
        Pa, Pb, Qa, Qb = smp.P[Ip], smp.P[I], smp.Q[Jp], smp.Q[J]
        area[p] = 0.5 * (np.linalg.norm(np.cross(Qb - Pa, Qa - Pa), axis=-1)
                         + np.linalg.norm(np.cross(Qb - Pa, Pb - Pa), axis=-1))
        g0[p] = np.linalg.norm(D - D[Ip, Jp], axis=-1)
    gP = np.zeros((3, n, K))
    gQ = np.zeros((3, n, K))
    e = smp.levels
    for col, dk in enumerate((0, -1, 1)):
        kp = np.arange(K) - dk
        ok = (kp >= 0) & (kp < K)
        for g, nrm in ((gP, smp.nP), (gQ, smp.nQ)):
            prev = np.roll(nrm, 1, axis=0)  # sample i - 1 (wrapped; unused at i = 0 when open)
            val = np.linalg.norm(e[None, :, None] * nrm[:, None, :]
                                 - e[np.clip(kp, 0, K - 1)][None, :, None] * prev[:, None, :], axis=-1)
            g[col] = np.where(ok[None, :], val, 0.0)  # (unused: no such move)
    return PatchTerms(area, d0u, d0v, t0, g0, gP, gQ, feet.M)


def _shift_like(x: np.ndarray, ref: np.ndarray, L: float, closed: bool) -> np.ndarray:
    """x shifted by whole periods to lie within half a period of ref (closed faces)."""
    if not closed:
        return x
    return ref + (np.mod(x - ref + 0.5 * L, L) - 0.5 * L)


def sshb_move(terms: PatchTerms, prev: tuple, cur: tuple, pattern: int, i: int, j: int, k: int, l: int,
              dk: int, dl: int) -> float:
    """SSHB of one move (float64) from the ruling terms (c, es, dku, dkv) of both rulings and the
    move's patch terms (pattern index into sampling.PATTERNS; the move ends at ruling (i, j) on
    levels (k, l), coming from levels (k - dk, l - dl))."""
    di, dj = PATTERNS[pattern]
    col = {0: 0, -1: 1, 1: 2}
    g = terms.g0[pattern, i, j] + (terms.gP[col[dk], i, k] if di else 0.0) + (terms.gQ[col[dl], j, l] if dj else 0.0)
    du = terms.d0u[pattern, i, j] + cur[2] + prev[2]
    dv = terms.d0v[pattern, i, j] + cur[3] + prev[3]
    Muu, Muv, Mvv = terms.M
    q = Muu * du * du + 2 * Muv * du * dv + Mvv * dv * dv
    return float(max(cur[0], prev[0]) + max(cur[1], prev[1]) + 0.125 * q + 0.25 * g * terms.t0[pattern, i, j])
