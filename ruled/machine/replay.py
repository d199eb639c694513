"""A machine file replayed: the moves it makes the machine do (ruled.machine.readback, or LinuxCNC's own
interpreter) put back in the part's space, and what they cut.

XYUV: each point's two guides on their planes (the file's 'ruled frame' comments give the machine frame, its
'planes=' the planes' heights; else the axis and planes the user gives), the wire swept between them over the
feed moves (ruled.machine.wirecut measures it against the design faces, less the kerf the file was written
with; a file written for the controller's wire compensation is its cut already), the largest taper, and the
guides' speeds (each feed move's time by the file's feed mode: G93's 1 / F, G94's F along the controller's
axes).  Flank: the tool (its CUTTER) swept along the CL points as a 5-axis machine moves it
(ruled.machine.swept)."""

from __future__ import annotations

import math
import os
from typing import Optional

import numpy as np

from ruled.core.errors import BadInputError
from ruled.machine.paths import Frame, MachinePath, frame_of
from ruled.machine.readback import ReadProgram


def _vec(meta: dict, key: str, n: int) -> Optional[np.ndarray]:
    if key not in meta:
        return None
    try:
        v = np.array([float(x) for x in meta[key].split(",")])
    except ValueError:
        return None
    return v if v.shape == (n,) and np.all(np.isfinite(v)) else None


def read_file(filename: str, post: Optional[str] = None, reader: str = "auto"):
    """(the post, the file read back, warnings): reader auto (LinuxCNC's interpreter for a LinuxCNC post where it
    is installed, else the project's), linuxcnc or ruled."""
    from ruled.machine import linuxcnc
    from ruled.machine.posts import load_post
    from ruled.machine.readback import detect_post, read_program
    if reader not in ("auto", "linuxcnc", "ruled"):
        raise BadInputError(f"«reader={reader}»: use auto, linuxcnc or ruled")
    if not os.path.isfile(filename):
        raise BadInputError(f"no such file: {filename}")
    if post is None or post == "auto":
        p = detect_post(filename)
    else:
        p = load_post(post, None)
    warnings = []
    use_lc = p.machine == "xyuv" and p.language == "gcode" and reader != "ruled" and (
        p.interpreter == "linuxcnc" or reader == "linuxcnc")
    if use_lc and any(c in "ABC" for c in p.letters):
        raise BadInputError(f"LinuxCNC reads {' '.join(c for c in p.letters if c in 'ABC')} as rotary axes (degrees), "
                            f"not a guide's position: leave «reader» out for the post {p.name}")
    if use_lc and not linuxcnc.available():
        if reader == "linuxcnc":
            raise BadInputError("LinuxCNC's interpreter is not installed (Debian: apt-get install linuxcnc-uspace); "
                                "leave «reader» out to read the file with Ruled's own reader")
        warnings.append("LinuxCNC's interpreter is not installed: the file was read by Ruled's own reader")
        use_lc = False
    if use_lc:
        prog = linuxcnc.to_program(filename, p)
        own = read_program(filename, p)          # the setup's values (the interpreter does not see templates)
        from dataclasses import replace
        prog = replace(prog, setup=own.setup, meta=prog.meta or own.meta)
    else:
        prog = read_program(filename, p)
    return p, prog, warnings


def program_frame(prog: ReadProgram, axis=None, planes=None) -> tuple[Frame, tuple]:
    """(the machine frame, the planes' heights (mm)) of an XYUV file: its 'ruled' comments, where the user gives
    neither; axis (x, y, z or a vector: the frame_of it) and planes (two heights) override them."""
    m = prog.meta
    if axis is not None:
        from ruled.machine.paths import _axis_spec
        spec = _axis_spec(axis)
        fr = frame_of(spec if isinstance(spec, tuple) else np.eye(3)["xyz".index(spec)])
    else:
        e1, e2, ax = (_vec(m, k, 3) for k in ("e1", "e2", "axis"))
        fr = Frame(e1, e2, ax) if e1 is not None and e2 is not None and ax is not None else frame_of([0, 0, 1])
        if e1 is None and "lower_plane" not in prog.setup:
            raise BadInputError("the file does not say where its machine frame and guide planes are (no 'ruled frame' "
                                "comments): give «axis» and «planes»")
    if planes is None:
        p = _vec(m, "planes", 2)
        if p is None and {"lower_plane", "upper_plane"} <= set(prog.setup):
            p = np.array([prog.setup["lower_plane"], prog.setup["upper_plane"]])
        if p is None:
            raise BadInputError("the file does not say the guide planes' heights: give «planes» a,b")
        planes = (float(p[0]), float(p[1]))
    planes = tuple(float(h) for h in planes)
    if len(planes) != 2 or planes[0] == planes[1]:
        raise BadInputError(f"«planes» takes two different heights a,b, not {planes!r}")
    return fr, planes


