"""Orchestration of a 2D ruled fit: direction choice, cost table, DP, refinement, rebuild, bound."""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace
from typing import Any, Optional

import numpy as np

from ruled.core.blas import one_thread
from ruled.core.errors import DegenerateFaceError, TooBigError
from ruled.core.nurbs import Surface
from ruled.core.progress import Progress
from ruled.fit.certify.cells import Certificate
from ruled.fit.certify.forward import certified_bound
from ruled.fit.dp import dp2d as dp
from ruled.fit.dp.follow import EXACT_RULINGS, follow_exact
from ruled.fit.dp.pairing import Pairing, delta_coefs, fit_delta, refine_pairing, smooth_pairing
from ruled.fit.face.cost import face_span, ruling_cost
from ruled.fit.face.extend import face_mask
from ruled.fit.options import Direction, FitOptions, Method, Metric, Objective  # noqa: F401 (re-exported)
from ruled.fit.rails import COMPACT, compact_fit, net_bound, rebuilt_boundaries
from ruled.fit.reparam import Boundaries, exact_boundaries, fit_boundaries, ruled_surface

# certification grids (nodes along the boundaries, across them): fine for results, coarse to choose
GRID_FINE: tuple[int, int] = (240, 80)
GRID_COARSE: tuple[int, int] = (80, 24)



@dataclass(frozen=True)
class DirectionFit:
    """The fit along one direction, in the coordinates of the oriented surface."""

    direction: str
    closed: bool
    surface: Surface              # the ruled result R(s, t)
    pairs: np.ndarray             # (K, 2) DP path, sample indices (unwrapped when closed)
    rulings: np.ndarray           # (K, 2, 3) end points of the DP rulings
    pair_params: np.ndarray       # (K, 2) boundary parameters of the DP rulings
    ruling_costs: np.ndarray      # (K,) line–surface distance of each DP ruling
    dp_score: float
    refined: tuple                # (sigma, delta, cost) of the continuous refinement
    pairing: Pairing
    boundary_fit_error: float
    certificate: Certificate
    timings: dict
    boundaries: Boundaries = None
    oriented: Surface = None      # the input surface oriented so that rulings run along v
    method: str = "2d"
    elevations: Optional[np.ndarray] = None   # (K, 2) 4D: elevation of each DP ruling's ends (model units)
    lift: Optional[dict] = None               # 4D: levels, step, metric, ns
    measured: Optional[float] = None          # sampled two-sided distance to the input (engine's own measure)
    trim: Optional[Any] = None                # the face's edges on the result (ruled.fit.face.trim.Trim): trimmed

    @property
    def error_bound(self) -> float:
        return self.certificate.bound


@dataclass(frozen=True)
class FitResult:
    best: DirectionFit
    candidates: dict              # direction -> DirectionFit (or error message)
    options: FitOptions
    timings: dict = field(default_factory=dict)
    notes: tuple = ()             # what the fit decided on its own (e.g. 4D fell back to 2D)
    other: Optional[DirectionFit] = None   # 4D: the fit it was compared with (2D, or the 4D attempt if 2D won)
    patch: Optional[Any] = None            # the face's patch (ruled.fit.face.fit.FacePatch) when fitted as a face

    @property
    def surface(self) -> Surface:
        return self.best.surface

    @property
    def error_bound(self) -> float:
        return self.best.error_bound

    @property
    def direction(self) -> str:
        return self.best.direction


def surface_area(S: Surface, n: int = 48) -> float:
    u0, u1, v0, v1 = S.domain
    g, w = np.polynomial.legendre.leggauss(n)
    u = 0.5 * (u1 - u0) * (g + 1) + u0
    v = 0.5 * (v1 - v0) * (g + 1) + v0
    UU, VV = np.meshgrid(u, v, indexing="ij")
    D = S.evaluate(UU.ravel(), VV.ravel(), 1)
    J = np.linalg.norm(np.cross(D.Su, D.Sv), axis=1).reshape(n, n)
    return float(0.25 * (u1 - u0) * (v1 - v0) * (w[:, None] * w[None, :] * J).sum())


