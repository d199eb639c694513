"""fit_surface: the ruled fit of a surface, by the method its options name (2D-DP, or 4D-DP with the
ruling ends lifted along the normal)."""

from __future__ import annotations

import numpy as np

from ruled.core.nurbs import Surface
from ruled.core.progress import Progress
from ruled.fit.fit2d import FitResult, fit_surface_2d
from ruled.fit.options import FitOptions, Method


def fit_surface(S: Surface, options: FitOptions = FitOptions(), progress: Progress = None,
                cutoff: float = np.inf, compact: bool = True) -> FitResult:
    """Globally optimal ruled fit over the sampled boundary points (2D-DP), refined and certified;
    with method 4d, the ruling ends also lifted along the normal (see fit4d).  cutoff: a bound some
    other candidate already has; a fit sampled at or above it is certified from one side only (its
    bound stays valid, only less tight: it cannot win).  compact=False: a 2D fit's rails are left as they are
    (ruled.fit.fit2d.compacted)."""
    opts = options.checked()
    if opts.method == Method.D4:
        from ruled.fit.fit4d import fit_surface_4d
        return fit_surface_4d(S, opts, progress)
    return fit_surface_2d(S, opts, progress, cutoff, compact)
