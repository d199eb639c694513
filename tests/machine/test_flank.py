"""Flank-milling CL data: the tool surfaces the APT moves sweep, sampled against exact distances to a
cylinder and a cone; and the refusals of machine inputs."""

from __future__ import annotations

import math
import os

import numpy as np
import pytest

from ruled.cli import main

gcodeparser = pytest.importorskip("gcodeparser")


from machine_helpers import hyp_file, parse_apt, patches, read_csv, run_cli  # noqa: E402,F401 (fixtures)

from ruled.core.nurbs import Surface  # noqa: E402
from ruled.occ.convert import container_to_face  # noqa: E402
from ruled.occ.io import write_step  # noqa: E402


def tool_cut(tip, axis, r, taper_deg, length, sd, moves=False, slices=17, angles=721):
    """Over- and undercut of the tool surfaces against a surface given by its exact signed distance sd:
    per circle along the tool, the minimum of sd over the circle (dense angles, then refined)."""
    if moves:
        tip = np.concatenate([tip, 0.5 * (tip[1:] + tip[:-1])])
        axis = np.concatenate([axis, 0.5 * (axis[1:] + axis[:-1])])
        axis = axis / np.linalg.norm(axis, axis=1)[:, None]
    ref = np.where(np.abs(axis[:, :1]) < 0.9, [[1.0, 0, 0]], [[0, 1.0, 0]])
    e1 = np.cross(axis, ref)
    e1 /= np.linalg.norm(e1, axis=1)[:, None]
    e2 = np.cross(axis, e1)
    worst_over, worst_under = 0.0, 0.0
    for s in np.linspace(0, length, slices):
        c = tip + s * axis
        rho = r + s * math.tan(math.radians(taper_deg))
        phi = np.linspace(0, 2 * np.pi, angles, endpoint=False)
        P = c[:, None] + rho * (np.cos(phi)[None, :, None] * e1[:, None] + np.sin(phi)[None, :, None] * e2[:, None])
        k = np.argmin(sd(P), axis=1)
        fine = phi[k][:, None] + np.linspace(-0.01, 0.01, 2001)[None, :]
        P = c[:, None] + rho * (np.cos(fine)[..., None] * e1[:, None] + np.sin(fine)[..., None] * e2[:, None])
        m = sd(P).min(axis=1)
        worst_over = max(worst_over, float(-m.min()))
        worst_under = max(worst_under, float(m.max()))
    return max(worst_over, 0.0), max(worst_under, 0.0)


def sd_cylinder(P):
    return np.hypot(P[..., 0], P[..., 1]) - 10.0


def sd_cone(P):
    a = math.radians(15.0)
    return (np.hypot(P[..., 0], P[..., 1]) - (10.0 + P[..., 2] * math.tan(a))) * math.cos(a)


