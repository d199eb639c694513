"""View provider of RuledFit: the result coloured by its measured distance to the source (blue: none,
red: the largest), with the rulings as lines, in a "Deviation" display mode beside Part's own, and a
colour legend in the 3D view (the range in the document's units).  Double-click opens the object's
task panel."""

from __future__ import annotations

import FreeCAD
import numpy as np

from .legend import LEGENDS, colour_ramp, exact_bound, hide_legend, show_legend  # noqa: F401  (re-exported)

# the colour scale never spans less than this fraction of the face's size (round-off on an exact fit)
FLOOR = 1e-6


def colour_range(dev: np.ndarray, size: float, hausdorff: float = 0.0) -> float:
    """The top of the colour scale: the measured Hausdorff distance (the legend's top reads as the property),
    or without one the largest distance, at least FLOOR x the face's size."""
    if hausdorff > 0:
        return float(hausdorff)
    top = float(dev.max()) if dev.size else 0.0
    return max(top, FLOOR * size, 1e-12)


class _LegendObserver:
    """The legend goes with its object however it goes (undo of its creation, a deletion by script), not only
    through the view provider's onDelete; registered once, with the first view provider (GUI only)."""

    def slotDeletedObject(self, obj):
        try:
            hide_legend(obj.Document.Name, obj.Name)
        except Exception:       # (an observer must never raise into FreeCAD)
            pass

    def slotDeletedDocument(self, doc):
        LEGENDS.pop(getattr(doc, "Name", None), None)

    def slotUndoDocument(self, doc):
        self._relegend(doc)

    def slotRedoDocument(self, doc):
        self._relegend(doc)

    @staticmethod
    def _relegend(doc):
        """After undo or redo, the legend of the last visible Ruled result of the document, where it has none
        (a redo brings an object back without attaching its view provider again)."""
        try:
            if doc.Name in LEGENDS:
                return
            for obj in reversed(doc.Objects):
                vp = getattr(getattr(obj, "ViewObject", None), "Proxy", None)
                if isinstance(vp, ViewProviderRuledFit) and obj.ViewObject.Visibility and hasattr(vp, "root"):
                    vp._rebuild(obj)
                    return
        except Exception:       # (an observer must never raise into FreeCAD)
            pass


_OBSERVER: list = []


def _observe() -> None:
    if not _OBSERVER:
        _OBSERVER.append(_LegendObserver())
        FreeCAD.addDocumentObserver(_OBSERVER[0])


class _Editable:
    """Double-click (or Edit in the context menu) opens the object's own task panel."""

    def doubleClicked(self, vobj):
        import FreeCADGui

        from .state import PANELS
        if type(vobj.Object.Proxy).__name__ not in PANELS:
            return False         # (the workbench's panels not loaded: its properties are its parameters)
        FreeCADGui.ActiveDocument.setEdit(vobj.Object.Name, 0)
        return True

    def setEdit(self, vobj, mode=0):
        """Mode 0 (double-click, Edit in the context menu): the object's own task panel."""
        if mode != 0:
            return None          # Part's transform dragger and the other modes

        from .busy import show_panel
        from .state import PANELS
        edit = PANELS.get(type(vobj.Object.Proxy).__name__)
        if edit is None:
            return False
        show_panel(edit(vobj.Object))
        return True

    def unsetEdit(self, vobj, mode=0):
        if mode != 0:
            return None
        return True

    def __getstate__(self):
        return None

    def __setstate__(self, state):
        return None

    dumps, loads = __getstate__, __setstate__


ICONS = {"RuledFit": "fit.svg", "RuledSplit": "split.svg", "RuledPartition": "partition.svg",
         "RuledConeSpline": "cone.svg", "RuledCurveOnFace": "curve.svg", "RuledWall": "wall.svg",
         "RuledReplace": "replace.svg"}


def _icon(vobj_or_obj) -> str:
    from . import icon
    obj = getattr(vobj_or_obj, "Object", vobj_or_obj)
    return icon(ICONS.get(type(getattr(obj, "Proxy", None)).__name__, "ruled.svg"))


class ViewProviderRuledCurve(_Editable):
    """RuledCurveOnFace: Part's display of its edges (thick, red), its own icon and panel."""

    def __init__(self, vobj):
        vobj.Proxy = self

    def attach(self, vobj):
        self.vobj = vobj

    def getIcon(self):
        return _icon(self.vobj)


class ViewProviderRuledReplace(ViewProviderRuledCurve):
    """RuledReplace: Part's display of the part, its own icon (a proxy of its own: FreeCAD 0.20 shows a
    FeaturePython's view provider without one again on reopening, whatever its saved visibility)."""


