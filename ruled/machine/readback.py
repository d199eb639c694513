"""Machine files read back: a post's G-code or APT file as the moves a controller makes (``ruled replay``).

The project's own reader follows the post the file was written for (ruled.machine.posts): its axis letters, its
comment style, the upper guide absolute or relative to the lower, G90 absolute coordinates, G20/G21, G92 origins,
G93/G94 feeds, line numbers and the tape's %; the setup's values (the planes, the chord tolerance) are read back
by matching the post's header templates.  APT: GOTO, RAPID, SET/UPPER/LOWER, SYNCTR, CUTTER, UNITS.  Every
coordinate is returned in mm.  ruled.machine.linuxcnc reads a linuxcnc file through LinuxCNC's own interpreter
instead, where it is installed.
"""

from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from ruled.core.errors import BadInputError
from ruled.machine.posts import SHIPPED, Post, load_post, template_pattern

INCH = 25.4
_WORD = re.compile(r"([A-Z])\s*([-+]?(?:\d+\.?\d*|\.\d+))")
AXES = "XYZABCUVW"


@dataclass(frozen=True)
class ReadProgram:
    """What a machine file makes the machine do.  xyuv: points (M, 4) X, Y of the lower guide and X, Y of the
    upper, absolute, in the machine frame, mm; flank: (M, 6) the tool's tip centre and unit axis, mm.  kinds[i]:
    'start' (where the machine stands: its first position, or a G92 origin), 'rapid' or 'feed' (the move that
    ends at point i); minutes[i]: that move's time (nan where unknown: rapids, the start); lines[i]: its line
    number in the file (1-based)."""

    post: str
    machine: str
    units: str
    points: np.ndarray
    kinds: tuple
    minutes: np.ndarray
    lines: tuple
    meta: dict = field(default_factory=dict)          # the file's 'ruled ...' comment
    setup: dict = field(default_factory=dict)         # values read back from the post's header lines (mm)
    comments: tuple = ()
    dwell: float = 0.0                                # seconds of dwell before the first feed move
    power: Optional[float] = None                     # the wire's power (M3 S)
    cutter: Optional[tuple] = None                    # flank: CUTTER/d,r,e,f,a,b,h (mm)
    reader: str = "ruled"                             # ruled | linuxcnc (LinuxCNC's own interpreter)

    @property
    def feed_moves(self) -> np.ndarray:
        """Indices i of the points a feed move ends at (the move from i - 1 to i cuts)."""
        return np.array([i for i, k in enumerate(self.kinds) if k == "feed" and i > 0], dtype=np.int64)


def meta_of(comments) -> dict:
    """The fields of the file's 'ruled key=value ...' comments (ruled.machine.program.metadata; empty when the file
    has none)."""
    out: dict = {}
    for c in comments:
        t = c.strip()
        if t.lower().startswith("ruled ") and "=" in t:
            for tok in t.split()[1:]:
                k, sep, v = tok.partition("=")
                if sep:
                    out.setdefault(k, v)
    return out


def detect_post(filename: str, text: Optional[str] = None) -> Post:
    """The post a file was written for: the one its 'ruled ... post=NAME' comment names (a shipped one), else by
    its contents (APT GOTOs; ';' comments or $H: grbl; % and O: iso-wedm; else linuxcnc)."""
    text = _read(filename) if text is None else text
    head = text[:20000]
    m = re.search(r"ruled \S+ post=(\S+) machine=(\S+)", head)
    if m:
        name = m.group(1).rstrip(")")
        if name in SHIPPED:
            return load_post(name, m.group(2).rstrip(")"))
        raise BadInputError(f"{os.path.basename(filename)} was written by the post {name}, which is not shipped: "
                            f"give its file («post=PATH.toml»)")
    if re.search(r"^\s*GOTO\s*/", head, re.MULTILINE | re.IGNORECASE):
        return load_post("apt-sync" if re.search(r"SET\s*/\s*UPPER", head, re.IGNORECASE) else "apt",
                         "xyuv" if re.search(r"SET\s*/\s*UPPER", head, re.IGNORECASE) else "flank")
    if re.search(r"^\s*;|^\s*\$H", head, re.MULTILINE):
        return load_post("grbl")
    if re.search(r"^\s*%|^\s*(N\d+\s*)?O\d+", head, re.MULTILINE):
        return load_post("iso-wedm")
    return load_post("linuxcnc")


def _read(filename: str) -> str:
    try:
        with open(filename, encoding="utf-8", errors="replace") as fh:
            return fh.read()
    except OSError as exc:
        raise BadInputError(f"cannot read {filename}: {exc.strerror}") from None


def read_program(filename: str, post: Optional[Post] = None) -> ReadProgram:
    """The file read by the project's own reader for its post (detect_post when none is given)."""
    text = _read(filename)
    post = post or detect_post(filename, text)
    name = os.path.basename(filename)
    if post.language == "apt":
        return _read_apt(text, post, name)
    return _read_gcode(text, post, name)