@pytest.mark.parametrize("name", ["cylinder", "cone"])
def test_flank_developable(tmp_path, patches, name):
    chord = 1e-3
    apt, rep, _ = run_cli(tmp_path, patches[name], 0, "--flank", "--tool-radius", "3", "--chord-tol", str(chord))
    tip, axis = parse_apt(apt)
    rows = read_csv(os.path.splitext(apt)[0] + ".csv")
    assert np.allclose(tip, [[float(r[k]) for k in "xyz"] for r in rows], atol=1e-6)
    assert np.allclose(np.linalg.norm(axis, axis=1), 1.0, atol=1e-8)
    size = 20.0 * math.sqrt(2)
    sd = sd_cylinder if name == "cylinder" else sd_cone
    over, under = tool_cut(tip, axis, 3.0, 0.0, 20.0 if name == "cylinder" else 20.0 / math.cos(math.radians(15)), sd)
    assert over <= 1e-6 * size and under <= 1e-6 * size
    over_m, under_m = tool_cut(tip, axis, 3.0, 0.0, 20.0, sd, moves=True)
    assert over_m <= chord and under_m <= chord
    e = rep["tool_envelope"]
    assert e["cl_positions"]["overcut"] <= 1e-6 * size and e["cl_positions"]["undercut"] <= 1e-6 * size
    assert e["with_moves"]["overcut"] <= chord
    assert rep["machine"]["envelope_deviation"] < 1e-9 * size
    assert not rep["warnings"]
    # from the face (its OCCT points against the tool swept through the moves): within the chords, every point
    # reached; the moves turn the axis by less than the chord tolerance allows on this radius
    sw = rep["swept_tool"]
    assert sw["unreached"] == 0 and sw["points"] > 500
    assert sw["overcut"] <= chord and sw["undercut"] <= chord
    assert len(sw["per_position"]["overcut"]) == len(tip) and max(sw["per_position"]["overcut"]) == sw["overcut"]
    # the axis turns as the APT's own axes show it (the CSV per point, the report's largest)
    turn = np.degrees(np.arccos(np.clip(np.einsum("ij,ij->i", axis[1:], axis[:-1]), -1.0, 1.0)))
    csv_turn = np.array([float(r["axis_turn_deg"]) for r in rows])
    assert csv_turn[0] == 0.0 and np.allclose(csv_turn[1:], turn, atol=1e-4)
    assert sw["axis_angle_max_deg"] == pytest.approx(turn.max(), abs=1e-4)


@pytest.mark.parametrize("tip", ["auto", "second"])
def test_flank_cone_tool(tmp_path, patches, tip):
    """A conical tool (taper 5 degrees) on the cylinder: a generator of the cone lies on each ruling, with
    the tip at either end (auto: the lower)."""
    apt, rep, _ = run_cli(tmp_path, patches["cylinder"], 0, "--flank", "--tool-radius", "2", "--taper", "5",
                          "--chord-tol", "1e-3", "--method", "4d", "--tip", tip)
    assert rep["fit"]["notes"]                                        # 4d: exact already, said so
    tip_pts, axis = parse_apt(apt)
    assert np.all(axis[:, 2] > 0.99) if tip == "auto" else np.all(axis[:, 2] < -0.99)
    assert np.all(tip_pts[:, 2] < 0.0) if tip == "auto" else np.all(tip_pts[:, 2] > 20.0)
    over, under = tool_cut(tip_pts, axis, 2.0, 5.0, 20.0 * math.cos(math.radians(5)), sd_cylinder)
    assert over <= 1e-6 * 28 and under <= 1e-6 * 28
    assert rep["tool_envelope"]["cl_positions"]["overcut"] <= 1e-6 * 28


