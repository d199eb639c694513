"""Errors raised by Ruled.

Every error a user can cause is a :class:`RuledError` whose message is one line
that names the problem and says what to do.  The command line maps every
RuledError to exit code 2; the FreeCAD workbench shows it on the object.
"""

from __future__ import annotations


class RuledError(Exception):
    """Base class of every error Ruled raises on purpose."""

    kind = "error"

    def __init__(self, message: str):
        super().__init__(" ".join(str(message).split()))


class BadInputError(RuledError):
    """The input file, face or option is unusable."""

    kind = "bad input"


class DegenerateFaceError(BadInputError):
    """The face has a collapsed boundary or no area."""

    kind = "degenerate face"


class ToleranceError(BadInputError):
    """The input cannot be met within the requested tolerance (a larger one may, or may not, do);
    creases_help: keeping creases (--allow-creases) would accept the result instead."""

    kind = "not within tolerance"

    def __init__(self, message: str, creases_help: bool = False):
        super().__init__(message)
        self.creases_help = creases_help


class InfeasibleError(RuledError):
    """No solution satisfies the requested constraint."""

    kind = "infeasible"


class TooBigError(RuledError):
    """The requested work would not fit in memory."""

    kind = "too big"


class CancelledError(RuledError):
    """The user interrupted the work."""

    kind = "cancelled"


def positive(name: str, value, what: str = "a distance in model units", zero_ok: bool = False) -> float:
    """value as a float, or the one wording every command uses for a bad size:
    '<name> must be a positive finite number (<what>), not <value>' ('zero or a positive ...' where
    zero is allowed)."""
    import math
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise BadInputError(f"{name} must be a number ({what}), not {value!r}") from None
    if not (math.isfinite(x) and (x > 0 or (zero_ok and x == 0))):
        raise BadInputError(f"{name} must be {'zero or ' if zero_ok else ''}a positive finite number ({what}), "
                            f"not {x:g}")
    return x


def whole(name: str, value, lo: float, hi: float, what: str) -> int:
    """value as an int in [lo, hi], or the one wording every option uses for a count:
    '<name> <value> <what>' (booleans and fractions are not counts)."""
    import numbers
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or not lo <= value <= hi:
        raise BadInputError(f"{name} {value!r} {what}")
    return int(value)
