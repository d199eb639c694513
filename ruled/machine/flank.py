"""Flank-milling tool paths of a ruled surface, and the entry point of every machine path.

The tool's tip centre lies at one end of each ruling (opts.tip: the t0 end, the t1 end, or auto: the end lower
in z, the tool pointing up to the spindle).  Its axis is, with positions="offset", the ruling offset by the tool
radius along the normal (ruled.machine.paths.Lines: exact on a cylinder or a cone); with positions="envelope"
(the default), that offset moved across the axis so that the tool swept through the path fits the face's
points, its overcut held to the gouge tolerance (ruled.machine.positions).

The gouge tolerance (default: the fit's bound, not below the chord tolerance where that is given, nor below
1e-5 of the part's diagonal) counts the machine's straight moves between CL points: the fitted positions are
held to the tolerance less the chord tolerance, and the chord tolerance, unless given, is at most half the
gouge tolerance (not below a tenth of its usual 1e-4 of the part's diagonal).  No move turns
the tool's axis by more than MAX_TURN degrees."""

from __future__ import annotations

import math
from typing import Optional

import numpy as np

from ruled.core.errors import BadInputError
from ruled.core.nurbs import Surface
from ruled.core.progress import Progress
from ruled.machine.paths import (
    _DENSE,
    Lines,
    MachineOptions,
    MachinePath,
    _check_rulings,
    _chord,
    _length,
    _seed_params,
    curvature_warnings,
    reversed_t,
    side_sign,
    xyuv_path,
)
from ruled.machine.sync import surface_grid, sync_params, tool_between

MAX_TURN = 2.0             # degrees: the largest turn of the tool's axis from one CL point to the next
_POINTS = 40               # the design surface's points per direction when no points of the face are given
FIT_POINTS = 34            # the face's points per direction a host samples for the positions (not the measure's)


def flank_path(R: Surface, opts: MachineOptions, sign: float = 1.0, progress: Progress = None,
               points: Optional[np.ndarray] = None, fit_bound: float = 0.0) -> MachinePath:
    """Tool axes for flank milling R with a cylindrical (or conical) tool on the side `sign` of R's normal (see
    the module); points (N, 3): the face's, for positions="envelope" (none: the offset rulings); fit_bound: the
    fit's certified bound (the default gouge tolerance)."""
    opts = opts.checked()
    tol = _chord(opts, R)
    u0, u1, t0, t1 = R.domain
    ud = np.linspace(u0, u1, _DENSE)
    low_second = float(np.mean(R(ud, np.full(ud.shape, t1))[:, 2] - R(ud, np.full(ud.shape, t0))[:, 2])) < 0
    tip_t1 = opts.tip == "second" or (opts.tip == "auto" and low_second)
    if tip_t1:
        R, sign = reversed_t(R), -sign
    lines = Lines(R, sign, opts.tool_radius, opts.taper_deg)
    _check_rulings(lines, ud)
    a, b, dev = lines.ends(ud)
    off_dev = float(dev.max())
    r, ta = opts.tool_radius, math.tan(math.radians(opts.taper_deg))
    length = np.linalg.norm(b - a, axis=1)
    warnings = curvature_warnings(R, sign, lambda t: r + t * float(length.max()) * ta, "tool radius")

    def offset(u):
        p, q, _ = lines.ends(u)
        return np.stack([p, q], axis=1)

    both = offset
    stats: dict = {}
    if opts.positions == "envelope" and points is not None:
        from ruled.machine.positions import envelope_positions
        # (defaults: the fit's bound, not below the chords the user chose, or a tenth of the default chords)
        gouge = opts.gouge_tol if opts.gouge_tol is not None else \
            max(float(fit_bound), tol if opts.chord_tol is not None else 0.1 * tol)
        if opts.chord_tol is None:
            tol = min(tol, max(0.5 * gouge, 0.1 * tol))
        hold = max(gouge - tol, 0.0)
        grid = sync_params(offset, u0, u1, tol, _seed_params(R, lines), 8 * opts.max_points, None,
                           max_turn=MAX_TURN / 2)
        both, info = envelope_positions(offset, grid, lines.closed, r, opts.taper_deg, points, hold, progress)
        stats["positions"] = {**info, "gouge_tol": gouge, "grid_stations": int(grid.size)}
        fit_over, off_over = (info.get(k, {}).get("overcut", 0.0) for k in ("after", "before"))
        if fit_over > hold * (1.0 + 1e-9) and off_over < fit_over:
            # the envelope could not hold the gouge tolerance and the offset rulings cut less: they are the path
            both = offset
            stats["positions"]["fallback"] = "offset rulings"
            warnings.append(f"the envelope positions overcut the face's points by {fit_over:.3g}, past the gouge "
                            f"tolerance {gouge:.3g} less the chords; the offset rulings overcut {off_over:.3g}: the "
                            f"path follows the offset rulings")
        if tol > gouge:
            warnings.append(f"the chord tolerance {tol:.3g} exceeds the gouge tolerance {gouge:.3g}: the moves "
                            f"between CL points may cut into the face by up to the chord tolerance; lower "
                            f"«chord_tol» to hold the gouge tolerance")
    else:
        stats["positions"] = {"method": "offset rulings (each ruling offset by the tool radius along the normal, "
                                        "the straight line closest to it)"}
    us = sync_params(both, u0, u1, tol, _seed_params(R, lines), opts.max_points, progress, max_turn=MAX_TURN,
                     between=tool_between)
    if us.size < 2:
        raise BadInputError("the tool path is empty: the ruled result has no extent along its rulings")
    E = both(us)
    stats.update({"cl_points": int(us.size), "length_tip": _length(E[:, 0]), "length_top": _length(E[:, 1]),
                  "tool_radius": r, "taper_deg": opts.taper_deg, "envelope_deviation": off_dev, "tip_at_t1": tip_t1})
    return MachinePath("flank", us, E[:, 0], E[:, 1], E, lines.closed, tol, off_dev, None, None, None, (),
                       r, opts.taper_deg, opts.feed, stats, tuple(warnings), both)


def fit_points(measure_samples) -> int:
    """The face's points per direction a host samples for the envelope positions: FIT_POINTS, never the measure's
    own number (the measure then checks points the fit did not see)."""
    return FIT_POINTS + 1 if measure_samples == FIT_POINTS else FIT_POINTS


def machine_path(R: Surface, S: Surface, opts: MachineOptions, side: float = 1.0, progress: Progress = None,
                 points: Optional[np.ndarray] = None, fit_bound: float = 0.0) -> MachinePath:
    """The XYUV contours or flank tool axes (opts.mode) of the ruled surface R fitted to the design surface S,
    on the side `side` of S (+1: its Su x Sv, the outside of a forward face).  Flank: points (N, 3) of the face
    as bounded by its edges for the envelope positions (none: a grid of S), fit_bound the fit's bound."""
    opts = opts.checked()
    if opts.mode == "xyuv":
        return xyuv_path(R, opts, side_sign(R, S, side), progress)
    pts = points if points is not None or opts.positions != "envelope" else surface_grid(S, _POINTS)[1]
    return flank_path(R, opts, side_sign(R, S, side), progress, pts, fit_bound)


__all__ = ["MAX_TURN", "FIT_POINTS", "fit_points", "flank_path", "machine_path"]
