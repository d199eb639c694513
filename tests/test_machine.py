"""Machine outputs (XYUV wire contours, flank-milling CL data) measured independently of ruled.machine:
the G-code is read back by an independent parser from PyPI (gcodeparser), the surface the machine sweeps
is rebuilt from the parsed moves alone and measured with OCCT against the design face (or its OCCT offset
surface), the contours are checked against the ruled result's trace computed from the CAM STEP file
with OCCT evaluation, and the flank tool surfaces are sampled against exact distances to a cylinder and
a cone."""

from __future__ import annotations

import csv
import json
import math
import os
import runpy
import shutil

import numpy as np
import pytest

from conftest import ROOT, data_file
from cases import hyperboloid
from ruled.cli import main

gcodeparser = pytest.importorskip("gcodeparser")

from OCP.BRep import BRep_Tool  # noqa: E402
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace  # noqa: E402
from OCP.BRepTools import BRepTools  # noqa: E402
from OCP.Geom import Geom_Line, Geom_OffsetSurface  # noqa: E402
from OCP.GeomAPI import GeomAPI_ExtremaCurveCurve  # noqa: E402
from OCP.TopAbs import TopAbs_REVERSED  # noqa: E402
from OCP.gp import gp_Ax3, gp_Cone, gp_Cylinder, gp_Dir, gp_Lin, gp_Pnt  # noqa: E402

from ruled.nurbs import Surface  # noqa: E402
from ruled.occ.convert import container_to_face  # noqa: E402
from ruled.occ.io import faces_of, get_face, read_shape, write_step  # noqa: E402
from ruled.occ.measure import _Projector, face_points, hausdorff, two_sided  # noqa: E402


# ------------------------------------------------------------------------------------------- helpers

def parse_moves(path):
    """Every motion line of a G-code file through gcodeparser: (command, X, Y, U, V, F)."""
    with open(path) as fh:
        lines = list(gcodeparser.parse_gcode_lines(fh.read()))
    moves = []
    for ln in lines:
        if ln.command[0] == "G" and ln.command[1] in (0, 1, 2, 3):
            moves.append((ln.command[1], ln.params))
    return moves


def read_csv(path):
    with open(path) as fh:
        return list(csv.DictReader(fh))


def run_cli(tmp_path, face_file, face, *args, name="out"):
    out = str(tmp_path / f"{name}.ngc") if "--xyuv" in args else str(tmp_path / f"{name}.apt")
    rep = str(tmp_path / f"{name}.json")
    cam = str(tmp_path / f"{name}-cam.step")
    rc = main(["machine", face_file, "--face", str(face), *args, "-o", out, "--report", rep, "--step", cam,
               "--quiet"])
    assert rc == 0
    with open(rep) as fh:
        return out, json.load(fh), cam


def check_sync(ngc, csv_path):
    """Every motion line moves X, Y, U and V together (F on every G1); the parsed moves equal the CSV."""
    moves = parse_moves(ngc)
    assert moves and moves[0][0] == 0
    for cmd, p in moves:
        assert {"X", "Y", "U", "V"} <= set(p), p
        if cmd == 1:
            assert "F" in p
    parsed = np.array([[p[k] for k in "XYUV"] for _, p in moves])
    rows = read_csv(csv_path)
    table = np.array([[float(r[k]) for k in "XYUV"] for r in rows])
    assert parsed.shape == table.shape
    assert np.array_equal(parsed, table)
    kinds = [r["kind"] for r in rows]
    return parsed, kinds


def lines_3d(parsed, rep):
    """The wire's lines (lower, upper 3D points) rebuilt from the parsed moves and the report's frame."""
    fr = rep["machine"]["frame"]
    e1, e2, ax = (np.array(fr[k]) for k in ("e1", "e2", "axis"))
    h0, h1 = rep["machine"]["plane_heights"]
    lo = parsed[:, :1] * e1 + parsed[:, 1:2] * e2 + h0 * ax
    hi = parsed[:, 2:3] * e1 + parsed[:, 3:4] * e2 + h1 * ax
    return lo, hi


def rect_face(face):
    """The face's surface over its (u, v) bounds (what the fit covers), its outside sign, its bounds."""
    surf = BRep_Tool.Surface_s(face)
    u0, u1, v0, v1 = BRepTools.UVBounds_s(face)
    sign = -1.0 if face.Orientation() == TopAbs_REVERSED else 1.0
    return BRepBuilderAPI_MakeFace(surf, u0, u1, v0, v1, 1e-7).Face(), surf, sign, (u0, u1, v0, v1)


