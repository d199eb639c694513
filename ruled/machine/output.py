"""Machine outputs written: the path's program by its post (G-code or APT: ruled.machine.program,
ruled.machine.apt), the CSV of either, the report's machine figures and the plot of the two contours with their
synchronisation links (ruled.machine.paths makes the paths)."""

from __future__ import annotations

import csv
import os
from typing import Optional

import numpy as np

from ruled.core.errors import BadInputError
from ruled.core.outputs import atomic, write_text
from ruled.machine.paths import MachinePath, frame_of
from ruled.machine.program import PostSettings, num, scale, side_text
from ruled.machine.swept import axis_angles


def _fmt(x: float, digits: int = 6) -> str:
    return num(x, digits)


def _scale(units: str) -> float:
    return scale(units)


def program_lines(path: MachinePath, settings: Optional[PostSettings] = None, units: str = "mm",
                  side: Optional[str] = None, title: str = "") -> tuple:
    """(the post, the file's lines) of the path written by the post the settings name (None: the default post
    for the path, linuxcnc for a wire, apt for flank milling), see ruled.machine.program and ruled.machine.apt."""
    from ruled.machine.apt import apt_sync_lines, flank_apt_lines
    from ruled.machine.program import gcode_lines
    post, s = (settings or PostSettings()).resolved(path.mode)
    if path.mode == "flank":
        return post, flank_apt_lines(path, post, units, title, s.corner_radius)
    if post.language == "apt":
        return post, apt_sync_lines(path, post, units, side, title)
    return post, gcode_lines(path, post, s, units, side, title)


def write_program(path: MachinePath, filename: str, settings: Optional[PostSettings] = None, units: str = "mm",
                  side: Optional[str] = None, title: str = ""):
    """The path's program for a post (program_lines) written to filename; the title is the file's name unless
    given (so that every front door writes the same bytes for the same path and settings).  Returns the post."""
    post, lines = program_lines(path, settings, units, side, title or os.path.splitext(os.path.basename(filename))[0])
    write_text(filename, "\n".join(lines) + "\n")
    return post


def write_checked(path: MachinePath, filename: str, settings: Optional[PostSettings] = None, units: str = "mm",
                  side: Optional[str] = None, csv_path: Optional[str] = None) -> dict:
    """The path's program (write_program) and its CSV, and, for a post its controller's own interpreter reads
    (LinuxCNC's, where Debian's linuxcnc-uspace is installed), the file checked by it: the report's "program"
    (the post, the file, the CSV, the check: None where the interpreter is not installed; else its move count
    and its error or None).  Every front door writes machine files through here."""
    from ruled.machine import linuxcnc
    post = write_program(path, filename, settings, units, side)
    csv_path = csv_path or os.path.splitext(filename)[0] + ".csv"
    write_csv(path, csv_path, units, side)
    check = None
    if post.interpreter == "linuxcnc":
        check = linuxcnc.check(filename, post.letters)
        if check is not None:
            check = {"interpreter": "LinuxCNC (gcode module, the AXIS preview's parser)", **check}
    return {"post": post.name, "post_file": post.source, "file": os.path.abspath(filename),
            "csv": os.path.abspath(csv_path), "check": check}


def write_gcode(path: MachinePath, filename: str, title: str = "", units: str = "mm",
                side: Optional[str] = None, settings: Optional[PostSettings] = None) -> None:
    """The XYUV path as G-code by a G-code post (default linuxcnc: RS274/NGC, see ruled.machine.program)."""
    if path.mode != "xyuv":
        raise BadInputError("G-code is written for XYUV contours; flank paths are written as CL data (.apt/.csv)")
    write_program(path, filename, settings, units, side, title)


def write_apt(path: MachinePath, filename: str, title: str = "", units: str = "mm",
              settings: Optional[PostSettings] = None) -> None:
    """The flank path as APT CL data (ruled.machine.apt: the 7-parameter CUTTER, MULTAX/ON, GOTO tip and axis)."""
    if path.mode != "flank":
        raise BadInputError("APT CL data is written for flank paths; XYUV contours are written as G-code")
    write_program(path, filename, settings, units, None, title)


def write_csv(path: MachinePath, filename: str, units: str = "mm", side: Optional[str] = None) -> None:
    """xyuv: one row per move (kind, X, Y, U, V, the two 3D points, u, the wire's taper: its angle from the
    machine axis, degrees, the kerf and the side it is on, as the G-code's header says them); flank: one row
    per CL point (u, tip x y z, axis i j k, the angle the axis turned by from the point before); lengths in the
    output units."""
    k = _scale(units)
    with atomic(filename) as tmp, open(tmp, "w", newline="") as fh:
        w = csv.writer(fh)
        if path.mode == "xyuv":
            w.writerow(["kind", "X", "Y", "U", "V", "lower_x", "lower_y", "lower_z", "upper_x", "upper_y",
                        "upper_z", "u", "taper_deg", "kerf", "side"])
            where = side_text(side).strip()
            (h0, h1), fr = path.planes, path.frame
            i = 0
            for kind, row in zip(path.kinds, path.moves):
                lo, hi = fr.point(row[:2], h0) * k, fr.point(row[2:], h1) * k
                uu = path.u[i] if kind == "cut" else ""
                i += kind == "cut"
                d = hi - lo
                taper = np.degrees(np.arccos(min(1.0, abs(float(d @ fr.axis)) / max(float(np.linalg.norm(d)),
                                                                                     1e-300))))
                w.writerow([kind, *map(_fmt, row * k), *map(_fmt, lo), *map(_fmt, hi),
                            uu if uu == "" else f"{uu:.12g}", f"{taper:.4f}", _fmt(path.radius * k), where])
        else:
            w.writerow(["u", "x", "y", "z", "i", "j", "k", "axis_turn_deg"])
            turn = np.concatenate([[0.0], axis_angles(path)])     # from the CL point before
            for uu, p, a, g in zip(path.u, path.lower, path.axes, turn):
                w.writerow([f"{uu:.12g}", *map(_fmt, p * k), *(_fmt(x, 9) for x in a), f"{g:.6f}"])


