"""Faces CadQuery users make (issue 72): lofts through 3-4 sections (ellipses, rectangles, closed splines),
sweeps of circles, ellipses and rectangles along 3D splines (a closed elliptic tube among them) and
variable-radius fillets of a box's edges (OCCT's BRepFilletAPI with two radii), each solid's B-spline faces
(at most two faces a solid: a loft of rectangles or a swept rectangle has four alike).  Built with CadQuery and OCCT
alone, from a seed."""

from __future__ import annotations

import numpy as np


def _bspline_faces(shape) -> list:
    """The solid's B-spline faces, the first two."""
    return [f.wrapped for f in shape.Faces() if f.geomType() in ("BSPLINE", "BEZIER")][:2]


def _lofts(rng, count: int) -> list:
    import cadquery as cq
    out = []
    for k in range(count):
        sects = []
        for i in range(3 + k % 2):
            z = 10.0 * i
            a, b = rng.uniform(3, 8), rng.uniform(2, 6)
            wp = cq.Workplane("XY").workplane(offset=z)
            if k % 3 == 0:
                sects.append(wp.center(rng.uniform(-1, 1), rng.uniform(-1, 1)).ellipse(a, b).wires().val())
            elif k % 3 == 1:
                sects.append(wp.rect(2 * a, 2 * b).wires().val())
            else:
                t = np.linspace(0, 2 * np.pi, 7)[:-1]
                r = rng.uniform(3, 7, 6)
                pts = [cq.Vector(float(r[j] * np.cos(t[j])), float(r[j] * np.sin(t[j])), z) for j in range(6)]
                sects.append(cq.Wire.assembleEdges([cq.Edge.makeSpline(pts, periodic=True)]))
        out += [(f"loft {k}", f) for f in _bspline_faces(cq.Solid.makeLoft(sects, False))]
    return out


def _sweeps(rng, count: int) -> list:
    import cadquery as cq
    out = []
    for k in range(count):
        pts = [cq.Vector(0, 0, 0)] + [cq.Vector(*rng.uniform(-6, 6, 2), 12.0 * (i + 1)) for i in range(3)]
        path = cq.Wire.assembleEdges([cq.Edge.makeSpline(pts)])
        if k % 3 == 0:      # the closed elliptic tube
            prof = cq.Wire.makeEllipse(3.0, 1.5, cq.Vector(0, 0, 0), cq.Vector(0, 0, 1), cq.Vector(1, 0, 0))
        elif k % 3 == 1:
            prof = cq.Wire.makeCircle(2.0, cq.Vector(0, 0, 0), cq.Vector(0, 0, 1))
        else:
            prof = cq.Workplane("XY").rect(4, 2).wires().val()
        solid = cq.Solid.sweep(prof, [], path, makeSolid=True, isFrenet=bool(k % 2))
        out += [(f"sweep {k}", f) for f in _bspline_faces(solid)]
    return out


def _fillets(rng, count: int) -> list:
    import cadquery as cq
    from OCP.BRepFilletAPI import BRepFilletAPI_MakeFillet
    out = []
    for k in range(count):
        box = cq.Workplane("XY").box(20, 14, 10).val()
        edges = box.Edges()
        mk = BRepFilletAPI_MakeFillet(box.wrapped)
        mk.Add(float(rng.uniform(1, 2)), float(rng.uniform(3, 4.5)), edges[(5 * k) % len(edges)].wrapped)
        mk.Build()
        if mk.IsDone():
            out += [(f"fillet {k}", f) for f in _bspline_faces(cq.Shape.cast(mk.Shape()))]
    return out


def cq_faces(seed: int = 72) -> list:
    """[(name, face)]: lofts, sweeps and variable-radius fillets (see the module doc)."""
    rng = np.random.default_rng(seed)
    return _lofts(rng, 7) + _sweeps(rng, 6) + _fillets(rng, 2)


__all__ = ["cq_faces"]
