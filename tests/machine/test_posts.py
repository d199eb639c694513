"""Machine files the controllers load (issue 71): every LinuxCNC file the tests write read by LinuxCNC's own
interpreter (Debian's linuxcnc-uspace, its gcode module, the AXIS preview's parser, with an X Y U V mask), the
GRBL file by a GRBL-dialect reader from PyPI (gcodeparser) under its letter map, the ISO wire-EDM file's relative
U V, the APT files, G93's times on a tapered cut, and ``ruled replay`` against ``ruled machine``'s own figures.

Measured independently of the code under test: the lines LinuxCNC's interpreter moves are put in the part's
space from the file's own comments by this file's code, and measured against the face by OCCT's BRepExtrema
(machine_helpers.trim_aware_cut, segment_distance); times by LinuxCNC's own feed rates."""

from __future__ import annotations

import json
import os
import re

import numpy as np
import pytest
from conftest import ROOT, data_file, ruled_here, ruled_process

gcodeparser = pytest.importorskip("gcodeparser")

from machine_helpers import (  # noqa: E402
    comments_nest,
    frame_of_file,
    interpreted,
    lines_of,
    rect_wall,
    segment_distance,
    trim_aware_cut,
)

from ruled.machine import linuxcnc  # noqa: E402
from ruled.occ.io import get_face, read_shape  # noqa: E402

needs_linuxcnc = pytest.mark.skipif(not linuxcnc.available(),
                                    reason="LinuxCNC's interpreter is not installed (apt-get install linuxcnc-uspace)")


def cli(tmp_path, *args):
    run = ruled_here(*map(str, args))
    assert run.returncode == 0, run.stderr
    return run


# ------------------------------------------------------------------------------------------------ fixtures

@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """The files the acceptance loads: kj66 face 6 (the command line, report), a wall with a kerf (a drafted
    rectangle), the die hole (the D-shaped hole, kerf 0.15), the demo; each with its 'ruled machine' report."""
    from wall_parts import d_hole

    from ruled.occ.io import write_step
    d = tmp_path_factory.mktemp("posts")
    out = {}
    kj = data_file("kj66_impeller.step")
    out["kj66"] = (kj, str(d / "blade.ngc"), str(d / "blade.json"), {"face": 6})
    cli(d, "machine", kj, "--face", 6, "--xyuv", "--chord-tol", 0.002, "-o", out["kj66"][1], "--report",
        out["kj66"][2], "--quiet")
    for name, build, word, kerf in (("wall", rect_wall, "auto", 0.1), ("hole", d_hole, "hole", 0.15)):
        step = str(d / f"{name}.step")
        write_step(build().wrapped, step)
        out[name] = (step, str(d / f"{name}.ngc"), str(d / f"{name}.json"), {"wall": word})
        cli(d, "machine", step, "--wall", word, "--xyuv", "--kerf", kerf, "-o", out[name][1], "--report",
            out[name][2], "--measure-samples", 12, "--quiet")
    demo = ruled_process("demo", "--quiet", cwd=str(d))
    assert demo.returncode == 0, demo.stderr
    r = d / "ruled-demo"
    out["demo"] = (str(r / "input.step"), str(r / "wire.ngc"), str(r / "wire.json"), {"face": 0})
    out["demo_run"] = demo
    return out


# ------------------------------------------------------------------------------------------ LinuxCNC reads

