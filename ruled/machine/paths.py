"""Machine outputs of a ruled surface: XYUV contours for 4-axis wire EDM and hot-wire cutters, and
flank-milling tool axes (CL data).

The machine moves along straight lines.  For a ruled result R(u, t) (rulings along t) each line is

* XYUV: the ruling itself, or with a kerf k its offset: the straight line closest (in the largest
  distance, by Lawson's reweighted least squares) to the offset curve R(u, t) + k n(u, t) of that
  ruling.  A wire of radius k whose axis sweeps these lines cuts the envelope of its cylinders, i.e.
  the offset of the line surface by k: the ruled surface itself where the offset is exact
  (developable surfaces), within the offset lines' deviation elsewhere (reported).
* Flank: the tool axis, the ruling offset by the tool radius r along the normal (a cylinder touches
  the surface along the ruling); for a conical tool of taper angle a the axis is tilted by a from the
  ruling in its normal plane and offset by r at the tip, so that a generator of the cone lies on the
  ruling.

Each line is extended to the two machine planes (XYUV) or kept between the ruling's ends (flank: the
tip at one end of the ruling, by default the lower in z).  The points on the two planes (or the tool's two
ends), as functions of u, are the two contours; the synchronized pairs are a subdivision of u: densified
by bisection until every move is within a sixteenth of the chord tolerance of both contours at the same
u, then thinned greedily to the longest moves within the chord tolerance at every sample taken.
Because the line surface between two planes is linear in the line parameter, the surface between the
exported polylines is then within the chord tolerance of the line surface everywhere between the
planes.

Data in and out are plain arrays; the G-code, CSV and APT writers, the report and the plot are in
ruled.machine.output; OCCT is not used.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable, Optional

import numpy as np

from ruled.core.errors import BadInputError, positive, whole
from ruled.core.nurbs import Surface
from ruled.core.progress import Progress
from ruled.machine.corners import round_corners, ruling_normals
from ruled.machine.leads import with_leads
from ruled.machine.loops import held_ends, one_sided, smooth_pieces, trimmed_guides
from ruled.machine.loops import held_fillet as held_fillet_of
from ruled.machine.sync import _seeds, sync_params

_LINE_SAMPLES = 9          # samples along a ruling for its offset line
_DENSE = 513               # rulings checked for plane crossings and curvature
_LAWSON = 8                # reweightings of an offset line towards the minimax line


@dataclass(frozen=True)
class MachineOptions:
    """What to make: XYUV contours (wire) or flank-milling tool axes, and how."""

    mode: str = "xyuv"                      # xyuv | flank
    chord_tol: Optional[float] = None       # default: 1e-4 of the part's diagonal
    planes: Optional[tuple] = None          # xyuv: the two plane heights along the axis (default: outside the part)
    axis: Any = "auto"                      # xyuv: auto (mean ruling direction) | x | y | z | a 3-vector
    margin: Optional[float] = None          # xyuv: default planes this far outside the part (default 2% of diagonal)
    kerf: float = 0.0                       # xyuv: wire radius plus spark gap, offset to the outside
    tool_radius: Optional[float] = None     # flank: tool radius (at the tip for a conical tool)
    taper_deg: float = 0.0                  # flank: half angle of a conical tool
    lead: Optional[float] = None            # xyuv: lead-in / lead-out length (default 5% of diagonal; 0: none)
    feed: float = 100.0                     # feed rate, model units per minute
    max_points: int = 50000
    tip: str = "auto"                       # flank: the tool tip at the rulings' first end, second, or auto (lower z)
    positions: str = "envelope"             # flank: envelope (fitted to the face) | offset (the offset rulings)
    gouge_tol: Optional[float] = None       # flank envelope: overcut allowed (default: the fit's bound)

    def __post_init__(self):
        """Validates every option on construction (one BadInputError line naming it) and normalises them in
        place."""
        def size(name, x, zero_ok=False, what="a distance in model units"):
            return None if x is None else positive(name, x, what, zero_ok)

        if self.mode not in ("xyuv", "flank"):
            raise BadInputError(f"unknown machine output {self.mode!r}; use xyuv or flank")
        planes = self.planes
        if planes is not None:
            try:
                planes = tuple(float(h) for h in planes)
            except (TypeError, ValueError):
                raise BadInputError(f"«planes» takes two heights a,b, not {self.planes!r}") from None
            if len(planes) != 2 or not all(math.isfinite(h) for h in planes) or planes[0] == planes[1]:
                raise BadInputError(f"«planes» takes two different heights a,b, not {self.planes!r}")
            planes = tuple(sorted(planes))
        r = size("tool_radius", self.tool_radius)
        if self.mode == "flank" and r is None:
            raise BadInputError("flank milling needs the tool radius («tool_radius» R)")
        try:
            taper = float(self.taper_deg)
        except (TypeError, ValueError):
            taper = math.nan
        if not (0.0 <= taper < 45.0):
            raise BadInputError(f"«taper» must be from 0 to 45 degrees (the tool's half angle), not {self.taper_deg!r}")
        feed = size("feed", self.feed, what="model units per minute")
        if self.tip not in ("auto", "first", "second"):
            raise BadInputError(f"«tip» is auto, first or second, not {self.tip!r}")
        if self.positions not in ("envelope", "offset"):
            raise BadInputError(f"«positions» is envelope (fitted to the face) or offset (the offset rulings), not "
                                f"{self.positions!r}")
        max_points = whole("max_points", self.max_points, 100, 10 ** 8, "must be a whole number from 100 to 100000000")
        values = dict(chord_tol=size("chord_tol", self.chord_tol), planes=planes, axis=_axis_spec(self.axis),
                      margin=size("margin", self.margin), kerf=size("kerf", self.kerf, True), tool_radius=r,
                      taper_deg=taper, lead=size("lead", self.lead, True), feed=feed,
                      max_points=max_points, gouge_tol=size("gouge_tol", self.gouge_tol, True))
        for name, value in values.items():
            object.__setattr__(self, name, value)

    def checked(self) -> "MachineOptions":
        """The options (validated on construction; kept for the callers that say so)."""
        return self


def _axis_spec(axis):
    if isinstance(axis, str):
        a = axis.strip().lower()
        if a in ("auto", "x", "y", "z"):
            return a
        try:
            axis = [float(s) for s in a.split(",")]
        except ValueError:
            raise BadInputError(f"«axis» is auto, x, y, z or a vector 'ax,ay,az', not {axis!r}") from None
    v = np.asarray(axis, float).ravel()
    if v.shape != (3,) or not np.all(np.isfinite(v)) or np.linalg.norm(v) == 0:
        raise BadInputError(f"«axis» is auto, x, y, z or a non-zero vector 'ax,ay,az', not {axis!r}")
    return tuple(v / np.linalg.norm(v))


# ---------------------------------------------------------------------------------------------- lines

class Lines:
    """The machine's straight lines as functions of u: the rulings of R(u, t) between its t-ends, or
    their offsets by a radius (kerf or tool) along the normal on the side `sign` (+1: R's Su x Sv),
    tilted by a taper angle for a conical tool."""

    def __init__(self, R: Surface, sign: float, radius: float = 0.0, taper_deg: float = 0.0):
        self.R, self.sign, self.radius = R, float(sign), float(radius)
        self.taper = math.radians(taper_deg)
        u0, u1, t0, t1 = R.domain
        self.domain = (u0, u1)
        self.t = (t0, t1)
        self.closed = bool(R.periodic_u)
        self.offset = self.radius > 0 or self.taper > 0

    def rulings(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        u = np.asarray(u, float)
        return self.R(u, np.full(u.shape, self.t[0])), self.R(u, np.full(u.shape, self.t[1]))

    def ends(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(A, B, dev): the line's points at the ruling's two ends and, for offsets, the largest
        distance between the offset curve of the ruling and the line (0 for the rulings themselves)."""
        u = np.asarray(u, float).ravel()
        A, B = self.rulings(u)
        if not self.offset:
            return A, B, np.zeros(u.size)
        m = _LINE_SAMPLES
        ts = self.t[0] + (self.t[1] - self.t[0]) * 0.5 * (1 - np.cos(np.pi * np.arange(m) / (m - 1)))
        U = np.repeat(u, m)
        D = self.R.evaluate(U, np.tile(ts, u.size), 1)
        P = D.P.reshape(u.size, m, 3)
        n = self.sign * ruling_normals(np.cross(D.Su, D.Sv).reshape(u.size, m, 3))
        ab = B - A
        L = np.linalg.norm(ab, axis=1)
        b = ab / np.where(L > 0, L, 1.0)[:, None]
        tau = np.einsum("kmc,kc->km", P - A[:, None], b) / np.where(L > 0, L, 1.0)[:, None]
        sa, ca = math.sin(self.taper), math.cos(self.taper)
        rho = self.radius + tau * L[:, None] * sa
        O = P + rho[..., None] * (ca * n - sa * b[:, None])
        best_dev = np.full(u.size, np.inf)
        best0, best1 = A.copy(), B.copy()
        w = np.full(tau.shape, 1.0 / m)
        for _ in range(_LAWSON):        # weighted least squares, reweighted towards the minimax line (Lawson)
            tm = (w * tau).sum(axis=1, keepdims=True)
            Om = np.einsum("km,kmc->kc", w, O)[:, None]
            var = (w * (tau - tm) ** 2).sum(axis=1)
            c1 = np.einsum("km,kmc->kc", w * (tau - tm), O - Om) / np.where(var > 0, var, 1.0)[:, None]
            c0 = Om[:, 0] - tm * c1
            r = np.linalg.norm(O - (c0[:, None] + tau[..., None] * c1[:, None]), axis=2)
            dev = r.max(axis=1)
            better = dev < best_dev
            best_dev = np.where(better, dev, best_dev)
            best0[better], best1[better] = c0[better], (c0 + c1)[better]
            w = w * (r + 1e-300)
            w /= w.sum(axis=1, keepdims=True)
        return best0, best1, best_dev


def side_sign(R: Surface, S: Surface, side: float = 1.0) -> float:
    """+1 or -1: the orientation of R's normal Su x Sv that points to the side `side` of the design
    surface S (+1: S's own Su x Sv, the outside of a forward face of a solid)."""
    from ruled.core.distance import project_points
    u0, u1, t0, t1 = R.domain
    g = np.linspace(0.1, 0.9, 5)
    uu, tt = np.meshgrid(u0 + (u1 - u0) * g, t0 + (t1 - t0) * g, indexing="ij")
    D = R.evaluate(uu.ravel(), tt.ravel(), 1)
    uv = _seeds(S, D.P)
    uv, _ = project_points(S, D.P, uv, iters=8, closed_u=S.periodic_u, closed_v=S.periodic_v)
    nS = S.evaluate(uv[:, 0], uv[:, 1], 1).normals()
    s = float(np.sum(np.einsum("ij,ij->i", D.normals(), nS)))
    return (1.0 if s >= 0 else -1.0) * (1.0 if side >= 0 else -1.0)


# ----------------------------------------------------------------------------------------- sync points


# ------------------------------------------------------------------------------------------------ XYUV

@dataclass(frozen=True)
class Frame:
    """Machine coordinates: X = p . e1, Y = p . e2 on both planes; heights p . axis."""

    e1: np.ndarray
    e2: np.ndarray
    axis: np.ndarray

    def xy(self, P: np.ndarray) -> np.ndarray:
        return np.stack([P @ self.e1, P @ self.e2], axis=-1)

    def point(self, xy: np.ndarray, h: float) -> np.ndarray:
        xy = np.asarray(xy, float)
        return xy[..., :1] * self.e1 + xy[..., 1:2] * self.e2 + h * self.axis


def frame_of(axis) -> Frame:
    d = np.asarray(axis, float)
    d = d / np.linalg.norm(d)
    ref = np.array([1.0, 0.0, 0.0]) if abs(d[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = ref - (ref @ d) * d
    e1 /= np.linalg.norm(e1)
    return Frame(e1, np.cross(d, e1), d)


@dataclass(frozen=True)
class MachinePath:
    """Synchronized machine data.  xyuv: `lower`/`upper` are the points on the two planes; flank: the
    tool tip centre and the point one ruling length up the axis.  `moves` (M, 4) are what the G-code
    moves to (X, Y, U, V), lead-in and lead-out included; `kinds` names each."""

    mode: str
    u: np.ndarray                 # (n,) parameters of the synchronized points on R
    lower: np.ndarray             # (n, 3)
    upper: np.ndarray             # (n, 3)
    part: np.ndarray              # (n, 2, 3) each line between the ruling's ends (the part of it that cuts)
    closed: bool
    chord_tol: float
    offset_deviation: float       # largest distance between an offset ruling and its straight line
    frame: Optional[Frame] = None
    planes: Optional[tuple] = None
    moves: Optional[np.ndarray] = None
    kinds: tuple = ()
    radius: float = 0.0           # kerf (xyuv) or tool radius (flank)
    taper_deg: float = 0.0
    feed: float = 100.0
    stats: dict = field(default_factory=dict)
    warnings: tuple = ()
    trace: Optional[Callable] = field(default=None, repr=False, compare=False)  # u -> the (n, 2, 3) exact ends

    @property
    def axes(self) -> np.ndarray:
        """Unit directions of the lines (lower to upper)."""
        d = self.upper - self.lower
        return d / np.linalg.norm(d, axis=1)[:, None]

    @property
    def flute(self) -> float:
        """The longest line (flank: the tool's cutting length, the APT CUTTER's h: the real tool is this long at
        every position, not only as long as its ruling there)."""
        return flute_of(self.lower, self.upper)


def flute_of(lower: np.ndarray, upper: np.ndarray) -> float:
    """The longest of the lines between the stations' lower and upper points (flank: the tool's cutting length)."""
    return float(np.linalg.norm(upper - lower, axis=1).max())


def _where(u, P) -> str:
    return f"u = {u:.6g}, at ({P[0]:.6g}, {P[1]:.6g}, {P[2]:.6g})"


def _axis_vector(spec, A: np.ndarray, B: np.ndarray, closed: bool) -> np.ndarray:
    """The machine axis: given, or the mean ruling direction (the principal direction of the unit
    rulings, weighted by the arc length of the middle curve), snapped to a world axis within 0.5
    degree and pointing up its largest world component."""
    if isinstance(spec, tuple):
        return np.array(spec)
    if spec in ("x", "y", "z"):
        return np.eye(3)["xyz".index(spec)]
    if closed:
        A, B = A[:-1], B[:-1]
    d = B - A
    d = d / np.maximum(np.linalg.norm(d, axis=1), 1e-300)[:, None]
    M = 0.5 * (A + B)
    step = np.linalg.norm(np.roll(M, -1, 0) - np.roll(M, 1, 0), axis=1) if closed else \
        np.linalg.norm(np.gradient(M, axis=0), axis=1)
    _, vec = np.linalg.eigh(np.einsum("i,ij,ik->jk", step, d, d))
    d = vec[:, -1]
    k = int(np.argmax(np.abs(d)))
    d = d if d[k] > 0 else -d
    if d[k] > math.cos(math.radians(0.5)):
        d = np.eye(3)[k]
    return d


def curvature_warnings(R: Surface, sign: float, radius_at: Callable[[np.ndarray], np.ndarray], what: str,
                       n: int = 129) -> list:
    """Where the surface bends towards the tool side more sharply than the tool (or wire) radius:
    the largest principal curvature towards that side, against 1 / radius."""
    u0, u1, t0, t1 = R.domain
    uu, tt = np.meshgrid(np.linspace(u0, u1, n), np.linspace(t0, t1, 9), indexing="ij")
    D = R.evaluate(uu.ravel(), tt.ravel(), 2)
    nrm = sign * D.normals()
    E, F, G = (np.einsum("ij,ij->i", a, b) for a, b in ((D.Su, D.Su), (D.Su, D.Sv), (D.Sv, D.Sv)))
    L, M, N = (np.einsum("ij,ij->i", a, nrm) for a in (D.Suu, D.Suv, D.Svv))
    a = E * G - F * F
    b = -(E * N + G * L - 2 * F * M)
    c = L * N - M * M
    disc = np.sqrt(np.maximum(b * b - 4 * a * c, 0.0))
    k1 = (-b + disc) / (2 * np.where(a > 0, a, np.inf))
    r = radius_at((tt.ravel() - t0) / max(t1 - t0, 1e-300))
    bad = k1 * r >= 1.0
    if not bad.any():
        return []
    i = int(np.argmax(np.where(bad, k1, -np.inf)))
    return [f"the {what} {r[i]:.6g} exceeds the surface's radius of curvature {1 / k1[i]:.6g} towards it "
            f"at {_where(uu.ravel()[i], D.P[i])}, t = {tt.ravel()[i]:.3g} (and {int(bad.sum()) - 1} more of "
            f"{bad.size} samples): it will cut into the surface there"]


def _chord(opts: MachineOptions, R: Surface) -> float:
    return opts.chord_tol if opts.chord_tol is not None else 1e-4 * R.diagonal()


def _seed_params(R: Surface, lines: Lines) -> np.ndarray:
    u0, u1 = lines.domain
    k = np.unique(R.knots_u)
    return np.concatenate([k[(k > u0) & (k < u1)], np.linspace(u0, u1, 17)])


def _check_rulings(lines: Lines, u: np.ndarray):
    A, B = lines.rulings(u)
    L = np.linalg.norm(B - A, axis=1)
    tiny = 1e-9 * max(float(L.max()), 1e-300)
    if np.any(L <= tiny):
        i = int(np.argmin(L))
        raise BadInputError(f"the ruling at {_where(u[i], A[i])} has no length (the ruled result is singular "
                            f"there): no line to cut along")
    return A, B


def xyuv_path(R: Surface, opts: MachineOptions, sign: float = 1.0, progress: Progress = None) -> MachinePath:
    """XYUV contours of the ruled surface R for a wire between two machine planes (see the module)."""
    opts = opts.checked()
    tol = _chord(opts, R)
    lines = Lines(R, sign, opts.kerf)
    u0, u1 = lines.domain
    ud = np.linspace(u0, u1, _DENSE)
    A0, B0 = _check_rulings(lines, ud)
    A, B, dev = lines.ends(ud)
    d = _axis_vector(opts.axis, A0, B0, lines.closed)
    fr = frame_of(d)
    ha, hb = A @ d, B @ d
    span = hb - ha
    cosang = np.abs(span) / np.linalg.norm(B - A, axis=1)
    if np.any(cosang < math.cos(math.radians(85.0))):
        i = int(np.argmin(cosang))
        raise BadInputError(f"ruling {i} of {_DENSE} ({_where(ud[i], A[i])}) is "
                            f"{math.degrees(math.acos(cosang[i])):.1f} degrees from the machine axis "
                            f"({d[0]:.4g}, {d[1]:.4g}, {d[2]:.4g}): it (almost) never crosses the planes; "
                            f"choose another «axis»")
    if np.any(np.sign(span) != np.sign(span[0])):
        i = int(np.argmax(np.sign(span) != np.sign(span[0])))
        raise BadInputError(f"the rulings turn over along the machine axis (ruling {i} of {_DENSE}, "
                            f"{_where(ud[i], A[i])}): one pair of planes cannot hold both guides; choose another "
                            f"«axis» or split the face")
    lo_h, hi_h = np.minimum(ha, hb), np.maximum(ha, hb)
    margin = opts.margin if opts.margin is not None else 0.02 * R.diagonal()
    if opts.planes is None:
        planes = (float(lo_h.min() - margin), float(hi_h.max() + margin))
    else:
        planes = opts.planes
        for h, inside in ((planes[0], lo_h < planes[0]), (planes[1], hi_h > planes[1])):
            if inside.any():
                i = int(np.argmax(inside))
                raise BadInputError(
                    f"the plane at height {h:g} crosses ruling {i} of {_DENSE} ({_where(ud[i], A[i])}, heights "
                    f"{lo_h[i]:.6g} to {hi_h[i]:.6g}): the planes must lie outside the part, the lower below "
                    f"{lo_h.min():.6g} and the upper above {hi_h.max():.6g} («planes» a,b)")

    def on_planes(u):
        a, b, _ = lines.ends(u)
        return to_planes(a, b, d, planes)

    off_dev = float(dev.max())
    warnings = []
    budget, absorbed = tol, True
    if lines.offset:
        warnings += curvature_warnings(R, sign, lambda t: np.full(t.shape, opts.kerf), "kerf")
        if off_dev > 0.5 * tol:
            warnings.append(f"the kerf offset of this surface is not ruled: its straight lines miss the offset "
                            f"surface by up to {off_dev:.3g} (more than half the chord tolerance {tol:.3g}); "
                            f"the cut carries that error")
            absorbed = False
        else:
            budget = tol - off_dev
    # the offset lines jump at a crease: followed piece by piece between the creases, each from its own side
    L = u1 - u0
    pieces = smooth_pieces(R, u0, u1) if lines.offset else [(u0, u1)]
    f, held_fillet = on_planes, 0.0
    if lines.offset:
        f, dense = trimmed_guides(on_planes, pieces, L, fr.xy, lines.closed)
        held_fillet = held_fillet_of(f, dense, lines, opts.kerf)
    seeds = _seed_params(R, lines)
    if len(pieces) == 1:
        us = sync_params(f, u0, u1, budget, seeds, opts.max_points, progress)
    else:
        us = np.concatenate([one_sided(sync_params(lambda u, a=a, b=b: f(one_sided(u, a, b, L)), a, b, budget,
                                                   seeds[(seeds > a) & (seeds < b)], opts.max_points, progress),
                                       a, b, L) for a, b in pieces])
    if us.size < 2:
        raise BadInputError("the machine path is empty: the ruled result has no extent along its rulings")
    a, b, _ = lines.ends(us)
    inside_turns: list = []
    if lines.offset:
        a, b = held_ends(f, us, a, b, d)
        us, a, b, inside_turns = round_corners(lines, us, a, b, budget)
    E = to_planes(a, b, d, planes)
    if len(pieces) > 1:     # both sides of a crease the offsets do not jump at (a tangent joint): one point
        same = np.linalg.norm(np.diff(E, axis=0), axis=2).max(axis=1) <= 1e-9 * R.diagonal()
        keep = np.concatenate([[True], ~same])
        us, a, b, E = us[keep], a[keep], b[keep], E[keep]
    lower, upper = E[:, 0], E[:, 1]
    part = np.stack([a, b], axis=1)
    moves, kinds = with_leads(lower, upper, lines, us, sign, fr, opts, R)
    taper = np.degrees(np.arccos(np.clip(cosang, 0.0, 1.0)))
    it = int(np.argmax(taper))
    if taper[it] > 30.0:
        warnings.append(f"the largest taper angle is {taper[it]:.1f} degrees ({_where(ud[it], A[it])}): more than "
                        f"most wire-EDM machines tilt (about 30 degrees)")
    stats = {"sync_points": int(us.size), "moves": int(len(moves) - 1),
             "length_xy": _length(fr.xy(lower)), "length_uv": _length(fr.xy(upper)),
             "max_taper_deg": float(taper[it]), "max_taper_at_u": float(ud[it]),
             "plane_heights": list(planes), "axis": d.tolist(),
             "cut_bound_beyond_fit": tol + (0.0 if absorbed else off_dev),
             # a wire of radius k leaves an inside corner (the normal turning by g) round: k (1 / cos(g / 2) - 1)
             "inside_corner_fillet": max([held_fillet] + [opts.kerf * (1.0 / math.cos(0.5 * g) - 1.0)
                                                          for g in inside_turns])}
    return MachinePath("xyuv", us, lower, upper, part, lines.closed, tol, off_dev, fr, planes, moves, kinds,
                       opts.kerf, 0.0, opts.feed, stats, tuple(warnings), on_planes)


def to_planes(a: np.ndarray, b: np.ndarray, d: np.ndarray, planes) -> np.ndarray:
    """(n, 2, 3): the lines through a and b met with the two planes normal to d at the heights planes."""
    h0, h1 = a @ d, b @ d
    return np.stack([a + ((h - h0) / (h1 - h0))[:, None] * (b - a) for h in planes], axis=1)


def _length(P: np.ndarray) -> float:
    return float(np.linalg.norm(np.diff(P, axis=0), axis=-1).sum())


# ----------------------------------------------------------------------------------------------- flank

def reversed_t(R: Surface) -> Surface:
    """R with its rulings run the other way (t reversed; the normal Su x Sv turns over)."""
    kv = R.knots_v[0] + R.knots_v[-1] - R.knots_v[::-1]
    W = None if R.weights is None else R.weights[:, ::-1].copy()
    return Surface(R.poles[:, ::-1].copy(), R.knots_u, kv, R.degree_u, R.degree_v, W, periodic_u=R.periodic_u)
