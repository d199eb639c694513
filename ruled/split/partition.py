"""Splitting a face for ruling (Wang & Elber §4) and partitioning it to a tolerance.

``split_face`` finds the optimal M-curve of the face by the split DP, turns it into a smooth domain
curve, and fits both sides through the virtual subdivision (ruled.split.strips); it also fits the best
iso-parametric split (the constant row the split DP scores best) and the v = 1/2 split, so that the
three can be compared.  ``partition`` goes beyond the paper: it splits, always the strip with the
largest certified error, until every strip's ruled fit is within a tolerance, and counts the strips
that uniform iso-parametric splitting needs for the same tolerance.

Everything here works on the oriented surface (rulings along v, the split curves running along u);
``transposed`` says whether that is the input's (u, v) exchanged.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace
from typing import Optional

import numpy as np

from ruled.core.errors import BadInputError, InfeasibleError, positive, whole
from ruled.core.nurbs import Curve, Surface
from ruled.core.progress import Progress
from ruled.fit.fit2d import FitResult
from ruled.fit.options import Direction, FitOptions
from ruled.fit.surface import fit_surface
from ruled.split.mcurve import check_memory, row_scores, split_dp, split_tables
from ruled.split.strips import SideSurface, Strip, graph_curve, side_surface


@dataclass(frozen=True)
class SplitOptions:
    samples: int = 30          # n: P-, Q- and M-columns
    interior: int = 10         # d: M-rows (eq. 20)
    objective: str = "max"     # of the split DP (the paper uses the maximal line metric)
    fit: FitOptions = FitOptions()
    max_strips: int = 16       # partition: refuse beyond this many strips
    memory_cap: Optional[float] = None
    dims: int = 4              # 4: nothing elevated; 5: M-points lifted along the normal; 7: P, Q and M
    levels: int = 2            # 5D / 7D: levels -levels..levels (2: the paper's 5)
    step: Optional[float] = None   # 5D / 7D: the lift per level (default: the strip's bound / (2 levels + 1))

    def __post_init__(self):
        """Validates every option on construction (one BadInputError line naming it)."""
        whole("samples", self.samples, 4, np.inf, "is too small for a split; use at least 4 (30 is the paper's)")
        whole("interior", self.interior, 1, np.inf,
              "must be a whole number of M-rows, at least 1 (10 is the paper's)")
        if self.objective not in ("sum", "max"):
            raise BadInputError(f"unknown split objective {self.objective!r}: use 'sum' or 'max'")
        if self.dims not in (4, 5, 7):
            raise BadInputError(f"«dims={self.dims}»: use 4 (nothing elevated), 5 (M elevated) or 7 (P, Q and M)")
        whole("split_elevations", self.levels, 1, 6, "must be a whole number from 1 to 6 (levels on each side of the "
              "surface; 2 gives the paper's 5)")
        if self.step is not None and not (np.isfinite(self.step) and self.step > 0):
            positive("lift_step", self.step)
        whole("max_strips", self.max_strips, 1, np.inf, "must be at least 1")
        if not isinstance(self.fit, FitOptions):
            raise BadInputError("the split's fit options must be a FitOptions")
        if self.memory_cap is not None:
            positive("memory_cap", self.memory_cap / 2.0 ** 20, "a size in MiB")

    def checked(self) -> "SplitOptions":
        """The options, refused with the estimate when the split's tables would not fit in memory."""
        m = 2 * self.levels + 1
        check_memory(self.samples, self.interior, m if self.dims == 7 else 1, m if self.dims == 7 else 1,
                     1 if self.dims == 4 else m, self.memory_cap)
        return self


@dataclass
class StripFit:
    """A strip, its side surface and the ruled fit of that surface (rulings across the strip)."""

    strip: Strip
    side: SideSurface
    fit: FitResult

    @property
    def bound(self) -> float:
        """Certified bound of the fit against the side surface, plus the side surface's measured
        deviation from S o Omega."""
        return float(self.fit.error_bound + self.side.deviation)


@dataclass
class SplitCandidate:
    name: str                  # "optimal", "best-iso" or "iso-0.5"
    curve: Curve               # the split curve in the oriented surface's domain
    sides: tuple               # (StripFit below the curve, StripFit above it)
    dp_score: Optional[float] = None
    t: Optional[float] = None  # iso splits: the strip parameter of the curve

    @property
    def bound(self) -> float:
        return max(s.bound for s in self.sides)


@dataclass
class SplitResult:
    oriented: Surface
    transposed: bool
    whole: StripFit
    candidates: dict           # name -> SplitCandidate
    m_points: np.ndarray       # (n, 2) the DP's M-points (u, v) on the oriented surface
    timings: dict = field(default_factory=dict)

    def best(self, key=None) -> SplitCandidate:
        """The candidate with the smallest key (default: the certified bound)."""
        return min(self.candidates.values(), key=key or (lambda c: c.bound))


def _stage(progress: Progress, name: str, frac: float) -> None:
    if progress is not None:
        progress(name, frac)