@pytest.mark.slow
@needs_linuxcnc
@pytest.mark.parametrize("name", ["kj66", "wall", "hole", "demo"])
def test_linuxcnc_reads_every_file_and_its_moves_cut_within_the_bound(files, name):
    src, ngc, rep_path, which = files[name]
    rep = json.load(open(rep_path))
    mrep = rep["machine"] if name != "demo" else rep["machine"]["machine"]
    cut = rep["cut"] if name != "demo" else rep["machine"]["cut"]
    P, kinds, out = interpreted(ngc)
    assert not comments_nest(open(ngc).read())
    assert len(P) == mrep["sync_points"] + mrep["leads"]                          # every synchronized pair, the leads
    assert kinds[0] == "rapid" and set(kinds[1:]) == {"feed"}
    lo, hi = lines_of(P, ngc)
    _, _, _, _, kerf = frame_of_file(ngc)
    bound = cut["bound"]
    if "face" in which:
        # the lines of the cut (the leads apart: they come square to the face, off it)
        face = get_face(src, which["face"])
        to_swept, d, kept = trim_aware_cut(face, lo[1:-1], hi[1:-1], n=16, every=2)
        assert kept > 50 and np.abs(d).max() <= bound, (np.abs(d).max(), bound)
        assert to_swept <= bound, (to_swept, bound)
    else:
        from ruled.occ.io import faces_of
        from ruled.occ.measure import face_points
        faces = faces_of(read_shape(src))
        W = np.concatenate([face_points(faces[i], 8) for i in rep["wall"]["faces"]])
        dw = segment_distance(W, lo[1:], hi[1:])
        # the wall's points are the kerf from the lines, within the bound (the inside corners' rounds in it)
        assert np.abs(dw - kerf).max() <= bound + 1e-9, (np.abs(dw - kerf).max(), bound)


@pytest.mark.slow
@needs_linuxcnc
def test_the_demo_is_a_wire_machines_job(files):
    """`ruled demo` (the README's command 1): the fit, the wire for the default post, checked by LinuxCNC's
    interpreter, replayed; a face a wire machine can cut (taper at most 30 degrees, no taper warning)."""
    run = files["demo_run"]
    for name in ("result.step", "report.json", "plot.png", "wire.ngc", "wire.csv", "wire.png", "wire.json",
                 "replay.png"):
        p = os.path.join(os.path.dirname(files["demo"][1]), name)
        assert os.path.exists(p) and p in run.stdout
    assert "LinuxCNC's interpreter reads it" in run.stdout and "replayed (LinuxCNC's interpreter" in run.stdout
    assert "taper" not in run.stderr
    rep = json.load(open(files["demo"][2]))
    assert rep["machine"]["machine"]["max_taper_deg"] <= 30.0
    assert rep["program"]["post"] == "linuxcnc" and rep["program"]["check"]["error"] is None
    text = open(files["demo"][1]).read()
    assert "G93" in text and "(AXIS,XY_Z_POS," in text and "(AXIS,UV_Z_POS," in text and "G64 P" in text


# -------------------------------------------------------------------------------------- replay = machine

@pytest.mark.slow
@needs_linuxcnc
@pytest.mark.parametrize("name", ["demo", "kj66", "hole"])
def test_replay_reports_the_machines_own_cut(files, name, tmp_path):
    src, ngc, rep_path, which = files[name]
    rep = json.load(open(rep_path))
    cut = rep["cut"] if name != "demo" else rep["machine"]["cut"]
    out = str(tmp_path / "replay.json")
    key, value = next(iter(which.items()))
    cli(tmp_path, "replay", ngc, "--against", src, f"--{key}", value, "--report", out, "--plot",
        tmp_path / "replay.png", "--quiet", "--measure-samples", cut["measure_samples"])
    r = json.load(open(out))
    assert r["reader"].startswith("LinuxCNC")
    size = float(np.linalg.norm(np.ptp(np.concatenate(lines_of(interpreted(ngc)[0], ngc)), axis=0)))
    for k in ("overcut", "undercut", "design_to_cut", "cut_to_design", "max"):
        assert abs(r["cut"][k] - cut[k]) <= 1e-6 * size, (k, r["cut"][k], cut[k])
    assert set(r["cut"]) - {"per_move"} <= set(cut)                     # the same keys as 'ruled machine''s


