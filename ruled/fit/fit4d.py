"""Orchestration of a 4D fit (Wang & Elber §2): rulings whose ends are lifted along the normal.

1. The 2D fit (fit2d.fit_surface_2d) chooses the direction and is the baseline;
   its measured distance sets the default elevation step.
2. Elevated samples (eqs. 1–3), the SSHB or LSAD tables (metrics4d) and the
   4D-DP (dp4d), open or periodic.  LSAD is the default cost: it follows the
   true (closest-point) distance of each ruling and steers the DP best; SSHB
   makes the DP minimize a certified bound of the discrete surface.
3. Rebuild (beyond the paper): the pairing and the lifts refined continuously
   per ruling (a golden-section search of the pairing within one sample step,
   each candidate with its best lifts under the line model), the pairing as
   in 2D a strictly monotone delta(sigma), the lifts smoothed, and the two
   boundary curves fitted through the lifted ends in one spline space.  The
   ruled face between them is certified like a 2D result
   (certify.certified_bound bounds H(S, R) directly, so the rebuild error is
   inside the reported bound).
4. Never worse than 2D: both results are measured (ruled.fit.certify.sampled)
   and the 4D one is kept only if it is closer and its certified bound is
   below the 2D result's measured distance (so that the 4D result's true
   distance cannot exceed the 2D one's, whatever the sampling missed);
   otherwise the 2D result is returned with a note saying so.
"""

from __future__ import annotations

import time
from dataclasses import replace
from typing import Optional

import numpy as np

from ruled.core.basis import bspline_basis_matrix
from ruled.core.distance import ruling_distances, wrap_u
from ruled.core.errors import InfeasibleError, TooBigError
from ruled.core.nearest import GOLD
from ruled.core.nurbs import Surface
from ruled.core.progress import Progress
from ruled.core.sampling import elevated_samples, unit_normals
from ruled.fit.certify.forward import certified_bound
from ruled.fit.certify.sampled import sampled_distance
from ruled.fit.dp import dp4d
from ruled.fit.dp.metrics4d import lsad_tables, patch_terms, ruling_feet, sshb_ruling_tables
from ruled.fit.dp.pairing import delta_coefs, fit_delta
from ruled.fit.face.extend import face_mask
from ruled.fit.fit2d import GRID_FINE, DirectionFit, FitResult, _stage, fit_surface_2d, memory_budget
from ruled.fit.options import FitOptions, Method, Metric
from ruled.fit.rails import COMPACT, compact_fit
from ruled.fit.reparam import fit_boundaries, ruled_surface

DEFAULT_LEVELS = 10          # m: 21 elevation levels
RANGE_FACTOR = 1.0           # default elevation range: +-(factor x the 2D measured distance)
REMAINDER_SHARE = 0.02       # SSHB nodes per ruling: interpolation remainder <= this share of the 2D error
NS_RANGE = (8, 48)           # SSHB nodes per ruling
TOL_SHARE = 0.01             # boundary fit tolerance: this share of the 2D measured distance
LIFT_COEF = 0.75             # coefficients of the smoothed lift functions per sample


def _choose_ns(S: Surface, scale: float) -> int:
    """Nodes per ruling so that the node-to-node remainder of a ruling straight across S
    (Mvv (V / (ns + 1))^2 / 8) stays a small share of the expected error."""
    _, _, v0, v1 = S.domain
    Mvv = float(S.derivative_bounds()["Svv"].max())
    ns = int(np.ceil((v1 - v0) * np.sqrt(Mvv / (8.0 * max(REMAINDER_SHARE * scale, 1e-300))))) - 1
    return int(min(max(ns, NS_RANGE[0]), NS_RANGE[1]))