@pytest.mark.slow
def test_flank_twisted_offset_and_envelope(tmp_path, hyp_file):
    """The twisted hyperboloid, r = 1: the offset rulings (--positions offset) overcut it, as two independent
    measures agree; the positions fitted to the envelope (the default) cut it within a third of that, the
    overcut within the gouge tolerance (the fit's bound), the axis turning at most 2 degrees a move."""
    apt, rep, _ = run_cli(tmp_path, hyp_file, 0, "--flank", "--tool-radius", "1", "--chord-tol", "0.01", "--positions",
                          "offset")
    e, m = rep["tool_envelope"]["cl_positions"], rep["machine"]
    assert m["envelope_deviation"] > 0.01
    assert e["overcut"] > 0 and e["undercut"] > 0
    bound = rep["fit"]["measured"] + m["envelope_deviation"]
    assert e["overcut"] <= 1.02 * bound and e["undercut"] <= 1.02 * bound
    assert rep["tool_envelope"]["with_moves"]["overcut"] <= 1.02 * bound + m["chord_tol"]
    # the face's points against the swept tool (ruled.machine.swept) and the tool's circles against the surface
    # (tool_envelope) are two independent measures of one cut: 0.2148 and 0.2151 over; under, the circles see only
    # where their feet lie on the face (0.071), the face's points its rims too (0.139: the tool's ends hang past them)
    sw, w = rep["swept_tool"], rep["tool_envelope"]["with_moves"]
    assert sw["unreached"] == 0
    assert abs(sw["overcut"] - w["overcut"]) <= 0.03 * w["overcut"], (sw["overcut"], w["overcut"])
    assert rep["overcut"]["agree"] and rep["overcut"]["larger"] == max(sw["overcut"], w["overcut"])
    assert 0 < w["undercut"] <= 1.1 * sw["undercut"], (sw["undercut"], w["undercut"])
    offset = max(sw["overcut"], sw["undercut"])
    # issue 61: the envelope's positions, measured both ways
    (tmp_path / "env").mkdir()
    apt, rep, _ = run_cli(tmp_path / "env", hyp_file, 0, "--flank", "--tool-radius", "1")
    sw, w, pos = rep["swept_tool"], rep["tool_envelope"]["with_moves"], rep["machine"]["positions"]
    assert pos["gouge_tol"] == rep["fit"]["error_bound"] and sw["unreached"] == 0
    assert max(sw["overcut"], sw["undercut"]) <= 0.3 * offset, (sw, offset)
    assert max(w["overcut"], w["undercut"]) <= 0.3 * offset, (w, offset)
    assert sw["overcut"] <= pos["gouge_tol"] and w["overcut"] <= pos["gouge_tol"]
    turn = max(float(r["axis_turn_deg"]) for r in read_csv(os.path.splitext(apt)[0] + ".csv"))
    assert turn <= 2.0 and sw["axis_angle_max_deg"] == pytest.approx(turn, abs=1e-4)
    assert not rep["warnings"]


def test_envelope_positions_on_a_twisted_blade():
    """Issue 61 on a blade of our own (tests/cases.twisted_blade: rulings 1 long turning 40 degrees over 1.5),
    r = 0.05 (5 % of the ruling): the positions fitted to the envelope against the offset rulings, both at the
    default chords and at the same ones, measured on points of the blade the fit never saw by the swept
    measure and by this file's own distance to the tool's axis swept through the moves (32 steps a move)."""
    from cases import twisted_blade

    from ruled import FitOptions, fit_surface
    from ruled.machine.flank import MAX_TURN, machine_path
    from ruled.machine.paths import MachineOptions
    from ruled.machine.swept import swept_measure
    S = twisted_blade(40.0, 1.5)
    ends = S(np.array([0.0, 0.0, 1.0, 1.0]), np.array([0.0, 1.0, 0.0, 1.0]))
    r0, r1 = ends[1] - ends[0], ends[3] - ends[2]
    assert math.degrees(math.acos(r0 @ r1 / np.linalg.norm(r0) / np.linalg.norm(r1))) >= 30.0
    res = fit_surface(S, FitOptions())
    uu, vv = np.meshgrid(np.linspace(0, 1, 101), np.linspace(0, 1, 27), indexing="ij")
    X = S(uu.ravel(), vv.ravel())
    r = 0.05

    def cut(pos, **kw):
        p = machine_path(res.surface, S, MachineOptions("flank", tool_radius=r, positions=pos, **kw), 1.0,
                         fit_bound=res.error_bound)
        m = swept_measure(p, X)
        d = _to_tool_axes(X, p.lower, p.axes, float(np.linalg.norm(p.upper - p.lower, axis=1).min()), 32) - r
        assert m["unreached"] == 0
        return p, m, max(m["overcut"], m["undercut"]), (float(max(0.0, -d.min())), float(max(0.0, d.max())))
    env, m, dev, own = cut("envelope")
    gouge = env.stats["positions"]["gouge_tol"]
    for pos, kw in (("offset", {}), ("offset", {"chord_tol": env.chord_tol})):
        _, mo, dev_o, own_o = cut(pos, **kw)
        assert dev <= 0.3 * dev_o and max(own) <= 0.3 * max(own_o), (dev, dev_o, own, own_o)
    assert m["overcut"] <= gouge and own[0] <= gouge * 1.01, (m, own, gouge)
    assert m["axis_angle_max_deg"] <= MAX_TURN and not env.warnings