def fit_strip(S: Surface, strip: Strip, fopts: FitOptions, progress: Progress = None,
              cutoff: float = np.inf) -> StripFit:
    """The strip's side surface and its fit (see fit_surface for cutoff)."""
    side = side_surface(S, strip)
    res = fit_surface(side.surface, replace(fopts, direction=Direction.V), progress, cutoff)
    return StripFit(strip, side, res)


def whole_fit(S: Surface, fopts: FitOptions, progress: Progress = None):
    """The fit of the whole face: it chooses the ruling direction; returns (oriented surface, transposed,
    its StripFit)."""
    res = fit_surface(S, fopts, progress)
    So = res.best.oriented
    transposed = res.direction == "u"
    return So, transposed, StripFit(Strip(), SideSurface(So, 0.0), res)


def _smoothed(s, t, spans: int, lo: float, hi: float):
    c = graph_curve(s, t, spans=spans)
    return lambda x: np.clip(c(x)[:, 1], lo, hi)


def _fourier(s, t, K: int, lo: float, hi: float):
    """A least-squares Fourier series of K harmonics through (s, t), s in [0, 1) (periodic)."""
    w = 2 * np.pi * np.arange(1, K + 1)

    def basis(x):
        x = np.asarray(x, float)
        return np.concatenate([np.ones((x.size, 1)), np.cos(np.outer(x, w)), np.sin(np.outer(x, w))], axis=1)
    coef = np.linalg.lstsq(basis(s), t, rcond=None)[0]
    return lambda x: np.clip(basis(x) @ coef, lo, hi)


def closed_split_dp(T, opts: SplitOptions):
    """The split DP of a face closed along the split: the M-curve ends on the row it starts on (the
    seam's two sides are one column); every start row tried, the best kept."""
    best = None
    d = T.v_levels.size
    for b0 in range(d):
        A = np.array(T.A, float)
        rows = np.arange(d) != b0
        if A.ndim == 3:
            A[:, 0, rows] = np.inf
        else:
            A[:, :, 0, rows] = np.inf
        r = split_dp(replace(T, A=A), opts.objective, opts.memory_cap, end_row=b0)
        if best is None or r.score < best.score:
            best = r
    return best


