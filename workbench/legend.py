"""The colour legend of a Ruled result in the 3D view (GUI): a bar at the view's right edge, blue 0 to red the
measured Hausdorff distance, its labels in the user's unit on an opaque panel; one colour and "exact, within" the
bound for an exact result.  One legend per document (the last result drawn or shown takes it); the view providers
(workbench.viewproviders) draw and remove it."""

from __future__ import annotations

import numpy as np

from .names import element


def colour_ramp(t: np.ndarray) -> np.ndarray:
    """0 -> blue, 0.5 -> green, 1 -> red (N, 3)."""
    t = np.clip(np.asarray(t, float), 0.0, 1.0)
    r = np.clip(2.0 * t - 0.5, 0.0, 1.0)
    g = np.clip(1.5 - np.abs(2.0 * t - 1.0) * 1.5, 0.0, 1.0)
    b = np.clip(1.5 - 2.0 * t, 0.0, 1.0)
    return np.stack([r, g, b], axis=1)


LEGENDS = {}             # document name -> (object name, the legend's Coin node, its label texts, the view)


def legend_labels(top: float) -> list:
    """Five values from 0 to top, in the unit the user's schema gives top and to the digits every figure of the
    workbench has (workbench.units, e.g. '0 µm' ... '1.462 µm'): the top label reads as the panel's Hausdorff."""
    from .units import length, unit_of
    unit = unit_of(top)
    return [length(top * t, unit=unit) for t in np.linspace(0.0, 1.0, 5)[:-1]] + [length(top)]


# a result measured within this fraction of its size is exact (round-off): drawn in one colour, its legend says so
EXACT = 1e-9


def exact_bound(obj):
    """The bound of an exact result (measured within EXACT of its size, or certified within the source's own
    tolerance, the file's edges'), None for any other: such a result's colours would be a rainbow of
    round-off."""
    from .units import magnitude
    h, bound = magnitude(getattr(obj, "Hausdorff", 0.0)), magnitude(getattr(obj, "ErrorBound", 0.0))
    if obj.Shape.isNull() or bound <= 0.0:
        return None
    tol = 0.0
    try:
        src, subs = obj.Source
        tol = max([e.Tolerance for e in element(src.Shape, subs[0]).Edges], default=0.0)
    except Exception:       # (no source face: a wall's, or one gone)
        pass
    return bound if h <= EXACT * obj.Shape.BoundBox.DiagonalLength or bound <= tol else None


def _legend_node(top: float, title: str, exact=None, view_px: int = 800):
    """A colour bar at the right edge of the view (its own orthographic camera: it stays put when the
    model turns), blue 0 at the bottom to red ``top``, with five labels and a title (two lines: the object, what
    the colours are), on an opaque panel so that the model behind never hides them; for an exact result (exact:
    its bound), one colour and one label, 'exact, within' the bound (Coin's fonts have no '≤').  view_px: the
    view's width in pixels, for the panel to hold the labels."""
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
    if exact is None:
        labels = [title] + legend_labels(top)
    else:
        from .units import length
        labels = [title, f"exact, within {length(exact)}"]
    # the panel behind, drawn first: as wide as the widest label (about 8 pixels a character at the font's size),
    # its width set again for the view's width in pixels each time the view is drawn (a window resized)
    chars = [(max(len(x) for x in labels[0].split(": ")), x1)] + [(len(x), x0 - 0.012) for x in labels[1:]]

    def left(px: int) -> float:
        return max(-0.95, min([0.60] + [right - 2.0 * (8 * c + 24) / max(px, 100) for c, right in chars]))
    panel = _backdrop(root, (left(view_px), y0 - 0.06, 0.985, y1 + 0.17))
    seen = [view_px]

    def resized(_data, action):
        try:
            if not action.isOfType(coin.SoGLRenderAction.getClassTypeId()):
                return
            px = int(coin.cast(action, "SoGLRenderAction").getViewportRegion().getViewportSizePixels()[0])
            if px != seen[0]:
                seen[0] = px
                x = left(px)
                panel.point.set1Value(0, (x, y0 - 0.06, -0.1))
                panel.point.set1Value(3, (x, y1 + 0.17, -0.1))
        except Exception:       # (a callback must never raise into Coin)
            pass
    cb = coin.SoCallback()
    cb.setCallback(resized)
    root.insertChild(cb, root.getNumChildren() - 1)
    ts = np.linspace(0.0, 1.0, n + 1)
    cols = colour_ramp(ts if exact is None else 0.0 * ts)     # (exact: the mesh's one colour, that of 0)
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
    text_col = coin.SoBaseColor()
    text_col.rgb = (0.1, 0.1, 0.1)
    root.addChild(text_col)
    font = coin.SoFont()
    font.size = 13
    root.addChild(font)
    places = [(x1, y1 + 0.11)] + ([(x0 - 0.012, y0 + (y1 - y0) * t - 0.012) for t in np.linspace(0, 1, 5)]
                                  if exact is None else [(x0 - 0.012, 0.5 * (y0 + y1))])
    for text, (x, y) in zip(labels, places):
        sep = coin.SoSeparator()
        tr = coin.SoTranslation()
        tr.translation = (x, y, 0.0)
        t2 = coin.SoText2()
        # (the title in two lines, the object's name and what the colours are: it stays inside the panel)
        lines = text.split(": ", 1) if text is labels[0] else [text]
        t2.string.setValues(0, len(lines), [ln if i == len(lines) - 1 else ln + ":" for i, ln in enumerate(lines)])
        t2.justification = coin.SoText2.RIGHT
        sep.addChild(tr)
        sep.addChild(t2)
        root.addChild(sep)
    return root, labels


def _backdrop(root, box):
    """An opaque, light rectangle (x0, y0, x1, y1) in the legend's coordinates, drawn before its bar and labels;
    returns its coordinates (its left side moves with the view's width)."""
    from pivy import coin
    x0, y0, x1, y1 = box
    col = coin.SoBaseColor()
    col.rgb = (0.97, 0.97, 0.95)
    coords = coin.SoCoordinate3()
    coords.point.setValues(0, 4, [(x0, y0, -0.1), (x1, y0, -0.1), (x1, y1, -0.1), (x0, y1, -0.1)])
    face = coin.SoFaceSet()
    face.numVertices.setValue(4)
    sep = coin.SoSeparator()
    for node in (col, coords, face):
        sep.addChild(node)
    root.addChild(sep)
    return coords


def show_legend(obj, top: float) -> None:
    """The document's colour legend for obj (one per document: the last one drawn or shown takes it)."""
    import FreeCADGui
    hide_legend(obj.Document.Name)
    gdoc = FreeCADGui.getDocument(obj.Document.Name)
    view = getattr(gdoc, "ActiveView", None) if gdoc else None
    if view is None or not hasattr(view, "getSceneGraph"):
        return
    what = "the wall" if type(getattr(obj, "Proxy", None)).__name__ == "RuledWall" else "the face"
    try:
        px = int(view.getSize()[0])
    except Exception:       # (a view without a size yet)
        px = 800
    node, labels = _legend_node(top, f"{obj.Label}: distance to {what}", exact_bound(obj), px)
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


__all__ = ["LEGENDS", "colour_ramp", "legend_labels", "exact_bound", "show_legend", "hide_legend", "EXACT"]