def span_area(S: Surface, m: int = 8, rtol: float = 1e-7, cells: int = 1 << 17) -> float:
    """The surface's area to about rtol: Gauss-Legendre with m x m points on every pair of knot spans (the
    integrand is smooth inside one, not across its knots), each cell whose m- and m/2-point rules differ
    by more than rtol of the area split in four, until they agree (a rational surface with extreme
    weights rushes through a corner of a span: a fixed rule was 43 % low on one) or ``cells`` are reached."""
    u0, u1, v0, v1 = S.domain
    ku = np.unique(np.clip(S.knots_u, u0, u1))
    kv = np.unique(np.clip(S.knots_v, v0, v1))
    U0, V0 = np.meshgrid(ku[:-1], kv[:-1], indexing="ij")
    U1, V1 = np.meshgrid(ku[1:], kv[1:], indexing="ij")
    box = np.stack([U0.ravel(), U1.ravel(), V0.ravel(), V1.ravel()], axis=1)
    rules = [np.polynomial.legendre.leggauss(k) for k in (m, max(2, m // 2))]
    total, estimate = 0.0, None
    while box.shape[0]:
        fine, coarse = (_cell_areas(S, box, g, w) for g, w in rules)
        if estimate is None:
            estimate = float(fine.sum())
        ok = np.abs(fine - coarse) <= rtol * abs(estimate)
        if 4 * np.count_nonzero(~ok) + box.shape[0] > cells:
            ok[:] = True            # as close as the budget allows
        total += float(fine[ok].sum())
        box = box[~ok]
        um, vm = 0.5 * (box[:, 0] + box[:, 1]), 0.5 * (box[:, 2] + box[:, 3])
        box = np.concatenate([np.stack([box[:, 0], um, box[:, 2], vm], 1), np.stack([um, box[:, 1], box[:, 2], vm], 1),
                              np.stack([box[:, 0], um, vm, box[:, 3]], 1), np.stack([um, box[:, 1], vm, box[:, 3]], 1)])
    return total


def _cell_areas(S: Surface, box: np.ndarray, g: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Each cell's (u0, u1, v0, v1) area by the tensor Gauss rule (g, w), in blocks of about 8192 points."""
    out = np.empty(box.shape[0])
    k = g.size
    block = max(1, 8192 // (k * k))
    x = 0.5 * (g + 1.0)
    W = np.outer(w, w).ravel()
    for i in range(0, box.shape[0], block):
        b = box[i:i + block]
        hu, hv = b[:, 1] - b[:, 0], b[:, 3] - b[:, 2]
        U, V = np.broadcast_arrays(b[:, 0, None, None] + hu[:, None, None] * x[None, :, None],
                                   b[:, 2, None, None] + hv[:, None, None] * x[None, None, :])
        D = S.evaluate(U.ravel(), V.ravel(), 1)
        J = np.linalg.norm(np.cross(D.Su, D.Sv), axis=1).reshape(b.shape[0], k * k)
        out[i:i + block] = 0.25 * hu * hv * (J @ W)
    return out


def zero_area(S: Surface) -> bool:
    """Whether the surface has no area to speak of (a point, a curve)."""
    diag = S.diagonal()
    return diag == 0 or surface_area(S) <= 1e-12 * diag ** 2


def _polyline_length(P: np.ndarray) -> float:
    return float(np.linalg.norm(np.diff(P, axis=0), axis=1).sum())


def check_direction(S: Surface) -> tuple[bool, Optional[str]]:
    """For the surface oriented along v: (closed boundaries?, reason it cannot be fitted or None)."""
    u0, u1, v0, v1 = S.domain
    diag = S.diagonal()
    tol = 1e-7 * max(diag, 1e-300)
    us = np.linspace(u0, u1, 65)
    vs = np.linspace(v0, v1, 17)
    C0 = S(us, np.full(us.size, v0))
    C1 = S(us, np.full(us.size, v1))
    if all(_polyline_length(C) <= 1e-9 * max(diag, 1e-300) for C in (C0, C1)):
        return False, "both boundaries collapse to points"
    if np.max(np.linalg.norm(C0 - C1, axis=1)) <= tol:
        return False, "the v-min and v-max boundaries coincide (the face is closed across the rulings)"
    closed = bool(np.max(np.linalg.norm(S(np.full(vs.size, u0), vs) - S(np.full(vs.size, u1), vs), axis=1)) <= tol)
    return closed and not S.__dict__.get("pinned_seam", False), None


def pinned_at_seam(S: Surface) -> Surface:
    """S, closed along u, to be fitted as an open surface: its end rulings pinned at its seam (a wall whose
    two contours both have a corner there: the corner line is a ruling of the result, ruled.occ.wall)."""
    S.__dict__["pinned_seam"] = True
    return S


def available_memory() -> int:
    try:
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    return 8 << 30


def memory_budget(cap: Optional[float] = None) -> int:
    """Bytes a fit may use: the cap when given, else 80 % of the free memory."""
    return int(cap) if cap is not None else int(available_memory() * 0.8)


def check_memory(n: int, closed: bool, cap: Optional[float] = None) -> None:
    extra = 200 * (1 << 20) if cap is None else 0  # the rest of the process, when the budget is the free memory
    need = dp.table_bytes(n, closed) + extra
    have = memory_budget(cap)
    if need > have:
        # largest n that fits
        lo, hi = 3, n
        while lo < hi:
            mid = (lo + hi + 1) // 2
            if dp.table_bytes(mid, closed) + extra <= have:
                lo = mid
            else:
                hi = mid - 1
        raise TooBigError(f"«samples={n}» needs about {need / 2**30:.1f} GiB for the DP tables but only "
                          f"{have / 2**30:.1f} GiB is allowed; use «samples={lo}» or fewer")


def _stage(progress: Progress, name: str, frac: float) -> None:
    if progress is not None:
        progress(name, frac)


def _dp_pairing(S: Surface, direction: str, opts: FitOptions, progress: Progress = None):
    """The DP's rulings along one direction and the pairing through them (refined when the options say
    so): (oriented surface, closed, cost table, DP result, path, pairing, (sigma, delta, cost))."""
    So = S if direction == "v" else S.transposed()
    closed, why = check_direction(So)
    if why is not None:
        raise DegenerateFaceError(f"cannot fit rulings along {direction}: {why}; "
                                  f"use «direction={'u' if direction == 'v' else 'v'}» or repair the face")
    n = opts.samples
    check_memory(n, closed, opts.memory_cap)
    T = {}
    u0, u1, v0, v1 = So.domain
    L = u1 - u0
    diag = So.diagonal()
    x = np.arange(n) / (n if closed else n - 1)
    up = u0 + L * x
    # cost table
    t0 = time.perf_counter()
    cost = np.empty((n, n))
    rows = max(1, 200000 // (opts.points_per_ruling * n))
    for i0 in range(0, n, rows):
        i1 = min(n, i0 + rows)
        uP = np.repeat(up[i0:i1], n)
        uQ = np.tile(up, i1 - i0)
        cost[i0:i1] = ruling_cost(So, uP, uQ, opts.points_per_ruling, 3, closed).reshape(i1 - i0, n)
        _stage(progress, f"cost table ({direction})", i1 / n)
    # distances at round-off level are all "exact": equal, so that ties keep the straight pairing
    cost[cost <= 1e-10 * diag] = 0.0
    T["cost_table"] = time.perf_counter() - t0
    # dynamic programming
    t0 = time.perf_counter()
    res = dp.solve(cost, closed, opts.objective.value, opts.max_error,
                   (lambda d, m: _stage(progress, f"dynamic programming ({direction})", d / m)))
    T["dp"] = time.perf_counter() - t0
    path = res.path.copy()
    if closed:
        # unwrap so that the rulings take the shorter way around: |a - b| <= 1/2 on average
        path[:, 0] -= n * int(np.round(np.mean(path[:, 0] - path[:, 1]) / n))
    h = 1.0 / (n if closed else n - 1)
    ab = path.astype(float) * h
    # continuous refinement
    t0 = time.perf_counter()
    G = max(2 * n, 64)
    if opts.refine:
        sig, dlt, rc = refine_pairing(So, u0, L, closed, ab, h, G,
                                      progress=lambda r, m: _stage(progress, f"refinement ({direction})", r / m))
    else:
        sp = 0.5 * (ab[:, 0] + ab[:, 1])
        sig = sp[0] + np.arange(G) / G if closed else np.linspace(0, 1, G)
        dlt = np.interp(sig, sp, 0.5 * (ab[:, 1] - ab[:, 0]))
        rc = ruling_cost(So, u0 + L * (sig - dlt), u0 + L * (sig + dlt), 15, 4, closed)
    pairing = smooth_pairing(So, sig, dlt, closed, delta_coefs(n))
    if opts.refine:
        pairing, sig, dlt, rc = follow_exact(So, closed, h, (sig, dlt, rc), pairing)
    T["refine"] = time.perf_counter() - t0
    return So, closed, cost, res, path, pairing, (sig, dlt, rc), T


def ruling_figure(S: Surface, options: FitOptions) -> float:
    """A quick figure to compare surfaces by (no rebuild, no certificate): over the directions the options
    allow, the smallest largest distance of the DP pairing's rulings (sampled between the DP's rulings
    too) from the surface.  inf when no direction can be fitted."""
    opts = options.checked()
    if zero_area(S):
        return np.inf
    dirs = ["v", "u"] if opts.direction == Direction.AUTO else [opts.direction.value]
    best = np.inf
    for d in dirs:
        try:
            rc = _dp_pairing(S, d, opts)[6][2]
        except DegenerateFaceError:
            continue
        best = min(best, float(np.max(rc)))
    return best


def fit_direction(S: Surface, direction: str, opts: FitOptions, progress: Progress = None,
                  grid: tuple[int, int] = GRID_FINE, cutoff: float = np.inf) -> DirectionFit:
    """Fit along one direction ('v': boundaries v-min/v-max; 'u': the surface is transposed first)."""
    So, closed, cost, res, path, pairing, (sig, dlt, rc), T = _dp_pairing(S, direction, opts, progress)
    n = opts.samples
    u0, u1, v0, v1 = So.domain
    L = u1 - u0
    diag = So.diagonal()
    h = 1.0 / (n if closed else n - 1)
    ab = path.astype(float) * h
    # rebuild
    t0 = time.perf_counter()
    C0 = So.iso_curve("u", v0)
    C1 = So.iso_curve("u", v1)
    tol = max(2e-7 * diag, 0.02 * float(np.max(rc)))
    bd, pairing = rebuilt_boundaries(C0, C1, u0, L, pairing, tol, lambda pr: face_span(So, pr),
                                     float(np.max(rc)) <= EXACT_RULINGS * diag)
    focus = face_span(So, pairing)
    R = ruled_surface(bd)
    T["rebuild"] = time.perf_counter() - t0
    _stage(progress, f"certify ({direction})", 0.0)
    t0 = time.perf_counter()
    cert = certified_bound(So, pairing, bd, R, grid[0], grid[1], cutoff)
    bd, R, cert = _coarser(So, pairing, (C0, C1, u0, L), bd, R, cert, tol, grid, focus)
    net = net_bound(So, pairing, bd) if face_mask(So) is None else None
    if net is not None and net + cert.rounding < cert.bound:     # (a result along the face's own v-lines)
        cert = replace(cert, bound=net + cert.rounding, node_max=net, remainder=0.0)
    T["certify"] = time.perf_counter() - t0
    _stage(progress, f"certify ({direction})", 1.0)
    pp = np.stack([u0 + L * ab[:, 0], u0 + L * ab[:, 1]], axis=1)
    ppw = u0 + np.mod(pp - u0, L) if closed else pp
    ends = So(np.concatenate([ppw[:, 0], ppw[:, 1]]),
              np.concatenate([np.full(len(pp), v0), np.full(len(pp), v1)]))
    rulings = np.stack([ends[: len(pp)], ends[len(pp):]], axis=1)
    pc = cost[path[:, 0] % n, path[:, 1] % n]
    return DirectionFit(direction, closed, R, path, rulings, pp, pc, res.score, (sig, dlt, rc), pairing,
                        bd.fit_error, cert, T, bd, So)


COARSE = 0.01     # rails within this fraction of a result's bound are fine enough
COMPACT_POLES = 40   # results with more poles than this are rebuilt coarser when far from the face


def _coarser(So: Surface, pairing, curves: tuple, bd, R: Surface, cert, tol: float, grid: tuple[int, int],
             focus: Optional[tuple] = None):
    """A result far from the face (its bound far above the rails' fitting tolerance, which follows the
    rulings' own distances) needs no rails finer than a fraction of its bound: refitted to that, kept
    when its certified bound is no more than 2 % higher and it has fewer poles (a hopeless face fitted
    into hundreds of poles is not a result anyone can use)."""
    coarse = COARSE * cert.bound
    n = bd.A.poles.shape[0]
    if not (np.isfinite(coarse) and coarse > 10.0 * tol and n > COMPACT_POLES):
        return bd, R, cert
    C0, C1, u0, L = curves
    bd2 = fit_boundaries(C0, C1, u0, L, pairing, coarse, focus=focus)
    if bd2.A.poles.shape[0] >= n:
        return bd, R, cert
    R2 = ruled_surface(bd2)
    cert2 = certified_bound(So, pairing, bd2, R2, grid[0], grid[1], 1.02 * cert.bound)
    return (bd2, R2, cert2) if cert2.bound <= 1.02 * cert.bound else (bd, R, cert)


def iso_fit(fit: DirectionFit, grid: tuple[int, int] = GRID_FINE, cutoff: float = np.inf) -> Optional[DirectionFit]:
    """The iso-parametric ruled surface between the same two boundaries (the pairing a = b, rulings
    joining equal parameters: what a CAD system's 'ruled surface between two edges' builds), exact
    and certified like a fit; None when it cannot be rebuilt exactly."""
    So, closed = fit.oriented, fit.closed
    u0, u1, v0, v1 = So.domain
    L = u1 - u0
    n = fit.pairs.shape[0]
    t0 = time.perf_counter()
    sig = np.linspace(0.0, 1.0, 64, endpoint=not closed)
    pairing = fit_delta(sig, np.zeros_like(sig), closed, 8)
    bd = exact_boundaries(So.iso_curve("u", v0), So.iso_curve("u", v1), u0, L, pairing)
    if bd is None:
        return None
    R = ruled_surface(bd)
    cert = certified_bound(So, pairing, bd, R, grid[0], grid[1], cutoff)
    x = np.linspace(0.0, 1.0, n, endpoint=not closed)
    rc = ruling_cost(So, u0 + L * sig, u0 + L * sig, 15, 4, closed)
    pc = ruling_cost(So, u0 + L * x, u0 + L * x, FitOptions.points_per_ruling, 3, closed)
    pp = np.stack([u0 + L * x, u0 + L * x], axis=1)
    ends = So(np.concatenate([pp[:, 0], pp[:, 1]]), np.concatenate([np.full(n, v0), np.full(n, v1)]))
    timings = {"iso": time.perf_counter() - t0}
    return replace(fit, surface=R, pairs=np.stack([np.arange(n), np.arange(n)], axis=1),
                   rulings=np.stack([ends[:n], ends[n:]], axis=1), pair_params=pp, ruling_costs=pc,
                   dp_score=float(pc.sum()), refined=(sig, np.zeros_like(sig), rc), pairing=pairing,
                   boundary_fit_error=bd.fit_error, certificate=cert, timings=timings, boundaries=bd,
                   elevations=None, lift=None, measured=None, method="iso")


def recertify(fit: DirectionFit, grid: tuple[int, int] = GRID_FINE, cutoff: float = np.inf) -> DirectionFit:
    """The same fit with its bound computed on another grid (see certified_bound for cutoff), or with the
    bound it has when that is lower (both are true: a finer grid, or one certified from one side only under
    a cutoff, can come out looser)."""
    t0 = time.perf_counter()
    cert = certified_bound(fit.oriented, fit.pairing, fit.boundaries, fit.surface, grid[0], grid[1], cutoff)
    timings = dict(fit.timings)
    timings["certify"] = timings.get("certify", 0.0) + time.perf_counter() - t0
    if fit.certificate is not None and fit.certificate.bound <= cert.bound:
        cert = fit.certificate
    return replace(fit, certificate=cert, timings=timings)


@one_thread
def fit_surface_2d(S: Surface, options: FitOptions = FitOptions(), progress: Progress = None,
                   cutoff: float = np.inf, compact: bool = True) -> FitResult:
    """Globally optimal ruled fit over the sampled boundary points (2D-DP), refined and certified.
    cutoff: a bound some other candidate already has; a fit sampled at or above it is certified from one
    side only (its bound stays valid, only less tight: it cannot win).  compact=False: the best's rails are
    not compacted (compacted(result) does it later, the same way, where the fit is the one returned).
    ruled.fit.surface.fit_surface chooses between this and the 4D fit."""
    opts = options.checked()
    t0 = time.perf_counter()
    if zero_area(S):
        raise DegenerateFaceError("the face has zero area; pick a proper face (see 'ruled faces')")
    dirs = ["v", "u"] if opts.direction == Direction.AUTO else [opts.direction.value]
    cands: dict = {}
    errors = []
    grid = GRID_FINE if len(dirs) == 1 else GRID_COARSE
    for d in dirs:
        try:
            # with two directions, R's side of the certificate only at first (cutoff 0) ...
            cands[d] = fit_direction(S, d, opts, progress, grid, cutoff if len(dirs) == 1 else 0.0)
        except DegenerateFaceError as exc:
            if len(dirs) == 1:
                raise
            cands[d] = str(exc)
            errors.append(exc)
    ok = {d: c for d, c in cands.items() if not isinstance(c, str)}
    if not ok:
        if len(errors) == 2 and all("closed across the rulings" in str(e) for e in errors):
            raise DegenerateFaceError("the face is closed in both directions (like a torus): there are no two "
                                      "boundaries to rule between; split the face first")
        raise DegenerateFaceError("degenerate face: " + "; ".join(e.template for e in errors))
    if len(ok) > 1:     # ... then S's side too, where it can make the direction win
        for d, c in list(ok.items()):
            rival = min([o.error_bound for e, o in ok.items() if e != d] + [cutoff])
            if c.certificate.bound >= rival > c.certificate.node_max:
                ok[d] = cands[d] = recertify(c, grid, rival)
    best = min(ok.values(), key=lambda c: c.error_bound)
    if grid is not GRID_FINE:
        _stage(progress, f"certify ({best.direction})", 0.0)
        best = recertify(best, GRID_FINE, min([o.error_bound for o in ok.values() if o is not best] + [cutoff]))
        ok[best.direction] = cands[best.direction] = best
        # the other direction too where its samples are closer than the best's bound (both bounds loose)
        for d, c in list(ok.items()):
            if c is not best and c.certificate.node_max < best.error_bound < c.error_bound:
                ok[d] = cands[d] = recertify(c, GRID_FINE, best.error_bound)
        best = min(ok.values(), key=lambda c: c.error_bound)
        _stage(progress, f"certify ({best.direction})", 1.0)
    res = FitResult(best, cands, opts, {"total": time.perf_counter() - t0})
    # (not a face's extended patch: its trim and flank paths follow the map)
    return compacted(res) if compact and face_mask(S) is None else res


def compacted(res: FitResult) -> FitResult:
    """A 2D fit with its best's rails compacted (ruled.fit.rails.compact_fit, within COMPACT of its bound): what
    fit_surface_2d does last, unless asked not to (compact=False) or the fit is of a face's extended patch."""
    best = compact_fit(res.best, COMPACT * res.best.error_bound)
    return replace(res, best=best, candidates={**res.candidates, best.direction: best})

