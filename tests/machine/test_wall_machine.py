"""A part's wall in one cut (issue 37): one closed XYUV loop over the wall's closed ruled surface, a single
lead-in and lead-out at the start the user names, the kerf round the whole loop with its corners handled.

Measured independently of the path's own measure: the G-code replayed through gcodeparser, the wire's
lines rebuilt from it alone, their distances to the wall's faces by BRepExtrema, and the wall's points'
distances to the lines by brute force over the segments."""

from __future__ import annotations

import os

import numpy as np
import pytest

pytest.importorskip("cadquery")

from tests.machine_helpers import check_sync, lines_3d  # noqa: E402
from tests.wall_parts import tapered_extrusion  # noqa: E402

HEIGHT = 15.0     # the tapered extrusion's bottom and top contours lie at z = 0 and z = 15


@pytest.fixture(scope="module")
def part(tmp_path_factory):
    from ruled.occ.io import write_step
    d = tmp_path_factory.mktemp("wall")
    path = str(d / "tapered.step")
    write_step(tapered_extrusion().wrapped, path)
    return path, d


def _run(part, name, *args):
    import json

    from ruled.cli.main import main
    path, d = part
    out, rep = str(d / f"{name}.ngc"), str(d / f"{name}.json")
    assert main(["machine", path, "--wall", "auto", "--xyuv", *args, "-o", out, "--report", rep, "--quiet",
                 "--measure-samples", "12"]) == 0
    with open(rep) as fh:
        return out, json.load(fh)


