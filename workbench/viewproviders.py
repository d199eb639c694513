"""View provider of RuledFit: the result coloured by its measured distance to the source (blue: none,
red: the largest), with the rulings as lines, in a "Deviation" display mode beside Part's own."""

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


class ViewProviderRuledFit:
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
        top = float(dev.max()) if dev is not None and dev.max() > 0 else 1.0
        cols = colour_ramp(dev / top) if dev is not None else np.tile([0.75, 0.78, 0.82], (n * n, 1))
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

    def __getstate__(self):
        return None

    def __setstate__(self, state):
        return None

    dumps, loads = __getstate__, __setstate__


def attach_view_provider(obj) -> None:
    if FreeCAD.GuiUp:
        ViewProviderRuledFit(obj.ViewObject)