def rebuilt_error(target, face, lo, hi, direction, n=40):
    """Two-sided distance between the target face and what the wire cuts, rebuilt from the parsed moves
    alone: samples of the target projected (OCCT) onto the surface of straight lines between the
    synchronized pairs, plane to plane; and points of those lines inside the part projected onto the
    target.  The part's ends on each exported line are its closest points to the two boundary curves
    its ruling joins (OCCT extrema on the face's surface); between two exported lines, the lines that
    the machine interpolates, with their ends' fractions of the line interpolated."""
    _, surf, _, (u0, u1, v0, v1) = rect_face(face)
    isos = [surf.VIso(v0), surf.VIso(v1)] if direction == "v" else [surf.UIso(u0), surf.UIso(u1)]
    d = hi - lo
    frac = np.zeros((len(lo), 2))
    for i, (a, b) in enumerate(zip(lo, hi)):
        line = Geom_Line(gp_Lin(gp_Pnt(*a), gp_Dir(*(b - a))))
        for k, c in enumerate(isos):
            ex = GeomAPI_ExtremaCurveCurve(line, c)
            assert ex.NbExtrema() > 0
            frac[i, k] = ex.LowerDistanceParameters()[0] / np.linalg.norm(b - a)
    s = np.linspace(0, 1, 4, endpoint=False)
    t = np.linspace(0, 1, 11)
    pts = []
    for i in range(len(lo) - 1):
        a = lo[i] + s[:, None] * (lo[i + 1] - lo[i])
        b = a + (d[i] + s[:, None] * (d[i + 1] - d[i]))
        f = frac[i] + s[:, None] * (frac[i + 1] - frac[i])
        g = f[:, :1] + t[None, :] * (f[:, 1:] - f[:, :1])
        pts.append((a[:, None] + g[..., None] * (b - a)[:, None]).reshape(-1, 3))
    pts.append(lo[-1] + (frac[-1, 0] + t[:, None] * (frac[-1, 1] - frac[-1, 0])) * d[-1])
    m = len(lo)
    swept = container_to_face(Surface(np.stack([lo, hi], axis=1), np.concatenate([[0.0], np.arange(m, dtype=float),
                                                                                  [m - 1.0]]),
                                      [0.0, 0.0, 1.0, 1.0], 1, 1))
    return two_sided(face_points(target, n), np.concatenate(pts), _Projector(target), _Projector(swept))


def trace_deviation(cam_step, parsed_cut, rep):
    """Largest distance between each exported contour and the trace of the ruled result on its plane
    (the result read from the CAM STEP file and evaluated by OCCT at 4000 rulings), both ways."""
    faces = faces_of(read_shape(cam_step))
    surf = BRep_Tool.Surface_s(faces[0])
    u0, u1, v0, v1 = BRepTools.UVBounds_s(faces[0])
    us = np.linspace(u0, u1, 4001)
    A = np.array([surf.Value(u, v0).Coord() for u in us])
    B = np.array([surf.Value(u, v1).Coord() for u in us])
    fr = rep["machine"]["frame"]
    e1, e2, ax = (np.array(fr[k]) for k in ("e1", "e2", "axis"))
    worst = 0.0
    for k, h in enumerate(rep["machine"]["plane_heights"]):
        s = ((h - A @ ax) / ((B - A) @ ax))[:, None]
        T = A + s * (B - A)
        T2 = np.stack([T @ e1, T @ e2], axis=1)
        C = parsed_cut[:, 2 * k:2 * k + 2]
        worst = max(worst, _to_polyline(T2, C), _to_polyline(_densify(C), T2))
    return worst


def _densify(C, k=8):
    s = np.linspace(0, 1, k, endpoint=False)
    return np.concatenate([C[:-1, None] + s[None, :, None] * (C[1:] - C[:-1])[:, None]], axis=0).reshape(-1, 2)


def _to_polyline(X, C):
    a, b = C[:-1], C[1:]
    ab = b - a
    L2 = np.maximum((ab * ab).sum(1), 1e-300)
    best = np.full(len(X), np.inf)
    for i in range(0, len(X), 500):
        x = X[i:i + 500, None]
        t = np.clip(((x - a) * ab).sum(-1) / L2, 0, 1)
        d = np.linalg.norm(x - (a + t[..., None] * ab), axis=-1).min(axis=1)
        best[i:i + 500] = d
    return float(best.max())