def split_curves(S: Surface, strip: Strip, side: SideSurface, opts: SplitOptions, scale: float, closed: bool = False):
    """The candidate split curves of a strip: the split DP's optimal M-curve (smoothed), the constant
    row the split DP scores best, and the middle; each as (name, domain curve, DP score, t).  scale:
    the strip's error, which sets the default lift per level of a 5D or 7D split; closed: the face is
    closed along the split (the curve closes up, its seam row the same at both ends)."""
    n, d = opts.samples, opts.interior
    Ss = side.surface
    s0, s1, t0, t1 = Ss.domain
    step = opts.step if opts.step is not None else max(scale, 1e-9 * Ss.diagonal()) / (2 * opts.levels + 1)
    T = split_tables(Ss, n, d, dims=opts.dims, levels=opts.levels if opts.dims != 4 else 0, step=step)
    path = closed_split_dp(T, opts) if closed else split_dp(T, opts.objective, opts.memory_cap)
    mc = path.m_curve(T)
    s = (mc[:, 0] - s0) / (s1 - s0)
    t = (mc[:, 1] - t0) / (t1 - t0)
    lo_t, hi_t = 0.5 / (d + 1), 1 - 0.5 / (d + 1)
    out: list = []
    # the M-points are on d rows: smoothed into a curve at three strengths, each scored by its fits later
    for k, level in enumerate((8, 4, 2)):
        if closed:    # a periodic smoothing: least-squares Fourier series
            out.append((f"optimal:{k}", strip.curve_at(S, _fourier(s[:-1], t[:-1], max(1, n // (2 * level)), lo_t,
                                                                   hi_t), max(16, n)), path.score, None))
        else:
            out.append((f"optimal:{k}", strip.curve_at(S, _smoothed(s, t, max(1, n // level), lo_t, hi_t),
                                                       max(16, n)), path.score, None))
    # the best constant row: the split DP on that row alone (a table of one row)
    scores = row_scores(T, opts.objective, opts.memory_cap)
    # rows that tie (to round-off, which differs between the kernels and their NumPy twins): the one
    # nearest the middle, then the lower
    rows = (np.arange(d) + 1.0) / (d + 1)
    tie = np.nonzero(scores <= scores.min() + 1e-9 * max(abs(float(scores.min())), 1e-300))[0]
    b = int(tie[np.lexsort((rows[tie], np.round(np.abs(rows[tie] - 0.5), 12)))[0]])
    tb = (b + 1.0) / (d + 1)
    out.append(("best-iso", strip.curve_at(S, tb), float(scores[b]), tb))
    if abs(tb - 0.5) > 1e-12:
        out.append(("iso-0.5", strip.curve_at(S, 0.5), None, 0.5))
    m_uv = np.stack(strip.omega(S, s, t), axis=1)
    return out, m_uv


def split_strip(S: Surface, sf: StripFit, opts: SplitOptions, progress: Progress = None,
                names=("optimal", "best-iso", "iso-0.5")):
    """Split one strip: every candidate curve with both sides fitted; of the optimal M-curve's smoothings
    the one whose fits are best is kept as "optimal"."""
    curves, m_uv = split_curves(S, sf.strip, sf.side, opts, sf.bound, sf.fit.best.closed)
    cands: dict = {}
    curves = [c for c in curves if c[0].split(":")[0] in names]
    best = np.inf       # the best candidate's bound so far: a side sampled above it cannot win
    for k, (name, curve, score, t) in enumerate(curves):
        lo, hi = sf.strip.cut(S, curve)
        sides = (fit_strip(S, lo, opts.fit, cutoff=best), fit_strip(S, hi, opts.fit, cutoff=best))
        c = SplitCandidate(name.split(":")[0], curve, sides, score, t)
        best = min(best, c.bound)
        if c.name not in cands or c.bound < cands[c.name].bound:
            cands[c.name] = c
        _stage(progress, "fitting the sides", (k + 1) / len(curves))
    return cands, m_uv


def split_face(S: Surface, opts: SplitOptions = SplitOptions(), progress: Progress = None) -> SplitResult:
    """Split the face once (Wang & Elber §4) and fit both sides: the optimal, best iso and middle splits."""
    opts = opts.checked()
    t0 = time.perf_counter()
    So, transposed, whole = whole_fit(S, opts.fit, progress)
    t1 = time.perf_counter()
    cands, m_uv = split_strip(So, whole, opts, progress)
    return SplitResult(So, transposed, whole, cands, m_uv,
                       {"whole_fit": t1 - t0, "split_and_fits": time.perf_counter() - t1})


@dataclass
class Partition:
    oriented: Surface
    transposed: bool
    tol: float
    strips: list               # StripFit, in order from v0 to v1
    uniform_count: Optional[int]   # strips uniform iso splitting needs (None: more than max_strips)
    greedy_count: int          # strips the recursive optimal splitting reached
    used: str                  # "optimal" or "uniform": whichever needed fewer strips
    history: list = field(default_factory=list)   # per split: (strip index, candidate name, bound)
    timings: dict = field(default_factory=dict)

    @property
    def bounds(self) -> list:
        return [s.bound for s in self.strips]


def uniform_partition(So: Surface, k: int, fopts: FitOptions, tol: Optional[float] = None):
    """k strips between the iso-lines v = v0 + i (v1 - v0) / k; with tol, stops at the first strip
    whose bound exceeds it (returns None then)."""
    whole = Strip()
    curves = [None] + [whole.curve_at(So, i / k) for i in range(1, k)] + [None]
    out = []
    for lo, hi in zip(curves[:-1], curves[1:]):
        f = fit_strip(So, Strip(lo, hi), fopts)
        if tol is not None and f.bound > tol:
            return None
        out.append(f)
    return out


def partition(S: Surface, tol: float, opts: SplitOptions = SplitOptions(), progress: Progress = None) -> Partition:
    """Split recursively, always the strip with the largest certified bound, each time at the better
    of its optimal M-curve and its best iso-parametric curve, until every strip's bound is within tol;
    then the fewest uniform iso-parametric strips for the same tolerance, and keep whichever is fewer."""
    opts = opts.checked()
    positive("tol", tol)
    t0 = time.perf_counter()
    So, transposed, whole = whole_fit(S, opts.fit, progress)
    strips = [whole]
    history = []
    while True:
        bounds = [s.bound for s in strips]
        k = int(np.argmax(bounds))
        _stage(progress, f"partition: {len(strips)} strips, worst {bounds[k]:.3g}", min(1.0, tol / bounds[k]))
        if bounds[k] <= tol:
            break
        if len(strips) >= opts.max_strips:
            raise InfeasibleError(f"the tolerance {tol:.4g} is not met with {opts.max_strips} strips (the best reached "
                                  f"is {max(bounds):.4g}); raise «max_strips» or the tolerance")
        cands, _ = split_strip(So, strips[k], opts, None, names=("optimal", "best-iso"))
        best = min(cands.values(), key=lambda c: c.bound)
        history.append((k, best.name, best.bound))
        strips[k:k + 1] = list(best.sides)
    t1 = time.perf_counter()
    uniform = None
    for m in range(1, opts.max_strips + 1):
        _stage(progress, f"uniform iso splitting: {m} strips", m / opts.max_strips)
        u = uniform_partition(So, m, opts.fit, tol) if m > 1 else ([whole] if whole.bound <= tol else None)
        if u is not None:
            uniform = (m, u)
            break
    greedy = len(strips)
    used = "optimal"
    if uniform is not None and uniform[0] < greedy:
        strips, used = uniform[1], "uniform"
    return Partition(So, transposed, tol, strips, None if uniform is None else uniform[0], greedy, used, history,
                     {"optimal": t1 - t0, "uniform": time.perf_counter() - t1})
