"""Walls of punches and dies drawn as a toolmaker draws a wire-EDM job (issue 56): a punch whose lines meet its
arcs at sharp corners (6 degree draft), a drafted polygon star (fan cones at its sharp concave corners), the
star as a ruled loft (concave creases), a die block with a drafted hole of lines and arcs, a D-shaped hole.

Measured independently of the code under test: the fits against the wall's faces by OCCT, both ways; each
line-arc corner's own distance from ruled (its joint curve's largest distance from the chord between its
ends, sampled with OCCT); the G-code replayed through gcodeparser, its lines against the wall's faces by
BRepExtrema and the wall's points against its lines by brute force, the wire's side by BRepClass3d."""

from __future__ import annotations

import json

import numpy as np
import pytest

pytest.importorskip("cadquery")

from tests.conftest import ruled_here  # noqa: E402
from tests.machine_helpers import wall_cut_check  # noqa: E402
from tests.wall_parts import d_hole, die_block, line_arc_punch, lofted_star, polygon_star  # noqa: E402

# name: (part, the wall's word, its contours' heights, exactly ruled)
PARTS = {"punch": (line_arc_punch, "auto", (0.0, 12.0), False), "star": (polygon_star, "auto", (0.0, 10.0), True),
         "lofted star": (lofted_star, "auto", (0.0, 10.0), True), "die": (die_block, "hole", (0.0, 15.0), False),
         "D hole": (d_hole, "hole", (0.0, 10.0), True)}


@pytest.fixture(scope="module")
def parts(tmp_path_factory):
    from ruled.occ.io import write_step
    d = tmp_path_factory.mktemp("dies")
    out = {}
    for name, (build, *_) in PARTS.items():
        path = str(d / f"{name.replace(' ', '_')}.step")
        write_step(build().wrapped, path)
        out[name] = path
    return out, d


def _run(d, *args) -> dict:
    from ruled.cli.main import main
    rep = str(d / f"r{abs(hash(args))}.json")
    assert main([*args, "--report", rep, "--quiet"]) == 0, args
    with open(rep) as fh:
        return json.load(fh)


def _bow(path: str, faces: list) -> float:
    """The largest distance of a joint between two of the wall's faces from the chord between its ends: how
    far from ruled the wall is there (OCCT's edge samples)."""
    from OCP.BRepAdaptor import BRepAdaptor_Curve
    from OCP.TopAbs import TopAbs_EDGE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    from ruled.occ.io import faces_of, read_shape
    part = faces_of(read_shape(path))
    fs = [part[i] for i in faces]
    edges = []
    for f in fs:
        ex = TopExp_Explorer(f, TopAbs_EDGE)
        while ex.More():
            edges.append(TopoDS.Edge_s(ex.Current()))
            ex.Next()
    worst = 0.0
    for e in edges:
        if sum(e.IsSame(g) for g in edges) < 2:          # a joint: an edge of two of the wall's faces
            continue
        c = BRepAdaptor_Curve(e)
        P = np.array([c.Value(t).Coord() for t in np.linspace(c.FirstParameter(), c.LastParameter(), 401)])
        d = (P[-1] - P[0]) / np.linalg.norm(P[-1] - P[0])
        worst = max(worst, float(np.linalg.norm(np.cross(P - P[0], d), axis=1).max()))
    return worst


def _smooth_parts(face):
    """The face's B-spline surface cut by OCCT at its C0 knots into faces (BRepExtrema's search does not cross
    a crease of a face)."""
    from OCP.BRepAdaptor import BRepAdaptor_Surface
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace

    from ruled.occ.io import compound
    s = BRepAdaptor_Surface(face).BSpline()
    cuts = [s.UKnot(i) for i in range(1, s.NbUKnots() + 1)
            if i in (1, s.NbUKnots()) or s.UMultiplicity(i) >= s.UDegree()]
    u0, u1, v0, v1 = s.Bounds()
    out = []
    for a, b in zip(cuts[:-1], cuts[1:]):
        piece = s.Copy()
        piece.Segment(a, b, v0, v1)
        out.append(BRepBuilderAPI_MakeFace(piece, 1e-9).Face())
    return compound(out)