def check_memory_4d(n: int, m: int, closed: bool, sshb: bool, cap: Optional[float]) -> None:
    have = memory_budget(cap)
    need = dp4d.table_bytes(n, 2 * m + 1, closed, sshb, NS_RANGE[1])
    if need <= have:
        return

    def largest(f, hi):
        lo = 0
        while lo < hi:
            mid = (lo + hi + 1) // 2
            if f(mid) <= have:
                lo = mid
            else:
                hi = mid - 1
        return lo
    n_fit = largest(lambda k: dp4d.table_bytes(k, 2 * m + 1, closed, sshb, NS_RANGE[1]), n)
    m_fit = largest(lambda k: dp4d.table_bytes(n, 2 * k + 1, closed, sshb, NS_RANGE[1]), m)
    hint = f"use «samples={n_fit}» or fewer" if n_fit >= 3 else "too big at any sample count"
    hint += f", or «elevations={m_fit}» or fewer" if dp4d.table_bytes(n, 1, closed, sshb) <= have else ""
    raise TooBigError(f"«samples={n}» with «elevations={m}» needs about {need / 2**20:.0f} MiB for the 4D tables "
                      f"but only {have / 2**20:.0f} MiB is allowed; {hint}")


def _smooth_lift(x: np.ndarray, e: np.ndarray, closed: bool, n_coef: int):
    """A smooth function e(x) by least squares (cubic B-spline), periodic with period 1 when closed
    (fitted on three copies of the data and read in the middle one)."""
    x0 = float(x[0])
    if closed:
        xs = np.concatenate([x - 1.0, x, x + 1.0])
        es = np.concatenate([e, e, e])
        lo, hi, nc = x0 - 1.0, x0 + 2.0, 3 * n_coef
    else:
        xs, es, lo, hi, nc = x, e, 0.0, 1.0, n_coef
    p = 3
    nc = max(nc, p + 1)
    knots = np.concatenate([np.full(p + 1, lo), np.linspace(lo, hi, nc - p + 1)[1:-1], np.full(p + 1, hi)])
    M = bspline_basis_matrix(knots, p, np.clip(xs, lo, hi))
    coef, *_ = np.linalg.lstsq(M, es, rcond=None)

    def f(q):
        q = np.asarray(q, float)
        if closed:
            q = x0 + np.mod(q - x0, 1.0)
        return bspline_basis_matrix(knots, p, np.clip(q, lo, hi)) @ coef
    return f


def line_model(So: Surface, a: np.ndarray, b: np.ndarray, closed: bool, points: int = 11):
    """First-order model of the distance of the rulings (a, b) (normalized boundary parameters)
    with lifted ends (metrics4d's LSAD, continuous): per ruling and sample q the normal residual
    rN, the tangential residual t2 and the lift coefficients alpha, beta, so that the lifted
    sample lies at sqrt((rN + eA alpha + eB beta)^2 + t2) from S.  Arrays (G, points)."""
    u0, u1, v0, v1 = So.domain
    L = u1 - u0
    uP, uQ = u0 + L * a, u0 + L * b
    _, _, tau, foot = ruling_distances(So, uP, uQ, points, 3, closed, feet=True)
    D = So.evaluate(foot[..., 0].ravel(), foot[..., 1].ravel(), 1)
    G = a.shape[0]
    F = D.P.reshape(G, points, 3)
    N = D.normals().reshape(G, points, 3)
    wa = wrap_u((u0, u1), uP, closed)
    wb = wrap_u((u0, u1), uQ, closed)
    P, Q = So(wa, np.full(G, v0)), So(wb, np.full(G, v1))
    nP, nQ = unit_normals(So, wa, v0, v1 - v0), unit_normals(So, wb, v1, v0 - v1)
    r = P[:, None] + tau[..., None] * (Q - P)[:, None] - F
    rN = (r * N).sum(-1)
    t2 = np.maximum((r * r).sum(-1) - rN * rN, 0.0)
    alpha = (1.0 - tau) * (nP[:, None] * N).sum(-1)
    beta = tau * (nQ[:, None] * N).sum(-1)
    return rN, t2, alpha, beta


def _model_cost(model, eA, eB):
    rN, t2, al, be = model
    d = np.sqrt((rN + eA[:, None] * al + eB[:, None] * be) ** 2 + t2).max(axis=1)
    return np.maximum(d, np.maximum(np.abs(eA), np.abs(eB)))