def test_flank_radius_warning(tmp_path, patches, capsys):
    """Inside the cylinder (radius 10) a tool of radius 12 gouges: warned, with where."""
    _, rep, _ = run_cli(tmp_path, patches["cylinder"], 0, "--flank", "--tool-radius", "12", "--side", "inside")
    assert any("radius of curvature" in w and "u =" in w for w in rep["warnings"])
    assert "radius of curvature" in capsys.readouterr().err


# ------------------------------------------------------------------------------------------ bad input

@pytest.mark.parametrize("args, needle", [
    pytest.param(["--xyuv", "--planes=-5,20", "--axis", "z"], "crosses ruling", marks=pytest.mark.slow),
    pytest.param(["--xyuv", "--axis", "x"], "from the machine axis", marks=pytest.mark.slow),
    (["--flank"], "--tool-radius"),
    (["--xyuv", "--kerf", "-1"], "--kerf"),
    (["--flank", "--tool-radius", "1", "--taper", "50"], "--taper"),
    (["--xyuv", "--planes", "3"], "--planes"),
    pytest.param(["--xyuv", "--chord-tol", "1e-12"], "chord", marks=pytest.mark.slow),
    (["--xyuv", "--ruled", "--method", "4d"], "give one of them"),
    (["--flank", "--tool-radius", "1", "--kerf", "0.1"], "--kerf is for --xyuv"),
    (["--flank", "--tool-radius", "1", "--gouge-tol", "-1"], "--gouge-tol"),
    (["--xyuv", "--gouge-tol", "0.1"], "--gouge-tol and --positions are for --flank"),
    (["--flank", "--tool-radius", "1", "--positions", "offset", "--gouge-tol", "0.1"], "has none to hold"),
])
def test_bad_input(tmp_path, hyp_file, capsys, args, needle):
    out = str(tmp_path / "x.ngc")
    rc = main(["machine", hyp_file, "--face", "0", *args, "-o", out, "--quiet"])
    err = capsys.readouterr().err.strip()
    assert rc == 2
    assert needle in err and len(err.splitlines()) == 1, err


def test_not_a_ruled_result(tmp_path, capsys):
    from cases import barrel
    p = str(tmp_path / "barrel.step")
    write_step(container_to_face(barrel()), p)
    rc = main(["machine", p, "--face", "0", "--xyuv", "--ruled", "-o", str(tmp_path / "b.ngc"), "--quiet"])
    err = capsys.readouterr().err.strip()
    assert rc == 2 and "not a ruled surface" in err and len(err.splitlines()) == 1


def test_empty_result():
    from ruled.core.errors import RuledError
    from ruled.machine.paths import MachineOptions, xyuv_path
    P = np.zeros((4, 2, 3))
    P[:, :, 0] = np.arange(4)[:, None]          # both rows the same curve: every ruling has no length
    R = Surface(P, [0, 0, 0, 0, 1, 1, 1, 1], [0, 0, 1, 1], 3, 1)
    with pytest.raises(RuledError, match="no length"):
        xyuv_path(R, MachineOptions())


def _inside_points(face, n: int = 48):
    """Points of the face's surface inside its edges (OCCT's classifier on an n x n grid of its bounds)."""
    from OCP.BRep import BRep_Tool
    from OCP.BRepClass import BRepClass_FaceClassifier
    from OCP.BRepTools import BRepTools
    from OCP.gp import gp_Pnt2d
    from OCP.TopAbs import TopAbs_IN
    surf = BRep_Tool.Surface_s(face)
    u0, u1, v0, v1 = BRepTools.UVBounds_s(face)
    out = []
    for u in np.linspace(u0, u1, n):
        for v in np.linspace(v0, v1, n):
            if BRepClass_FaceClassifier(face, gp_Pnt2d(u, v), 1e-9).State() == TopAbs_IN:
                out.append(surf.Value(u, v).Coord())
    return np.array(out)


