"""What a container's array field may hold (numpy only): finite real numbers of a sensible size,
whole degrees, finite positive weights of a moderate range.  Each check answers a bad field with one
BadInputError line that names it (the scalar options' counterparts, positive and whole, are in
ruled.core.errors, which the command line imports before numpy)."""

from __future__ import annotations

import numpy as np

from ruled.core.errors import BadInputError

MAX_COORD = 1e15           # beyond this a coordinate's unit is below double precision's resolution
MAX_WEIGHT_RATIO = 1e6     # a rational surface whose weights span more than this is degenerate


def real_array(a, name: str, limit: float = np.inf) -> np.ndarray:
    """a as finite float64 numbers, or the one-line refusal naming the field: complex values, values
    that are not numbers, NaN or infinite values, or values beyond limit in size."""
    arr = np.asarray(a)
    if np.iscomplexobj(arr):
        raise BadInputError(f"{name} must be real numbers, not complex ones")
    try:
        out = np.ascontiguousarray(arr, dtype=np.float64)
    except (TypeError, ValueError):
        raise BadInputError(f"{name} must be numbers") from None
    if not np.isfinite(out).all():
        raise BadInputError(f"{name} contain NaN or infinite values; repair the model")
    if out.size and np.abs(out).max() > limit:
        raise BadInputError(f"{name} reach {np.abs(out).max():.3g}, beyond {limit:.0e}: double precision cannot "
                            f"resolve the model there; scale the model down or move it nearer the origin")
    return out


def whole_degree(d, name: str) -> int:
    """d as an int from 1 to 25 (OCCT's largest degree), or the refusal naming the field."""
    try:
        ok = float(d) == int(d) and not isinstance(d, (bool, np.bool_))
    except (TypeError, ValueError, OverflowError):
        ok = False
    if not ok or not 1 <= int(d) <= 25:
        raise BadInputError(f"{name} degree must be a whole number from 1 to 25, not {d!r}")
    return int(d)


def positive_weights(w, shape, name: str) -> np.ndarray:
    """w as finite positive float64 weights of the given shape whose largest / smallest ratio is at most
    MAX_WEIGHT_RATIO, or the refusal naming the field."""
    w = real_array(w, f"{name} weights")
    if w.shape != tuple(shape):
        raise BadInputError(f"{name} weights must have shape {tuple(shape)}, got {w.shape}")
    if np.any(w <= 0):
        raise BadInputError(f"{name} weights must be positive (the smallest is {w.min():.3g})")
    ratio = w.max() / w.min()
    if not ratio <= MAX_WEIGHT_RATIO:
        raise BadInputError(f"{name} weights range over a ratio of {ratio:.2g} (more than {MAX_WEIGHT_RATIO:.0e}): "
                            f"the surface is degenerate there and no error can be certified; rebuild it with "
                            f"moderate weights")
    return w
