"""View provider of RuledFit: the result coloured by its measured distance to the source (blue: none,
red: the largest), with the rulings as lines, in a "Deviation" display mode beside Part's own, and a
colour legend in the 3D view (the range in the document's units).  Double-click opens the object's
task panel."""

from __future__ import annotations

import numpy as np

import FreeCAD


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


def user_length(x: float) -> str:
    """A length in the user's unit schema (e.g. '0.12 mm')."""
    try:
        return FreeCAD.Units.Quantity(float(x), FreeCAD.Units.Length).UserString
    except Exception:
        return f"{float(x):.4g} mm"


def colour_range(dev: np.ndarray, size: float) -> float:
    """The top of the colour scale: the largest distance, at least FLOOR x the face's size."""
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
    x0, x1, y0, y1, n = 0.80, 0.85, -0.75, 0.65, 32
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
    labels = [title] + [user_length(top * t) for t in np.linspace(0.0, 1.0, 5)]
    text_col = coin.SoBaseColor()
    text_col.rgb = (0.1, 0.1, 0.1)
    root.addChild(text_col)
    font = coin.SoFont()
    font.size = 13
    root.addChild(font)
    # the title right-aligned at the view's right edge, above the bar; the values beside the bar
    places = [(0.98, y1 + 0.08)] + [(x1 + 0.01, y0 + (y1 - y0) * t - 0.01) for t in np.linspace(0, 1, 5)]
    for k, (text, (x, y)) in enumerate(zip(labels, places)):
        sep = coin.SoSeparator()
        tr = coin.SoTranslation()
        tr.translation = (x, y, 0.0)
        t2 = coin.SoText2()
        t2.string = text
        if k == 0:
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
    node, labels = _legend_node(top, f"{obj.Label}: distance to the face")
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
        FreeCADGui.ActiveDocument.setEdit(vobj.Object.Name, 0)
        return True

    def setEdit(self, vobj, mode=0):
        """Mode 0 (double-click, Edit in the context menu): the object's own task panel."""
        if mode != 0:
            return None          # Part's transform dragger and the other modes
        import FreeCADGui

        from .taskpanels import panel_for
        FreeCADGui.Control.showDialog(panel_for(vobj.Object))
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


class ViewProviderRuledSplit(_Editable):
    """RuledSplit: Part's display of its two fitted halves and the split curve, its own icon and panel."""

    def __init__(self, vobj):
        vobj.Proxy = self

    def attach(self, vobj):
        self.vobj = vobj

    def getIcon(self):
        from . import icon
        return icon("split.svg")


class ViewProviderRuledFit(_Editable):
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
        from . import icon
        return icon("fit.svg")

    def _rebuild(self, obj):
        from pivy import coin

        from .measure import face_bounds
        self.mesh.removeAllChildren()
        self.lines.removeAllChildren()
        if not obj.Shape.Faces:
            return
        face = obj.Shape.Faces[0]
        dev = np.asarray(getattr(obj, "Deviation", []), float)
        n = int(round(np.sqrt(len(dev)))) if len(dev) else 0
        if n < 2 or n * n != len(dev):
            n, dev = 24, None
        u0, u1, v0, v1 = face_bounds(face)
        s = face.Surface
        pts = [s.value(float(u), float(v)) for u in np.linspace(u0, u1, n) for v in np.linspace(v0, v1, n)]
        if dev is not None:
            top = colour_range(dev, face.BoundBox.DiagonalLength)
            cols = colour_ramp(dev / top)
            if getattr(self.vobj, "Visibility", True):
                show_legend(obj, top)
        else:
            cols = np.tile([0.75, 0.78, 0.82], (n * n, 1))
            hide_legend(obj.Document.Name, obj.Name)
        mat = coin.SoMaterial()
        mat.diffuseColor.setValues(0, n * n, [tuple(map(float, c)) for c in cols])
        bind = coin.SoMaterialBinding()
        bind.value = coin.SoMaterialBinding.PER_VERTEX_INDEXED
        hints = coin.SoShapeHints()
        hints.vertexOrdering = coin.SoShapeHints.COUNTERCLOCKWISE
        hints.creaseAngle = 0.8
        coords = coin.SoCoordinate3()
        coords.point.setValues(0, n * n, [(p.x, p.y, p.z) for p in pts])
        idx = []
        for i in range(n - 1):
            for j in range(n - 1):
                a, b, c, d = i * n + j, (i + 1) * n + j, (i + 1) * n + j + 1, i * n + j + 1
                idx += [a, b, c, -1, a, c, d, -1]
        faces = coin.SoIndexedFaceSet()
        faces.coordIndex.setValues(0, len(idx), idx)
        faces.materialIndex.setValues(0, len(idx), idx)
        for node in (hints, mat, bind, coords, faces):
            self.mesh.addChild(node)
        # the view properties are restored after attach() when a document opens: defaults until then
        if getattr(self.vobj, "ShowRulings", True) and getattr(obj, "RulingLines", None):
            lm = coin.SoMaterial()
            lm.diffuseColor = (0.1, 0.1, 0.1)
            style = coin.SoDrawStyle()
            style.lineWidth = 1.5
            lc = coin.SoCoordinate3()
            lp = [(p.x, p.y, p.z) for p in obj.RulingLines]
            lc.point.setValues(0, len(lp), lp)
            ls = coin.SoLineSet()
            ls.numVertices.setValues(0, len(lp) // 2, [2] * (len(lp) // 2))
            for node in (lm, style, lc, ls):
                self.lines.addChild(node)

def attach_view_provider(obj) -> None:
    if FreeCAD.GuiUp:
        ViewProviderRuledFit(obj.ViewObject)
