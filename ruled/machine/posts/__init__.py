"""Posts: how a machine path is written for one controller, as data.

A post is a small TOML file (docs/posts/custom.md): the controller's axis letters, whether the upper guide is
written absolute or relative to the lower, the comment style, the number format, the feed modes it takes, line
numbers, and the blocks of the program as templates (header, homing, origin, start, wire on and off, footer) whose
``{placeholders}`` the writer fills (ruled.machine.program).  The shipped posts are such files, in this folder:
``linuxcnc`` (the default for a wire), ``grbl``, ``iso-wedm`` and ``apt-sync`` for a wire, ``apt`` for flank milling.
A user's own post is a file of the same form, given by its path.  Writing a file and reading it back
(ruled.machine.readback) use the same post, so a round trip is a test of both.
"""

from __future__ import annotations

import os
import re
import string
from dataclasses import dataclass, field
from typing import Any, Optional

from ruled.core.errors import BadInputError

HERE = os.path.dirname(os.path.abspath(__file__))
SHIPPED = ("linuxcnc", "grbl", "iso-wedm", "apt-sync", "apt")
DEFAULT = {"xyuv": "linuxcnc", "flank": "apt"}

# the placeholders a template may name, and what the writer puts there
PLACEHOLDERS = {
    "units": "the units code ([codes] mm or inch)",
    "feed_mode": "the feed mode's code ([codes] g93 or g94)",
    "chord": "the chord tolerance (the path's largest deviation from the ruled surface between its points)",
    "lower_plane": "the lower guide plane's height along the machine axis",
    "upper_plane": "the upper guide plane's height along the machine axis",
    "guide_distance": "the upper plane's height above the lower",
    "position": "the axis words of the path's first point",
    "vertical_position": "the axis words of the wire upright at the first point's lower guide",
    "power": "the wire's power (S)",
    "dwell": "seconds to heat the wire (G4 P)",
    "feed": "the feed, output units per minute",
    "program": "the program number",
}
LISTS = ("header", "home", "origin", "start", "wire_on", "approach", "wire_off", "footer")
GCODE_FIELDS = {"letters": list, "upper": str, "comment": str, "decimals": int, "feed_modes": list, "header": list,
                "start": list, "rapid": str, "cut": str, "footer": list, "codes": dict}
COMMON_FIELDS = {"name": str, "description": str, "machine": str, "language": str, "extension": str,
                 "decimals": int}
COMMENTS = ("()", ";", "$$", "none")


@dataclass(frozen=True)
class Post:
    """One controller's post (see the module); `source` is the file it was read from."""

    name: str
    description: str
    machine: str                            # xyuv | flank
    language: str                           # gcode | apt
    extension: str
    source: str
    decimals: int = 6
    comment: str = "()"
    letters: tuple = ("X", "Y", "U", "V")   # lower X, lower Y, upper X, upper Y
    upper: str = "absolute"                 # absolute | relative (U V: upper minus lower)
    feed_digits: int = 7
    line_numbers: int = 0
    percent: bool = False                   # a % line before and after the program (tape format)
    feed_modes: tuple = ("g94",)
    interpreter: str = ""                   # linuxcnc: checked by LinuxCNC's own interpreter where installed
    feed_along: str = "lower"               # G94's F: along the lower guide's X Y (LinuxCNC, ISO) or all four axes
    rapid: str = "G0"
    cut: str = "G1"
    blocks: dict = field(default_factory=dict)      # header, home, origin, start, wire_on, approach, wire_off, footer
    codes: dict = field(default_factory=dict)
    defaults: dict = field(default_factory=dict)

    def block(self, name: str) -> tuple:
        return tuple(self.blocks.get(name, ()))

    def with_letters(self, letters: Optional[str]) -> "Post":
        """The post with other axis letters (four, e.g. 'XYZA'), checked."""
        if not letters:
            return self
        from dataclasses import replace
        ls = tuple(letters.upper().replace(",", "").replace(" ", ""))
        _check_letters(ls, f"«letters={letters}»")
        return replace(self, letters=ls)