class ViewProviderRuledFit(_Editable):
    """Every Ruled object with result faces (RuledFit, RuledSplit, RuledPartition, RuledConeSpline): each
    face coloured by its measured distance to the source, the rulings, the faces' outlines and the
    split curves (the shape's edges that bound no face) in red."""

    def __init__(self, vobj):
        vobj.addProperty("App::PropertyBool", "ShowRulings", "Ruled", "draw the DP rulings as lines")
        vobj.ShowRulings = True
        vobj.Proxy = self

    def attach(self, vobj):
        from pivy import coin
        _observe()
        self.vobj = vobj
        self.root = coin.SoSeparator()
        self.mesh = coin.SoSeparator()
        self.lines = coin.SoSeparator()
        self.root.addChild(self.mesh)
        self.root.addChild(self.lines)
        vobj.addDisplayMode(self.root, "Deviation")
        self._rebuild(vobj.Object)

    def getDisplayModes(self, vobj):
        return ["Deviation"]

    def getDefaultDisplayMode(self):
        return "Deviation"

    def setDisplayMode(self, mode):
        return mode

    def updateData(self, obj, prop):
        if prop in ("Deviation", "RulingLines", "Shape") and hasattr(self, "root"):
            self._rebuild(obj)

    def onChanged(self, vobj, prop):
        if prop == "ShowRulings" and hasattr(self, "root"):
            self._rebuild(vobj.Object)
        if prop == "Visibility" and hasattr(self, "root"):
            obj = vobj.Object
            if vobj.Visibility:
                self._rebuild(obj)
            else:
                hide_legend(obj.Document.Name, obj.Name)

    def onDelete(self, vobj, subelements):
        hide_legend(vobj.Object.Document.Name, vobj.Object.Name)
        return True

    def getIcon(self):
        return _icon(self.vobj) if hasattr(self, "vobj") else _icon(None)

    def _rebuild(self, obj):
        from .measure import trimmed
        self.mesh.removeAllChildren()
        self.lines.removeAllChildren()
        faces = obj.Shape.Faces if not obj.Shape.isNull() else []
        if not faces:
            hide_legend(obj.Document.Name, obj.Name)
            return
        dev = np.asarray(getattr(obj, "Deviation", []), float)
        n = int(round(np.sqrt(len(dev) / len(faces)))) if len(dev) else 0
        if n < 2 or n * n * len(faces) != len(dev):
            n, dev = 16, None
        if dev is not None:
            top = colour_range(dev, obj.Shape.BoundBox.DiagonalLength, float(getattr(obj.Hausdorff, "Value",
                                                                                       obj.Hausdorff or 0.0)))
            if getattr(self.vobj, "Visibility", True):
                show_legend(obj, top)
        else:
            hide_legend(obj.Document.Name, obj.Name)
        m = max(n, MESH * (4 if type(getattr(obj, "Proxy", None)).__name__ == "RuledWall" else 1))   # (round a part)
        if dev is not None and exact_bound(obj) is not None:
            dev = np.zeros_like(dev)        # an exact result: one colour (its legend says 'exact'), not round-off's
        for k, face in enumerate(faces):
            if trimmed(face):     # a result trimmed by the face's edges: shown inside them
                grid = None if dev is None else dev[k * n * n:(k + 1) * n * n].reshape(n, n) / top
                self.mesh.addChild(_trimmed_mesh(face, grid))
                self.lines.addChild(_polylines(face.Edges, (0.25, 0.25, 0.25), 1.0))
                continue
            cols = np.tile([0.75, 0.78, 0.82], (m * m, 1)) if dev is None else \
                colour_ramp(_resampled(dev[k * n * n:(k + 1) * n * n].reshape(n, n), m).ravel() / top)
            self.mesh.addChild(_face_mesh(face, m, cols))
        if len(faces) > 1:       # the strips' or patches' outlines
            self.lines.addChild(_polylines([e for f in faces for e in f.Edges], (0.25, 0.25, 0.25), 1.0))
        free = [c for c in obj.Shape.childShapes() if c.ShapeType in ("Edge", "Wire")]
        if free:                 # the split curves on the face
            self.lines.addChild(_polylines([e for c in free for e in c.Edges], (0.85, 0.1, 0.1), 4.0))
        # the view properties are restored after attach() when a document opens: defaults until then
        lp = [(p.x, p.y, p.z) for p in getattr(obj, "RulingLines", None) or []]
        if getattr(self.vobj, "ShowRulings", True) and lp:
            self.lines.addChild(_segments(lp, (0.1, 0.1, 0.1), 1.5))


class ViewProviderRuledSplit(ViewProviderRuledFit):
    """Documents saved before the split had colours name this class: the same view provider."""


MESH = 24               # the least grid of a face's mesh (the measured grid may be coarser: interpolated)


