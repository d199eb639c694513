"""Curves on surfaces (Yang et al. 2008): the issue's acceptance, measured with OCCT.

Every distance here comes from ruled.occ.measure (OCCT's curve on surface, Extrema and
projections, no engine code); joint angles from OCCT's one-sided derivatives at the knots."""
import json
import os

import numpy as np
import pytest
from cases import random_surface
from conftest import data_file

from ruled.core.basis import find_spans
from ruled.core.errors import BadInputError
from ruled.core.nurbs import Curve
from ruled.curves.curve_on_surface import approximate
from ruled.curves.domain import polyline_curve
from ruled.examples import yang_curve, yang_surface

OCP = pytest.importorskip("OCP")
from OCP.BRep import BRep_Tool  # noqa: E402
from OCP.BRepCheck import BRepCheck_Analyzer  # noqa: E402

from ruled.occ.convert import (  # noqa: E402
    container_to_bspline,
    container_to_face,
    curve2d_to_bspline,
    curve_to_bspline,
    edge_on_face,
)
from ruled.occ.curve_measure import curve_on_surface_measure  # noqa: E402


def _measure(S, D, res, n=800):
    return curve_on_surface_measure(container_to_bspline(S), curve2d_to_bspline(D), curve_to_bspline(res.curve), n,
                                    curve2d_to_bspline(res.pcurve))


def _pcurve_deviation(S, res, n=400):
    """max |C(t) - S(c(t))| over the edge built on the face, all evaluated by OCCT."""
    face = container_to_face(S)
    edge = edge_on_face(res.curve, res.pcurve, face)
    assert BRepCheck_Analyzer(edge).IsValid()
    c2 = BRep_Tool.CurveOnSurface_s(edge, face, 0.0, 1.0)
    c3 = BRep_Tool.Curve_s(edge, 0.0, 1.0)
    srf = BRep_Tool.Surface_s(face)
    dev = 0.0
    for t in np.linspace(c3.FirstParameter(), c3.LastParameter(), n):
        p2 = c2.Value(t)
        dev = max(dev, srf.Value(p2.X(), p2.Y()).Distance(c3.Value(t)))
    return dev


@pytest.mark.parametrize("angle", [10.0, 1.0])
def test_paper_first_example(angle):
    S, D = yang_surface(), yang_curve()
    res = approximate(S, D, 1e-3, angle)
    m = _measure(S, D, res)
    assert res.degree == 4 and res.curve.degree == 4
    assert res.control_points == 4 * res.segments + 1
    assert m.on_surface <= 1e-12 and _pcurve_deviation(S, res) <= 1e-12
    assert m.hausdorff <= 1e-3
    assert res.error_bound >= m.hausdorff and res.error_bound <= 1e-3
    assert m.max_joint_angle_deg(angle) <= angle + 1e-9 and not m.corners(angle)
    assert abs(m.max_joint_angle_deg() - res.max_joint_angle_deg) <= 1e-6
    # The paper reports 8 segments for 1e-3 / 10 degrees, but 8 chords cannot come within 1e-3 of this
    # image: benchmarks/run.py --suite cos measures 0.033 for 8 equal chords and finds the fewest
    # chords that reach 1e-3.  The counts here are the certified ones.
    assert res.segments <= (60 if angle == 10.0 else 210)


@pytest.mark.slow
def test_tolerance_sweep_measured_error_stays_under_the_tolerance():
    S, D = yang_surface(), yang_curve()
    rows = []
    for tol in (1.0, 0.5, 0.3, 0.1, 0.01, 1e-3, 1e-4):
        res = approximate(S, D, tol, 10.0)
        m = _measure(S, D, res, n=400 if tol < 1e-3 else 800)
        rows.append((tol, res.segments, m.hausdorff, m.hausdorff / tol))
        assert m.hausdorff <= tol
        assert res.error_bound >= m.hausdorff
        assert m.on_surface <= 1e-12
    ratios = [r[3] for r in rows]
    assert min(ratios[-3:]) >= 0.1  # the bound is not wastefully loose at small tolerances
    print("\n".join(f"tol {t:g}: {n} segments, measured {h:.3g}, ratio {r:.2f}" for t, n, h, r in rows))