def refine_lifts(model, eA: np.ndarray, eB: np.ndarray, step: float, iters: int = 60):
    """Per ruling, the lifts (eA, eB) minimizing the modelled largest distance (a convex function
    of the lifts), by a pattern search started from the DP's lifts with the DP's step."""
    eA, eB = eA.copy(), eB.copy()
    f = _model_cost(model, eA, eB)
    h = np.full(eA.shape, step)
    offs = [(1, 0), (-1, 0), (0, 1), (0, -1), (1, 1), (-1, -1), (1, -1), (-1, 1)]
    for _ in range(iters):
        moved = np.zeros(eA.shape, bool)
        for da, db in offs:
            ca, cb = eA + da * h, eB + db * h
            fc = _model_cost(model, ca, cb)
            better = fc < f
            eA, eB, f = np.where(better, ca, eA), np.where(better, cb, eB), np.where(better, fc, f)
            moved |= better
        h = np.where(moved, h, 0.5 * h)
    return eA, eB, f


def _reach(So: Surface, v: float, inward: float, grid: int = 1024):
    """The largest lift along the boundary v that keeps the lifted boundary C + e n regular: half of
    |C'| / |n'| (n' the normal's turning rate, by central differences), so that an offset never reaches
    a focal point of the boundary, where it would fold into a cusp.  Tabulated, then made continuous (a
    moving maximum of the turning rate, then a moving average: the rate jumps at knots where S is only
    C1, and a cap that jumps would tear the lifted boundary).  Returns reach(u)."""
    from scipy.ndimage import maximum_filter1d, uniform_filter1d
    u0, u1 = So.domain[:2]
    L = u1 - u0
    u = np.linspace(u0, u1, grid + 1)
    d = 0.25 * L / grid
    lo, hi = np.maximum(u - d, u0), np.minimum(u + d, u1)
    dn = (unit_normals(So, hi, v, inward) - unit_normals(So, lo, v, inward)) / (hi - lo)[:, None]
    dc = np.linalg.norm(So.evaluate(u, np.full(u.shape, v), 1).Su, axis=1)
    rate = np.linalg.norm(dn, axis=1) / np.maximum(0.5 * dc, 1e-300 * L)
    mode = "wrap" if So.periodic_u else "nearest"
    rate = uniform_filter1d(maximum_filter1d(rate, 9, mode=mode), 9, mode=mode)

    def reach(x):
        x = np.asarray(x, float)
        if So.periodic_u:
            x = u0 + np.mod(x - u0, L)
        return 1.0 / np.maximum(np.interp(x, u, rate), 1e-300)
    return reach


def _saturated(e: np.ndarray, cap: np.ndarray) -> np.ndarray:
    """e, smoothly kept below cap in size: e / sqrt(1 + (e / cap)^2) (e itself where |e| << cap)."""
    return e / np.sqrt(1.0 + (e / cap) ** 2)


def _crease_taper(So: Surface, v: float, inward: float, lift: float, tol: float, width: float):
    """w(u) in [0, 1]: 0 at every crease of the boundary v (a knot of So where it is only C0) across which
    the normal turns enough that a lift of this size would tear the lifted boundary apart (by more than
    tol), rising smoothly (3x^2 - 2x^3) to 1 within width; 1 elsewhere.  The lifted boundary is then
    continuous (a kink at the crease, which the boundary fit's knots of full multiplicity follow) instead
    of a jump that a spline can only chase with steep, badly bounded pieces (issue 22)."""
    u0, u1 = So.domain[:2]
    L = u1 - u0
    uc = So.creases(0)
    if So.periodic_u:
        uc = np.concatenate([uc, [u0]])
    if uc.size:
        eps = 1e-9 * L
        n_lo = unit_normals(So, np.where(uc - eps < u0, uc - eps + L, uc - eps), v, inward)
        n_hi = unit_normals(So, uc + eps, v, inward)
        uc = uc[lift * np.linalg.norm(n_hi - n_lo, axis=1) > tol]

    def w(u):
        u = np.asarray(u, float)
        if uc.size == 0:
            return np.ones(u.shape)
        d = np.abs(u[:, None] - uc[None, :])
        if So.periodic_u:
            d = np.minimum(d, L - np.mod(d, L))
        x = np.clip(d.min(axis=1) / width, 0.0, 1.0)
        return x * x * (3.0 - 2.0 * x)
    return w


