"""Reading and writing CAD files (STEP, BREP) and listing faces."""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Optional

from OCP.BRep import BRep_Builder
from OCP.BRepGProp import BRepGProp
from OCP.BRepTools import BRepTools
from OCP.GProp import GProp_GProps
from OCP.IFSelect import IFSelect_ReturnStatus
from OCP.Interface import Interface_Static
from OCP.Message import Message, Message_Gravity
from OCP.STEPControl import STEPControl_Reader, STEPControl_StepModelType, STEPControl_Writer
from OCP.TopAbs import TopAbs_ShapeEnum
from OCP.TopExp import TopExp_Explorer
from OCP.TopoDS import TopoDS, TopoDS_Compound, TopoDS_Shape

from ruled.core.errors import BadInputError
from ruled.core.facecount import out_of_range, remember

# keep OCCT's transfer statistics off the user's terminal
for _printer in Message.DefaultMessenger_s().Printers():
    _printer.SetTraceLevel(Message_Gravity.Message_Fail)


def read_shape(path: str) -> TopoDS_Shape:
    """Read a STEP (.step/.stp) or BREP (.brep/.brp) file."""
    if not os.path.exists(path):
        raise BadInputError(f"{path}: no such file; check the path")
    if os.path.isdir(path):
        raise BadInputError(f"{path}: is a folder, not a CAD file; give a .step or .brep file")
    with open(path, "rb") as fh:
        head = fh.read(4096)
    ext = os.path.splitext(path)[1].lower()
    text = head.decode("latin-1", "replace")
    if "ISO-10303-21" in text or ext in (".step", ".stp"):
        if "ISO-10303-21" not in text:
            raise BadInputError(f"{path}: not a STEP file (no ISO-10303-21 header); "
                                "export STEP AP203/AP214 from your CAD system")
        reader = STEPControl_Reader()
        status = reader.ReadFile(path)
        if status != IFSelect_ReturnStatus.IFSelect_RetDone:
            raise BadInputError(f"{path}: the STEP reader failed ({status.name}); check the file in a CAD viewer")
        reader.TransferRoots()
        shape = reader.OneShape()
    elif "CASCADE Topology" in text or ext in (".brep", ".brp"):
        shape = TopoDS_Shape()
        ok = BRepTools.Read_s(shape, path, BRep_Builder())
        if not ok or shape.IsNull():
            raise BadInputError(f"{path}: not a readable OCCT BREP file; export STEP or BREP from your CAD system")
    else:
        raise BadInputError(f"{path}: not a CAD file Ruled can read; give a STEP (.step/.stp) or BREP (.brep) file")
    if shape is None or shape.IsNull():
        raise BadInputError(f"{path}: the file holds no shape")
    return shape


def shapes_of(shape: TopoDS_Shape, kind: TopAbs_ShapeEnum) -> list:
    """The sub-shapes of one kind in TopExp_Explorer order (as TopoDS_Shape)."""
    out = []
    exp = TopExp_Explorer(shape, kind)
    while exp.More():
        out.append(exp.Current())
        exp.Next()
    return out


def faces_of(shape: TopoDS_Shape) -> list:
    """Faces in TopExp_Explorer order (the index the CLI's --face uses)."""
    return [TopoDS.Face_s(f) for f in shapes_of(shape, TopAbs_ShapeEnum.TopAbs_FACE)]


def compound(shapes) -> TopoDS_Compound:
    """The shapes as one compound."""
    comp = TopoDS_Compound()
    b = BRep_Builder()
    b.MakeCompound(comp)
    for s in shapes:
        b.Add(comp, s)
    return comp


def get_face(path: str, index: int, shape: Optional[TopoDS_Shape] = None):
    """Face ``index`` of the file (of shape, the file read already, when given)."""
    faces = faces_of(read_shape(path) if shape is None else shape)
    remember(path, len(faces))
    err = out_of_range(path, index, len(faces))
    if err is not None:
        raise err
    return faces[index]


def read_faces(path: str) -> list:
    """The file's faces (see faces_of); their count is remembered for a later wrong --face."""
    faces = faces_of(read_shape(path))
    remember(path, len(faces))
    return faces


def face_area(face, eps: float = None) -> float:
    """The face's area by OCCT: its fixed-order rule, or integrated adaptively to a relative error of eps
    (the fixed rule is off by 0.5 % on a face of many degree-1 spans; neither is exact on every face)."""
    props = GProp_GProps()
    if eps is None:
        BRepGProp.SurfaceProperties_s(face, props)
    else:
        BRepGProp.SurfaceProperties_s(face, props, eps)
    return props.Mass()


@dataclass(frozen=True)
class FaceInfo:
    index: int
    surface_type: str
    degrees: tuple | None
    poles: tuple | None
    closed: tuple
    periodic: tuple
    area: float

    def line(self) -> str:
        deg = f"{self.degrees[0]}x{self.degrees[1]}" if self.degrees else "-"
        pol = f"{self.poles[0]}x{self.poles[1]}" if self.poles else "-"
        cl = "".join(n for n, f in zip("uv", self.closed) if f) or "-"
        pe = "".join(n for n, f in zip("uv", self.periodic) if f) or "-"
        return (f"{self.index:4d}  {self.surface_type:<10s} degrees {deg:<7s} poles {pol:<8s} "
                f"closed {cl:<2s} periodic {pe:<2s} area {self.area:.6g}")


def face_info(index: int, face) -> FaceInfo:
    from ruled.occ.convert import face_surface_type
    st = face_surface_type(face)
    from OCP.BRepAdaptor import BRepAdaptor_Surface
    ad = BRepAdaptor_Surface(face)
    degrees = poles = None
    if st == "bspline":
        bs = ad.BSpline()
        degrees = (bs.UDegree(), bs.VDegree())
        poles = (bs.NbUPoles(), bs.NbVPoles())
    elif st == "bezier":
        bz = ad.Bezier()
        degrees = (bz.UDegree(), bz.VDegree())
        poles = (bz.NbUPoles(), bz.NbVPoles())
    closed = (bool(ad.IsUClosed()), bool(ad.IsVClosed()))
    periodic = (bool(ad.IsUPeriodic()), bool(ad.IsVPeriodic()))
    return FaceInfo(index, st, degrees, poles, closed, periodic, face_area(face))


def list_faces(path: str) -> list[FaceInfo]:
    return [face_info(i, f) for i, f in enumerate(read_faces(path))]


def write_step(shapes, path: str) -> None:
    """Write one shape or a list of shapes (as a compound) to STEP AP214."""
    comp = compound(shapes if isinstance(shapes, (list, tuple)) else [shapes])
    Interface_Static.SetCVal_s("write.step.schema", "AP214IS")
    w = STEPControl_Writer()
    w.Transfer(comp, STEPControl_StepModelType.STEPControl_AsIs)
    d = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(d):
        raise BadInputError(f"cannot write {path}: folder {d} does not exist")
    from ruled.core.outputs import atomic
    with atomic(path) as tmp:
        if w.Write(tmp) != IFSelect_ReturnStatus.IFSelect_RetDone:
            raise BadInputError(f"cannot write {path}; check that the folder is writable")


__all__ = ["read_shape", "shapes_of", "faces_of", "compound", "get_face", "face_area", "list_faces", "write_step",
           "FaceInfo"]