def _cubic_domain_curve(rng, lo, hi, n=8):
    knots = np.concatenate([np.zeros(4), np.linspace(0, 1, n - 2)[1:-1], np.ones(4)])
    t = np.linspace(0.03, 0.97, n)
    P = np.stack([t, 0.5 + 0.4 * np.sin(3 * t + rng.uniform(0, 1)) * rng.uniform(0.6, 1.0)], axis=1)
    return Curve(lo + P * (hi - lo), knots, 3)


@pytest.mark.parametrize("rational", [False, pytest.param(True, marks=pytest.mark.slow)])
def test_multi_span_surfaces_crossing_knot_lines(rational):
    rng = np.random.default_rng(11)
    S = random_surface(np.random.default_rng(4), pu=3, pv=3, nu=9, nv=8, rational=rational)
    u0, u1, v0, v1 = S.domain
    D = _cubic_domain_curve(rng, np.array([u0, v0]), np.array([u1, v1]))
    tol = 1e-3 * S.diagonal()
    res = approximate(S, D, tol, 5.0)
    m = _measure(S, D, res)
    scale = S.diagonal()
    assert m.on_surface <= 1e-12 * scale and _pcurve_deviation(S, res) <= 1e-12 * scale
    assert m.hausdorff <= tol and res.error_bound >= m.hausdorff
    assert m.max_joint_angle_deg(5.0) <= 5.0 + 1e-9 and not m.corners(5.0)
    # every segment's chord stays in one knot span: the curve crossed the knot lines
    V = res.pcurve.poles
    mid = 0.5 * (V[:-1] + V[1:])
    spans = set()
    for a, b, c in zip(V[:-1], V[1:], mid):
        iu = find_spans(S.knots_u, 3, S.poles.shape[0], np.array([c[0]]))[0]
        iv = find_spans(S.knots_v, 3, S.poles.shape[1], np.array([c[1]]))[0]
        spans.add((iu, iv))
        for x in (a, b):
            assert S.knots_u[iu] - 1e-12 <= x[0] <= S.knots_u[iu + 1] + 1e-12
            assert S.knots_v[iv] - 1e-12 <= x[1] <= S.knots_v[iv + 1] + 1e-12
    assert len(spans) >= 5


def _uv_circle(c, r):
    """A closed rational quadratic circle in (u, v)."""
    P = np.array([[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1], [1, 0]], float)
    w = np.array([1, np.sqrt(.5), 1, np.sqrt(.5), 1, np.sqrt(.5), 1, np.sqrt(.5), 1])
    knots = [0, 0, 0, .25, .25, .5, .5, .75, .75, 1, 1, 1]
    return Curve(c + r * P, knots, 2, w)


def test_closed_rational_domain_curve_gives_a_closed_curve():
    S = random_surface(np.random.default_rng(5), pu=3, pv=3, nu=8, nv=8, rational=True)
    D = _uv_circle(np.array([0.5, 0.5]), 0.3)
    tol = 1e-3 * S.diagonal()
    res = approximate(S, D, tol, 2.0)
    assert res.closed and not res.corners
    C = curve_to_bspline(res.curve)
    assert C.IsClosed()
    m = _measure(S, D, res)
    assert m.hausdorff <= tol and res.error_bound >= m.hausdorff
    assert m.max_joint_angle_deg() <= 2.0 + 1e-9        # the closing joint included
    assert m.on_surface <= 1e-12 * S.diagonal()