def _resampled(grid: np.ndarray, m: int) -> np.ndarray:
    """An n x n grid of values over a face's parameters, bilinearly interpolated to m x m."""
    n = grid.shape[0]
    if m == n:
        return grid
    x, y = np.linspace(0.0, 1.0, n), np.linspace(0.0, 1.0, m)
    rows = np.array([np.interp(y, x, r) for r in grid])
    return np.array([np.interp(y, x, c) for c in rows.T]).T


def _trimmed_mesh(face, values):
    """A face trimmed inside its surface's rectangle as Part's own triangulation (so that it shows inside
    its edges only), coloured per vertex by values, an n x n grid over its parameter range (None: grey)."""
    from scipy.interpolate import RegularGridInterpolator

    from .measure import face_bounds
    pts, tris = face.tessellate(face.BoundBox.DiagonalLength / 400.0)
    if values is None:
        cols = np.tile([0.75, 0.78, 0.82], (len(pts), 1))
    else:
        u0, u1, v0, v1 = face_bounds(face)
        n = values.shape[0]
        f = RegularGridInterpolator((np.linspace(u0, u1, n), np.linspace(v0, v1, n)), values, bounds_error=False,
                                    fill_value=None)
        uv = np.array([face.Surface.parameter(p) for p in pts], float)
        cols = colour_ramp(np.clip(f(uv), 0.0, None))
    return _mesh_node([(p.x, p.y, p.z) for p in pts], cols, [i for t in tris for i in (*map(int, t), -1)])


def _face_mesh(face, n: int, cols):
    """The face's n x n parameter grid as triangles, coloured per vertex."""
    from .measure import grid
    pts = grid(face, n)            # the same grid (and order) as the measured deviations
    idx = []
    for i in range(n - 1):
        for j in range(n - 1):
            a, b, c, d = i * n + j, (i + 1) * n + j, (i + 1) * n + j + 1, i * n + j + 1
            idx += [a, b, c, -1, a, c, d, -1]
    return _mesh_node([tuple(map(float, p)) for p in pts], cols, idx)


def _mesh_node(points: list, cols, idx: list):
    """Triangles (idx: three vertex indices and -1 each) through points, coloured per vertex."""
    from pivy import coin
    sep = coin.SoSeparator()
    mat = coin.SoMaterial()
    mat.diffuseColor.setValues(0, len(cols), [tuple(map(float, c)) for c in cols])
    bind = coin.SoMaterialBinding()
    bind.value = coin.SoMaterialBinding.PER_VERTEX_INDEXED
    hints = coin.SoShapeHints()
    hints.vertexOrdering = coin.SoShapeHints.COUNTERCLOCKWISE
    hints.creaseAngle = 0.8
    coords = coin.SoCoordinate3()
    coords.point.setValues(0, len(points), points)
    tri = coin.SoIndexedFaceSet()
    tri.coordIndex.setValues(0, len(idx), idx)
    tri.materialIndex.setValues(0, len(idx), idx)
    for node in (hints, mat, bind, coords, tri):
        sep.addChild(node)
    return sep


def _line_node(points, counts, colour, width):
    from pivy import coin
    sep = coin.SoSeparator()
    lm = coin.SoMaterial()
    lm.diffuseColor = colour
    style = coin.SoDrawStyle()
    style.lineWidth = width
    lc = coin.SoCoordinate3()
    lc.point.setValues(0, len(points), points)
    ls = coin.SoLineSet()
    ls.numVertices.setValues(0, len(counts), counts)
    for node in (lm, style, lc, ls):
        sep.addChild(node)
    return sep


def _segments(points, colour, width):
    """Line segments between consecutive pairs of points."""
    return _line_node(points, [2] * (len(points) // 2), colour, width)


def _polylines(edges, colour, width):
    """The edges as polylines (FreeCAD's discretization)."""
    pts, counts = [], []
    for e in edges:
        if e.Degenerated:
            continue
        q = e.discretize(Deflection=max(2e-4 * e.Length, 1e-7))
        pts += [(p.x, p.y, p.z) for p in q]
        counts.append(len(q))
    return _line_node(pts, counts, colour, width)


def attach_view_provider(obj) -> None:
    if not FreeCAD.GuiUp:
        return
    if type(obj.Proxy).__name__ == "RuledReplace":
        ViewProviderRuledReplace(obj.ViewObject)
    elif type(obj.Proxy).__name__ == "RuledCurveOnFace":
        ViewProviderRuledCurve(obj.ViewObject)
        obj.ViewObject.LineColor = (0.85, 0.1, 0.1)
        obj.ViewObject.LineWidth = 4.0
    else:
        ViewProviderRuledFit(obj.ViewObject)