def fit_error(face, cam_step, n=30):
    """The fit's error measured here: the ruled result of the CAM STEP file against the design face."""
    return hausdorff(rect_face(face)[0], faces_of(read_shape(cam_step))[0], n).max


def xyuv_round_trip(tmp_path, face_file, face_index, chord, kerf=0.0, name="out"):
    args = ["--xyuv", "--chord-tol", str(chord)] + (["--kerf", str(kerf)] if kerf else [])
    ngc, rep, cam = run_cli(tmp_path, face_file, face_index, *args, name=name)
    parsed, kinds = check_sync(ngc, os.path.splitext(ngc)[0] + ".csv")
    cut = parsed[[k == "cut" for k in kinds]]
    face = get_face(face_file, face_index)
    lo, hi = lines_3d(cut, rep)
    design, surf, sign, (u0, u1, v0, v1) = rect_face(face)
    if kerf:
        design = BRepBuilderAPI_MakeFace(Geom_OffsetSurface(surf, sign * kerf), u0, u1, v0, v1, 1e-7).Face()
    h = rebuilt_error(design, face, lo, hi, rep["fit"]["direction"])
    fit = fit_error(face, cam)
    return dict(rep=rep, cut=cut, cam=cam, h=h, fit=fit, kinds=kinds, chord=chord, ngc=ngc)


@pytest.fixture(scope="module")
def hyp_file(tmp_path_factory):
    p = str(tmp_path_factory.mktemp("hyp") / "hyperboloid.step")
    write_step(container_to_face(hyperboloid(10.0, 10.0, 10.0)), p)
    return p


@pytest.fixture(scope="module")
def patches(tmp_path_factory):
    d = tmp_path_factory.mktemp("patches")
    ax = gp_Ax3(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1))
    out = {}
    for name, surf in (("cylinder", gp_Cylinder(ax, 10.0)), ("cone", gp_Cone(ax, math.radians(15.0), 10.0))):
        p = str(d / f"{name}.step")
        write_step(BRepBuilderAPI_MakeFace(surf, 0.0, math.pi / 2, 0.0, 20.0).Face(), p)
        out[name] = p
    return out


# --------------------------------------------------------------------------------------------- XYUV

def test_xyuv_hyperboloid_round_trip(tmp_path, hyp_file):
    """An exactly ruled closed surface: the rebuilt cut is within the chord tolerance (the fit is exact)."""
    r = xyuv_round_trip(tmp_path, hyp_file, 0, 0.01)
    rep, h = r["rep"], r["h"]
    assert rep["fit"]["closed"] and r["fit"] < 1e-9
    assert np.allclose(r["cut"][0], r["cut"][-1], atol=1e-6)       # the closed contour returns to its start
    assert r["kinds"][0] == "lead-in" and r["kinds"][-1] == "lead-out"
    moves = np.array([[float(x[k]) for k in "XYUV"] for x in read_csv(os.path.splitext(r["ngc"])[0] + ".csv")])
    for k in (0, 2):                                                    # both leads start outside the part
        r_lead = np.hypot(*moves[[0, -1], k:k + 2].T)
        assert np.all(r_lead > np.hypot(*r["cut"][:, k:k + 2].T).max() + 1.0)
    assert h.max <= r["fit"] + r["chord"]
    assert h.max > 0.05 * r["chord"]                                  # the chords are really used
    assert trace_deviation(r["cam"], r["cut"], rep) <= r["chord"] * (1 + 1e-6)
    assert abs(rep["cut"]["max"] - h.max) <= 0.2 * r["chord"]          # the report's own measure agrees
    assert rep["machine"]["sync_points"] == len(r["cut"])
    assert abs(rep["machine"]["max_taper_deg"] - 45.0) < 0.1         # the hyperboloid's rulings: 45 degrees


def test_xyuv_hyperboloid_kerf(tmp_path, hyp_file):
    r = xyuv_round_trip(tmp_path, hyp_file, 0, 0.01, kerf=0.01, name="kerf")
    assert r["h"].max <= r["fit"] + r["chord"]
    assert 0 < r["rep"]["machine"]["offset_deviation"] < 0.5 * r["chord"]
    # the wire runs outside: every lower point is farther from the axis than the design's bottom circle
    lo, _ = lines_3d(r["cut"], r["rep"])
    assert np.all(np.hypot(lo[:, 0], lo[:, 1]) > 14.0)