# --------------------------------------------------------------------------------------------------- G-code

def _strip_comments(line: str, style: str, where: str) -> tuple:
    """(the code, [comment texts]) of a G-code line; a nested or unclosed '(' refused as LinuxCNC refuses it."""
    comments = []
    if ";" in line and style != "()":
        line, _, c = line.partition(";")
        comments.append(c.strip())
    out: list = []
    cur: list = []
    depth = 0
    for ch in line:
        if ch == "(":
            if depth:
                raise BadInputError(f"{where}: a comment inside a comment (RS274/NGC forbids it)")
            depth, cur = 1, []
        elif ch == ")" and depth:
            depth = 0
            comments.append("".join(cur).strip())
        elif depth:
            cur.append(ch)
        else:
            out.append(ch)
    if depth:
        raise BadInputError(f"{where}: a comment that never closes")
    code = "".join(out)
    if style == "()" and ";" in code:           # (LinuxCNC also takes ';' to the line's end)
        code, _, c = code.partition(";")
        comments.append(c.strip())
    return code.strip(), comments


def _read_gcode(text: str, post: Post, name: str) -> ReadProgram:
    letters = post.letters
    idx = {c: i for i, c in enumerate(letters)}
    templates = [template_pattern(t) for b in ("header", "origin", "start") for t in post.block(b)]
    pos = [math.nan] * 4                          # modal, as written (the upper relative where the post says so)
    motion, mode, scale = None, post.feed_modes[0], 1.0
    feed = math.nan
    pts: list = []
    kinds: list = []
    mins: list = []
    lines: list = []
    comments: list = []
    setup: dict = {}
    dwell, power, cutting = 0.0, None, False
    for no, raw in enumerate(text.splitlines(), 1):
        where = f"{name} line {no}"
        code, cs = _strip_comments(raw, post.comment, where)
        comments += cs
        if not cutting:         # (the header's lines, comments included: AXIS's plane comments)
            bare = re.sub(r"^\s*N\d+\s*", "", raw, flags=re.IGNORECASE)
            for pat in templates:
                m = pat.match(bare)
                if m:
                    setup.update({k: float(v) for k, v in m.groupdict().items()})
        if not code or code == "%" or code.startswith("$"):
            continue
        code = re.sub(r"^N\d+\s*", "", code, flags=re.IGNORECASE)
        if re.match(r"^O\d+\s*$", code, re.IGNORECASE):
            continue
        words = _WORD.findall(code.upper())
        if "".join(a + b for a, b in words).replace(" ", "") != re.sub(r"\s+", "", code.upper()):
            raise BadInputError(f"{where}: cannot read {code!r} (not G-code words of the post {post.name})")
        gs = [float(v) for a, v in words if a == "G"]
        ms = [float(v) for a, v in words if a == "M"]
        vals = {a: float(v) for a, v in words if a not in "GM"}
        for g in gs:
            if g in (20.0, 21.0):
                scale = INCH if g == 20.0 else 1.0
            elif g in (93.0, 94.0):
                mode = f"g{int(g)}"
            elif g == 91.0:
                raise BadInputError(f"{where}: G91 (incremental coordinates): Ruled's posts write absolute ones")
            elif g in (2.0, 3.0):
                raise BadInputError(f"{where}: an arc (G{int(g)}): Ruled's wire paths are straight moves")
            elif g in (0.0, 1.0):
                motion = int(g)
        if 3.0 in ms and "S" in vals:
            power = vals["S"]
        if 4.0 in gs and "P" in vals:
            dwell += vals["P"] if not cutting else 0.0
        if "F" in vals:
            feed = vals["F"]
        moved = {a: v for a, v in vals.items() if a in AXES}
        stray = [a for a in moved if a not in idx]
        if stray:
            raise BadInputError(f"{where}: the file moves the axis {stray[0]}, which the post {post.name} does not "
                                f"have (its letters {' '.join(letters)}): a file of another post? («post»)")
        if not moved:
            continue
        for a, v in moved.items():
            pos[idx[a]] = v * scale
        if 92.0 in gs:
            kind = "start"
        elif motion is None:
            raise BadInputError(f"{where}: axis words with no motion (G0 or G1) before them")
        else:
            kind = "rapid" if motion == 0 else "feed"
        if any(math.isnan(p) for p in pos):
            raise BadInputError(f"{where}: the first move does not give every axis ({' '.join(letters)})")
        p = np.array(pos, float)
        if post.upper == "relative":
            p[2:] += p[:2]
        if not pts:
            kind = "start"
        t = math.nan
        if kind == "feed" and pts:
            t = _minutes(pts[-1], p, feed * (scale if mode == "g94" else 1.0), mode, post)
            cutting = True
        pts.append(p)
        kinds.append(kind)
        mins.append(t)
        lines.append(no)
    if not pts:
        raise BadInputError(f"{name}: no moves in the file")
    setup = {k: v * (scale if k not in ("power", "dwell", "program") else 1.0) for k, v in setup.items()}
    return ReadProgram(post.name, "xyuv", "inch" if scale != 1.0 else "mm", np.array(pts), tuple(kinds),
                       np.array(mins), tuple(lines), meta_of(comments), setup, tuple(comments), dwell, power)