def refine_rulings(So: Surface, sig: np.ndarray, dlt: np.ndarray, eA: np.ndarray, eB: np.ndarray, closed: bool,
                   step: float, tau: float, rounds: int = 14):
    """Continuous refinement of a 4D path (beyond the paper, like the 2D refinement): for every
    ruling of a fine grid, a bounded golden-section search of its pairing delta within one sample
    step, each candidate scored by its best lifts (refine_lifts).  Returns (delta, eA, eB, cost)."""
    if closed:
        lo, hi = dlt - step, dlt + step
    else:
        lim = np.minimum(sig, 1.0 - sig)
        lo, hi = np.maximum(dlt - step, -lim), np.minimum(dlt + step, lim)

    def score(d, ea, eb):
        return refine_lifts(line_model(So, sig - d, sig + d, closed), ea, eb, tau, 30)

    ea0, eb0, f0 = score(dlt, eA, eB)
    x1, x2 = hi - GOLD * (hi - lo), lo + GOLD * (hi - lo)
    a1, b1, f1 = score(x1, ea0, eb0)
    a2, b2, f2 = score(x2, ea0, eb0)
    for _ in range(rounds):
        left = f1 <= f2
        hi = np.where(left, x2, hi)
        lo = np.where(left, lo, x1)
        nx = np.where(left, hi - GOLD * (hi - lo), lo + GOLD * (hi - lo))
        na, nb, fn = score(nx, np.where(left, a1, a2), np.where(left, b1, b2))
        x2n = np.where(left, x1, nx)
        x1n = np.where(left, nx, x2)
        a2n, b2n, f2n = np.where(left, a1, na), np.where(left, b1, nb), np.where(left, f1, fn)
        a1n, b1n, f1n = np.where(left, na, a2), np.where(left, nb, b2), np.where(left, fn, f2)
        x1, x2, a1, b1, f1, a2, b2, f2 = x1n, x2n, a1n, b1n, f1n, a2n, b2n, f2n
    first = f1 <= f2
    xb = np.where(first, x1, x2)
    ab_, bb_, fb = np.where(first, a1, a2), np.where(first, b1, b2), np.minimum(f1, f2)
    keep = f0 <= fb
    return (np.where(keep, dlt, xb), np.where(keep, ea0, ab_), np.where(keep, eb0, bb_), np.where(keep, f0, fb))


