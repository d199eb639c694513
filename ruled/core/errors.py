"""Errors raised by Ruled.

Every error a user can cause is a :class:`RuledError` whose message is one line
that names the problem and says what to do.  The engine names the options it
concerns by key (``opt("samples", 40)`` in a message): each front door renders
them in its own terms, ``samples=40`` in Python (``str(exc)``), ``--samples 40``
on the command line (which maps every RuledError to exit code 2), ``Samples = 40``
on a FreeCAD object (its Status).  The fields: ``problem`` (what went wrong),
``remedy`` (what to do, after the first '; '), ``option`` (the first option named)
and ``options`` (all of them), each of the last two a key.
"""

from __future__ import annotations

import re
from typing import Any, Callable, Mapping, Optional

# an option in a message: «key» or «key=value» (value as the message shows it)
_MARK = re.compile(r"«([a-z_0-9]+)(?:=([^»]*))?»")

# the Python keywords of the options whose key is not the keyword itself, and the remedies that name a call
PYTHON_NAMES = {"lift_step": "step", "arc_step": "step",
                "fit_first": "fit a ruled surface to it first (fit=True)",
                "keep_creases": "pass allow_creases=True to keep the creases", "taper": "taper_deg",
                "split_elevations": "levels", "fit_help": "help(ruled.FitOptions)",
                "edges_listing": "the edge indices 'ruled faces INPUT --edges' lists",
                "partition": "ruled.partition(surface, tol=T)",
                "walls_listing": "pick the ring of faces between the bottom and the top contour (ruled.cq.fit_wall "
                                 "finds it in a part)",
                "one_face": "ruled.cq.fit_face"}


def opt(key: str, value: Any = None) -> str:
    """An option (and its value) in an engine message, for each front door to name in its own terms."""
    return f"«{key}»" if value is None else f"«{key}={value}»"


def render(text: str, name: Callable[[str, Optional[str]], str]) -> str:
    """text with each option mark replaced by name(key, value or None)."""
    return _MARK.sub(lambda m: name(m.group(1), m.group(2)), text)


def names_from(table: Mapping[str, str], default: Callable[[str], str], sep: str = " ",
               flag_values: tuple = ()) -> Callable[[str, Optional[str]], str]:
    """A front door's namer: its name of each key (table, else default(key)) and 'name<sep>value';
    a value in flag_values (a switch's 'True') shows the name alone."""
    def name(key: str, value: Optional[str]) -> str:
        n = table.get(key) or default(key)
        return n if value is None or value in flag_values else f"{n}{sep}{value}"
    return name


# the Python door's namer: the keyword, and keyword=value
python_name = names_from(PYTHON_NAMES, str, "=")


class Text(str):
    """An engine message that is not an error (a warning, a note) naming options by key: as a str it reads in
    Python's terms; a front door renders it with in_terms(text, its namer)."""

    template: str

    def __new__(cls, template: str) -> "Text":
        t = " ".join(str(template).split())
        obj = super().__new__(cls, render(t, python_name))
        obj.template = t
        return obj


def in_terms(message: Any, name: Callable[[str, Optional[str]], str]) -> str:
    """An engine error (RuledError), Text or plain str in a front door's terms."""
    return render(getattr(message, "template", str(message)), name)


class RuledError(Exception):
    """Base class of every error Ruled raises on purpose."""

    kind = "error"

    def __init__(self, message: str):
        self.template = " ".join(str(message).split())
        super().__init__(render(self.template, python_name))

    @property
    def options(self) -> tuple:
        """The keys of the options the message names, in order."""
        return tuple(dict.fromkeys(m.group(1) for m in _MARK.finditer(self.template)))

    @property
    def option(self) -> Optional[str]:
        """The key of the option the error concerns first (None: no option)."""
        return self.options[0] if self.options else None

    def _parts(self) -> tuple:
        head, sep, tail = self.template.partition("; ")
        return head, tail

    @property
    def problem(self) -> str:
        return render(self._parts()[0], python_name)

    @property
    def remedy(self) -> str:
        return render(self._parts()[1], python_name)

    def in_terms(self, name: Callable[[str, Optional[str]], str]) -> str:
        """The message with its options named by a front door (see names_from)."""
        return render(self.template, name)


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


class FiguresError(RuledError):
    """A result whose own figures contradict each other (its measured distance above its certified bound):
    never returned."""

    kind = "figures disagree"


class TimeLimitError(RuledError):
    """The work ran past the time limit the user gave it."""

    kind = "time limit"


class CancelledError(RuledError):
    """The user interrupted the work."""

    kind = "cancelled"


def parse_faces(spec: str, option: str = "--faces", words: tuple = ("all", "bspline", "ruled-candidates")) -> object:
    """One of words (default 'all', 'bspline', 'ruled-candidates'), or indices 'K,L-M' (a sorted list)."""
    if spec in words:
        return spec
    out: set = set()
    try:
        for part in spec.split(","):
            a, _, b = part.strip().partition("-")
            lo, hi = int(a), int(b) if b else int(a)
            if lo < 0 or hi < lo:
                raise ValueError
            out.update(range(lo, hi + 1))
    except ValueError:
        raise BadInputError(f"{option} {spec!r}: use {', '.join(words)} or indices like 0,3-7") from None
    return sorted(out)


def positive(name: str, value: Any, what: str = "a distance in model units", zero_ok: bool = False) -> float:
    """value as a float, or the one wording every command uses for a bad size:
    '<name> must be a positive finite number (<what>), not <value>' ('zero or a positive ...' where
    zero is allowed).  name: the option's key."""
    import math
    name = opt(name)
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise BadInputError(f"{name} must be a number ({what}), not {value!r}") from None
    if not (math.isfinite(x) and (x > 0 or (zero_ok and x == 0))):
        raise BadInputError(f"{name} must be {'zero or ' if zero_ok else ''}a positive finite number ({what}), "
                            f"not {x:g}")
    return x


def whole(name: str, value: Any, lo: float, hi: float, what: str) -> int:
    """value as an int in [lo, hi], or the one wording every option uses for a count:
    '<name> <value> <what>' (booleans and fractions are not counts).  name: the option's key."""
    import numbers
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or not lo <= int(value) <= hi:
        raise BadInputError(f"{opt(name, repr(value))} {what}")
    return int(value)