@pytest.mark.slow
@needs_linuxcnc
def test_replay_catches_a_move_shifted_by_hand(files, tmp_path):
    """kj66 face 6's file with one cut move shifted 0.1 off the face (both guides, along the face's normal in the
    machine's plane): the replay's undercut rises by that 0.1."""
    from OCP.BRep import BRep_Tool
    from OCP.BRepGProp import BRepGProp_Face
    from OCP.gp import gp_Pnt, gp_Vec
    from OCP.ShapeAnalysis import ShapeAnalysis_Surface
    src, ngc, rep_path, which = files["kj66"]
    rep = json.load(open(rep_path))
    P, _, _ = interpreted(ngc)
    lo, hi = lines_of(P, ngc)
    e1, e2, ax, (h0, h1), _ = frame_of_file(ngc)
    face = get_face(src, 6)
    k = len(P) // 2
    mid = 0.5 * (lo[k] + hi[k])
    uv = ShapeAnalysis_Surface(BRep_Tool.Surface_s(face)).ValueOfUV(gp_Pnt(*map(float, mid)), 1e-9)
    u, v = uv.X(), uv.Y()
    p, n = gp_Pnt(), gp_Vec()
    BRepGProp_Face(face).Normal(u, v, p, n)                 # the face's normal, its orientation counted
    n = np.array(n.Coord()) / n.Magnitude()
    nxy = np.array([n @ e1, n @ e2])
    step = 0.1 * nxy / np.linalg.norm(nxy)
    lines = open(ngc).read().splitlines()
    g1 = [i for i, ln in enumerate(lines) if ln.startswith("G1 ")]
    i = g1[k - 1]                                           # the move that ends at point k
    w = dict(re.findall(r"([XYUVF])(-?[\d.]+)", lines[i]))
    x, y, uu, vv = (float(w[c]) for c in "XYUV")
    lines[i] = (f"G1 X{x + step[0]:.6f} Y{y + step[1]:.6f} U{uu + step[0]:.6f} V{vv + step[1]:.6f} F{w['F']}")
    edited = str(tmp_path / "edited.ngc")
    open(edited, "w").write("\n".join(lines) + "\n")
    out = str(tmp_path / "r.json")
    cli(tmp_path, "replay", edited, "--against", src, "--face", 6, "--report", out, "--quiet")
    r = json.load(open(out))
    rise = 0.1 * float(np.linalg.norm(nxy))                  # the shift along the face's normal
    assert abs(r["cut"]["undercut"] - (rep["cut"]["undercut"] + rise)) <= 0.1 * rise, (r["cut"], rise)
    assert r["cut"]["max"] >= rep["cut"]["max"] + 0.9 * rise


# ------------------------------------------------------------------------------------- the other posts

@pytest.fixture(scope="module")
def blade(files, tmp_path_factory):
    """kj66 face 6's path once (the job's), for the other posts (the same path in every file)."""
    from ruled.jobs.machine import machine_job
    from ruled.machine.paths import MachineOptions
    fm = machine_job(get_face(files["kj66"][0], 6), MachineOptions(chord_tol=0.002), measure_samples=None)
    return fm, tmp_path_factory.mktemp("blade")


def _write(fm, path, **settings):
    from ruled.machine.output import write_checked
    from ruled.machine.program import PostSettings
    return write_checked(fm.path, str(path), PostSettings(**settings), "mm", fm.report.get("side"))


@pytest.mark.slow
@needs_linuxcnc
def test_the_command_line_and_cadquery_write_the_same_bytes(files, blade):
    """One file from every door: kj66 face 6's G-code from the command line (the fixture) and from the job's
    path written as ruled.cq writes it, the same name, the same bytes."""
    fm, d = blade
    os.makedirs(d / "cq", exist_ok=True)
    from ruled.cq import MachineData
    MachineData(fm.path, None, fm.report, fm.fit, fm.surface).write_gcode(str(d / "cq" / "blade.ngc"))
    assert open(d / "cq" / "blade.ngc", "rb").read() == open(files["kj66"][1], "rb").read()


@pytest.mark.slow
@needs_linuxcnc
def test_grbl_files_read_by_a_grbl_reader_under_their_letters(files, blade):
    fm, d = blade
    ref = interpreted(files["kj66"][1])[0]
    for letters in ("XYZA", "XYUV"):
        path = d / f"blade-{letters}.gcode"
        _write(fm, path, post="grbl", letters=None if letters == "XYZA" else letters)
        text = open(path).read()
        assert text.startswith(";") and "(" not in text and "M3 S1000" in text and "G4 P2" in text
        lines = list(gcodeparser.parse_gcode_lines(text))
        moves = [ln for ln in lines if ln.command[0] == "G" and ln.command[1] in (0, 1)]
        got = np.array([[ln.params[c] for c in letters] for ln in moves])
        assert got.shape == ref.shape and np.abs(got - ref).max() <= 0.5e-4 + 1e-6      # (4 decimals)
        assert all("F" in ln.params for ln in moves[1:])