def _two_sided(wall: list, result, n: int = 400) -> float:
    """The largest distance, by OCCT's BRepExtrema, from n points of the wall's faces to the result and from n
    points of the result to the wall's faces (their union)."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeVertex
    from OCP.BRepExtrema import BRepExtrema_DistShapeShape
    from OCP.gp import gp_Pnt

    from ruled.occ.io import compound
    from ruled.occ.measure import face_points

    def worst(P, to):
        P = P[np.linspace(0, len(P) - 1, min(n, len(P))).astype(int)]
        return max(BRepExtrema_DistShapeShape(BRepBuilderAPI_MakeVertex(gp_Pnt(*map(float, p))).Vertex(),
                                              to).Value() for p in P)
    W = np.concatenate([face_points(f, 12) for f in wall])
    return max(worst(W, _smooth_parts(result)), worst(face_points(result, 30), compound(wall)))


def _corner_rulings(wall: list, result, n: int = 400) -> float:
    """The largest distance, by OCCT's BRepExtrema, from n points along each of the result's rulings at its C0
    knots (its corners; degree 1 along v) to the wall's faces (their union)."""
    from OCP.BRepAdaptor import BRepAdaptor_Surface
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeVertex
    from OCP.BRepExtrema import BRepExtrema_DistShapeShape

    from ruled.occ.io import compound
    s = BRepAdaptor_Surface(result).BSpline()
    assert s.VDegree() == 1
    u0, u1, v0, v1 = s.Bounds()
    to, worst = compound(wall), 0.0
    for i in range(1, s.NbUKnots() + 1):
        if s.UMultiplicity(i) >= s.UDegree():
            for v in np.linspace(v0, v1, n):
                p = s.Value(s.UKnot(i), float(v))
                worst = max(worst, BRepExtrema_DistShapeShape(BRepBuilderAPI_MakeVertex(p).Vertex(), to).Value())
    return worst


@pytest.mark.parametrize("name", [pytest.param(n, marks=pytest.mark.slow) if "star" in n else n for n in PARTS])
def test_each_wall_is_fitted_within_its_bound_and_its_distance_from_ruled(parts, name):
    from ruled.occ.io import faces_of, read_shape
    paths, d = parts
    _, word, _, exact = PARTS[name]
    out = str(d / f"{name.replace(' ', '_')}.fit.step")
    rep = _run(d, "fit", paths[name], "--wall", word, "-o", out, "--measure-samples", "16")
    faces = rep["faces"]
    design = faces_of(read_shape(paths[name]))
    result = faces_of(read_shape(out))
    assert len(result) == 1
    measured = _two_sided([design[i] for i in faces], result[0])
    size = rep["size"]
    assert measured <= rep["error_bound"], (measured, rep["error_bound"])
    # issue 72: the report's measure samples the rulings through the contours' corners densely (the punch's
    # corner ruling is the farthest from its wall, 0.1308: the measure's grid missed it, 0.104)
    corners = _corner_rulings([design[i] for i in faces], result[0])
    assert corners <= rep["error_bound"], (corners, rep["error_bound"])
    if corners > 1e-9 * size:       # (an exactly ruled wall: both round-off)
        assert rep["hausdorff"]["max"] >= 0.95 * corners, (corners, rep["hausdorff"])
    if exact:
        assert rep["error_bound"] <= 1e-6 * size and measured <= 1e-6 * size
    else:
        bow = _bow(paths[name], faces)
        assert bow > 1e-5 * size                            # (the corners are not straight: the premise)
        assert measured <= bow * (1 + 1e-6), (measured, bow)   # within the corners' own distance from ruled
        assert rep["error_bound"] <= 1.25 * bow, (rep["error_bound"], bow)
    if name == "punch":
        # issue 72: the rulings paired anew across its sharp corners (the corner ruling lies 0.1308 off the wall)
        assert rep["error_bound"] <= 0.09 and rep["crossed_corners"] >= 2, rep
    if name == "die":
        # issue 72: the ring certified as a whole, one way at a time (its joints bow 0.0025 off the corner lines
        # the pieces' own certificates send them to; their points lie 0.00098 from the result past the corner)
        assert rep["error_bound"] <= 2 * max(measured, corners, rep["hausdorff"]["max"]), rep


