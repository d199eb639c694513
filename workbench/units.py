"""Lengths as the user reads them (no GUI imports): as FreeCAD's property editor prints them (its unit schema's
UserString: the unit it prefers for the value, e.g. nm for a bound of 0.0004 mm, with its Decimals preference),
wherever that carries at least four significant digits, else to four significant digits in that unit; everywhere
the workbench prints one (the task panels, the colour legend, the report view), so that a figure reads the same
wherever it is shown."""

from __future__ import annotations

import math
import re

import FreeCAD

DIGITS = 4


def magnitude(value) -> float:
    """A length property (a Quantity) or a number as a float in model units (0 for None)."""
    return float(getattr(value, "Value", value) or 0.0)


def length(value, digits: int = DIGITS, unit=None) -> str:
    """The length value (model units, mm) in the user's preferred unit: the property editor's own text where it has
    at least digits significant digits ('462.62 nm'), else digits of them ('1.862 µm' where the editor says
    '1.86 µm'); unit: (factor, name) to print it in instead (a legend's values, in its top's unit).  'no limit' is
    the caller's to say for a 0 that means none."""
    v = magnitude(value)
    factor, name = unit or unit_of(v)
    if unit is None and abs(v) >= 1e-9:
        try:
            text = FreeCAD.Units.Quantity(v, FreeCAD.Units.Length).UserString
            if _digits(text.rsplit(" ", 1)[0]) >= digits:
                return text
        except Exception:       # (no unit schema)
            pass
    return f"{v / factor:.{digits}g} {name}"


def unit_of(value) -> tuple:
    """(factor, unit) of the user's preferred unit for a length of this size."""
    v = magnitude(value)
    if 0.0 < abs(v) < 1e-9:          # (below the schema's smallest unit's range: in that unit, as its neighbours)
        v = 1e-9
    try:
        _, factor, unit = FreeCAD.Units.Quantity(v, FreeCAD.Units.Length).getUserPreferred()
        return float(factor) or 1.0, unit
    except Exception:           # (no unit schema: the model's own unit)
        return 1.0, "mm"


_UNITS = r"(?:mm|µm|nm|cm|m|km|in|ft|thou|mil)"      # (a figure already with its unit is left as it is)
_NUMBER = re.compile(r"(?<![\w.])(\d+(?:\.\d*)?(?:[eE][+-]?\d+)?)(?![\w.%])(?! degree| times)(?! ?" + _UNITS + r"\b)")
_LENGTH_WORD = re.compile(r"(?:bound|trimmed|pinned|otherwise|up to) $")


def _digits(figure: str) -> int:
    """Significant digits of a printed figure ('0.0004626': 4; '1,234.56': 6, whatever the separators)."""
    return max(1, len(re.sub(r"\D", "", figure.lower().split("e")[0]).lstrip("0")))


def lengths_in(text: str, shown: dict | None = None) -> str:
    """text (an engine's note, warning or error, its lengths bare numbers in model units) with its lengths printed
    as length() prints them: each figure that is one of the lengths in shown ({the engine's figure, or (low, high)
    of it: the figure the workbench shows for it, e.g. (the fit's bound, the object's): the object's ErrorBound})
    to the digits it was printed with, and each figure right after 'bound', 'trimmed', 'pinned', 'otherwise' or
    'up to'."""
    known = []
    for k, show in (shown or {}).items():
        lo, hi = (min(k), max(k)) if isinstance(k, tuple) else (k, k)
        if lo and lo > 0:
            known.append((float(lo), float(hi), show))

    def one(m) -> str:
        figure = m.group(1)
        v, digits = float(figure), _digits(figure)
        if v > 0 and digits >= 2:
            half = 0.51 * 10 ** (math.floor(math.log10(v)) - digits + 1)
            for lo, hi, show in known:
                if lo - half <= v <= hi + half:
                    return length(show)
        return length(v) if _LENGTH_WORD.search(text[:m.start()]) else figure
    return _NUMBER.sub(one, str(text))


__all__ = ["length", "lengths_in", "magnitude", "unit_of", "DIGITS"]