@pytest.mark.slow
@needs_linuxcnc
def test_iso_wedm_relative_uv_gives_the_same_wire_lines(files, blade, tmp_path):
    """The iso-wedm post's U V are the upper guide's offset from X Y: read back (the project's reader), the same
    wire lines as the LinuxCNC file's, to 1e-6 with a post of six decimals (a user's own post: the shipped
    file copied, one field changed), to the shipped post's four decimals with it."""
    from ruled.machine.posts import HERE
    from ruled.machine.readback import read_program
    fm, d = blade
    ref_lo, ref_hi = lines_of(interpreted(files["kj66"][1])[0], files["kj66"][1])
    own = tmp_path / "my-wedm.toml"
    own.write_text(open(os.path.join(HERE, "iso-wedm.toml")).read().replace("decimals = 4", "decimals = 6"))
    for post, tol in ((str(own), 1e-6), ("iso-wedm", 1.5e-4)):
        path = d / f"blade-{os.path.basename(post)}.nc"
        _write(fm, path, post=post)
        text = open(path).read()
        assert text.startswith("%\n") and re.search(r"^N\d+ G92 X", text, re.M) and "M60" in text
        prog = read_program(str(path))
        # the start: the wire upright (U V 0) where G92 declares it, then tilted to the first line
        assert np.allclose(prog.points[0, 2:], prog.points[0, :2])
        lo, hi = lines_of(prog.points[1:], files["kj66"][1])
        assert lo.shape == ref_lo.shape
        assert np.abs(lo - ref_lo).max() <= tol and np.abs(hi - ref_hi).max() <= 2 * tol
        rel = [ln for ln in text.splitlines() if " G1 X" in ln][5]
        w = dict(re.findall(r"([XYUV])(-?[\d.]+)", rel))
        assert abs(float(w["U"])) < 20 and abs(float(w["V"])) < 20     # offsets, not the upper guide's position


@pytest.mark.slow
@needs_linuxcnc
def test_apt_sync_and_flank_apt_read_back(files, blade, tmp_path):
    from ruled.machine.readback import read_program
    fm, d = blade
    path = d / "blade-sync.apt"
    _write(fm, path, post="apt-sync")
    text = open(path).read()
    assert "SET/UPPER," in text and text.splitlines().count("SYNCTR") == fm.path.moves.shape[0] - 2
    prog = read_program(str(path))
    ref = interpreted(files["kj66"][1])[0]
    assert np.abs(prog.points - ref).max() <= 1e-6 + 1e-6 * np.abs(ref).max()
    # flank APT: the 7-parameter cutter of a tapered tool with a corner radius
    from cases import hyperboloid

    from ruled.jobs.machine import machine_job
    from ruled.machine.paths import MachineOptions
    from ruled.occ.convert import container_to_face
    face = container_to_face(hyperboloid(10.0, 10.0, 10.0))
    fl = machine_job(face, MachineOptions("flank", chord_tol=0.05, tool_radius=1.0, taper_deg=5.0,
                                          positions="offset"), measure_samples=None)
    apt = tmp_path / "hyp.apt"
    _write(fl, apt, corner_radius=0.25)
    d_, r, e, f, a, b, h = (float(x) for x in re.search(r"^CUTTER/(.*)$", open(apt).read(), re.M).group(1).split(","))
    assert (d_, r, e, f, a, b) == (2.0, 0.25, 0.75, 0.25, 0.0, 5.0)
    lengths = np.linalg.norm(fl.path.upper - fl.path.lower, axis=1)
    assert abs(h - lengths.max()) <= 1e-6
    assert "MULTAX/ON" in open(apt).read()
    prog = read_program(str(apt))
    assert prog.machine == "flank" and prog.cutter[1] == 0.25
    assert np.abs(prog.points[:, :3] - fl.path.lower).max() <= 1e-6
    assert np.abs(prog.points[:, 3:] - fl.path.axes).max() <= 1e-8