def _rebuild(So: Surface, path: np.ndarray, smp, n: int, closed: bool, tol: float, refine: bool = True):
    """Pairing, lifted boundaries and ruled surface from a 4D path (i, j, k, l level indices)."""
    u0, u1, v0, v1 = So.domain
    L = u1 - u0
    h = 1.0 / (n if closed else n - 1)
    path = path.copy()
    if closed:  # the shorter way around, as in 2D
        path[:, 0] -= n * int(np.round(np.mean(path[:, 0] - path[:, 1]) / n))
    ab = path[:, :2].astype(float) * h
    sig_p = 0.5 * (ab[:, 0] + ab[:, 1])
    del_p = 0.5 * (ab[:, 1] - ab[:, 0])
    G = max(2 * n, 64)
    sig = sig_p[0] + np.arange(G) / G if closed else np.linspace(0.0, 1.0, G)
    dlt = np.interp(sig, sig_p, del_p)
    pairing = fit_delta(sig, dlt, closed, delta_coefs(n))
    lev = smp.levels
    # elevation per boundary sample, in the path's (unwrapped) parameters
    xa, ia = np.unique(ab[:, 0], return_index=True)
    xb, ib = np.unique(ab[:, 1], return_index=True)
    ea, eb = lev[path[ia, 2]], lev[path[ib, 3]]
    lift = None
    info: dict = {"lift_refined": False}
    curves = (sig, dlt, None, None, None)
    if np.any(ea != 0) or np.any(eb != 0):
        if closed:  # one period of samples (the last equals the first)
            xa, ea, xb, eb = xa[:-1], ea[:-1], xb[:-1], eb[:-1]
        nc = max(4, int(n * LIFT_COEF))
        fa = _smooth_lift(xa, ea, closed, nc)
        fb = _smooth_lift(xb, eb, closed, nc)
        a_s, b_s = sig - dlt, sig + dlt
        eA, eB = fa(a_s), fb(b_s)
        f1 = _model_cost(line_model(So, a_s, b_s, closed), eA, eB)
        if refine:
            f0 = f1
            dlt, eA, eB, f1 = refine_rulings(So, sig, dlt, eA, eB, closed, h, smp.tau)
            pairing = fit_delta(sig, dlt, closed, delta_coefs(n))
            info = {"lift_refined": True, "model_max_before": float(f0.max()), "model_max_after": float(f1.max())}
        curves = (sig, dlt, f1, eA, eB)
        ga = _smooth_lift(sig, eA, closed, nc)
        gb = _smooth_lift(sig, eB, closed, nc)
        s0 = pairing.sigma0
        big = max(float(np.abs(eA).max()), float(np.abs(eB).max()))
        wa = _crease_taper(So, v0, v1 - v0, big, tol, h * L)
        wb = _crease_taper(So, v1, v0 - v1, big, tol, h * L)

        ra, rb = _reach(So, v0, v1 - v0), _reach(So, v1, v0 - v1)

        def lift(s, ua, ub):  # s: the pairing's parameter, sigma = sigma0 + s
            na = unit_normals(So, ua, v0, v1 - v0)
            nb = unit_normals(So, ub, v1, v0 - v1)
            return (_saturated(ga(s0 + s) * wa(ua), ra(ua)))[:, None] * na, \
                (_saturated(gb(s0 + s) * wb(ub), rb(ub)))[:, None] * nb
    C0 = So.iso_curve("u", v0)
    C1 = So.iso_curve("u", v1)
    bd = fit_boundaries(C0, C1, u0, L, pairing, tol, lift=lift)
    return path, ab, pairing, bd, ruled_surface(bd), curves, info