@pytest.mark.slow
def test_xyuv_blade_round_trip(tmp_path):
    path = data_file("kj66_impeller.step")
    r = xyuv_round_trip(tmp_path, path, 6, 0.002)
    assert r["h"].max <= r["fit"] * (1 + 1e-3) + r["chord"]
    assert trace_deviation(r["cam"], r["cut"], r["rep"]) <= r["chord"] * (1 + 1e-6)
    k = xyuv_round_trip(tmp_path, path, 6, 0.005, kerf=0.005, name="kerf")
    assert k["rep"]["machine"]["offset_deviation"] < 0.5 * k["chord"]
    assert k["h"].max <= k["fit"] * (1 + 1e-3) + k["chord"]
    # the report measures the cut against the trimmed face offset by the kerf (not its surface's rectangle)
    assert k["rep"]["cut"]["max"] <= k["rep"]["cut"]["bound"] and k["rep"]["cut"]["max"] <= 2 * k["fit"] + k["chord"]


def test_xyuv_planes_given(tmp_path, hyp_file):
    ngc, rep, _ = run_cli(tmp_path, hyp_file, 0, "--xyuv", "--planes", "12,-11", "--axis", "z", "--lead", "0")
    assert rep["machine"]["plane_heights"] == [-11.0, 12.0]     # given as 12,-11: sorted
    parsed, kinds = check_sync(ngc, os.path.splitext(ngc)[0] + ".csv")
    assert len(parsed) == rep["machine"]["sync_points"] and set(kinds) == {"cut"}     # no leads


def test_xyuv_of_a_ruled_result(tmp_path, hyp_file):
    """A ruled result of Ruled (here 'ruled fit' of the hyperboloid) is machined as it is (--ruled)."""
    fits = str(tmp_path / "fit.step")
    assert main(["fit", hyp_file, "--face", "0", "-o", fits, "--quiet"]) == 0
    ngc, rep, _ = run_cli(tmp_path, fits, "all", "--xyuv", "--ruled", "--chord-tol", "0.01")
    assert rep["fit"]["method"].startswith("given") and rep["cut"]["max"] <= 0.01
    # one patch; the hyperboloid x^2 + y^2 - z^2 = 10^2 is not developable: along a ruling (45 degrees) from
    # z = -10 to 10 its tangent plane turns by 2 atan(s / b), s = 10 sqrt 2 from the waist, b = 10
    assert len(rep["patches"]) == 1
    assert rep["patches"][0]["twist_deg"] == pytest.approx(2 * math.degrees(math.atan(math.sqrt(2))), abs=1.0)
    parsed, kinds = check_sync(ngc, os.path.splitext(ngc)[0] + ".csv")
    lo, hi = lines_3d(parsed[[k == "cut" for k in kinds]], rep)
    design = container_to_face(hyperboloid(10.0, 10.0, 10.0))
    assert rebuilt_error(design, design, lo, hi, "v", 30).max <= 0.01
    # a fit that is not a surface of revolution (Elber's ex2): the wire against the ruled result itself
    from ruled.examples import elber_ex2
    src, fits = str(tmp_path / "ex2.step"), str(tmp_path / "ex2-fit.step")
    write_step(container_to_face(elber_ex2()), src)
    assert main(["fit", src, "--face", "0", "-o", fits, "--quiet"]) == 0
    ngc, rep, _ = run_cli(tmp_path, fits, 0, "--xyuv", "--ruled", name="ex2")
    chord = rep["machine"]["chord_tol"]
    parsed, kinds = check_sync(ngc, os.path.splitext(ngc)[0] + ".csv")
    lo, hi = lines_3d(parsed[[k == "cut" for k in kinds]], rep)
    result = get_face(fits, 0)
    assert rebuilt_error(result, result, lo, hi, "v", 30).max <= chord
    assert rep["cut"]["max"] <= chord


