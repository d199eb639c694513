"""Parts with walls, built with CadQuery: exactly ruled walls (a tapered extrusion of lines and arcs, a ruled
square-to-circle loft, a ruled loft between two airfoils), walls that are not ruled (a loft through three
airfoil sections, a twisted extrusion), and bad rings."""

from __future__ import annotations

import math

import numpy as np


def tapered_extrusion():
    """A profile of three lines and two arcs, extruded 15 with an 8 degree draft: planes and cones (and the
    draft's sliver faces at the arcs' tangent joins)."""
    import cadquery as cq
    return (cq.Workplane("XY").moveTo(0, 0).lineTo(40, 0).threePointArc((50, 10), (40, 20)).lineTo(10, 20)
            .threePointArc((10 - 5 * math.sqrt(2), 10 + 5 * math.sqrt(2)), (0, 10)).close()
            .extrude(15, taper=8)).val()


def square_to_circle():
    import cadquery as cq
    return cq.Workplane("XY").rect(20, 20).workplane(offset=25).circle(12).loft(ruled=True).val()


def _naca(t: float, n: int = 30):
    x = (1 - np.cos(np.linspace(0, math.pi, n))) / 2
    y = 5 * t * (0.2969 * np.sqrt(x) - 0.126 * x - 0.3516 * x ** 2 + 0.2843 * x ** 3 - 0.1036 * x ** 4)
    return x, y


def airfoil_wire(chord: float, thickness: float, z: float, twist: float = 0.0):
    """A NACA 4-digit symmetric section as two splines (upper, lower) meeting at a sharp trailing edge."""
    import cadquery as cq
    x, y = _naca(thickness)
    c, s = math.cos(twist), math.sin(twist)

    def P(a, b):
        return cq.Vector(chord * (a * c - b * s), chord * (a * s + b * c), z)
    upper = [P(a, b) for a, b in zip(x, y)][::-1]
    lower = [P(a, -b) for a, b in zip(x, y)]
    return cq.Wire.assembleEdges([cq.Edge.makeSpline(upper), cq.Edge.makeSpline(lower)])


def airfoil_loft(ruled: bool = True, sections=((100, 0.12, 0, 0.0), (70, 0.09, 150, 0.0))):
    import cadquery as cq
    return cq.Solid.makeLoft([airfoil_wire(*s) for s in sections], ruled)


def three_section_loft():
    return airfoil_loft(False, ((100, 0.12, 0, 0.0), (80, 0.10, 80, 0.15), (60, 0.08, 160, 0.3)))


def twisted_extrusion():
    import cadquery as cq
    return cq.Workplane("XY").rect(30, 12).twistExtrude(40, 30).val()


def crossed_extrusion():
    """A bow-tie profile (its outline crosses itself at (10, 10)) extruded 10: a wall whose contours cross (its
    side faces, read back from STEP, are 0, 2, 4 and 7)."""
    import cadquery as cq
    return cq.Workplane("XY").polyline([(0, 0), (20, 20), (20, 0), (0, 20)]).close().extrude(10).val()


def box_with_a_hole():
    """A box whose side is drilled through: its four sides and the hole's wall are no band (three contours)."""
    import cadquery as cq
    return cq.Workplane("XY").box(30, 20, 10).faces(">X").workplane().hole(4).val()


EXACT = {"tapered extrusion": tapered_extrusion, "square to circle": square_to_circle, "two airfoils": airfoil_loft}
NOT_RULED = {"three airfoil sections": three_section_loft, "twisted extrusion": twisted_extrusion}


def hexagon_to_circle():
    """A ruled loft from a hexagon to a circle: a wall of six faces, fitted closed (the circle has no corner)."""
    import cadquery as cq
    return cq.Workplane("XY").polygon(6, 40).workplane(offset=30).circle(15).loft(ruled=True).val()


def hexagon_to_circles():
    """A smooth loft from a hexagon through two circles: a wall of six faces that is not ruled, fitted closed."""
    import cadquery as cq
    return (cq.Workplane("XY").polygon(6, 40).workplane(offset=15).circle(18).workplane(offset=15).circle(13)
            .loft(ruled=False).val())
