"""Machine outputs (XYUV wire contours, flank-milling CL data) measured independently of ruled.machine.paths:
the G-code is read back by an independent parser from PyPI (gcodeparser), the surface the machine sweeps
is rebuilt from the parsed moves alone and measured with OCCT against the design face (or its OCCT offset
surface), the contours are checked against the ruled result's trace computed from the CAM STEP file
with OCCT evaluation, and the flank tool surfaces are sampled against exact distances to a cylinder and
a cone."""

from __future__ import annotations

import json
import math
import os
import runpy
import shutil

import numpy as np
import pytest
from cases import hyperboloid
from conftest import ROOT, data_file

from ruled.cli import main

gcodeparser = pytest.importorskip("gcodeparser")

from machine_helpers import (  # noqa: E402
    _bilinear,
    check_sync,
    hyp_file,  # noqa: E402,F401 (a fixture)
    lines_3d,
    read_csv,
    rebuilt_error,
    run_cli,
    trace_deviation,
    trim_aware_cut,
    xyuv_round_trip,
)
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace  # noqa: E402

from ruled.core.nurbs import Surface  # noqa: E402
from ruled.occ.convert import container_to_face  # noqa: E402
from ruled.occ.io import faces_of, get_face, read_shape, write_step  # noqa: E402
from ruled.occ.measure import _Projector, face_points, hausdorff  # noqa: E402

# --------------------------------------------------------------------------------------------- XYUV

@pytest.mark.slow
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


@pytest.mark.slow
def test_xyuv_hyperboloid_kerf(tmp_path, hyp_file):
    r = xyuv_round_trip(tmp_path, hyp_file, 0, 0.01, kerf=0.01, name="kerf")
    assert r["h"].max <= r["fit"] + r["chord"]
    assert 0 < r["rep"]["machine"]["offset_deviation"] < 0.5 * r["chord"]
    # the wire runs outside: every lower point is farther from the axis than the design's bottom circle
    lo, _ = lines_3d(r["cut"], r["rep"])
    assert np.all(np.hypot(lo[:, 0], lo[:, 1]) > 14.0)


def _blade_cut(tmp_path, chord, kerf=0.0, name="out", index=6, every=1):
    """kj66 face `index` machined at the defaults (its fit as 'ruled fit' returns it: the result trimmed by the
    face's edges, rulings that cross its end edges), the G-code replayed through gcodeparser, what the wire
    cuts measured trim-aware (trim_aware_cut), and the fit's own error (the CAM STEP's trimmed result against
    the face, both bounded)."""
    path = data_file("kj66_impeller.step")
    args = ["--xyuv", "--chord-tol", str(chord)] + (["--kerf", str(kerf)] if kerf else [])
    ngc, rep, cam = run_cli(tmp_path, path, index, *args, name=name)
    parsed, kinds = check_sync(ngc, os.path.splitext(ngc)[0] + ".csv")
    cut = parsed[[k == "cut" for k in kinds]]
    face = get_face(path, index)
    lo, hi = lines_3d(cut, rep)
    to_swept, d, kept = trim_aware_cut(face, lo, hi, every=every)
    fit = hausdorff(face, faces_of(read_shape(cam))[0], 30).max
    return rep, cut, cam, to_swept, d, kept, fit


@pytest.mark.slow
def test_xyuv_blade_sweeps_the_rulings_that_cross_its_end_edges(tmp_path):
    """Issue 35: the blade's trimmed result is machined: the wire sweeps its rulings that cross the face,
    plane to plane.  Rebuilt from the parsed G-code alone, the lines lie within fit + chord of the face where
    they run over it, and the face within fit + chord of the surface they sweep (both trim-aware); the
    contours follow the CAM STEP's ruled surface within the chord.  With a kerf, the lines run outside the
    face at the kerf +- (fit + chord)."""
    rep, cut, cam, to_swept, d, kept, fit = _blade_cut(tmp_path, 0.002)
    assert rep["machine"]["trimmed"] and rep["fit"]["region"]["how"].endswith("trimmed by the face's edges")
    assert fit <= rep["fit"]["error_bound"] <= 5e-4     # the trimmed fit's bound (the pinned fit's is 0.00229)
    assert kept > 200 and np.abs(d).max() <= fit * (1 + 1e-3) + 0.002 and to_swept <= fit * (1 + 1e-3) + 0.002
    bound = rep["fit"]["error_bound"] + 0.002           # the certified cut: the fit's bound + the chord
    assert rep["cut"]["bound"] == pytest.approx(bound, rel=1e-12) and max(np.abs(d).max(), to_swept) <= bound
    assert trace_deviation(cam, cut, rep) <= 0.002 * (1 + 1e-6)
    assert rep["cut"]["max"] <= rep["cut"]["bound"]
    rep, cut, cam, to_swept, d, kept, fit = _blade_cut(tmp_path, 0.005, kerf=0.005, name="kerf")
    assert rep["machine"]["offset_deviation"] < 0.5 * 0.005 and kept > 100
    assert "kerf 0.005 on the outside," in (tmp_path / "kerf.ngc").read_text()      # the header says the side
    assert np.all(d > 0) and np.abs(d - 0.005).max() <= fit * (1 + 1e-3) + 0.005     # outside, at the kerf
    assert abs(to_swept - 0.005) <= fit * (1 + 1e-3) + 0.005
    assert rep["cut"]["max"] <= rep["cut"]["bound"]


