"""A G-code file read by LinuxCNC's own interpreter: Debian's ``linuxcnc-uspace`` and its Python module ``gcode``,
the parser AXIS's preview uses, with a canon that records the moves of the axes a mask chooses (X Y U V for a
foam cutter or a wire EDM).  The module is Debian's Python's (a compiled extension), not the venv's: it runs in
a process of /usr/bin/python3 (or the interpreter RULED_LINUXCNC_PYTHON names), which prints what it read as
JSON.  LinuxCNC's interpreter works in inches inside: its positions come back in mm here."""

from __future__ import annotations

import json
import os
import subprocess
from functools import lru_cache
from typing import Optional

import numpy as np

from ruled.core.errors import BadInputError

AXES = "XYZABCUVW"

# the canon: LinuxCNC's interpreter calls it for every move, feed, dwell and comment (rs274/interpret.py and
# AXIS's glcanon.py are its models); its positions are in inches, in the program's coordinates (offsets apart)
_SCRIPT = r'''
import json, os, sys, tempfile
import gcode

class Canon:
    def __init__(self, mask):
        fd, self.parameter_file = tempfile.mkstemp(suffix=".var")
        os.close(fd)
        self.mask, self.moves, self.comments, self.dwells = mask, [], [], []
        self.line, self.rate, self.inverse = 0, 0.0, False
    def get_axis_mask(self): return self.mask
    def get_external_angular_units(self): return 1.0
    def get_external_length_units(self): return 1.0 / 25.4
    def get_block_delete(self): return False
    def get_tool(self, idx): return (idx,) + (0.0,) * 12 + (0,)
    def change_tool(self, idx): pass
    def next_line(self, st): self.line = st.sequence_number
    def comment(self, s):
        if s.startswith("interpreter: feed mode set to"):
            self.inverse = "inverse time" in s
        else:
            self.comments.append(s)
    def message(self, s): pass
    def check_abort(self): return False
    def set_plane(self, p): pass
    def set_feed_rate(self, f): self.rate = f
    def set_spindle_rate(self, *a): self.spindle = a[-1]
    def set_traverse_rate(self, *a): pass
    def set_g5x_offset(self, *a): pass
    def set_g92_offset(self, *a):
        if not self.moves and self.line > 0:    # (a G92 line, the machine at 0: it stands at minus the offset)
            self.start = [-x for x in a]
    def set_xy_rotation(self, t): pass
    def tool_offset(self, *a): pass
    def user_defined_function(self, *a): pass
    def rigid_tap(self, *a): pass
    def straight_probe(self, *a): pass
    def straight_traverse(self, *p): self.moves.append(["rapid", self.line, list(p), 0.0, False])
    def straight_feed(self, *p): self.moves.append(["feed", self.line, list(p), self.rate, self.inverse])
    def arc_feed(self, *a): self.moves.append(["arc", self.line, [], self.rate, self.inverse])
    def dwell(self, t): self.dwells.append([self.line, t])

canon = Canon(int(sys.argv[2]))
result, seq = gcode.parse(sys.argv[1], canon, "", "")
error = None if result <= gcode.MIN_ERROR else [int(result), int(seq), gcode.strerror(result)]
os.unlink(canon.parameter_file)
print(json.dumps({"error": error, "moves": canon.moves, "start": getattr(canon, "start", None),
                  "comments": canon.comments, "dwells": canon.dwells, "spindle": getattr(canon, "spindle", None)}))
'''


def _python() -> str:
    return os.environ.get("RULED_LINUXCNC_PYTHON", "/usr/bin/python3")


@lru_cache(maxsize=1)
def available() -> bool:
    """Whether LinuxCNC's interpreter (the Python module gcode of Debian's linuxcnc-uspace) can be run here."""
    exe = _python()
    if not os.path.exists(exe):
        return False
    try:
        run = subprocess.run([exe, "-c", "import gcode"], capture_output=True, timeout=60)
    except (OSError, subprocess.SubprocessError):
        return False
    return run.returncode == 0


def mask_of(letters) -> int:
    """The axis mask of the letters (X = 1, Y = 2, Z = 4, ... W = 256)."""
    return sum(1 << AXES.index(c) for c in letters)


