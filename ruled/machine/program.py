"""A wire's synchronized path written as a controller's G-code, by its post (ruled.machine.posts).

The program: Ruled's comment lines (what the file is, and machine-readable lines, ``ruled ... planes= frame
e1= ...``, from which ``ruled replay`` puts the wire back in the part's space), the post's header (units,
absolute coordinates, blending, the guide planes, the feed mode), optionally homing and an origin (G92: the
wire stands at the first point), the move to the first point, the wire switched on (a hot wire's power and
dwell; a wire EDM's thread and flush), the approach (a wire EDM's tilt from upright to the first line), one move
per synchronized pair with every axis word, the wire off, the footer.

Feeds: G94 writes the feed asked (units per minute) on every move: LinuxCNC applies it to X Y (Z) only, so on
a tapered cut the upper guide runs faster or slower.  G93 (inverse time) writes each move's F as the inverse of
its time in minutes, the time being the longer guide's length over the feed asked: the faster guide runs at
that speed, the other slower, both arriving together.

Wire compensation (G41/G42 D, a wire EDM's): the path is the uncompensated one (no kerf in it) and the
controller offsets the wire by its D register; G41 or G42 is the side the path's lead-in comes from (the wire's
side: left or right of the direction of travel), switched on with the lead-in and off (G40) with the lead-out.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional

import numpy as np

from ruled.core.errors import BadInputError, positive
from ruled.machine.posts import Post, load_post

UNITS = {"mm": 1.0, "inch": 1.0 / 25.4}     # output unit -> its coordinates per model unit (mm)


def scale(units: str) -> float:
    if units not in UNITS:
        raise BadInputError(f"unknown output units {units!r}: use mm or inch")
    return UNITS[units]


@dataclass(frozen=True)
class PostSettings:
    """How a post writes this file: the feed mode (None: the post's first), a hot wire's power S and dwell
    (seconds; None: the post's default, and no wire block without a power unless the post always writes it),
    other axis letters (e.g. 'XYZA'), homing, an origin by G92 (None: the post's default), wire compensation by
    a D register (a number: G41/G42 D with the uncompensated path), the program number, and a flank tool's
    corner radius (APT's CUTTER)."""

    post: Optional[str] = None
    feed_mode: Optional[str] = None
    power: Optional[float] = None
    dwell: Optional[float] = None
    letters: Optional[str] = None
    home: bool = False
    origin: Optional[bool] = None
    compensation: Optional[int] = None
    program: Optional[int] = None
    corner_radius: float = 0.0

    def __post_init__(self):
        if self.feed_mode is not None and str(self.feed_mode).lower() not in ("g93", "g94"):
            raise BadInputError(f"«feed_mode={self.feed_mode}»: use g93 (inverse time) or g94 (units per minute)")
        if self.power is not None:
            positive("power", self.power, "the wire's power, S")
        if self.dwell is not None:
            positive("dwell", self.dwell, "seconds", zero_ok=True)
        if self.compensation is not None and (isinstance(self.compensation, bool) or
                                              not isinstance(self.compensation, int) or self.compensation < 0):
            raise BadInputError(f"«compensation={self.compensation}»: give the controller's D register, a whole "
                                f"number")
        positive("corner_radius", self.corner_radius, zero_ok=True)

    def resolved(self, machine: str) -> tuple["Post", "PostSettings"]:
        """(the post, these settings with the post's defaults filled in), checked against each other."""
        from dataclasses import replace
        post = load_post(self.post, machine).with_letters(self.letters)
        d = post.defaults
        s = replace(self, feed_mode=(self.feed_mode or (post.feed_modes[0] if post.language == "gcode" else "g94"))
                    .lower(),
                    power=self.power if self.power is not None else d.get("power"),
                    dwell=self.dwell if self.dwell is not None else float(d.get("dwell", 0.0)),
                    origin=self.origin if self.origin is not None else bool(d.get("origin", False)),
                    program=self.program if self.program is not None else int(d.get("program", 1000)))
        if post.language == "gcode" and s.feed_mode not in post.feed_modes:
            raise BadInputError(f"the post {post.name} takes {' or '.join(post.feed_modes)} feeds, not "
                                f"«feed_mode={s.feed_mode}»: leave it out, or choose another post")
        if s.compensation is not None and not {"left", "right", "cancel"} <= set(post.codes):
            raise BadInputError(f"the post {post.name} has no wire compensation codes ([codes] left, right, cancel): "
                                f"leave «compensation» out (Ruled offsets the wire by «kerf») or use «post=iso-wedm»")
        if s.home and not post.block("home"):
            raise BadInputError(f"the post {post.name} has no homing block: leave «home» out")
        return post, s


def num(x: float, decimals: int) -> str:
    """x with `decimals` digits after the point, never '-0.000'."""
    s = f"{x:.{decimals}f}"
    return s[1:] if s.startswith("-") and not s.strip("-0.") else s


def fixed(x: float, decimals: int) -> str:
    """x to `decimals` digits after the point, its trailing zeros dropped (round-off below them: 0)."""
    s = num(x, decimals)
    return s.rstrip("0").rstrip(".") if "." in s else s


def sig(x: float, digits: int) -> str:
    """x to `digits` significant digits, in fixed notation (G-code has no exponents), trailing zeros dropped."""
    if x == 0 or not math.isfinite(x):
        return "0"
    d = max(0, digits - 1 - int(math.floor(math.log10(abs(x)))))
    s = f"{x:.{d}f}"
    return s.rstrip("0").rstrip(".") if "." in s else s


def comment_text(text: str, style: str) -> str:
    """A comment in the post's style: '(text)' with no parenthesis inside it (RS274/NGC forbids nesting; no style
    gets one, for the senders that read them), or '; text'; '' when the post writes none."""
    text = " ".join(str(text).split())[:MAX_COMMENT].replace("(", "[").replace(")", "]")
    if style == "()":
        return "(" + text + ")"
    if style == "none":
        return ""
    return f"{style} {text}"


def metadata(path, post: Post, units: str, compensation: Optional[int], side: Optional[str] = None,
             approach: int = 0) -> list:
    """The machine-readable comments: where the file's coordinates are in the part's space (``ruled replay`` reads
    them back): the machine frame (X = p . e1, Y = p . e2, heights p . axis), the planes, the kerf, the side the
    wire runs on (+1: the side the faces' normals point to, off the material), how many moves lead the wire to
    the path and away from it, in model units (mm); three lines, each well within LinuxCNC's 255 characters."""
    from ruled import __version__
    fr, (h0, h1) = path.frame, path.planes
    kinds = list(path.kinds)
    leads = f"{kinds.count('lead-in') + approach},{kinds.count('lead-out')}"

    def vec(v, d=12):       # (fixed digits: the unit vectors to 1e-12, the heights to 1e-6 mm as the moves)
        return ",".join(fixed(x, d) for x in v)
    return [f"ruled {__version__} post={post.name} machine=xyuv units={units} planes={vec((h0, h1), 6)} "
            f"kerf={vec([path.radius], 9)} side={wire_side(side):+d} leads={leads} "
            f"compensation={'none' if compensation is None else compensation} closed={int(path.closed)}",
            f"ruled frame e1={vec(fr.e1)} e2={vec(fr.e2)}", f"ruled frame axis={vec(fr.axis)}"]


def wire_side(side: Optional[str]) -> int:
    """+1 where the wire runs on the side of the faces' normals (a face's outside, a wall's side off the
    material), -1 on the other, from the side as the reports word it."""
    return -1 if side and (side == "inside" or "in the material" in side) else 1


MAX_COMMENT = 240       # characters of a comment line (LinuxCNC reads lines of up to 255)


def axis_words(post: Post, row, decimals: int) -> str:
    """The axis words of a move (X, Y of the lower guide, X, Y of the upper) in the post's letters, the upper
    relative to the lower where the post says so."""
    lx, ly, ux, uy = (float(v) for v in row)
    if post.upper == "relative":
        ux, uy = ux - lx, uy - ly
    return " ".join(f"{k}{num(v, decimals)}" for k, v in zip(post.letters, (lx, ly, ux, uy)))


def move_times(moves: np.ndarray, feed: float) -> np.ndarray:
    """(M - 1,) minutes of each move at `feed` (units per minute) along its longer guide."""
    d = np.diff(moves, axis=0)
    return np.maximum(np.linalg.norm(d[:, :2], axis=1), np.linalg.norm(d[:, 2:], axis=1)) / feed


def gcode_lines(path, post: Post, settings: PostSettings, units: str = "mm", side: Optional[str] = None,
                title: str = "") -> list:
    """The program's lines (see the module) of an XYUV path; settings resolved already."""
    if path.mode != "xyuv":
        raise BadInputError("G-code is written for XYUV contours; flank paths are written as CL data (.apt)")
    k = scale(units)
    dec = post.decimals + (1 if units == "inch" else 0)
    moves = path.moves * k
    kinds = list(path.kinds)
    (h0, h1), fr = path.planes, path.frame
    comp = settings.compensation
    if comp is not None and path.radius > 0:
        raise BadInputError("wire compensation («compensation») offsets the wire in the controller: leave «kerf» out "
                            "(the path is written uncompensated)")
    if comp is not None and (not kinds or kinds[0] != "lead-in" or len(moves) < 3):
        raise BadInputError("wire compensation («compensation») is switched on along the lead-in: give the path one "
                            "(«lead» above 0)")
    first = moves[0]
    vertical = np.concatenate([first[:2], first[:2]])
    fields = {"units": post.codes["inch" if units == "inch" else "mm"], "feed_mode": post.codes[settings.feed_mode],
              "chord": num(path.chord_tol * k, dec), "lower_plane": num(h0 * k, dec), "upper_plane": num(h1 * k, dec),
              "guide_distance": num((h1 - h0) * k, dec), "position": axis_words(post, first, dec),
              "vertical_position": axis_words(post, vertical, dec),
              "power": sig(settings.power, 6) if settings.power is not None else "",
              "dwell": sig(settings.dwell or 0.0, 6), "feed": sig(path.feed, post.feed_digits),
              "program": str(settings.program)}
    c = post.comment
    name = title or "ruled wire path"
    lx, ly, ux, uy = post.letters
    rel = "relative to the lower guide" if post.upper == "relative" else "its own position"
    words = [
        f"{name}: ruled XYUV wire path, post {post.name}",
        *metadata(path, post, units, comp, side, sum(ln.startswith(post.cut) for ln in
                                                     _render(post.block("approach"), fields))),
        f"lower guide {lx} {ly} on the plane at height {num(h0 * k, dec)}, upper guide {ux} {uy} ({rel}) at height "
        f"{num(h1 * k, dec)}, along the machine axis {_vec(fr.axis)}",
        f"{lx} = p . {_vec(fr.e1)}, {ly} = p . {_vec(fr.e2)}, in {units}",
        f"{path.stats.get('sync_points', len(moves))} synchronized points, chord tolerance "
        f"{sig(path.chord_tol * k, 6)}, " + (f"wire compensation D{comp} ({_comp_side(moves, post)}), the path "
                                              f"uncompensated" if comp is not None else
                                              f"kerf {sig(path.radius * k, 6)}{side_text(side)}")
        + f", {'closed' if path.closed else 'open'} contour",
        (f"feed G93 inverse time: each move's F is 1 / its minutes, the faster guide at {sig(path.feed, 7)} {units}/min"
         if settings.feed_mode == "g93" else f"feed G94 {sig(path.feed, 7)} {units}/min along {lx} {ly}"),
    ]
    out = [comment_text(w, c) for w in words]
    out += _render(post.block("header"), fields)
    if settings.home:
        out += _render(post.block("home"), fields)
    if settings.origin:
        out += _render(post.block("origin"), fields)
    else:
        out += _render(post.block("start"), fields)
    wire = settings.power is not None or bool(post.defaults.get("wire", False))
    if wire:        # (a line that names the power without one, or a dwell of 0, is left out)
        drop = ({"power"} if settings.power is None else set()) | ({"dwell"} if not settings.dwell else set())
        out += _render(post.block("wire_on"), fields, frozenset(drop))
    out += _render(post.block("approach"), fields)
    # (G93: each move's time from the coordinates as written, which the controller moves between)
    times = move_times(np.round(moves, dec), path.feed) if settings.feed_mode == "g93" else None
    for i in range(1, len(moves)):
        line = f"{post.cut} {axis_words(post, moves[i], dec)}"
        if comp is not None and i == 1:
            line = f"{post.codes[_comp_side(moves, post)]} D{comp} {line}"
        if comp is not None and i == len(moves) - 1 and kinds[-1] == "lead-out":
            line = f"{post.codes['cancel']} {line}"
        f = 1.0 / times[i - 1] if times is not None else path.feed
        out.append(f"{line} F{sig(f, post.feed_digits)}")
    if wire:
        out += _render(post.block("wire_off"), fields)
    out += _render(post.block("footer"), fields)
    return _numbered([ln for ln in out if ln], post)


def _render(block, fields: dict, drop: frozenset = frozenset()) -> list:
    """The block's lines filled in; a line that names a placeholder in drop is left out."""
    import string
    return [line.format(**fields).strip() for line in block
            if not drop & {f for _, f, _, _ in string.Formatter().parse(line) if f}]


def _numbered(lines: list, post: Post) -> list:
    """N words on the code lines (not on comment lines) where the post numbers them; % around the program for a
    tape-format post."""
    if post.line_numbers:
        n, out = 0, []
        for ln in lines:
            if ln.startswith(("(", ";", "%", "O")):
                out.append(ln)
            else:
                n += post.line_numbers
                out.append(f"N{n} {ln}")
        lines = out
    return ["%", *lines, "%"] if post.percent else lines


def _comp_side(moves: np.ndarray, post: Post) -> str:
    """'left' or 'right': the side of the direction of travel the wire runs on (its lead-in comes from there)."""
    t = moves[2, :2] - moves[1, :2]
    m = moves[0, :2] - moves[1, :2]
    return "left" if t[0] * m[1] - t[1] * m[0] > 0 else "right"


def side_text(side: Optional[str]) -> str:
    """The side beside the kerf: ' on the outside' (a face's normal), ' inside the hole (off the material)'."""
    return "" if not side else f" {side}" if " " in side else f" on the {side}"


def _vec(v) -> str:
    """A unit vector to 12 decimals (its round-off below them shown as 0: the same from every door)."""
    return "[" + " ".join(fixed(x, 12) for x in v) + "]"


__all__ = ["PostSettings", "gcode_lines", "num", "sig", "comment_text", "side_text", "metadata", "wire_side",
           "move_times", "scale", "UNITS"]