def test_fit_cone_machine_chain(tmp_path, capsys):
    """A face that is not ruled, fitted and cone-splined ('ruled cone --fit'), then its patches machined
    as one wire path ('ruled machine --face all --ruled'): the G-code's lines, rebuilt from the parsed
    moves, lie within the fit's bound + the cone tolerance + the chord tolerance of the design face
    (OCCT projection) and cover it; each patch's taper is what the lines show, and a cone patch has no
    twist along the wire."""
    from cases import bumped_cone
    design, cone, cone_rep = (str(tmp_path / n) for n in ("design.step", "cone.step", "cone.json"))
    face = container_to_face(bumped_cone())
    write_step(face, design)
    tol, chord = 0.01, 0.002
    assert main(["cone", design, "--face", "0", "--fit", "--tol", str(tol), "-o", cone, "--report", cone_rep,
                 "--quiet"]) == 0
    with open(cone_rep) as fh:
        fit_bound = json.load(fh)["fit"]["error_bound"]
    n_patches = len(faces_of(read_shape(cone)))
    assert n_patches >= 2
    ngc, rep, _ = run_cli(tmp_path, cone, "all", "--xyuv", "--ruled", "--axis", "z", "--chord-tol", str(chord))
    assert rep["face"] == list(range(n_patches)) and len(rep["patches"]) == n_patches
    parsed, kinds = check_sync(ngc, os.path.splitext(ngc)[0] + ".csv")
    lo, hi = lines_3d(parsed[[k == "cut" for k in kinds]], rep)
    d = (hi - lo) / np.linalg.norm(hi - lo, axis=1)[:, None]
    angles = np.degrees(np.arccos(d[:, 2]))
    lows = [p["taper_min_deg"] for p in rep["patches"]]
    highs = [p["taper_max_deg"] for p in rep["patches"]]
    assert min(lows) - 0.05 <= angles.min() and angles.max() <= max(highs) + 0.05
    assert 44.0 < min(lows) and max(highs) < 46.0            # the cone r = 10 - z: 45 degrees
    assert max(p["twist_deg"] for p in rep["patches"]) < 1e-5
    # the lines between the face's heights z = 0 and 3, against the design face; and the face against them
    s = np.linspace(0, 1, 41)
    pts = (lo[:, None] + s[None, :, None] * (hi - lo)[:, None]).reshape(-1, 3)
    pts = pts[(pts[:, 2] >= 0) & (pts[:, 2] <= 3)]
    bound = fit_bound + tol + chord
    assert _Projector(face).distances(pts).max() <= bound
    swept = BRepBuilderAPI_MakeFace(_bilinear(lo, hi), 1e-7).Face()
    assert _Projector(swept).distances(face_points(face, 20)).max() <= bound
    # patches that do not follow one another, and several faces without --ruled, are refused in one line
    capsys.readouterr()
    for face_arg, extra, needle in (("0,2", ["--ruled"], "face 2 does not start where face 0 ends"),
                                    ("all", [], "add --ruled")):
        out = str(tmp_path / "x.ngc")
        rc = main(["machine", cone, "--face", face_arg, "--xyuv", *extra, "-o", out, "--quiet"])
        err = capsys.readouterr().err.strip()
        assert rc == 2 and needle in err and len(err.splitlines()) == 1, err
        assert not os.path.exists(out)


def test_patches_join_exactly_whichever_way_they_run():
    """Three rational ruled patches in a row, given reversed in u or t: the joined surface is each patch,
    point for point, and patches that do not meet are refused."""
    from ruled.chain import join_patches
    rng = np.random.default_rng(7)
    ends = [rng.normal(size=(2, 3)) for _ in range(4)]          # the rulings where the patches meet
    patches, plain = [], []
    for k in range(3):
        P = np.stack([ends[k], rng.normal(size=(2, 3)), ends[k + 1]])          # (3, 2, 3): degree 2 along u
        W = np.array([[1.0, 1.0], [0.6 + k, 0.6 + k], [1.0, 1.0]])
        R = Surface(P, [0, 0, 0, 1, 1, 1], [0, 0, 1, 1], 2, 1, W)
        plain.append(R)
        if k == 1:
            R = Surface(P[::-1].copy(), [0, 0, 0, 1, 1, 1], [0, 0, 1, 1], 2, 1, W[::-1].copy())     # backwards
        if k == 2:
            R = Surface(P[:, ::-1].copy(), [0, 0, 0, 1, 1, 1], [0, 0, 1, 1], 2, 1, W[:, ::-1].copy())  # t flipped
        patches.append(R)
    J, sign = join_patches(patches)
    assert sign == 1.0 and J.domain[:2] == (0.0, 3.0)
    s, t = np.meshgrid(np.linspace(0, 1, 9), np.linspace(0, 1, 5), indexing="ij")
    for k, R in enumerate(plain):
        assert np.abs(J(k + s.ravel(), t.ravel()) - R(s.ravel(), t.ravel())).max() < 1e-12
    from ruled.errors import BadInputError
    with pytest.raises(BadInputError, match="patch 1 does not start where patch 0 ends"):
        join_patches([plain[0], plain[2]])