def _to_tool_axes(P, tip, axis, length, per_move: int = 8, r=None):
    """Each point's distance to the tool's axis swept through the moves (tip and axis direction linear
    between CL positions, per_move steps each), the axis a segment of the tool's length from its tip.  With r:
    the signed distance to the flat-ended cylinder of radius r instead (negative: inside it, by its depth;
    a point past the tool's tip or top is not inside, however near the axis)."""
    f = np.arange(per_move) / per_move
    T = (tip[:-1, None] + f[None, :, None] * (tip[1:] - tip[:-1])[:, None]).reshape(-1, 3)
    A = (axis[:-1, None] + f[None, :, None] * (axis[1:] - axis[:-1])[:, None]).reshape(-1, 3)
    T, A = np.concatenate([T, tip[-1:]]), np.concatenate([A, axis[-1:]])
    A /= np.linalg.norm(A, axis=1)[:, None]
    best = np.full(len(P), np.inf)
    for i in range(0, len(T), 200):
        d = P[:, None] - T[None, i:i + 200]
        h0 = np.einsum("pkc,kc->pk", d, A[i:i + 200])
        h = np.clip(h0, 0.0, length)
        if r is None:
            best = np.minimum(best, np.linalg.norm(d - h[..., None] * A[None, i:i + 200], axis=2).min(axis=1))
            continue
        rad = np.linalg.norm(d - h0[..., None] * A[None, i:i + 200], axis=2)
        inside = (h0 >= 0.0) & (h0 <= length) & (rad <= r)
        out = np.hypot(np.maximum(rad - r, 0.0), h0 - h)
        depth = np.minimum(np.minimum(r - rad, h0), length - h0)
        best = np.minimum(best, np.where(inside, -depth, out).min(axis=1))
    return best


@pytest.mark.slow
def test_flank_on_a_trimmed_face_reports_the_cut_of_the_face(tmp_path):
    """Flank milling kj66 face 6 from its trimmed result (rulings that cross the face's end edges, the tool
    running past them): the over- and undercut it reports are against the face as bounded by its edges,
    and agree with what the APT's tool, swept through its moves, does to the face's own points (OCCT's
    surface inside its edges): the tool's surface is never deeper than the reported overcut past any face
    point, no face point farther from it than the reported undercut plus the moves' chord, both within
    the report's bound."""
    from conftest import data_file

    from ruled.occ.io import faces_of, read_shape
    src = data_file("kj66_impeller.step")
    r = 0.05
    apt, rep, _ = run_cli(tmp_path, src, 6, "--flank", "--tool-radius", str(r), "--samples", "30")
    assert "trimmed" in rep["machine"]                  # the rulings that cross the face, past its end edges
    e = rep["tool_envelope"]
    # issue 55: at its CL points, the tool against the bounded face within the trimmed fit's bound + 1e-5
    assert max(e["cl_positions"]["overcut"], e["cl_positions"]["undercut"]) <= rep["fit"]["error_bound"] + 1e-5
    assert e["against"].startswith("the face as bounded by its edges")
    tip, axis = parse_apt(apt)
    with open(apt) as fh:
        length = float(next(ln for ln in fh if ln.startswith("CUTTER/")).split(",")[-1])
    P = _inside_points(faces_of(read_shape(src))[6])
    d = _to_tool_axes(P, tip, axis, length, 32) - r    # > 0: material left at the point; < 0: the tool past it
    over, under = float(max(0.0, -d.min())), float(max(0.0, d.max()))
    chord, sw = rep["machine"]["chord_tol"], rep["swept_tool"]
    assert over <= max(e["with_moves"]["overcut"], sw["overcut"]) * 1.05 + 1e-6
    assert under <= max(e["with_moves"]["undercut"], sw["undercut"]) + chord
    # the tool positions fitted to the face's envelope: the overcut within the gouge tolerance (the fit's bound)
    gouge = rep["machine"]["positions"]["gouge_tol"]
    assert gouge == rep["fit"]["error_bound"] and over <= gouge and sw["overcut"] <= gouge
    # (issue 61: no worse than the offset rulings, whose moves cut 0.0017 into face 6, three times its bound)
    assert max(sw["overcut"], sw["undercut"]) <= rep["fit"]["error_bound"], sw
    # the same through ruled.cq from the RuledFit the user has: the tool follows that fit
    import ruled.cq as rcq
    face = faces_of(read_shape(src))[6]
    fit = rcq.fit_face(face, samples=30, measure_samples=12)
    mill = rcq.flank_face(face, r, fit=fit, measure_samples=12)
    cl = mill.report["tool_envelope"]["cl_positions"]
    assert mill.report["fit"]["error_bound"] == fit.error_bound and "trimmed" in mill.report["machine"]
    assert max(cl["overcut"], cl["undercut"]) <= fit.error_bound + 1e-5, cl