def test_polyline_domain_curve_keeps_its_corners_and_is_exact():
    S = random_surface(np.random.default_rng(6), pu=3, pv=2, nu=7, nv=6, rational=False)
    pts = [(0.1, 0.1), (0.9, 0.2), (0.8, 0.9), (0.2, 0.8), (0.1, 0.1)]
    D = polyline_curve(pts)
    res = approximate(S, D, 1e-3, 1.0)
    assert res.closed
    assert len(res.corners) == 4
    assert res.error_bound <= 1e-12
    m = _measure(S, D, res)
    assert m.hausdorff <= 1e-12 * S.diagonal()
    assert len(m.corners(1.0)) == 4 and m.max_joint_angle_deg(1.0) <= 1e-9   # OCCT sees the same four corners
    assert sorted(round(t, 9) for t, _, _ in m.corners(1.0)) == sorted(round(t, 9) for t, _ in res.corners)
    # the image passes through every vertex's image
    V = np.asarray(pts, float)
    X = S(V[:, 0], V[:, 1])
    C = res.curve(np.arange(len(pts), dtype=float))
    assert np.abs(C - X).max() <= 1e-12 * S.diagonal()


@pytest.mark.slow
def test_kj66_face_with_interior_knots(tmp_path):
    from ruled.cli import main
    path = data_file("kj66_impeller.step")
    from ruled.core.region import four_sides
    from ruled.fit.face.coons import coons_map
    from ruled.occ.convert import face_to_container
    from ruled.occ.io import get_face
    from ruled.occ.region import face_region
    face = get_face(path, 6)
    S = face_to_container(face)
    u0, u1, v0, v1 = S.domain
    # the face is trimmed to 8 % of its surface's rectangle: a curve across the rectangle leaves it, refused
    D = _cubic_domain_curve(np.random.default_rng(3), np.array([u0, v0]), np.array([u1, v1]))
    cj = tmp_path / "c.json"
    cj.write_text(json.dumps({"degree": 3, "knots": D.knots.tolist(), "points": D.poles.tolist()}))
    assert main(["curve-on-surface", path, "--face", "6", "--uv-curve", str(cj), "-o", str(tmp_path / "x.step"),
                 "--quiet"]) == 2
    # a wavy cubic inside the face: control points on a diagonal of the face's own Coons map
    region = face_region(face, S)
    m = coons_map(region, four_sides(region))
    x = np.linspace(0.1, 0.9, 8)
    u, v = m.omega(S, x, 0.5 + 0.3 * np.sin(4 * x))
    knots = np.concatenate([np.zeros(4), np.linspace(0, 1, 6)[1:-1], np.ones(4)])
    D = Curve(np.stack([u, v], axis=1), knots, 3)
    assert region.contains(D(np.linspace(0, 1, 400))).all()
    cj.write_text(json.dumps({"degree": 3, "knots": D.knots.tolist(), "points": D.poles.tolist()}))
    out, rep = tmp_path / "c.step", tmp_path / "r.json"
    tol = 1e-3
    assert main(["curve-on-surface", path, "--face", "6", "--uv-curve", str(cj), "--tol", str(tol), "--angle", "1",
                 "-o", str(out), "--report", str(rep), "--quiet", "--measure-samples", "600"]) == 0
    r = json.loads(rep.read_text())
    for key in ("segments", "degree", "control_points", "error_bound", "hausdorff", "max_distance_to_surface",
                "max_joint_angle_deg"):
        assert key in r
    assert r["degree"] == 6 and r["segments"] > 10
    assert r["hausdorff"] <= tol and r["error_bound"] >= r["hausdorff"]
    assert r["max_distance_to_surface"] <= 1e-9 and r["max_joint_angle_deg"] <= 1.0 + 1e-9
    from OCP.TopAbs import TopAbs_EDGE
    from OCP.TopExp import TopExp_Explorer

    from ruled.occ.io import read_shape
    ex = TopExp_Explorer(read_shape(str(out)), TopAbs_EDGE)
    n = 0
    while ex.More():
        n += 1
        ex.Next()
    assert n == 1


