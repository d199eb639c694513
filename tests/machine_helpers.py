"""What the machine tests share: readers of the G-code, APT and CSV outputs, the CLI run, the swept
surface rebuilt from the parsed moves, and the faces the tests machine (module fixtures)."""

from __future__ import annotations

import csv
import json
import math
import os
import re

import numpy as np
import pytest
from cases import hyperboloid

from ruled.cli import main

gcodeparser = pytest.importorskip("gcodeparser")

from OCP.BRep import BRep_Tool  # noqa: E402
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace  # noqa: E402
from OCP.BRepTools import BRepTools  # noqa: E402
from OCP.Geom import Geom_Line, Geom_OffsetSurface  # noqa: E402
from OCP.GeomAPI import GeomAPI_ExtremaCurveCurve  # noqa: E402
from OCP.gp import gp_Ax3, gp_Cone, gp_Cylinder, gp_Dir, gp_Lin, gp_Pnt  # noqa: E402
from OCP.TopAbs import TopAbs_REVERSED  # noqa: E402

from ruled.core.nurbs import Surface  # noqa: E402
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
    rc = main(["machine", face_file, "--face", str(face), *args, "-o", out, "--report", rep, "--cam-step", cam,
               "--quiet"])
    assert rc == 0
    with open(rep) as fh:
        report = json.load(fh)
    check = report["program"]["check"]          # every LinuxCNC file checked by LinuxCNC's interpreter (issue 71)
    assert check is None or check["error"] is None, check
    return out, report, cam


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


def trim_aware_cut(face, lo, hi, n=30, along=41, every=3):
    """What the wire cuts against the face as bounded by its edges, rebuilt from the parsed moves alone:
    (the largest distance of the face's points to the surface the straight lines sweep, plane to plane;
    the signed distances of the lines' points that lie over the face; how many those are).  A point lies
    over the face where its closest point on the bounded face (OCCT's BRepExtrema) is inside the face, not
    on an edge: points past the face's end edges or beyond its rails are not part of what cuts it.  Every
    `every`-th line and the lines half way between them (what the machine interpolates), `along` points
    each.  Signed: positive on the outside of the face (its normal, the face's orientation counted)."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeVertex
    from OCP.BRepExtrema import BRepExtrema_DistShapeShape, BRepExtrema_SupportType
    from OCP.GeomLProp import GeomLProp_SLProps
    surf = BRep_Tool.Surface_s(face)
    sign = -1.0 if face.Orientation() == TopAbs_REVERSED else 1.0
    t = np.linspace(0.0, 1.0, along)
    d = []
    for i in range(0, len(lo) - 1, every):
        for s in (0.0, 0.5):
            a = lo[i] + s * (lo[i + 1] - lo[i])
            b = hi[i] + s * (hi[i + 1] - hi[i])
            for p in a[None, :] + t[:, None] * (b - a)[None, :]:
                ds = BRepExtrema_DistShapeShape(BRepBuilderAPI_MakeVertex(gp_Pnt(*map(float, p))).Vertex(), face)
                if not ds.IsDone() or ds.SupportTypeShape2(1) != BRepExtrema_SupportType.BRepExtrema_IsInFace:
                    continue
                u, v = ds.ParOnFaceS2(1)
                props = GeomLProp_SLProps(surf, u, v, 1, 1e-9)
                side = np.dot(p - np.array(surf.Value(u, v).Coord()), np.array(props.Normal().Coord()) * sign)
                d.append(ds.Value() * (1.0 if side >= 0 else -1.0))
    m = len(lo)
    swept = container_to_face(Surface(np.stack([lo, hi], axis=1), np.concatenate([[0.0], np.arange(m, dtype=float),
                                                                                  [m - 1.0]]),
                                      [0.0, 0.0, 1.0, 1.0], 1, 1))
    to_swept = _Projector(swept).distances(face_points(face, n))
    return float(to_swept.max()), np.array(d), len(d)


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


# ------------------------------------------------------------------------------------------- walls

def segment_distance(X: np.ndarray, A: np.ndarray, B: np.ndarray) -> np.ndarray:
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


def wall_cut_check(path: str, ngc: str, rep: dict, kerf: float, heights: tuple):
    """The replayed loop of a wall's G-code: closed in XY and UV with equal move counts, one lead-in and one
    lead-out; the wire's lines (between the contours' heights) within kerf +- the cut's bound of the wall's
    faces both ways; with a kerf, the wire off the material (the default side: outside a punch, inside a
    hole), by BRepClass3d.  Returns (the cut moves, the lines' lower points)."""
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
    t = (np.linspace(heights[0], heights[1], 7)[None, :, None] - lo[:, None, 2:3]) / (hi - lo)[:, None, 2:3]
    pts = (lo[:, None] + t * (hi - lo)[:, None]).reshape(-1, 3)
    shape = read_shape(path)
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
    dw = segment_distance(W, lo, hi)
    assert np.abs(dw - kerf).max() <= bound + 1e-9, (np.abs(dw - kerf).max(), bound)
    # with a kerf, the wire runs off the material
    cls = BRepClass3d_SolidClassifier(shape)
    for p in pick[::7] if kerf else ():
        cls.Perform(gp_Pnt(*map(float, p)), 1e-7)
        assert cls.State() == TopAbs_OUT
    return cut, lo


# ------------------------------------------------------------------------------------- posts (issue 71)

def frame_of_file(path: str):
    """(e1, e2, axis, (h0, h1), kerf) from the file's 'ruled' comments, read here with a regular expression."""
    head = open(path).read(4000)

    def vec(key):
        return np.array([float(x) for x in re.search(rf"\b{key}=([-\d.e,+]+)", head).group(1).split(",")])
    return vec("e1"), vec("e2"), vec("axis"), tuple(vec("planes")), float(vec("kerf")[0])


def lines_of(points, path):
    """The wire's lines (lower, upper 3D points) of X Y U V points, by the file's frame."""
    e1, e2, ax, (h0, h1), _ = frame_of_file(path)
    P = np.asarray(points, float)
    return (P[:, :1] * e1 + P[:, 1:2] * e2 + h0 * ax, P[:, 2:3] * e1 + P[:, 3:4] * e2 + h1 * ax)


def interpreted(path):
    """LinuxCNC's moves of the file (X Y U V in mm) and their kinds; asserts it reads the file without an error."""
    from ruled.machine import linuxcnc
    out = linuxcnc.interpret(path, ("X", "Y", "U", "V"))
    assert out["error"] is None, out["error"]
    return np.array([m[2] for m in out["moves"]]), [m[0] for m in out["moves"]], out


def rect_wall():
    """A rectangle 40 x 20 extruded 10 with a 5 degree draft: its two longest bottom edges tie (y = -10, y = 10)."""
    import cadquery as cq
    return cq.Workplane("XY").rect(40, 20).extrude(10, taper=5).val()


def comments_nest(text: str) -> bool:
    """Whether any comment of the G-code holds a '(' (RS274/NGC forbids nesting: LinuxCNC's error 5)."""
    return any("(" in c for c in re.findall(r"\(([^)]*)\)", text))
