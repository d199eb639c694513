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


# --------------------------------------------------------------------------------- punches and dies (issue 56)
def line_arc_punch():
    """A punch whose profile's lines meet its arcs at sharp corners, drafted 6 degrees: the drafted planes meet
    the cones along curves, so the wall is not exactly ruled at those corners.  Height 12."""
    import cadquery as cq
    return (cq.Workplane("XY").moveTo(0, 0).lineTo(30, 0).threePointArc((36, 10), (30, 20)).lineTo(0, 20)
            .threePointArc((5, 10), (0, 0)).close().extrude(12, taper=6)).val()


def _star(n: int, r1: float, r2: float, k: float = 1.0) -> list:
    return [((r1 if i % 2 == 0 else r2) * k * math.cos(math.pi / 2 + i * math.pi / n),
             (r1 if i % 2 == 0 else r2) * k * math.sin(math.pi / 2 + i * math.pi / n)) for i in range(2 * n)]


def polygon_star():
    """A five-pointed star drafted 5 degrees, height 10: sharp concave corners at the bottom, where OCCT's draft
    puts small fan cones (an apex on the bottom contour, an arc on the top one)."""
    import cadquery as cq
    return cq.Workplane("XY").polyline(_star(5, 20, 9)).close().extrude(10, taper=5).val()


def lofted_star():
    """The star as a ruled loft to a smaller copy 10 up: sharp concave corners on both contours (creases)."""
    import cadquery as cq
    return (cq.Workplane("XY").polyline(_star(5, 20, 9)).close().workplane(offset=10)
            .polyline(_star(5, 20, 9, 0.85)).close().loft(ruled=True)).val()


def die_block():
    """A block 60 x 40 x 15 with a hole of two lines and two arcs drafted 4 degrees (narrowing upwards): one arc
    meets the lines tangentially, the other at sharp corners."""
    import cadquery as cq
    block = cq.Workplane("XY").box(60, 40, 15).translate((0, 0, 7.5))
    hole = (cq.Workplane("XY").moveTo(-10, -6).lineTo(10, -6).threePointArc((14, 0), (10, 6)).lineTo(-10, 6)
            .threePointArc((-16, 0), (-10, -6)).close().extrude(15, taper=4))
    return block.cut(hole).val()


def d_hole():
    """A block 50 x 40 x 10 with a straight D-shaped hole (a line and a half circle)."""
    import cadquery as cq
    block = cq.Workplane("XY").box(50, 40, 10).translate((0, 0, 5))
    return block.cut(cq.Workplane("XY").moveTo(-8, -10).lineTo(-8, 10).threePointArc((2, 0), (-8, -10)).close()
                     .extrude(10)).val()