def _minutes(a: np.ndarray, b: np.ndarray, f: float, mode: str, post: Post) -> float:
    """A feed move's minutes: G93's F is 1 / minutes; G94's F is per minute along the lower guide (LinuxCNC's and
    the ISO controls' X Y), or along all four axes together where the post says so (feed_along: GRBL's)."""
    if not f > 0:
        return math.nan
    if mode == "g93":
        return 1.0 / f
    d = b - a
    length = float(np.linalg.norm(d)) if post.feed_along == "all" else float(np.linalg.norm(d[:2]) or
                                                                             np.linalg.norm(d[2:]))
    return length / f


# ------------------------------------------------------------------------------------------------------ APT

def _apt_statements(text: str):
    """(line number, major word, [arguments]) of an APT file, '$$' comments apart, '$' continuations joined."""
    buf, start = "", 0
    for no, raw in enumerate(text.splitlines(), 1):
        line = raw.rstrip()
        if line.lstrip().startswith("$$"):
            yield no, "$$", [line.lstrip()[2:].strip()]
            continue
        if "$$" in line:
            line = line[:line.index("$$")].rstrip()
        if not buf:
            start = no
        if line.endswith("$"):
            buf += line[:-1]
            continue
        buf += line
        stmt, buf = buf.strip(), ""
        if not stmt:
            continue
        major, _, rest = stmt.partition("/")
        yield start, major.strip().upper(), [a.strip() for a in rest.split(",")] if rest else []


def _read_apt(text: str, post: Post, name: str) -> ReadProgram:
    scale, planes, cutter = 1.0, None, None
    pts: list = []
    kinds: list = []
    lines: list = []
    comments: list = []
    rapid, feed = False, math.nan
    for no, major, args in _apt_statements(text):
        where = f"{name} line {no}"
        try:
            if major == "$$":
                comments.append(args[0])
            elif major == "UNITS":
                scale = INCH if args and args[0].upper().startswith("INCH") else 1.0
            elif major == "SET" and len(args) >= 4 and args[0].upper() == "UPPER" and args[2].upper() == "LOWER":
                planes = (float(args[3]) * scale, float(args[1]) * scale)
            elif major == "CUTTER":
                cutter = tuple(float(a) * (scale if i in (0, 1, 2, 3, 6) else 1.0) for i, a in enumerate(args))
            elif major == "FEDRAT":
                feed = float(args[0]) * scale
            elif major == "RAPID":
                rapid = True
            elif major == "GOTO":
                v = [float(a) for a in args]
                if len(v) != 6:
                    raise BadInputError(f"{where}: GOTO/{','.join(args)}: Ruled reads GOTO/x,y,z,i,j,k")
                p = np.array(v[:3]) * scale
                a = np.array(v[3:]) / max(np.linalg.norm(v[3:]), 1e-300)
                pts.append(np.concatenate([p, a]))
                kinds.append("start" if not kinds else "rapid" if rapid else "feed")
                lines.append(no)
                rapid = False
        except ValueError:
            raise BadInputError(f"{where}: cannot read {major}/{','.join(args)} (not numbers where APT has "
                                f"them)") from None
    if not pts:
        raise BadInputError(f"{name}: no GOTO in the file")
    P = np.array(pts)
    if post.machine == "xyuv":
        if planes is None:
            raise BadInputError(f"{name}: no SET/UPPER,h,LOWER,h: the guide planes are not in the file")
        h0, h1 = planes
        ends = P[:, :2] + ((h1 - P[:, 2]) / P[:, 5])[:, None] * P[:, 3:5]
        P = np.column_stack([P[:, :2], ends])
    elif cutter is None or len(cutter) != 7:
        raise BadInputError(f"{name}: no 7-parameter CUTTER/d,r,e,f,a,b,h: the tool is not in the file")
    mins = np.full(len(P), math.nan)
    for i in range(1, len(P)):
        if kinds[i] == "feed" and feed > 0:         # (FEDRAT along the longer guide, or the tool's tip)
            d = P[i] - P[i - 1]
            length = max(np.linalg.norm(d[:2]), np.linalg.norm(d[2:4])) if post.machine == "xyuv" else \
                np.linalg.norm(d[:3])
            mins[i] = float(length) / feed
    setup = {} if planes is None else {"lower_plane": planes[0], "upper_plane": planes[1]}
    return ReadProgram(post.name, post.machine, "inch" if scale != 1.0 else "mm", P, tuple(kinds), mins,
                       tuple(lines), meta_of(comments), setup, tuple(comments), cutter=cutter)


__all__ = ["ReadProgram", "read_program", "detect_post", "meta_of", "INCH"]