def wire_lines(prog: ReadProgram, fr: Frame, planes: tuple) -> tuple[np.ndarray, np.ndarray]:
    """(lower, upper) (M, 3): the wire's lines at the file's points, in the part's space (mm)."""
    P = prog.points
    return fr.point(P[:, :2], planes[0]), fr.point(P[:, 2:], planes[1])


def leads_of(prog: ReadProgram) -> tuple:
    """(moves before the first cut line, after the last): the file's 'leads=' (ruled.machine.program), else none."""
    try:
        a, b = (int(x) for x in prog.meta.get("leads", "0,0").split(","))
    except ValueError:
        return (0, 0)
    return (a, b)


def kerf_of(prog: ReadProgram, kerf=None) -> tuple[float, str]:
    """(the kerf to measure the lines by, what it is): given, else the file's; 0 where the controller offsets the
    wire (a file written for wire compensation: its lines are the cut)."""
    comp = prog.meta.get("compensation", "none")
    if kerf is not None:
        return float(kerf), "given"
    if comp not in ("none", ""):
        return 0.0, f"none: the controller offsets the wire (compensation D{comp})"
    try:
        return float(prog.meta.get("kerf", 0.0)), "the file's"
    except ValueError:
        return 0.0, "none"


def guide_speeds(prog: ReadProgram, lower: np.ndarray, upper: np.ndarray) -> dict:
    """The guides' speeds (model units per minute) over the feed moves whose time the file sets: each guide's
    least and largest, the faster guide's least and largest, and the minutes in all."""
    i = prog.feed_moves
    t = prog.minutes[i] if i.size else np.zeros(0)
    ok = np.isfinite(t) & (t > 0)
    i, t = i[ok], t[ok]
    if not i.size:
        return {"moves_timed": 0}
    lo = np.linalg.norm(lower[i] - lower[i - 1], axis=1) / t
    up = np.linalg.norm(upper[i] - upper[i - 1], axis=1) / t
    fast = np.maximum(lo, up)
    return {"moves_timed": int(i.size), "lower": [float(lo.min()), float(lo.max())],
            "upper": [float(up.min()), float(up.max())], "faster": [float(fast.min()), float(fast.max())],
            "minutes": float(t.sum())}


def flank_tool(prog: ReadProgram) -> MachinePath:
    """The flank file's tool at its CL points as a MachinePath (tips, tops one CUTTER length up the axes, the
    CUTTER's radius at the tip and taper), for ruled.machine.swept."""
    d, r, e, f, a, b, h = prog.cutter
    tip, ax = prog.points[:, :3], prog.points[:, 3:]
    top = tip + h * ax
    return MachinePath("flank", np.arange(len(tip), dtype=float), tip, top, np.stack([tip, top], axis=1), False,
                       0.0, 0.0, radius=0.5 * d, taper_deg=b)


MISMATCH = 0.05         # a file whose wire passes farther than this of the face's size from half its points