def fit_surface_4d(S: Surface, opts: FitOptions, progress: Progress = None) -> FitResult:
    """4D fit (see the module doc); opts already checked, method 4d."""
    t_start = time.perf_counter()
    m = DEFAULT_LEVELS if opts.elevations is None else opts.elevations
    sshb = opts.metric == Metric.SSHB
    check_memory_4d(opts.samples, m, False, sshb, opts.memory_cap)  # before any work (closed: checked again)
    try:  # the baseline honours --max-error when it can (it is what a fallback returns)
        base = fit_surface_2d(S, replace(opts, method=Method.D2), progress)
    except InfeasibleError:
        base = fit_surface_2d(S, replace(opts, method=Method.D2, max_error=None), progress)
    b2 = base.best
    So, closed, n = b2.oriented, b2.closed, opts.samples
    diag = So.diagonal()
    T = {}
    t0 = time.perf_counter()
    m2 = sampled_distance(So, b2.pairing, b2.boundaries, b2.surface)
    b2 = replace(b2, measured=m2)
    T["measure_2d"] = time.perf_counter() - t0
    notes = []
    if opts.step is None and m2 <= 1e-9 * diag:
        notes.append("the 2D fit is exact to round-off (an exactly ruled face): no elevation needed")
        return replace(base, best=b2, candidates={**base.candidates, b2.direction: b2}, notes=tuple(notes))
    tau = opts.step if opts.step is not None else RANGE_FACTOR * m2 / max(m, 1)
    check_memory_4d(n, m, closed, sshb, opts.memory_cap)
    # elevated samples and cost tables
    t0 = time.perf_counter()
    _stage(progress, "elevated samples (4d)", 0.0)
    smp = elevated_samples(So, n, m, tau, closed)
    if sshb:
        ns = _choose_ns(So, m2)
        feet = ruling_feet(So, smp, ns)
        terms = patch_terms(So, smp, feet)
        T["samples"] = time.perf_counter() - t0
        t0 = time.perf_counter()
        _stage(progress, "cost tables (4d, sshb)", 0.0)
        tables = dp4d.Tables(True, n, 2 * m + 1, None, sshb_ruling_tables(smp, feet), terms)
    else:
        ns = opts.points_per_ruling
        feet = ruling_feet(So, smp, ns, edges=False)  # the 2D cost's samples: m = 0 is the 2D program
        T["samples"] = time.perf_counter() - t0
        t0 = time.perf_counter()
        _stage(progress, "cost tables (4d, lsad)", 0.0)
        lc = lsad_tables(smp, feet)
        lc[lc <= 1e-10 * diag] = 0.0  # round-off level: equal, as in 2D
        tables = dp4d.Tables(False, n, 2 * m + 1, lc)
    T["cost_table"] = time.perf_counter() - t0
    _stage(progress, "cost tables (4d)", 1.0)
    t0 = time.perf_counter()
    res = dp4d.solve(tables, closed, opts.objective.value, opts.max_error,
                     (lambda d, k: _stage(progress, "dynamic programming (4d)", d / k)))
    T["dp"] = time.perf_counter() - t0
    _stage(progress, "dynamic programming (4d)", 1.0)
    # rebuild and certify
    t0 = time.perf_counter()
    tol = max(2e-6 * diag, TOL_SHARE * m2)
    path, ab, pairing, bd, R, (sig, dlt, fmod, eA, eB), rinfo = _rebuild(So, res.path, smp, n, closed, tol,
                                                                         opts.refine)
    T["rebuild"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    _stage(progress, "certify (4d)", 0.0)
    cert = certified_bound(So, pairing, bd, R, *GRID_FINE)
    T["certify"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    m4 = sampled_distance(So, pairing, bd, R)
    T["measure_4d"] = time.perf_counter() - t0
    _stage(progress, "certify (4d)", 1.0)
    u0, u1, v0, v1 = So.domain
    L = u1 - u0
    pp = u0 + L * ab
    P = smp.points("P", path[:, 0], path[:, 2])
    Q = smp.points("Q", path[:, 1], path[:, 3])
    elev = np.stack([smp.levels[path[:, 2]], smp.levels[path[:, 3]]], axis=1)
    costs = np.concatenate([[0.0], dp4d.move_costs(tables, res.path)])  # (the path includes the shift)
    signed = path.copy()
    signed[:, 2:] -= m
    fit4 = DirectionFit(b2.direction, closed, R, signed, np.stack([P, Q], axis=1), pp, costs, res.score,
                        (sig, dlt, fmod if fmod is not None else np.interp(sig, 0.5 * (ab[:, 0] + ab[:, 1]), costs)),
                        pairing, bd.fit_error,
                        cert, {**b2.timings, **{f"4d.{k}": v for k, v in T.items()}}, bd, So, "4d", elev,
                        {"levels": m, "step": tau, "metric": opts.metric.value, "nodes_per_ruling": ns,
                         "dp_score": res.score, "dp_max_move_cost": res.max_cost, "shift": res.shift, **rinfo,
                         "refined_lifts": None if eA is None else (sig, eA, eB)},
                        m4)
    total = {"total": time.perf_counter() - t_start}
    # kept only where it cannot be worse: its certified bound below the 2D result's measured distance
    # (a sampled maximum, at most the 2D result's true distance)
    why = (f"elevation did not lower the measured distance (2D {m2:.6g}, 4D {m4:.6g})" if not m4 < m2 else
           f"elevation lowered the measured distance from {m2:.6g} (2D) to {m4:.6g} (4D) but its certified "
           f"bound ({cert.bound:.6g}) is not below the 2D distance" if not cert.bound < m2 else None)
    if why is not None:
        notes.append(why + ": the 2D result is returned")
        return FitResult(b2, {**base.candidates, b2.direction: b2}, opts, total, tuple(notes), fit4)
    notes.append(f"elevation lowered the measured distance from {m2:.6g} (2D) to {m4:.6g} (4D)")
    if face_mask(So) is None:       # (not a face's extended patch: see fit2d.fit_surface_2d)
        fit4 = compact_fit(fit4, COMPACT * fit4.error_bound)
    return FitResult(fit4, {**base.candidates, fit4.direction: fit4}, opts, total, tuple(notes), b2)


__all__ = ["fit_surface_4d", "check_memory_4d", "TooBigError"]