@pytest.mark.slow
@needs_linuxcnc
def test_g93_times_each_move_by_its_longer_guide_on_a_tapered_cut(tmp_path):
    """Elber's ex2 fitted (its rulings 47 degrees from the machine axis): every move's time, as LinuxCNC's
    interpreter runs the file (its X Y length at the feed rate it derives from G93's F), is the longer guide's
    length over the wire speed asked."""
    from ruled.examples import elber_ex2
    from ruled.jobs.machine import machine_job
    from ruled.machine.paths import MachineOptions
    from ruled.occ.convert import container_to_face
    fm = machine_job(container_to_face(elber_ex2()), MachineOptions(feed=250.0), measure_samples=None)
    assert fm.report["machine"]["max_taper_deg"] > 45.0
    path = tmp_path / "ex2.ngc"
    _write(fm, path, feed_mode="g93")
    out = linuxcnc.interpret(str(path), ("X", "Y", "U", "V"))
    assert out["error"] is None
    moves = out["moves"]
    worst = 0.0
    for (_, _, a, _, _), (kind, _, b, rate, inverse) in zip(moves[:-1], moves[1:]):
        assert kind == "feed" and inverse
        a, b = np.array(a), np.array(b)
        lxy, luv = np.linalg.norm(b[:2] - a[:2]), np.linalg.norm(b[2:] - a[2:])
        minutes = (lxy if lxy > 0 else luv) / rate                   # as LinuxCNC times a move
        worst = max(worst, abs(minutes - max(lxy, luv) / 250.0) / minutes)
    assert worst <= 2e-6, worst                     # (F's seven significant digits, the moves' six decimals)


# -------------------------------------------------------------------------------------------- bad input

def test_bad_posts_are_refused_in_one_line_before_any_work(tmp_path):
    from ruled.machine.posts import HERE
    kj = data_file("kj66_impeller.step")
    bad = tmp_path / "bad.toml"
    bad.write_text("\n".join(ln for ln in open(os.path.join(HERE, "linuxcnc.toml")).read().splitlines()
                             if not ln.startswith("cut =")))
    typo = tmp_path / "typo.toml"
    typo.write_text(open(os.path.join(HERE, "linuxcnc.toml")).read().replace('"G64 P{chord}"', '"G64 P{chord_tol}"'))
    for args, words in (
            (("machine", kj, "--face", 6, "--xyuv", "--post", "fanuc-9000", "-o", tmp_path / "a.ngc"),
             "unknown post --post fanuc-9000: use one of linuxcnc, grbl"),
            (("machine", kj, "--face", 6, "--xyuv", "--post", bad, "-o", tmp_path / "a.ngc"),
             "the post bad.toml has no field cut"),
            (("machine", kj, "--face", 6, "--xyuv", "--post", typo, "-o", tmp_path / "a.ngc"),
             "names {chord_tol}, which Ruled does not fill"),
            (("machine", kj, "--face", 6, "--flank", "--tool-radius", 1, "--post", "grbl", "-o", tmp_path / "a.apt"),
             "the post grbl writes a wire's XYUV path, not a flank-milling tool path"),
            (("machine", kj, "--face", 6, "--xyuv", "--compensation", 1, "-o", tmp_path / "a.ngc"),
             "the post linuxcnc has no wire compensation codes"),
            (("replay", tmp_path / "none.ngc", "--against", kj, "--face", 6), "no such file")):
        run = ruled_here(*map(str, args))
        assert run.returncode == 2 and words in run.stderr and run.stderr.count("\n") == 1, run.stderr
    assert not os.path.exists(tmp_path / "a.ngc")


@pytest.mark.slow
@needs_linuxcnc
def test_a_file_for_another_face_is_refused_in_one_line(files):
    kj = files["kj66"][0]
    run = ruled_here("replay", files["kj66"][1], "--against", kj, "--face", "7")
    assert run.returncode == 2 and run.stderr.count("\n") == 1, run.stderr
    assert "blade.ngc does not cut face 7 of kj66_impeller.step" in run.stderr, run.stderr