def measure_program(prog: ReadProgram, target, n: int = 30, axis=None, planes=None, kerf=None,
                    what: str = "the face", name: str = "the file") -> tuple[dict, dict]:
    """What the file's moves cut of the target's faces (a host's: ruled.machine.wirecut.Target): the report's
    "moves", "cut" (the keys of ``ruled machine``'s) and "machine" (and a flank file's "swept_tool"), and what
    its plot needs.  A file whose wire passes far from half the faces' points (a file of another face) is
    refused in one line."""
    from ruled.machine.wirecut import wire_cut
    feed = prog.feed_moves
    rep: dict = {"moves": {"points": int(len(prog.points)), "feed": int(feed.size),
                           "rapid": int(sum(k == "rapid" for k in prog.kinds)), "units": prog.units}}
    if feed.size == 0:
        raise BadInputError("the file has no feed moves (G1): nothing is cut")
    if prog.machine == "flank":
        from ruled.machine.swept import swept_measure
        tool = flank_tool(prog)
        w = swept_measure(tool, target.design(n)[0])
        rep["swept_tool"] = w
        rep["cut"] = {"against": target.against, "overcut": w["overcut"], "undercut": w["undercut"],
                      "max": max(w["overcut"], w["undercut"]), "samples": w["points"]}
        rep["machine"] = {"mode": "flank", "cl_points": int(len(prog.points)), "cutter": list(prog.cutter),
                          "tool_radius": 0.5 * prog.cutter[0], "taper_deg": prog.cutter[5]}
        return rep, {"lower": tool.lower, "upper": None, "per": w["per_position"], "cut": rep["cut"]}
    fr, hs = program_frame(prog, axis, planes)
    lower, upper = wire_lines(prog, fr, hs)
    k, why = kerf_of(prog, kerf)
    leads = leads_of(prog)
    cut = wire_cut(target, lower, upper, feed, n, k, leads)
    if cut["design_to_cut_median"] > MISMATCH * target.size:
        raise BadInputError(f"{name} does not cut {what}: half the face's points lie more than "
                            f"{cut['design_to_cut_median']:.4g} from its wire (the face is {target.size:.4g} across); "
                            f"is it the file of another face or part? (check «face», and the file's «axis» and "
                            f"«planes»)")
    rep["cut"] = cut
    body = feed[leads[0]:len(feed) - leads[1]] if len(feed) > sum(leads) else feed
    ends = np.unique(np.concatenate([body - 1, body]))
    rep["machine"] = {"mode": "xyuv", "plane_heights": list(hs), "axis": fr.axis.tolist(),
                      "frame": {"e1": fr.e1.tolist(), "e2": fr.e2.tolist(), "axis": fr.axis.tolist()},
                      "kerf": k, "kerf_from": why, "leads": list(leads),
                      "max_taper_deg": taper_deg(lower[ends], upper[ends], fr.axis),
                      "speeds": guide_speeds(prog, lower, upper), "dwell_s": prog.dwell, "power": prog.power}
    return rep, {"lower": fr.xy(lower), "upper": fr.xy(upper), "per": cut["per_move"], "cut": cut,
                 "lines": (lower, upper)}


def plot_replay(filename: str, lower: np.ndarray, upper: np.ndarray, moves: np.ndarray, cut: dict, title: str,
                per: Optional[dict] = None) -> None:
    """The wire's two guides' paths (XY of the machine frame: lower blue, upper red) and, below, the over- and
    undercut along the lower guide's path, per move (cut["per_move"], or per: a flank's per CL point)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ruled.core.outputs import atomic
    per = per or cut["per_move"]
    over, under = np.asarray(per["overcut"]), np.asarray(per["undercut"])
    fig, (ax, ax2) = plt.subplots(2, 1, figsize=(7, 8.5), gridspec_kw={"height_ratios": [3, 1.3]})
    if upper is not None:
        ax.plot(lower[:, 0], lower[:, 1], "-", color="tab:blue", lw=1.2, label="lower guide")
        ax.plot(upper[:, 0], upper[:, 1], "-", color="tab:red", lw=1.2, label="upper guide")
        ax.set_xlabel("X, U")
        ax.set_ylabel("Y, V")
    else:
        ax.plot(lower[:, 0], lower[:, 1], "-", color="tab:blue", lw=1.2, label="tool tip (x, y)")
    ax.set_aspect("equal", adjustable="datalim")
    ax.legend(loc="best", fontsize=8)
    ax.set_title(title, fontsize=9)
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(lower, axis=0), axis=1))])
    ax2.fill_between(s, 0.0, under, step="mid", color="tab:green", alpha=0.5, lw=0,
                     label=f"undercut (material left), largest {cut['undercut']:.4g}")
    ax2.fill_between(s, 0.0, -over, step="mid", color="tab:red", alpha=0.5, lw=0,
                     label=f"overcut (gouge), largest {cut['overcut']:.4g}")
    ax2.axhline(0.0, color="0.3", lw=0.6)
    ax2.set_xlabel("along the lower guide's path" if upper is not None else "along the tool tip's path")
    ax2.set_ylabel("the cut against the design")
    ax2.legend(loc="best", fontsize=8)
    fig.tight_layout()
    with atomic(filename) as tmp:
        fig.savefig(tmp, dpi=110)
    plt.close(fig)


def taper_deg(lower: np.ndarray, upper: np.ndarray, axis) -> float:
    """The largest angle, degrees, between a line and the machine axis."""
    d = upper - lower
    c = np.abs(d @ np.asarray(axis, float)) / np.maximum(np.linalg.norm(d, axis=1), 1e-300)
    return float(math.degrees(math.acos(min(1.0, float(c.min())))))


__all__ = ["read_file", "measure_program", "MISMATCH", "program_frame", "wire_lines", "leads_of", "kerf_of",
           "guide_speeds", "flank_tool", "plot_replay", "taper_deg"]