@pytest.mark.slow
@pytest.mark.parametrize("r", [1.0, 3.0])
def test_envelope_positions_on_a_bumped_twisted_face(tmp_path, r):
    """Issue 72: a 15-degree twisted strip with a 0.05 Gaussian bump (tests/cases.bumped_twist), tools r = 1 and 3:
    the envelope positions' overcut within the gouge tolerance by both of the report's measures and by this
    file's own (OCCT's points inside the face against the APT's tool axes swept at 32 steps a move), or a
    warning naming both figures; and never worse than the offset rulings by any of them."""
    from cases import bumped_twist

    from ruled.occ.io import faces_of, read_shape
    src = str(tmp_path / "bump.step")
    write_step(container_to_face(bumped_twist()), src)
    P = _inside_points(faces_of(read_shape(src))[0], 40)
    figs = {}
    for pos in ("envelope", "offset"):
        apt, rep, _ = run_cli(tmp_path, src, 0, "--flank", "--tool-radius", str(r), "--positions", pos,
                              "--samples", "20", "--measure-samples", "20", name=pos)
        tip, axis = parse_apt(apt)
        with open(apt) as fh:
            length = float(next(ln for ln in fh if ln.startswith("CUTTER/")).split(",")[-1])
        own = float(max(0.0, -_to_tool_axes(P, tip, axis, length, 32, r).min()))
        oc = rep["overcut"]
        assert oc["larger"] == max(oc["swept_tool"], oc["tool_envelope"])
        figs[pos] = (oc["swept_tool"], oc["tool_envelope"], own, rep)
    sw, en, own, rep = figs["envelope"]
    gouge = rep["machine"]["positions"]["gouge_tol"]
    said = [w for w in rep["warnings"] if "past the gouge tolerance" in w]
    if max(sw, en) > gouge:
        assert said and f"{sw:.3g}" in said[0] and f"{en:.3g}" in said[0], rep["warnings"]
    else:
        assert not said and own <= gouge * 1.02, (own, gouge)
    for k in range(3):      # (the offset rulings cut into the bump's flanks several times deeper)
        assert figs["envelope"][k] <= figs["offset"][k], (k, figs["envelope"][:3], figs["offset"][:3])


