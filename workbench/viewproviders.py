"""View provider of RuledFit: the result coloured by its measured distance to the source (blue: none,
red: the largest), with the rulings as lines, in a "Deviation" display mode beside Part's own, and a
colour legend in the 3D view (the range in the document's units).  Double-click opens the object's
task panel."""

from __future__ import annotations

import FreeCAD
import numpy as np


def colour_ramp(t: np.ndarray) -> np.ndarray:
    """0 -> blue, 0.5 -> green, 1 -> red (N, 3)."""
    t = np.clip(np.asarray(t, float), 0.0, 1.0)
    r = np.clip(2.0 * t - 0.5, 0.0, 1.0)
    g = np.clip(1.5 - np.abs(2.0 * t - 1.0) * 1.5, 0.0, 1.0)
    b = np.clip(1.5 - 2.0 * t, 0.0, 1.0)
    return np.stack([r, g, b], axis=1)


# the colour scale never spans less than this fraction of the face's size (round-off on an exact fit)
FLOOR = 1e-6
LEGENDS = {}             # document name -> (object name, the legend's Coin node, its label texts, the view)


def legend_labels(top: float) -> list:
    """Five values from 0 to top, three significant digits each, in the unit the user's schema gives top
    (e.g. '0 µm' ... '1.46 µm'): the top label reads as the Hausdorff property does."""
    try:
        _, factor, unit = FreeCAD.Units.Quantity(float(top), FreeCAD.Units.Length).getUserPreferred()
        factor = float(factor) or 1.0
    except Exception:
        factor, unit = 1.0, "mm"
    return [f"{top * t / factor:.3g} {unit}" for t in np.linspace(0.0, 1.0, 5)]


def colour_range(dev: np.ndarray, size: float, hausdorff: float = 0.0) -> float:
    """The top of the colour scale: the measured Hausdorff distance (the legend's top reads as the property),
    or without one the largest distance, at least FLOOR x the face's size."""
    if hausdorff > 0:
        return float(hausdorff)
    top = float(dev.max()) if dev.size else 0.0
    return max(top, FLOOR * size, 1e-12)


def _legend_node(top: float, title: str):
    """A colour bar at the right edge of the view (its own orthographic camera: it stays put when the
    model turns), blue 0 at the bottom to red ``top``, with five labels and a title."""
    from pivy import coin
    root = coin.SoAnnotation()           # drawn last, over the model (no depth test)
    cam = coin.SoOrthographicCamera()
    cam.viewportMapping = getattr(coin.SoCamera, "LEAVE_AS_IS", 4)   # not exposed by every pivy
    cam.position = (0.0, 0.0, 1.0)
    cam.height = 2.0
    cam.nearDistance, cam.farDistance = 0.5, 1.5
    root.addChild(cam)
    light = coin.SoLightModel()
    light.model = coin.SoLightModel.BASE_COLOR
    root.addChild(light)
    # (the view's x and y each run from -1 to 1 across it: the bar at its right edge, the labels to the bar's
    # left and the title above it, right-aligned, so that nothing reaches past the edge at any window size,
    # the bar's top a third of the way down, under the navigation cube, its foot above the axis cross)
    x0, x1, y0, y1, n = 0.90, 0.94, -0.72, 0.35, 32
    ts = np.linspace(0.0, 1.0, n + 1)
    cols = colour_ramp(ts)
    pts, colours, idx = [], [], []
    for k, t in enumerate(ts):
        y = y0 + (y1 - y0) * t
        pts += [(x0, y, 0.0), (x1, y, 0.0)]
        colours += [tuple(map(float, cols[k]))] * 2
        if k:
            a = 2 * (k - 1)
            idx += [a, a + 1, a + 3, a + 2, -1]
    mat = coin.SoMaterial()
    mat.diffuseColor.setValues(0, len(colours), colours)
    bind = coin.SoMaterialBinding()
    bind.value = coin.SoMaterialBinding.PER_VERTEX_INDEXED
    coords = coin.SoCoordinate3()
    coords.point.setValues(0, len(pts), pts)
    faces = coin.SoIndexedFaceSet()
    faces.coordIndex.setValues(0, len(idx), idx)
    faces.materialIndex.setValues(0, len(idx), idx)
    for node in (mat, bind, coords, faces):
        root.addChild(node)
    labels = [title] + legend_labels(top)
    text_col = coin.SoBaseColor()
    text_col.rgb = (0.1, 0.1, 0.1)
    root.addChild(text_col)
    font = coin.SoFont()
    font.size = 13
    root.addChild(font)
    places = [(x1, y1 + 0.05)] + [(x0 - 0.012, y0 + (y1 - y0) * t - 0.012) for t in np.linspace(0, 1, 5)]
    for text, (x, y) in zip(labels, places):
        sep = coin.SoSeparator()
        tr = coin.SoTranslation()
        tr.translation = (x, y, 0.0)
        t2 = coin.SoText2()
        t2.string = text
        t2.justification = coin.SoText2.RIGHT
        sep.addChild(tr)
        sep.addChild(t2)
        root.addChild(sep)
    return root, labels


def show_legend(obj, top: float) -> None:
    """The document's colour legend for obj (one per document: the last one drawn or shown takes it)."""
    import FreeCADGui
    hide_legend(obj.Document.Name)
    gdoc = FreeCADGui.getDocument(obj.Document.Name)
    view = getattr(gdoc, "ActiveView", None) if gdoc else None
    if view is None or not hasattr(view, "getSceneGraph"):
        return
    what = "the wall" if type(getattr(obj, "Proxy", None)).__name__ == "RuledWall" else "the face"
    node, labels = _legend_node(top, f"{obj.Label}: distance to {what}")
    view.getSceneGraph().addChild(node)
    LEGENDS[obj.Document.Name] = (obj.Name, node, labels, view)


def hide_legend(doc_name: str, owner: str = None) -> None:
    """Remove the document's legend (only if it is owner's, when given)."""
    entry = LEGENDS.get(doc_name)
    if entry is None or (owner is not None and entry[0] != owner):
        return
    LEGENDS.pop(doc_name)
    try:
        entry[3].getSceneGraph().removeChild(entry[1])
    except Exception:       # the view was closed
        pass


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
         "RuledConeSpline": "cone.svg", "RuledCurveOnFace": "curve.svg", "RuledWall": "wall.svg"}


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
    if type(obj.Proxy).__name__ == "RuledCurveOnFace":
        ViewProviderRuledCurve(obj.ViewObject)
        obj.ViewObject.LineColor = (0.85, 0.1, 0.1)
        obj.ViewObject.LineWidth = 4.0
    else:
        ViewProviderRuledFit(obj.ViewObject)