def _check_letters(ls: tuple, where: str) -> None:
    if len(ls) != 4 or len(set(ls)) != 4 or not all(x in "XYZABCUVW" for x in ls):
        raise BadInputError(f"{where}: the axis letters are four different ones of X Y Z A B C U V W (lower X, lower "
                            f"Y, upper X, upper Y), not {' '.join(ls) or 'none'}")


def post_names() -> list:
    """The shipped posts' names (their files are in this folder)."""
    return list(SHIPPED)


def load_post(spec: Optional[str], machine: Optional[str] = "xyuv") -> Post:
    """A shipped post by name, or a user's post by its .toml path; None or 'auto': the default for the machine
    (linuxcnc for a wire, apt for flank milling).  Refuses, in one line each, an unknown name, a file that is
    not TOML, a missing or mistyped field, a template naming an unknown placeholder, and a post for the other
    machine (machine None: a post for either)."""
    if spec is None or spec == "auto":
        spec = DEFAULT[machine or "xyuv"]
    if spec.lower().endswith(".toml") or os.sep in spec:
        path = os.path.abspath(spec)
        if not os.path.isfile(path):
            raise BadInputError(f"«post={spec}»: no such file; give a shipped post ({', '.join(SHIPPED)}) or the path "
                                f"of a post's .toml")
    elif spec in SHIPPED:
        path = os.path.join(HERE, f"{spec}.toml")
    else:
        raise BadInputError(f"unknown post «post={spec}»: use one of {', '.join(SHIPPED)} ('ruled posts' lists them) "
                            f"or the path of your own post's .toml")
    post = read_post(path)
    if machine is not None and post.machine != machine:
        raise BadInputError(f"the post {post.name} writes {_what(post.machine)}, not {_what(machine)}: use "
                            f"«post={DEFAULT[machine]}» or another post for {_what(machine)}")
    return post


def _what(machine: str) -> str:
    return "a wire's XYUV path" if machine == "xyuv" else "a flank-milling tool path"