def test_rational_hub_face_of_kj66():
    path = data_file("kj66_impeller.step")
    from ruled.occ.convert import face_to_container
    from ruled.occ.io import get_face
    face = get_face(path, 87)
    S = face_to_container(face)
    assert S.rational and S.periodic_v
    # the container (OCCT's unclamped non-periodic form) goes back to OCCT unchanged
    g, srf = container_to_bspline(S), BRep_Tool.Surface_s(face)
    for u, v in np.random.default_rng(0).uniform(0, 1, (20, 2)):
        assert g.Value(u, v).Distance(srf.Value(u, v)) <= 1e-9 * S.diagonal()
    u0, u1, v0, v1 = S.domain
    D = polyline_curve([(u0 + 0.1 * (u1 - u0), v0 + 0.2 * (v1 - v0)), (u0 + 0.6 * (u1 - u0), v0 + 0.7 * (v1 - v0)),
                        (u0 + 0.9 * (u1 - u0), v0 + 0.3 * (v1 - v0))])
    res = approximate(S, D, 0.01, 1.0)
    m = _measure(S, D, res, n=400)
    assert m.hausdorff <= 1e-9 * S.diagonal() and m.on_surface <= 1e-9 * S.diagonal()


def test_bad_input_is_refused_in_one_line(tmp_path):
    S, D = yang_surface(), yang_curve()
    with pytest.raises(BadInputError, match="leaves the surface's parameter domain"):
        approximate(S, Curve(np.array([(0.1, 0.1), (0.5, 2.5), (0.8, 0.1)]), [0, 0, 0, 1, 1, 1], 2), 1e-3, 10)
    with pytest.raises(BadInputError, match="zero length"):
        approximate(S, Curve(np.full((3, 2), 0.4), [0, 0, 0, 1, 1, 1], 2), 1e-3, 10)
    with pytest.raises(BadInputError, match="zero length"):
        polyline_curve([(0.2, 0.2), (0.2, 0.2)])
    for tol in (0.0, -1.0, float("nan")):
        with pytest.raises(BadInputError, match="^tol must be a positive finite number"):
            approximate(S, D, tol, 10)
    for ang in (0.0, 180.0, -5.0):
        with pytest.raises(BadInputError, match="angle tolerance"):
            approximate(S, D, 1e-3, ang)
    from ruled.cli import main
    from ruled.occ.io import write_step
    step = str(tmp_path / "y.step")
    write_step(container_to_face(S), step)
    bad = tmp_path / "bad.json"
    bad.write_text('{"degree": 2, "points": [[0.1, 0.1]]}')
    cases = [["--uv", "0.1,0.1;0.5,1.5"], ["--uv", "0.3,0.3;0.3,0.3"], ["--uv", "0.1;0.2"], ["--uv", "a,b;c,d"],
             ["--uv", "0.1,0.1;0.5,0.5", "--tol", "0"], ["--uv", "0.1,0.1;0.5,0.5", "--tol", "-1"],
             ["--uv", "0.1,0.1;0.5,0.5", "--angle", "0"], ["--uv-curve", str(bad)],
             ["--uv-curve", str(tmp_path / "missing.json")]]
    for extra in cases:
        rc = main(["curve-on-surface", step, "--face", "0", "-o", str(tmp_path / "o.step"), "--quiet"] + extra)
        assert rc == 2, extra
    assert not os.path.exists(tmp_path / "o.step")


def test_cadquery_entry_gives_an_edge_on_the_face():
    cq = pytest.importorskip("cadquery")
    from ruled.cq import curve_on_face
    face = cq.Workplane().box(10, 10, 10).faces(">Z").val()      # a plane, converted to a B-spline
    c = curve_on_face(face, [(0.1, 0.1), (0.9, 0.5), (0.2, 0.9)], tol=1e-3, angle=1.0, measure_samples=200)
    assert isinstance(c.edge, cq.Edge) and c.warnings
    assert c.measure.hausdorff <= 1e-9 and c.measure.on_surface <= 1e-9
    assert c.result.segments == 2 and len(c.result.corners) == 1