def _bilinear(lo, hi):
    """The surface the wire sweeps between consecutive lines, as an OCCT degree 1 x 1 B-spline."""
    from OCP.Geom import Geom_BSplineSurface
    from OCP.TColgp import TColgp_Array2OfPnt
    from OCP.TColStd import TColStd_Array1OfInteger, TColStd_Array1OfReal
    n = len(lo)
    P = TColgp_Array2OfPnt(1, n, 1, 2)
    for i in range(n):
        P.SetValue(i + 1, 1, gp_Pnt(*lo[i]))
        P.SetValue(i + 1, 2, gp_Pnt(*hi[i]))
    ku, mu = TColStd_Array1OfReal(1, n), TColStd_Array1OfInteger(1, n)
    for i in range(n):
        ku.SetValue(i + 1, float(i))
        mu.SetValue(i + 1, 2 if i in (0, n - 1) else 1)
    kv, mv = TColStd_Array1OfReal(1, 2), TColStd_Array1OfInteger(1, 2)
    for j in range(2):
        kv.SetValue(j + 1, float(j))
        mv.SetValue(j + 1, 2)
    return Geom_BSplineSurface(P, ku, kv, mu, mv, 1, 1)


# ---------------------------------------------------------------------------------------------- flank

def parse_apt(path):
    tip, axis = [], []
    with open(path) as fh:
        for ln in fh:
            if ln.startswith("GOTO/"):
                v = [float(x) for x in ln[5:].split(",")]
                tip.append(v[:3])
                axis.append(v[3:])
    return np.array(tip), np.array(axis)


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


def test_flank_twisted_reported(tmp_path, hyp_file):
    apt, rep, _ = run_cli(tmp_path, hyp_file, 0, "--flank", "--tool-radius", "1", "--chord-tol", "0.01")
    e, m = rep["tool_envelope"]["cl_positions"], rep["machine"]
    assert m["envelope_deviation"] > 0.01
    assert e["overcut"] > 0 and e["undercut"] > 0
    bound = rep["fit"]["measured"] + m["envelope_deviation"]
    assert e["overcut"] <= 1.02 * bound and e["undercut"] <= 1.02 * bound
    assert rep["tool_envelope"]["with_moves"]["overcut"] <= 1.02 * bound + m["chord_tol"]


def test_flank_radius_warning(tmp_path, patches, capsys):
    """Inside the cylinder (radius 10) a tool of radius 12 gouges: warned, with where."""
    _, rep, _ = run_cli(tmp_path, patches["cylinder"], 0, "--flank", "--tool-radius", "12", "--side", "inside")
    assert any("radius of curvature" in w and "u =" in w for w in rep["warnings"])
    assert "radius of curvature" in capsys.readouterr().err


# ------------------------------------------------------------------------------------------ bad input