def read_post(path: str) -> Post:
    """The post in the TOML file at path, every field checked (one BadInputError line naming the file and the
    field)."""
    try:
        import tomllib
    except ImportError:                                      # Python 3.10
        import tomli as tomllib  # type: ignore[no-redef]
    name = os.path.basename(path)
    try:
        with open(path, "rb") as fh:
            data = tomllib.load(fh)
    except OSError as exc:
        raise BadInputError(f"cannot read the post {path}: {exc.strerror}") from None
    except tomllib.TOMLDecodeError as exc:
        raise BadInputError(f"the post {name} is not valid TOML ({exc}); fix it (docs/posts/custom.md)") from None

    def need(key: str, kind: type, table: dict = data, where: str = "") -> Any:
        if key not in table:
            raise BadInputError(f"the post {name} has no field {where}{key}: add it (docs/posts/custom.md says what "
                                f"each field holds)")
        x = table[key]
        if kind is int and isinstance(x, bool) or not isinstance(x, kind):
            raise BadInputError(f"the post {name}'s field {where}{key} must be a {kind.__name__}, not {x!r}")
        return x

    common = {k: need(k, t) for k, t in COMMON_FIELDS.items()}
    if common["machine"] not in ("xyuv", "flank"):
        raise BadInputError(f"the post {name}'s field machine is xyuv or flank, not {common['machine']!r}")
    if common["language"] not in ("gcode", "apt"):
        raise BadInputError(f"the post {name}'s field language is gcode or apt, not {common['language']!r}")
    if not 0 <= common["decimals"] <= 9:
        raise BadInputError(f"the post {name}'s field decimals is from 0 to 9, not {common['decimals']}")
    kw: dict = dict(common, source=path, comment=data.get("comment", "$$" if common["language"] == "apt" else "()"))
    if kw["comment"] not in COMMENTS:
        raise BadInputError(f"the post {name}'s field comment is one of {', '.join(COMMENTS)}, not {kw['comment']!r}")
    kw["defaults"] = dict(data.get("defaults", {}))
    if common["language"] == "gcode":
        if common["machine"] != "xyuv":
            raise BadInputError(f"the post {name}: G-code posts are for a wire (machine = \"xyuv\"); flank milling "
                                f"is written as APT (language = \"apt\")")
        g = {k: need(k, t) for k, t in GCODE_FIELDS.items()}
        letters = tuple(str(x).upper() for x in g["letters"])
        _check_letters(letters, f"the post {name}'s field letters")
        if g["upper"] not in ("absolute", "relative"):
            raise BadInputError(f"the post {name}'s field upper is absolute or relative, not {g['upper']!r}")
        modes = tuple(str(m).lower() for m in g["feed_modes"])
        if not modes or any(m not in ("g93", "g94") for m in modes):
            raise BadInputError(f"the post {name}'s field feed_modes lists g93 and/or g94, not {g['feed_modes']!r}")
        codes = {str(k): str(v) for k, v in g["codes"].items()}
        for key in ("mm", "inch", *modes):
            need(key, str, codes, "codes.")
        blocks = {}
        for key in LISTS:
            lines = data.get(key, [])
            if not isinstance(lines, list) or not all(isinstance(x, str) for x in lines):
                raise BadInputError(f"the post {name}'s field {key} must be a list of lines, not {lines!r}")
            for line in lines:
                _check_template(line, name, key)
            blocks[key] = tuple(lines)
        for key in ("feed_digits", "line_numbers"):
            if key in data and (isinstance(data[key], bool) or not isinstance(data[key], int) or data[key] < 0):
                raise BadInputError(f"the post {name}'s field {key} must be a whole number >= 0, not {data[key]!r}")
        along = str(data.get("feed_along", "lower"))
        if along not in ("lower", "all"):
            raise BadInputError(f"the post {name}'s field feed_along is lower or all, not {along!r}")
        kw.update(letters=letters, upper=g["upper"], feed_modes=modes, rapid=g["rapid"], cut=g["cut"], feed_along=along,
                  blocks=blocks, codes=codes, feed_digits=int(data.get("feed_digits", 7)),
                  line_numbers=int(data.get("line_numbers", 0)), percent=bool(data.get("percent", False)),
                  interpreter=str(data.get("interpreter", "")))
    return Post(**kw)


def _check_template(line: str, name: str, key: str) -> None:
    try:
        fields = [f for _, f, _, _ in string.Formatter().parse(line) if f is not None]
    except ValueError as exc:
        raise BadInputError(f"the post {name}'s {key} line {line!r} is not a template ({exc}): write braces as "
                            f"{{{{ and }}}}") from None
    for f in fields:
        if f not in PLACEHOLDERS:
            raise BadInputError(f"the post {name}'s {key} line {line!r} names {{{f}}}, which Ruled does not fill "
                                f"(it fills {', '.join('{' + k + '}' for k in PLACEHOLDERS)})")


def template_pattern(line: str) -> "re.Pattern":
    """A regular expression that matches the template's lines as written, a number for each numeric placeholder
    (a named group), anything for the others: the reader takes the setup's values back from the file."""
    out = []
    for text, f, _, _ in string.Formatter().parse(line):
        words = text.split()
        out.append(r"\s*" + r"\s*".join(re.escape(c) for c in words) + (r"\s*" if words else ""))
        if f is not None:
            out.append(rf"(?P<{f}>[-+]?\d*\.?\d+(?:[eE][-+]?\d+)?)" if f in NUMERIC else r".*?")
    return re.compile("^" + "".join(out) + r"\s*$", re.IGNORECASE)


NUMERIC = {"chord", "lower_plane", "upper_plane", "guide_distance", "power", "dwell", "feed", "program"}


__all__ = ["Post", "load_post", "read_post", "post_names", "template_pattern", "SHIPPED", "DEFAULT", "PLACEHOLDERS"]