def test_posts_lists_the_shipped_posts_and_prints_one():
    run = ruled_here("posts")
    assert run.returncode == 0
    for name in ("linuxcnc", "grbl", "iso-wedm", "apt-sync", "apt"):
        assert re.search(rf"^  {re.escape(name)}\s", run.stdout, re.M)
    one = ruled_here("posts", "grbl")
    assert 'letters = ["X", "Y", "Z", "A"]' in one.stdout


@pytest.mark.slow
@needs_linuxcnc
def test_a_walls_start_and_direction_by_a_rule(files):
    """The drafted rectangle's bottom contour has two longest straight edges of the same length (y = -10 and
    y = 10): the loop starts in the middle of the one of least y, whichever order a host lists the edges in, and
    runs counter-clockwise about the axis (seen from above)."""
    from ruled.fit.wall.ring import RingEdge
    from ruled.machine.wall import longest_edge
    P, _, _ = interpreted(files["wall"][1])
    lo, hi = lines_of(P, files["wall"][1])
    first = lo[1] + (hi[1] - lo[1]) * (0.0 - lo[1][2]) / (hi[1] - lo[1])[2]     # the first cut line at z = 0
    assert abs(first[0]) < 0.05 and abs(first[1] - (-10.1)) < 1e-3, first          # (the kerf 0.1 outside it)
    loop = lo[1:-1]
    area = 0.5 * np.sum(loop[:-1, 0] * loop[1:, 1] - loop[1:, 0] * loop[:-1, 1])
    assert area > 0                                          # counter-clockwise about +z
    a = RingEdge(np.array([0.0, 0, 0]), np.array([40.0, 0, 0]), np.array([[0.0, 0, 0], [20, 0, 0], [40, 0, 0]]), 40.0,
                 straight=True)
    b = RingEdge(np.array([40.0, 20, 0]), np.array([0.0, 20, 0]), np.array([[40.0, 20, 0], [20, 20, 0], [0, 20, 0]]),
                 40.0 + 1e-9, straight=True)
    assert longest_edge([a, b], 50.0) is a and longest_edge([b, a], 50.0) is a


def test_lint_post_files_are_in_the_package():
    """The posts ship with the package (pyproject's package data) and every one loads."""
    text = open(os.path.join(ROOT, "pyproject.toml")).read()
    assert '"ruled.machine.posts" = ["*.toml"]' in text
    from ruled.machine.posts import SHIPPED, load_post
    for name in SHIPPED:
        assert load_post(name, None).name == name


@pytest.mark.slow
@needs_linuxcnc
def test_wire_compensation_is_on_the_wires_side(blade, files):
    """iso-wedm with the controller's compensation (D1): the path uncompensated, G41 or G42 as the face's outside
    lies left or right of the direction of travel (measured here: the face's normal at the first cut line by OCCT,
    against the lower guide's direction), switched on with the lead-in and off with the lead-out."""
    from OCP.BRep import BRep_Tool
    from OCP.BRepGProp import BRepGProp_Face
    from OCP.gp import gp_Pnt, gp_Vec
    from OCP.ShapeAnalysis import ShapeAnalysis_Surface

    from ruled.machine.readback import read_program
    fm, d = blade
    path = d / "comp.nc"
    _write(fm, path, post="iso-wedm", compensation=1)
    text = open(path).read()
    on = [ln for ln in text.splitlines() if re.search(r"\bG4[12] D1 G1\b", ln)]
    off = [ln for ln in text.splitlines() if " G40 G1 " in ln]
    assert len(on) == 1 and len(off) == 1 and "compensation=1" in text
    prog = read_program(str(path))
    lo, hi = lines_of(prog.points, files["kj66"][1])
    e1, e2, ax, _, _ = frame_of_file(files["kj66"][1])
    k = 2                                                   # (upright start, approach, lead-in: the first cut line)
    mid = 0.5 * (lo[k] + hi[k])
    face = get_face(files["kj66"][0], 6)
    uv = ShapeAnalysis_Surface(BRep_Tool.Surface_s(face)).ValueOfUV(gp_Pnt(*map(float, mid)), 1e-9)
    p, n = gp_Pnt(), gp_Vec()
    BRepGProp_Face(face).Normal(uv.X(), uv.Y(), p, n)
    nxy = np.array([np.dot(n.Coord(), e1), np.dot(n.Coord(), e2)])
    t = prog.points[k + 1, :2] - prog.points[k, :2]
    left = t[0] * nxy[1] - t[1] * nxy[0] > 0
    assert on[0].split()[1] == ("G41" if left else "G42"), (on, t, nxy)


