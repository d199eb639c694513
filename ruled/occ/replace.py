"""A face's result put back into its part (issue 35, point 6): the part's face K replaced by the ruled
result and sewn to its neighbours, the part's faces kept in their order (face K of the written part is the
result), refused in one line where the sewn part is no longer closed, naming the edges that did not meet."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from OCP.BRep import BRep_Builder, BRep_Tool
from OCP.BRepAdaptor import BRepAdaptor_Curve
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeSolid, BRepBuilderAPI_MakeVertex, BRepBuilderAPI_Sewing
from OCP.BRepCheck import BRepCheck_Analyzer
from OCP.BRepExtrema import BRepExtrema_DistShapeShape
from OCP.BRepLib import BRepLib
from OCP.BRepTools import BRepTools_ReShape
from OCP.TopAbs import TopAbs_ShapeEnum
from OCP.TopExp import TopExp
from OCP.TopoDS import TopoDS, TopoDS_Shape, TopoDS_Shell
from OCP.TopTools import TopTools_IndexedDataMapOfShapeListOfShape

from ruled.core.errors import BadInputError, RuledError
from ruled.occ.io import faces_of, shapes_of

MARGIN = 1.1      # the sewing tolerance: this many times the result's bound (its edges lie that near the face's)
FLOOR = 1e-7      # ... and never below this, nor below the tolerances the edges carry


class SewingError(RuledError):
    """The result could not be sewn into its part."""

    kind = "not sewn"


@dataclass(frozen=True)
class Replaced:
    """The part with face ``index`` replaced by a result: its shape, the sewn result face, and the figures."""

    shape: TopoDS_Shape
    face: Any             # TopoDS_Face
    index: int
    tolerance: float
    solid: bool           # the face's owner was, and is, a closed solid
    faces: int
    free_edges: int       # the owner's free edges (as many as before)

    def report(self) -> dict:
        return {"face": self.index, "sewing_tolerance": self.tolerance, "closed_solid": self.solid,
                "faces": self.faces, "free_edges": self.free_edges}


def _owner(shape, face) -> tuple:
    """(the solid, or else the shell, holding face; None when it is a lone face), and whether a solid."""
    for kind, solid in ((TopAbs_ShapeEnum.TopAbs_SOLID, True), (TopAbs_ShapeEnum.TopAbs_SHELL, False)):
        for s in shapes_of(shape, kind):
            if any(f.IsSame(face) for f in shapes_of(s, TopAbs_ShapeEnum.TopAbs_FACE)):
                return s, solid
    return None, False


def free_edges(shape) -> list:
    """The edges of shape that bound one face only (not seams, not degenerate): where it is open."""
    m = TopTools_IndexedDataMapOfShapeListOfShape()
    TopExp.MapShapesAndAncestors_s(shape, TopAbs_ShapeEnum.TopAbs_EDGE, TopAbs_ShapeEnum.TopAbs_FACE, m)
    out = []
    for i in range(1, m.Extent() + 1):
        e = TopoDS.Edge_s(m.FindKey(i))
        if BRep_Tool.Degenerated_s(e):
            continue
        faces: list = []
        for f in m.FindFromIndex(i):
            if not any(f.IsSame(g) for g in faces):
                faces.append(f)
        if len(faces) == 1 and not BRep_Tool.IsClosed_s(e, TopoDS.Face_s(faces[0])):
            out.append(e)
    return out


def sewing_tolerance(bound: float, *faces) -> float:
    """MARGIN x the result's bound, at least the tolerances the faces' edges carry and FLOOR."""
    return max([FLOOR, MARGIN * float(bound)] + [BRep_Tool.Tolerance_s(TopoDS.Edge_s(e)) for f in faces
                                                    for e in shapes_of(f, TopAbs_ShapeEnum.TopAbs_EDGE)])


def _distance(a, b) -> float:
    d = BRepExtrema_DistShapeShape(a, b)
    return float(d.Value()) if d.IsDone() and d.NbSolution() > 0 else float("inf")


def _points(edge, n: int = 9) -> list:
    ad = BRepAdaptor_Curve(edge)
    a, b = ad.FirstParameter(), ad.LastParameter()
    return [BRepBuilderAPI_MakeVertex(ad.Value(a + (b - a) * i / (n - 1))).Vertex() for i in range(n)]


def _unmet(new_free: list, old_face) -> str:
    """Which edges of face K (as 'ruled faces --edges' numbers them; its holes' edges after) the result's
    free edges lie along, each with how far the result's edge strays from it."""
    from ruled.occ.region import outer_edges
    outer = outer_edges(old_face)
    edges = outer + [e for e in shapes_of(old_face, TopAbs_ShapeEnum.TopAbs_EDGE)
                     if not any(e.IsSame(o) for o in outer)]
    found: dict = {}
    for fe in new_free:
        pts = _points(fe)
        d = [_distance(pts[len(pts) // 2], e) for e in edges]
        j = min(range(len(d)), key=d.__getitem__)
        found[j] = max([found.get(j, 0.0)] + [_distance(p, edges[j]) for p in pts])
    return ", ".join(f"{j} (off by {g:.3g})" for j, g in sorted(found.items()))


def replaced_part(shape: TopoDS_Shape, index: int, new_face, tol: float) -> Replaced:
    """shape with its face ``index`` (faces_of order) replaced by new_face, sewn to the face's neighbours
    within tol: the face's solid (or shell) rebuilt with its faces in their order, the rest of the part as
    it was.  Raises SewingError naming the face's edges that did not meet, where the owner had no more free
    edges before, or a solid is no longer a valid closed solid."""
    faces = faces_of(shape)
    if not 0 <= index < len(faces):
        raise BadInputError(f"face {index} is not in the part ({len(faces)} faces); see 'ruled faces'")
    old = faces[index]
    owner, solid = _owner(shape, old)
    target = owner if owner is not None else shape
    own = faces_of(target)
    sew = BRepBuilderAPI_Sewing(tol)
    for f in own:
        sew.Add(new_face if f.IsSame(old) else f)
    sew.Perform()
    if sew.NbMultipleEdges() > 0:
        raise SewingError(f"face {index}'s result sewn into the part meets {sew.NbMultipleEdges()} edges of more "
                          f"than two faces (the sewing tolerance {tol:.3g} is larger than a feature of the part); "
                          "fit it closer («samples») or write the face alone (without replacing it)")
    # the owner's faces in their order, face K's place taken by the sewn result
    # (each face as it lies in the sewn shape: sewing orients the result face to its neighbours)
    b, shell = BRep_Builder(), TopoDS_Shell()
    b.MakeShell(shell)
    sewn = faces_of(sew.SewedShape())
    sewn_new = None
    for f in own:
        m = sew.Modified(new_face if f.IsSame(old) else f)
        g = next((x for x in sewn if x.IsSame(m)), m)
        if f.IsSame(old):
            sewn_new = g
        b.Add(shell, g)
    before = len(free_edges(target))
    after = free_edges(shell)
    new_free = [e for e in after if any(e.IsSame(x) for x in shapes_of(sewn_new, TopAbs_ShapeEnum.TopAbs_EDGE))]
    if len(after) > before and new_free:
        raise SewingError(f"face {index}'s result could not be sewn into the part: along edges "
                          f"{_unmet(new_free, old)} of face {index} it did not meet the neighbouring "
                          f"faces within the sewing tolerance {tol:.3g}; write the face alone (without replacing "
                          "it), or fit it closer («samples»)")
    if solid:
        shell.Closed(True)
        mk = BRepBuilderAPI_MakeSolid(shell)
        built: TopoDS_Shape = mk.Solid() if mk.IsDone() else TopoDS_Shape()
        if built.IsNull() or not BRepLib.OrientClosedSolid_s(TopoDS.Solid_s(built)) \
                or not BRepCheck_Analyzer(built).IsValid():
            raise SewingError(f"face {index}'s result sewn into the part does not give a valid closed solid "
                              "(OCCT's check); write the face alone (without replacing it)")
    else:
        built = shell
    if owner is None:
        out = built
    else:
        rs = BRepTools_ReShape()
        rs.Replace(owner, built)
        out = rs.Apply(shape)
    got = faces_of(out)
    if len(got) != len(faces):
        raise SewingError(f"face {index}'s result sewn into the part gives {len(got)} faces where it had "
                          f"{len(faces)}; write the face alone (without replacing it)")
    k = next((i for i, f in enumerate(got) if f.IsSame(sewn_new)), index)
    return Replaced(out, got[k], k, tol, solid, len(got), len(after))


__all__ = ["Replaced", "SewingError", "free_edges", "replaced_part", "sewing_tolerance"]
