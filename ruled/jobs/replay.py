"""``ruled replay``'s whole job: a machine file read back (through LinuxCNC's own interpreter where the post is
LinuxCNC's and the interpreter is installed, else the project's reader for the file's post), its moves put back
in the part's space and what they cut measured against a face or a wall of the part, as bounded by its edges,
both ways (ruled.machine.wirecut for a wire, ruled.machine.swept for a flank tool): the report (its "cut" has the
keys of ``ruled machine``'s), and a plot of the deviation along the path."""

from __future__ import annotations

import os
from typing import Optional

from ruled import __version__
from ruled.core.errors import BadInputError


def _target(part: str, face, wall, side: Optional[str], meta_side: int):
    """(FacesTarget, what, the faces' size) for --face K or --wall SPEC of the part, the wire on side."""
    from ruled.occ.io import read_faces, read_shape
    from ruled.occ.wirecut import FacesTarget
    if (face is None) == (wall is None):
        raise BadInputError("replay against one face («face» K) or one wall («wall» auto|K,L-M) of the part")
    if face is not None:
        faces = read_faces(part)
        if not 0 <= face < len(faces):
            raise BadInputError(f"{part} has {len(faces)} faces (0 to {len(faces) - 1}); see 'ruled faces {part}'")
        if side not in (None, "outside", "inside"):
            raise BadInputError(f"«side={side}»: a face's side is outside (its normal's side) or inside")
        s = meta_side if side is None else (1 if side == "outside" else -1)
        return FacesTarget([faces[face]], s), f"face {face}", s
    from ruled.machine.wall import wall_side
    from ruled.occ.wall import wall_of
    w = wall_of(read_shape(part), wall)
    if side is None:
        s = meta_side
    else:
        s = int(wall_side(w.ring.role, side)[0])
    return FacesTarget([w.faces[k] for k in w.ring.kept], s, "the wall's faces"), \
        f"the wall (faces {','.join(str(k) for k in w.ring.faces)})", s


def replay_job(filename: str, part: str, face: Optional[int] = None, wall=None, post: Optional[str] = None,
               reader: str = "auto", axis=None, planes=None, kerf=None, side: Optional[str] = None,
               measure_samples: int = 30, progress=None) -> tuple[dict, dict]:
    """The replay's report, and what its plot needs ({"lower", "upper", "per", "cut"})."""
    from ruled.core.outputs import check_measure_samples
    from ruled.machine.replay import measure_program, read_file
    check_measure_samples(measure_samples, 4)
    p, prog, warnings = read_file(filename, post, reader)
    if progress:
        progress("read", 1.0)
    meta_side = int(prog.meta.get("side", "+1") or 1) if prog.machine == "xyuv" else 1
    target, what, s = _target(part, face, wall, side, meta_side)
    rep: dict = {"version": __version__, "file": os.path.abspath(filename), "post": p.name,
                 "reader": "LinuxCNC's interpreter (gcode module)" if prog.reader == "linuxcnc" else "Ruled's reader",
                 "input": os.path.abspath(part), "against": what, "side": "+1 (off the material / outside)" if s > 0
                 else "-1 (in the material / inside)"}
    if face is not None:
        rep["face"] = face
    more, plot = measure_program(prog, target, measure_samples, axis, planes, kerf,
                                 f"{what} of {os.path.basename(part)}", os.path.basename(filename))
    rep.update(more)
    rep["warnings"] = warnings + rep.get("warnings", [])
    return rep, plot


def plot_of(rep: dict, plot: dict, filename: str) -> None:
    from ruled.machine.replay import plot_replay
    title = (f"replay of {os.path.basename(rep['file'])} ({rep['post']}) against {rep['against']}: overcut "
             f"{rep['cut']['overcut']:.4g}, undercut {rep['cut']['undercut']:.4g}")
    plot_replay(filename, plot["lower"], plot["upper"], None, plot["cut"], title, plot["per"])


__all__ = ["replay_job", "plot_of"]