def _segment_distance(X: np.ndarray, A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """(N,) each point's distance to the surface of the quads between consecutive lines A[i]B[i]: per quad,
    64 lines between its two, then a golden-section search between the nearest one's neighbours (exact
    segment distances throughout)."""
    def seg(f, i):
        a, b = A[i] + f[..., None] * (A[i + 1] - A[i]), B[i] + f[..., None] * (B[i + 1] - B[i])
        D = b - a
        t = np.clip(np.einsum("...c,...c->...", X - a, D) / np.einsum("...c,...c->...", D, D), 0, 1)
        return np.linalg.norm(X - (a + t[..., None] * D), axis=-1)
    best = np.full(len(X), np.inf)
    g = 0.5 * (np.sqrt(5.0) - 1.0)
    for i in range(len(A) - 1):
        fs = np.linspace(0.0, 1.0, 65)
        d = np.stack([seg(np.full(len(X), f), i) for f in fs], axis=1)
        k = np.argmin(d, axis=1)
        lo, hi = fs[np.maximum(k - 1, 0)], fs[np.minimum(k + 1, 64)]
        for _ in range(50):
            x1, x2 = hi - g * (hi - lo), lo + g * (hi - lo)
            left = seg(x1, i) < seg(x2, i)
            lo, hi = np.where(left, lo, x1), np.where(left, x2, hi)
        best = np.minimum(best, np.minimum(d.min(axis=1), seg(0.5 * (lo + hi), i)))
    return best


def _wall_check(part, ngc: str, rep: dict, kerf: float):
    """The replayed loop: closed in XY and UV with equal move counts, one lead-in and one lead-out; the wire's
    lines within kerf +- (fit + chord) of the wall's faces both ways, on the outside."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeVertex
    from OCP.BRepClass3d import BRepClass3d_SolidClassifier
    from OCP.BRepExtrema import BRepExtrema_DistShapeShape
    from OCP.gp import gp_Pnt
    from OCP.TopAbs import TopAbs_OUT

    from ruled.occ.io import compound, faces_of, read_shape
    parsed, kinds = check_sync(ngc, os.path.splitext(ngc)[0] + ".csv")
    assert kinds[0] == "lead-in" and kinds[-1] == "lead-out" and kinds.count("lead-in") == 1
    cut = parsed[[k == "cut" for k in kinds]]
    xy, uv = cut[:, :2], cut[:, 2:]
    assert len(xy) == len(uv) >= 20
    assert np.linalg.norm(xy[0] - xy[-1]) <= 1e-3 and np.linalg.norm(uv[0] - uv[-1]) <= 1e-3   # closed loops
    lo, hi = lines_3d(cut, rep)
    # the lines inside the part: between the contours' heights
    t = (np.linspace(0.0, HEIGHT, 7)[None, :, None] - lo[:, None, 2:3]) / (hi - lo)[:, None, 2:3]
    pts = (lo[:, None] + t * (hi - lo)[:, None]).reshape(-1, 3)
    shape = read_shape(part[0])
    faces = faces_of(shape)
    wall = compound([faces[i] for i in rep["wall"]["faces"]])
    pick = pts[np.linspace(0, len(pts) - 1, min(400, len(pts))).astype(int)]
    d = np.array([BRepExtrema_DistShapeShape(BRepBuilderAPI_MakeVertex(gp_Pnt(*map(float, p))).Vertex(), wall).Value()
                  for p in pick])
    bound = rep["cut"]["bound"]
    assert np.abs(d - kerf).max() <= bound, (np.abs(d - kerf).max(), bound)
    # the wall's points are the kerf from the lines
    from ruled.occ.measure import face_points
    W = np.concatenate([face_points(faces[i], 10) for i in rep["wall"]["faces"]])
    dw = _segment_distance(W, lo, hi)
    assert np.abs(dw - kerf).max() <= bound + 1e-9, (np.abs(dw - kerf).max(), bound)
    # with a kerf, the wire runs outside the part (a punch: the side asked for)
    cls = BRepClass3d_SolidClassifier(shape)
    for p in pick[::7] if kerf else ():
        cls.Perform(gp_Pnt(*map(float, p)), 1e-7)
        assert cls.State() == TopAbs_OUT
    return cut, lo


def test_the_wall_is_one_closed_xyuv_loop_from_the_longest_straight_stretch(part):
    ngc, rep = _run(part, "plain")
    cut, lo = _wall_check(part, ngc, rep, 0.0)
    # the default start: the middle of the bottom contour's longest straight edge, (0, 0)-(40, 0)
    assert np.allclose(rep["wall"]["start"], [20.0, 0.0, 0.0], atol=0.5)
    assert rep["machine"]["axis"] == [0.0, 0.0, 1.0]
    assert rep["cut"]["max"] <= rep["cut"]["bound"]
    # the taper per ruling: each line's angle from the axis, from the CSV's own points; at least the draft
    from tests.machine_helpers import read_csv
    rows = [r for r in read_csv(os.path.splitext(ngc)[0] + ".csv") if r["kind"] == "cut"]
    for r in rows:
        d = np.array([float(r[f"upper_{c}"]) - float(r[f"lower_{c}"]) for c in "xyz"])
        assert float(r["taper_deg"]) == pytest.approx(np.degrees(np.arccos(abs(d[2]) / np.linalg.norm(d))), abs=1e-3)
    assert min(float(r["taper_deg"]) for r in rows) >= 8.0 - 1e-3


def test_the_kerf_runs_round_the_whole_loop_and_its_corner(part):
    """Outside (a punch), the wire of radius 0.15 pivots round the sharp corner at (0, 0): every line is at
    the kerf from the wall, within the fit and the chord tolerance, both ways."""
    ngc, rep = _run(part, "kerf", "--kerf", "0.15", "--start", "30,0")
    cut, lo = _wall_check(part, ngc, rep, 0.15)
    assert np.allclose(rep["wall"]["start"][:2], [30.0, 0.0], atol=0.5)
    assert rep["cut"]["inside_corner_fillet"] <= 1e-9


def test_a_start_off_the_contour_is_refused_in_one_line(part, tmp_path):
    from tests.conftest import ruled_here
    r = ruled_here("machine", part[0], "--wall", "auto", "--xyuv", "--start", "25,7", "-o", tmp_path / "x.ngc")
    assert r.returncode == 2
    assert r.stderr.strip() == ("ruled: error: --start (25, 7) is 7 off the wall's bottom contour (its nearest point "
                                "is (25.01, 0)); give a point on it")


def test_cadquery_xyuv_wall_writes_the_same_loop_as_the_command_line(part, tmp_path):
    import ruled.cq as rcq
    from ruled.machine.output import write_machine
    from tests.machine_helpers import parse_moves
    ngc, _ = _run(part, "cli")
    data = rcq.xyuv_wall(tapered_extrusion(), measure=False)
    out = str(tmp_path / "cq.ngc")
    write_machine(data.path, out, "wall", str(tmp_path / "cq.csv"))
    a = np.array([[p[k] for k in "XYUV"] for _, p in parse_moves(ngc)])
    b = np.array([[p[k] for k in "XYUV"] for _, p in parse_moves(out)])
    assert a.shape == b.shape and np.abs(a - b).max() <= 1e-6