def interpret(filename: str, letters=("X", "Y", "U", "V"), timeout: float = 300.0) -> dict:
    """What LinuxCNC's interpreter makes of the file with the letters' axis mask: {"error": None or (code, line,
    text), "moves": [(kind, line, (the letters' positions, mm), feed rate in mm per minute, inverse time)],
    "comments", "dwells": [(line, seconds)], "spindle": the last S}; a G92 origin before the first move is
    a move of kind "origin" first (where the machine stands).  Raises BadInputError when the interpreter
    is not installed or does not finish."""
    if not available():
        raise BadInputError("LinuxCNC's interpreter is not installed (Debian: apt-get install linuxcnc-uspace)")
    cols = [AXES.index(c) for c in letters]
    try:
        run = subprocess.run([_python(), "-c", _SCRIPT, os.path.abspath(filename), str(mask_of(letters))],
                             capture_output=True, text=True, timeout=timeout, cwd=os.path.dirname(
                                 os.path.abspath(filename)) or None)
    except subprocess.TimeoutExpired:
        raise BadInputError(f"LinuxCNC's interpreter did not finish reading {filename} in {timeout:g} s") from None
    if run.returncode != 0 or not run.stdout.strip():
        tail = (run.stderr.strip().splitlines() or ["no output"])[-1]
        raise BadInputError(f"LinuxCNC's interpreter failed on {os.path.basename(filename)}: {tail}")
    out = json.loads(run.stdout.strip().splitlines()[-1])
    out["moves"] = [(k, ln, tuple(25.4 * p[c] for c in cols) if p else (), 25.4 * rate, inv)
                    for k, ln, p, rate, inv in out["moves"]]
    if out["start"] is not None:        # a G92 origin before the first move: where the machine stands
        out["moves"].insert(0, ("origin", 0, tuple(25.4 * out["start"][c] for c in cols), 0.0, False))
    return out


def check(filename: str, letters=("X", "Y", "U", "V")) -> Optional[dict]:
    """The file checked by LinuxCNC's interpreter where it is installed: None where it is not; else
    {"moves": the count of moves, "error": None or "line N: text"}."""
    if not available():
        return None
    out = interpret(filename, letters)
    err = out["error"]
    return {"moves": len(out["moves"]), "error": None if err is None else f"line {err[1]}: {err[2]}"}


def to_program(filename: str, post, letters=None):
    """The file as LinuxCNC's interpreter reads it, as a ReadProgram (ruled.machine.readback): its moves in mm,
    each feed move's minutes by LinuxCNC's rule (the X Y Z length at the feed rate, else the U V W length);
    refused in one line at the interpreter's first error."""
    from ruled.machine.readback import ReadProgram, meta_of
    letters = tuple(letters or post.letters)
    out = interpret(filename, letters)
    if out["error"] is not None:
        code, line, text = out["error"]
        raise BadInputError(f"LinuxCNC's interpreter refuses {os.path.basename(filename)} at line {line}: {text}")
    moves = [m for m in out["moves"] if m[0] != "arc"]
    if len(moves) != len(out["moves"]):
        raise BadInputError(f"{os.path.basename(filename)}: arcs; Ruled's wire paths are straight moves")
    if not moves:
        raise BadInputError(f"{os.path.basename(filename)}: no moves in the file")
    P = np.array([m[2] for m in moves], float)
    if post.upper == "relative":
        P[:, 2:] += P[:, :2]
    mins = np.full(len(P), np.nan)
    for i in range(1, len(P)):
        if moves[i][0] == "feed" and moves[i][3] > 0:
            d = P[i] - P[i - 1]
            length = np.linalg.norm(d[:2]) or np.linalg.norm(d[2:])     # (X Y, else U V: LinuxCNC's rule)
            mins[i] = float(length) / moves[i][3]
    kinds = ("start",) + tuple("rapid" if m[0] == "rapid" else "feed" for m in moves[1:])
    first_feed = next((m[1] for m in moves if m[0] == "feed"), None)
    dwell = sum(t for ln, t in out["dwells"] if first_feed is None or ln <= first_feed)
    return ReadProgram(post.name, "xyuv", "mm", P, kinds, mins, tuple(m[1] for m in moves),
                       meta_of(out["comments"]), {}, tuple(out["comments"]), dwell,
                       out["spindle"] if out["spindle"] else None, reader="linuxcnc")


__all__ = ["available", "interpret", "check", "to_program", "mask_of"]