@pytest.mark.parametrize("args, needle", [
    (["--xyuv", "--planes=-5,20", "--axis", "z"], "crosses ruling"),
    (["--xyuv", "--axis", "x"], "from the machine axis"),
    (["--flank"], "--tool-radius"),
    (["--xyuv", "--kerf", "-1"], "--kerf"),
    (["--flank", "--tool-radius", "1", "--taper", "50"], "--taper"),
    (["--xyuv", "--planes", "3"], "--planes"),
    (["--xyuv", "--chord-tol", "1e-12"], "chord"),
    (["--xyuv", "--ruled", "--method", "4d"], "give one of them"),
    (["--flank", "--tool-radius", "1", "--kerf", "0.1"], "--kerf is for --xyuv"),
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
    from ruled.errors import RuledError
    from ruled.machine import MachineOptions, xyuv_path
    P = np.zeros((4, 2, 3))
    P[:, :, 0] = np.arange(4)[:, None]          # both rows the same curve: every ruling has no length
    R = Surface(P, [0, 0, 0, 0, 1, 1, 1, 1], [0, 0, 1, 1], 3, 1)
    with pytest.raises(RuledError, match="no length"):
        xyuv_path(R, MachineOptions())


# --------------------------------------------------------------------------------------------- CadQuery

def _readme_example() -> str:
    with open(os.path.join(ROOT, "README.md")) as fh:
        s = fh.read()
    i = s.index("<!-- example: cadquery-gcode -->")
    j = s.index("```python", i) + len("```python")
    return s[j:s.index("```", j)]


@pytest.mark.slow
def test_readme_cadquery_example(tmp_path, monkeypatch):
    pytest.importorskip("cadquery")
    import cadquery as cq
    from ruled.cq import WORKPLANE_METHODS, unregister
    src = data_file("kj66_impeller.step")
    os.makedirs(tmp_path / "tests" / "data")
    shutil.copy(src, tmp_path / "tests" / "data" / "kj66_impeller.step")
    script = tmp_path / "example.py"
    script.write_text(_readme_example())
    monkeypatch.chdir(tmp_path)
    try:
        runpy.run_path(str(script), run_name="__main__")
        assert all(hasattr(cq.Workplane, k) for k in WORKPLANE_METHODS)
    finally:
        unregister()
    assert not any(hasattr(cq.Workplane, k) for k in WORKPLANE_METHODS)
    # its G-code passes the round trip: rebuilt from the parsed moves, against the design face
    face = get_face(src, 6)
    parsed2, _ = check_sync("blade2.ngc", "blade2.csv")              # the chained Workplane method's file
    parsed, kinds = check_sync("blade.ngc", "blade.csv")
    assert np.array_equal(parsed, parsed2)                              # the same path both ways
    cut = parsed[[k == "cut" for k in kinds]]
    rep = _report_from_header("blade.ngc")
    lo, hi = lines_3d(cut, rep)
    direction = "u"                     # kj66 face 6 rules along u (the CLI's report says so)
    h = rebuilt_error(rect_face(face)[0], face, lo, hi, direction)
    cam = faces_of(read_shape("blade-cam.step"))
    fit = hausdorff(rect_face(face)[0], cam[0], 30).max
    assert h.max <= fit * (1 + 1e-3) + 0.002
    assert len(cam) == 1                # the ruled face (its rulings are edges beside it)


def _report_from_header(ngc) -> dict:
    """The frame and the planes as the G-code header states them."""
    import re
    with open(ngc) as fh:
        head = fh.read(2000)
    h0, h1 = (float(x) for x in re.search(r"at height (\S+), upper guide UV at height (\S+),", head).groups())
    vec = [np.array([float(x) for x in g.split(",")]) for g in re.findall(r"\(([-\d.e, ]+)\)", head)]
    axis, e1, e2 = vec[0], vec[1], vec[2]
    return {"machine": {"frame": {"e1": e1, "e2": e2, "axis": axis}, "plane_heights": [h0, h1]}}


# ------------------------------------------------------------------------------------- sync (engine)

def test_sync_params_against_the_circle():
    """Synchronized points of two circles (radii 10 and 20, the same angle): every move within the
    tolerance at 2000 samples, and not many more points than the fewest uniform moves that pass."""
    from ruled.machine import sync_params

    def f(u):
        u = np.asarray(u, float)
        c = np.stack([np.cos(u), np.sin(u), np.zeros_like(u)], axis=1)
        return np.stack([10 * c, 20 * c + [0, 0, 5]], axis=1)
    tol = 1e-3
    u = sync_params(f, 0.0, 2 * np.pi, tol, np.linspace(0, 2 * np.pi, 5))
    s = np.linspace(0, 1, 2000)[1:-1]
    for a, b in zip(u[:-1], u[1:]):
        X = f(a + (b - a) * s)
        lin = f(np.array([a]))[0] + s[:, None, None] * (f(np.array([b]))[0] - f(np.array([a]))[0])
        assert np.linalg.norm(X - lin, axis=-1).max() <= tol
    fewest = math.ceil(2 * np.pi / (2 * math.acos(1 - tol / 20)))   # sagitta of the outer circle
    assert fewest <= len(u) - 1 <= 1.5 * fewest + 2
    # a straight motion needs no point between its ends, whatever the seeds
    line = sync_params(lambda x: np.stack([np.stack([x, 2 * x, 0 * x], 1)] * 2, 1), 0.0, 1.0, tol,
                       np.linspace(0, 1, 33))
    assert line.tolist() == [0.0, 1.0]
