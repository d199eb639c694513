"""A face's result put back into its part (issue 35, point 6): ``ruled fit INPUT --face K --replace`` and
``ruled.cq.replace_face``.  Checked with OCCT alone: the written part read back, its solids by BRepCheck and
ShapeAnalysis_FreeBounds (no free edges), its faces counted and their areas compared with the input's,
and its face K measured against the input's face K (ruled.occ.measure, trim-aware both ways)."""

from __future__ import annotations

import json

import pytest

pytest.importorskip("OCP")

from conftest import data_file, ruled_here  # noqa: E402

from ruled.occ.io import face_area, faces_of, read_shape  # noqa: E402
from ruled.occ.measure import hausdorff  # noqa: E402

N = 20


def _solids(shape) -> list:
    return _sub(shape, "SOLID")


def _open_edges(solid) -> int:
    """Free edges by ShapeAnalysis_FreeBounds (OCCT's own, not ruled.occ.replace.free_edges)."""
    from OCP.ShapeAnalysis import ShapeAnalysis_FreeBounds
    fb = ShapeAnalysis_FreeBounds(solid, 1e-9, False, False)
    return sum(len(_edges(comp)) for comp in (fb.GetClosedWires(), fb.GetOpenWires()))


def _sub(shape, kind: str) -> list:
    from OCP.TopAbs import TopAbs_ShapeEnum
    from OCP.TopExp import TopExp_Explorer
    out, exp = [], TopExp_Explorer(shape, getattr(TopAbs_ShapeEnum, f"TopAbs_{kind}"))
    while exp.More():
        out.append(exp.Current())
        exp.Next()
    return out


def _edges(face) -> list:
    return _sub(face, "EDGE")


def _length(edge) -> float:
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps
    g = GProp_GProps()
    BRepGProp.LinearProperties_s(edge, g)
    return g.Mass()


def _check_part(src: str, out_shape, k: int, bound: float, as_is: str) -> float:
    """The written part against the input: every solid valid and closed, as many faces, every face but K
    of the same area as in the input written as it is (as_is: the file's own STEP round trip moves some
    faces of the space ship), face K within bound of the input's face K.  Returns face K's measure."""
    from OCP.BRepCheck import BRepCheck_Analyzer
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps
    shape = read_shape(src)
    before, after = faces_of(read_shape(as_is)), faces_of(out_shape)
    assert len(after) == len(before)
    for s in _solids(out_shape):
        assert BRepCheck_Analyzer(s).IsValid()
        assert _open_edges(s) == 0
        g = GProp_GProps()
        BRepGProp.VolumeProperties_s(s, g)
        assert g.Mass() > 0                           # oriented outward
    # the faces away from K as they were; K's neighbours moved by at most the bound along K's edges
    K = _edges(before[k])
    perimeter = sum(_length(e) for e in K)
    for i, (a, b) in enumerate(zip(before, after)):
        if i == k:
            continue
        near = any(e.IsSame(x) for e in _edges(a) for x in K)
        area = face_area(a, 1e-6)
        assert abs(face_area(b, 1e-6) - area) <= (bound * perimeter if near else 1e-6 * abs(area))
    face = faces_of(shape)[k]
    measured = hausdorff(face, after[k], N).max
    assert measured <= bound
    assert face_area(after[k], 1e-6) == pytest.approx(face_area(face, 1e-6), rel=5e-3)
    return measured


@pytest.mark.slow
def test_replace_on_kj66_face_6_writes_a_closed_valid_part(tmp_path):
    """`ruled fit kj66 --face 6 --replace`: the part's 92 faces, its 11 solids valid and closed, face 6 the
    ruled result (degree 1 across its rulings) within the reported bound of the input's face 6."""
    src = data_file("kj66_impeller.step")
    out, rep = tmp_path / "part.step", tmp_path / "r.json"
    r = ruled_here("fit", src, "--face", "6", "--replace", "-o", out, "--report", rep, "--samples", "30",
                   "--measure-samples", str(N), "--quiet", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert "face 6 replaced" in r.stdout and "a valid closed solid" in r.stdout
    report = json.loads(rep.read_text())
    assert report["replace"]["closed_solid"] and report["replace"]["face"] == 6
    from ruled.occ.io import write_step
    write_step(read_shape(src), str(tmp_path / "as_is.step"))
    shape = read_shape(str(out))
    measured = _check_part(src, shape, 6, report["error_bound"], str(tmp_path / "as_is.step"))
    # sewn, the face's edges are the part's own: the measure loses the file's edge gap (0.0004), never gains
    assert measured <= report["hausdorff"]["max"] * 1.2 + 1e-5
    from OCP.BRep import BRep_Tool
    from OCP.Geom import Geom_BSplineSurface
    S = BRep_Tool.Surface_s(faces_of(shape)[6])
    assert isinstance(S, Geom_BSplineSurface) and 1 in (S.UDegree(), S.VDegree())

    # the same face, sewn within a hundredth of what it needs: refused, naming the face's edges
    from ruled.core.errors import RuledError
    from ruled.occ.replace import replaced_part
    with pytest.raises(RuledError, match=r"could not be sewn into the part: along edges \d.*of face 6"):
        replaced_part(read_shape(src), 6, faces_of(shape)[6], 0.01 * report["replace"]["sewing_tolerance"])


@pytest.mark.slow
def test_replace_face_in_cadquery_on_a_space_ship_face(tmp_path):
    """ruled.cq.replace_face on space-ship face 80 (its result pinned at the face's corners, sewn to faces
    whose edges lie 0.001 off their surfaces): the part's solids valid and closed, face 80 within its bound."""
    cq = pytest.importorskip("cadquery")
    from ruled.cq import replace_face
    src = data_file("occt_trj3_s1-al-214_space_ship.stp")
    part = cq.importers.importStep(src)
    rp = replace_face(part, 80, samples=30, measure_samples=N)
    assert rp.index == 80 and rp.closed_solid
    path, as_is = str(tmp_path / "ship.step"), str(tmp_path / "as_is.step")
    cq.exporters.export(rp.part, path)
    cq.exporters.export(part, as_is)
    _check_part(src, read_shape(path), 80, rp.fit.error_bound, as_is)


def test_replace_refusals_exit_2_in_one_line(tmp_path):
    """--replace with strips (--tol with --ends pinned) is refused before any work, in one line, exit 2."""
    src = data_file("kj66_impeller.step")
    r = ruled_here("fit", src, "--face", "6", "--replace", "--tol", "0.01", "--ends", "pinned", "-o",
                   tmp_path / "x.step", cwd=tmp_path)
    assert r.returncode == 2
    assert len(r.stderr.strip().splitlines()) == 1 and "--replace" in r.stderr
    assert not (tmp_path / "x.step").exists()