@pytest.mark.slow
@pytest.mark.parametrize("index", [1, 8])
def test_xyuv_of_the_other_blades_follows_their_trimmed_fits(tmp_path, index):
    """Issue 55: kj66 faces 1 and 8 at the defaults: the wire follows the fit 'ruled fit' returns (trimmed by
    the face's edges: bound 0.0019 and 0.0018 against 0.027 pinned), and the lines rebuilt from the G-code lie
    within its bound + the chord of the bounded face, and the face within that of the lines."""
    rep, cut, cam, to_swept, d, kept, fit = _blade_cut(tmp_path, 0.002, index=index, every=3)
    bound = rep["fit"]["error_bound"]
    assert rep["machine"]["trimmed"] and fit <= bound < 0.0025 and "fallback" not in rep
    assert kept > 50 and np.abs(d).max() <= bound + 0.002 and to_swept <= bound + 0.002


FALLBACK_AXIS = "0.3864,-0.7174,0.5798"   # 88 degrees from a ruling of face 8's trimmed fit, 60 from its pinned one's


@pytest.mark.slow
def test_a_trimmed_fit_that_cannot_be_machined_falls_back_saying_so(tmp_path, capsys):
    """Issue 55, no silent fallback: along an axis that a ruling of kj66 face 8's trimmed fit (and none of its
    pinned fit's) nearly lies across, the wire follows the pinned fit, and the command line (stderr and
    report) and Python (a warning) say so with both fits' figures."""
    import warnings

    import ruled.cq as rcq
    path = data_file("kj66_impeller.step")
    ngc, rep, _ = run_cli(tmp_path, path, 8, "--xyuv", "--axis", FALLBACK_AXIS)
    fb, err = rep["fallback"], capsys.readouterr().err
    assert fb["pinned_bound"] > 10 * fb["trimmed_bound"] and rep["fit"]["error_bound"] == fb["pinned_bound"]
    line = next(ln for ln in err.splitlines() if "corner-pinned" in ln)
    assert line.startswith(f"ruled: warning: face 8: the wire follows the corner-pinned fit (bound "
                           f"{fb['pinned_bound']:.4g}, measured {fb['pinned_measured']:.4g})")
    assert line.endswith(f"the trimmed fit is bound {fb['trimmed_bound']:.4g}, measured {fb['trimmed_measured']:.4g}")
    assert "degrees from the machine axis" in line and "--axis" in line and rep["warnings"][0] in line
    with warnings.catch_warnings(record=True) as got:
        warnings.simplefilter("always")
        md = rcq.xyuv_face(get_face(path, 8), axis=tuple(float(x) for x in FALLBACK_AXIS.split(",")),
                           measure_samples=10)
    assert md.report["fallback"]["followed"] == "pinned"
    assert any(str(w.message).startswith("the wire follows the corner-pinned fit") for w in got)


@pytest.mark.slow
def test_xyuv_planes_given(tmp_path, hyp_file):
    ngc, rep, _ = run_cli(tmp_path, hyp_file, 0, "--xyuv", "--planes", "12,-11", "--axis", "z", "--lead", "0")
    assert rep["machine"]["plane_heights"] == [-11.0, 12.0]     # given as 12,-11: sorted
    parsed, kinds = check_sync(ngc, os.path.splitext(ngc)[0] + ".csv")
    assert len(parsed) == rep["machine"]["sync_points"] and set(kinds) == {"cut"}     # no leads


@pytest.mark.slow
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
    from ruled.machine.chain import join_patches
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
    from ruled.core.errors import BadInputError
    with pytest.raises(BadInputError, match="patch 1 does not start where patch 0 ends"):
        join_patches([plain[0], plain[2]])


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
    # the fit's trimmed result: what the wire cuts of the face, trim-aware (trim_aware_cut)
    cam = faces_of(read_shape("blade-cam.step"))
    fit = hausdorff(face, cam[0], 30).max
    to_swept, d, kept = trim_aware_cut(face, lo, hi, every=2)
    assert kept > 100 and max(to_swept, float(np.abs(d).max())) <= fit * (1 + 1e-3) + 0.002
    assert len(cam) == 1                # the ruled face (its rulings are edges beside it)


def _report_from_header(ngc) -> dict:
    """The frame and the planes as the G-code header states them (its 'ruled ... planes= e1= e2= axis=' comments)."""
    import re
    with open(ngc) as fh:
        head = fh.read(3000)

    def vec(key):
        return np.array([float(x) for x in re.search(rf"\b{key}=([-\d.e,+]+)", head).group(1).split(",")])
    h0, h1 = vec("planes")
    return {"machine": {"frame": {"e1": vec("e1"), "e2": vec("e2"), "axis": vec("axis")}, "plane_heights": [h0, h1]}}


# ------------------------------------------------------------------------------------- sync (engine)

def test_sync_params_against_the_circle():
    """Synchronized points of two circles (radii 10 and 20, the same angle): every move within the
    tolerance at 2000 samples, and not many more points than the fewest uniform moves that pass."""
    from ruled.machine.sync import sync_params

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