def test_the_tool_envelope_counts_only_the_circles_kept():
    """tool_envelope's keep(s, t) on a twisted bilinear patch (its own design): keeping every circle is the
    whole measure; keeping none gives no cut and no samples; keeping the half of the tool from its tip
    counts that half's circles only (9 of 17 per position, half way through the moves too, but the circles
    past the patch's edges), and its cut is no deeper than the whole tool's."""
    from ruled.machine.envelope import tool_envelope
    from ruled.machine.flank import flank_path
    from ruled.machine.paths import MachineOptions
    P = np.array([[[0.0, 0, 0], [0, 10, 0]], [[10, 0, 0], [10, 10, 4]]])
    R = Surface(P, [0.0, 0, 1, 1], [0.0, 0, 1, 1], 1, 1)
    path = flank_path(R, MachineOptions("flank", chord_tol=0.01, tool_radius=1.0).checked())
    rows = 2 * path.lower.shape[0] - 1
    whole = tool_envelope(R, 1.0, path)
    assert tool_envelope(R, 1.0, path, keep=lambda s, t: np.ones(s.shape, bool)) == whole
    none = tool_envelope(R, 1.0, path, keep=lambda s, t: np.zeros(s.shape, bool))
    assert none["samples"] == 0 and none["with_moves"]["overcut"] == none["with_moves"]["undercut"] == 0.0
    half = tool_envelope(R, 1.0, path, keep=lambda s, t: t <= 0.5)
    # (every circle counts but those whose deepest point lies past the patch's edge, its foot held there)
    # (and the half is of each position's own line, the circles spaced along the tool's whole length)
    assert 0.8 * 17 * rows <= whole["samples"] <= 17 * rows and 0.6 * 9 * rows <= half["samples"] <= 9 * rows
    assert whole["with_moves"]["overcut"] > 0
    for k in ("overcut", "undercut"):
        assert half["with_moves"][k] <= whole["with_moves"][k]
        assert half["cl_positions"][k] <= whole["cl_positions"][k]


def test_swept_tool_distances_by_hand():
    """ruled.machine.swept on moves worked out by hand: a cylinder (r = 2, axis z, 10 long) moved from x = 0 to
    x = 10 sweeps a slab |y| <= 2 over 0 <= x <= 10 (round at its ends): a point at y = 2 + d is d from it,
    at y = 2 - d inside it by d; past the tool's tip nothing reaches it.  A cone (taper 10 degrees, tip radius
    1) standing still: a point off its side by d, along the side's normal, is d away."""
    from ruled.machine.paths import MachinePath
    from ruled.machine.swept import swept_distances, swept_measure

    def path(lower, upper, r, taper):
        lower, upper = np.asarray(lower, float), np.asarray(upper, float)
        return MachinePath("flank", np.arange(len(lower), dtype=float), lower, upper,
                           np.stack([lower, upper], axis=1), False, 0.01, 0.0, radius=r, taper_deg=taper)
    p = path([[0, 0, 0], [10, 0, 0]], [[0, 0, 10], [10, 0, 10]], 2.0, 0.0)
    X = np.array([[5, 2.3, 5], [5, 1.6, 2], [3.33, -2.0, 9.5], [12.0, 0, 5], [5, 2.5, -1.0]])
    d, at = swept_distances(p, X, steps=8)
    assert np.allclose(d[:4], [0.3, -0.4, 0.0, 0.0], atol=1e-12) and at[3] == 1
    assert at[4] == -1 and np.isinf(d[4])
    m = swept_measure(p, X)
    assert m["unreached"] == 1 and m["overcut"] == pytest.approx(0.4) and m["undercut"] == pytest.approx(0.3)
    assert m["axis_angle_max_deg"] == 0.0
    a = math.radians(10.0)
    c = path([[0, 0, 0]], [[0, 0, 10]], 1.0, 10.0)
    side = np.array([1.0 + 6.0 * math.tan(a), 0.0, 6.0])                 # on the side, 6 up the axis
    nrm = np.array([math.cos(a), 0.0, -math.sin(a)])
    d, _ = swept_distances(c, np.array([side + 0.05 * nrm, side - 0.05 * nrm, side]))
    assert np.allclose(d, [0.05, -0.05, 0.0], atol=1e-12)
