"""Lengths as the user reads them (no GUI imports): in the unit FreeCAD's unit schema prefers for the value (the
property editor's own, e.g. µm for a bound of 0.0004 mm), to four significant digits, everywhere the workbench
prints one (the task panels, the colour legend, the report view), so that a figure reads the same wherever it is
shown."""

from __future__ import annotations

import FreeCAD

DIGITS = 4


def magnitude(value) -> float:
    """A length property (a Quantity) or a number as a float in model units (0 for None)."""
    return float(getattr(value, "Value", value) or 0.0)


def length(value, digits: int = DIGITS) -> str:
    """The length value (model units, mm) in the user's preferred unit, e.g. '462.6 nm'; 'no limit' is the
    caller's to say for a 0 that means none."""
    v = magnitude(value)
    factor, unit = unit_of(v)
    return f"{v / factor:.{digits}g} {unit}"


def unit_of(value) -> tuple:
    """(factor, unit) of the user's preferred unit for a length of this size."""
    v = magnitude(value)
    try:
        _, factor, unit = FreeCAD.Units.Quantity(v, FreeCAD.Units.Length).getUserPreferred()
        return float(factor) or 1.0, unit
    except Exception:           # (no unit schema: the model's own unit)
        return 1.0, "mm"


__all__ = ["length", "magnitude", "unit_of", "DIGITS"]