def write_machine(path: MachinePath, filename: str, title: str = "", csv_path: Optional[str] = None,
                  units: str = "mm", side: Optional[str] = None, settings: Optional[PostSettings] = None) -> str:
    """The path's own file by its post (settings.post; default linuxcnc G-code for XYUV, APT for flank) and its
    CSV (default: beside it, .csv), in the output units (mm or inch); returns the CSV's name.  side: said in the
    file's header."""
    write_program(path, filename, settings, units, side, title)
    csv_path = csv_path or os.path.splitext(filename)[0] + ".csv"
    write_csv(path, csv_path, units, side)
    return csv_path


def path_report(path: MachinePath) -> dict:
    d = {"mode": path.mode, "chord_tol": path.chord_tol, "closed": path.closed, **path.stats,
         "offset_deviation": path.offset_deviation, "feed": path.feed, "warnings": list(path.warnings)}
    if path.mode == "xyuv":
        d.update(kerf=path.radius, frame={"e1": path.frame.e1.tolist(), "e2": path.frame.e2.tolist(),
                                          "axis": path.frame.axis.tolist()},
                 leads=int(sum(k != "cut" for k in path.kinds)))
    return d


def plot_path(path: MachinePath, filename: str, title: str = "", swept: Optional[dict] = None) -> None:
    """The two contours (XY and UV, or tip and top of the tool) with their synchronisation links; with swept
    (a flank report's "swept_tool"), below them the over- and undercut along the path, per CL point."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fr = path.frame or frame_of(np.mean(path.axes, axis=0))
    a, b = fr.xy(path.lower), fr.xy(path.upper)
    per = (swept or {}).get("per_position")
    if per:
        fig, (ax, ax2) = plt.subplots(2, 1, figsize=(7, 8.5), gridspec_kw={"height_ratios": [3, 1.2]})
        s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(path.lower, axis=0), axis=1))])
        k = max(1, len(s) // 100)               # the largest over runs of k CL points (many have no point)
        starts = np.arange(0, len(s), k)
        mid = s[np.minimum(starts + k // 2, len(s) - 1)]
        ax2.fill_between(mid, 0.0, np.maximum.reduceat(np.asarray(per["undercut"]), starts), color="tab:green",
                         alpha=0.5, lw=0, label=f"undercut (material left), largest {swept['undercut']:.3g}")
        ax2.fill_between(mid, 0.0, -np.maximum.reduceat(np.asarray(per["overcut"]), starts), color="tab:red",
                         alpha=0.5, lw=0, label=f"overcut (gouge), largest {swept['overcut']:.3g}")
        ax2.axhline(0.0, color="0.3", lw=0.6)
        ax2.set_xlabel("along the tool tip's path")
        ax2.set_ylabel("the face against the tool")
        ax2.legend(loc="best", fontsize=8)
        ax2.set_title(f"the face's points against the swept tool, per CL point (the axis turns at most "
                      f"{swept['axis_angle_max_deg']:.3g} deg a move)", fontsize=9)
    else:
        fig, ax = plt.subplots(figsize=(7, 6))
    step = max(1, len(a) // 150)
    for p, q in zip(a[::step], b[::step]):
        ax.plot([p[0], q[0]], [p[1], q[1]], color="0.75", lw=0.5)
    names = ("XY (lower guide)", "UV (upper guide)") if path.mode == "xyuv" else ("tool tip", "tool top")
    ax.plot(a[:, 0], a[:, 1], "-", color="tab:blue", lw=1.2, label=names[0])
    ax.plot(b[:, 0], b[:, 1], "-", color="tab:red", lw=1.2, label=names[1])
    if path.moves is not None and path.kinds and path.kinds[0] == "lead-in":
        m = path.moves
        for ends in ([0, 1], [-2, -1]):
            ax.plot(m[ends, 0], m[ends, 1], ":", color="tab:blue")
            ax.plot(m[ends, 2], m[ends, 3], ":", color="tab:red")
    ax.set_xlabel("X, U" if path.mode == "xyuv" else "e1")
    ax.set_ylabel("Y, V" if path.mode == "xyuv" else "e2")
    ax.set_aspect("equal", adjustable="datalim")      # the axes fill the figure, however narrow the part
    ax.legend(loc="best", fontsize=8)
    ax.set_title(title or f"{path.mode}: {len(a)} synchronized points, chord tolerance {path.chord_tol:.3g} "
                 f"(links every {step})", fontsize=9)
    fig.tight_layout()
    with atomic(filename) as tmp:
        fig.savefig(tmp, dpi=110)
    plt.close(fig)