@pytest.mark.slow
@needs_linuxcnc
def test_the_batch_writes_each_faces_file_as_the_command_line(files, tmp_path):
    """ruled batch --post grbl: face 6's wire file beside its STEP, the command line's byte for byte (the same
    name, post and defaults)."""
    kj = files["kj66"][0]
    run = ruled_process("batch", kj, "--faces", "6", "--post", "grbl", "--no-plots", "--jobs", "1",
                        "--measure-samples", "12", "-o", tmp_path / "out", "--quiet")
    assert run.returncode == 0, run.stderr
    got = tmp_path / "out" / "kj66_impeller" / "face_6.gcode"
    rep = json.load(open(tmp_path / "out" / "kj66_impeller" / "face_6.json"))
    m = rep["machine"]
    assert m["program"]["post"] == "grbl" and m["cut"]["max"] <= m["cut"]["bound"]
    os.makedirs(tmp_path / "cli")
    cli(tmp_path, "machine", kj, "--face", 6, "--xyuv", "--post", "grbl", "-o", tmp_path / "cli" / "face_6.gcode",
        "--measure-samples", 4, "--quiet")
    assert open(got, "rb").read() == open(tmp_path / "cli" / "face_6.gcode", "rb").read()


def test_every_post_round_trips_a_path_through_its_reader(tmp_path):
    """The engine alone, for the loop: a twisted ruled quad's XYUV path (no fit) written by every wire post and read
    back by the project's reader for it (and LinuxCNC's interpreter for the LinuxCNC file, where it is installed):
    the same X Y U V, the upper guide absolute, to the post's digits; G93's times by the longer guide."""
    from ruled.core.nurbs import Surface
    from ruled.machine.output import write_checked
    from ruled.machine.paths import MachineOptions, xyuv_path
    from ruled.machine.program import PostSettings
    from ruled.machine.readback import read_program
    P = np.array([[[0.0, 0, 0], [3.0, 1, 10]], [[20.0, 0, 0], [16.0, -3, 10]]])     # rulings tilted up to 22 degrees
    R = Surface(P, np.array([0, 0, 1, 1.0]), np.array([0, 0, 1, 1.0]), 1, 1)
    path = xyuv_path(R, MachineOptions(chord_tol=0.01, feed=120.0))
    for post, digits in (("linuxcnc", 6), ("grbl", 4), ("iso-wedm", 4), ("apt-sync", 6)):
        f = tmp_path / f"quad-{post}.txt"
        out = write_checked(path, str(f), PostSettings(post=post, power=500.0), "mm", "outside")
        prog = read_program(str(f))
        got = prog.points[-len(path.moves):]
        assert got.shape == path.moves.shape and prog.post == post
        rounding = (1.0 if post in ("linuxcnc", "grbl") else 2.0) * 0.5 * 10.0 ** -digits   # (two numbers: U V, APT's)
        assert np.abs(got - path.moves).max() <= rounding + 1e-9
        if post == "linuxcnc":
            assert "G93" in f.read_text() and prog.power == 500.0
            t = prog.minutes[prog.feed_moves]
            d = np.diff(prog.points, axis=0)[prog.feed_moves - 1]
            longer = np.maximum(np.linalg.norm(d[:, :2], axis=1), np.linalg.norm(d[:, 2:], axis=1))
            assert np.allclose(t, longer / 120.0, rtol=1e-6)
            if linuxcnc.available():
                from ruled.machine.posts import load_post
                assert out["check"]["error"] is None and out["check"]["moves"] == len(path.moves)
                lc = linuxcnc.to_program(str(f), load_post("linuxcnc"))
                assert np.abs(lc.points - prog.points).max() <= 1e-9