@pytest.mark.slow
@pytest.mark.parametrize("name,kerf", [("punch", 0.0), ("punch", 0.15), ("star", 0.15), ("lofted star", 0.15),
                                       ("die", 0.15), ("D hole", 0.0), ("D hole", 0.15)])
def test_each_wall_is_one_closed_loop_at_the_kerf_off_the_material(parts, name, kerf):
    paths, d = parts
    _, word, heights, _ = PARTS[name]
    ngc = str(d / f"{name.replace(' ', '_')}-{kerf}.ngc")
    rep = _run(d, "machine", paths[name], "--wall", word, "--xyuv", "--kerf", str(kerf), "-o", ngc,
               "--measure-samples", "12")
    cut, lo = wall_cut_check(paths[name], ngc, rep, kerf, heights)
    hole = word == "hole"
    assert rep["wall"]["role"] == ("hole" if hole else "outer")
    assert rep["side"] == ("inside the hole (off the material)" if hole else "outside the part (off the material)")
    header = [ln for ln in open(ngc).read().splitlines() if ln.startswith("(")]
    side = rep["side"].replace("(", "[").replace(")", "]")        # (RS274/NGC comments do not nest)
    assert any(f"kerf {kerf:g} {side}" in ln for ln in header), header
    assert rep["cut"]["max"] <= rep["cut"]["bound"]
    if name == "punch":
        # issue 72: its fit crosses its sharp corners; a wire of no kerf cuts that fit, a kerf's offset of the
        # crossed corners twists, and the loop cuts the corners' own rulings (the lower cut bound), saying so
        w = rep["wall"]
        if kerf:
            assert w["crossed_corners"] == 0 and rep["fit"]["error_bound"] > 0.12, rep["fit"]
            assert w["corners_note"].startswith("the corners' own rulings are cut"), w
        else:
            assert w["crossed_corners"] >= 2 and rep["fit"]["error_bound"] <= 0.09 and "corners_note" not in w, w


def test_a_die_lists_its_walls_and_auto_names_them_all(parts, tmp_path):
    paths, _ = parts
    listing = ruled_here("faces", paths["die"], "--walls")
    assert listing.returncode == 0
    lines = [ln for ln in listing.stdout.splitlines() if ln.startswith("wall ")]
    assert lines == ["wall 0: outer  faces 0,1,5,3  (outer wall; bottom contour 4 edges, top contour 4 edges)",
                     "wall 1: hole 1  faces 6,9,8,7  (inner wall, a hole's: --wall hole; bottom contour 4 edges, top "
                     "contour 4 edges)"]
    r = ruled_here("fit", paths["die"], "--wall", "auto", "-o", tmp_path / "x.step")
    assert r.returncode == 2
    assert r.stderr.strip() == ("ruled: error: the part has 2 walls: outer (faces 0,1,5,3); hole 1 (faces 6,9,8,7); "
                                "choose one with --wall outer, --wall hole or its faces --wall K,L-M")
    r = ruled_here("machine", paths["die"], "--wall", "hole:2", "--xyuv", "-o", tmp_path / "x.ngc")
    assert r.returncode == 2
    assert r.stderr.strip() == ("ruled: error: --wall hole:2: the part has 1 hole wall: outer (faces 0,1,5,3); "
                                "hole 1 (faces 6,9,8,7); choose one with --wall outer, --wall hole or its faces "
                                "--wall K,L-M")
