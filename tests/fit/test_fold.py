"""Issue 58: a face closed in one direction (a tube) is ruled across it, both its sides folded onto one ruled
surface through its middle (ruled.fit.face.fold), where that is closer than the rulings between its ends.
Figures checked against OCCT's measure (ruled.occ.measure, no engine code) and against what the geometry
says: a tube of elliptic section is within its semi-minor axis of the ribbon through its major axes, no ruled
surface nearer than that at its section's minor vertices; FreeCAD's Part Ruled between the helix's seam and
itself reversed (the seam's chords) is farther."""

from __future__ import annotations

import os
import sys

import numpy as np
import pytest

sys.path.insert(0, os.path.dirname(os.path.dirname(__file__)))
from trimmed_faces import measure, part_ruled  # noqa: E402

import ruled.cq as rcq  # noqa: E402
from ruled.occ.io import read_faces  # noqa: E402

DATA = os.path.join(os.path.dirname(os.path.dirname(__file__)), "data")


def elliptic_tube(bend: float = 30.0, a: float = 3.0, b: float = 1.0, angle: float = 60.0):
    """A tube of elliptic section (semi-axes a in the bending plane, b across it) swept along an arc of radius
    bend through angle degrees (OCCT's pipe), as a B-spline face closed round its section."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeWire, BRepBuilderAPI_NurbsConvert
    from OCP.BRepOffsetAPI import BRepOffsetAPI_MakePipe
    from OCP.GC import GC_MakeArcOfCircle
    from OCP.gp import gp_Ax2, gp_Circ, gp_Dir, gp_Elips, gp_Pnt

    from ruled.occ.io import faces_of
    arc = GC_MakeArcOfCircle(gp_Circ(gp_Ax2(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)), bend), 0.0, np.radians(angle),
                             True).Value()
    spine = BRepBuilderAPI_MakeWire(BRepBuilderAPI_MakeEdge(arc).Edge()).Wire()
    section = gp_Elips(gp_Ax2(gp_Pnt(bend, 0, 0), gp_Dir(0, 1, 0), gp_Dir(1, 0, 0)), a, b)
    profile = BRepBuilderAPI_MakeWire(BRepBuilderAPI_MakeEdge(section).Edge()).Wire()
    pipe = faces_of(BRepOffsetAPI_MakePipe(spine, profile).Shape())[0]
    return faces_of(BRepBuilderAPI_NurbsConvert(pipe).Shape())[0]


def test_a_bent_elliptic_tube_is_within_its_semi_minor_axis_of_its_folded_fit():
    """The ribbon through the sections' major axes is a flat annulus sector (exactly ruled): the tube is within
    b of it, and no surface is nearer the two minor vertices of a section than b (they are 2b apart, the surface
    between them).  The fold finds it: measured by OCCT within b of the tube, bound within 1 % of b; the rulings
    between the tube's two end ellipses are 4x farther (its note says so)."""
    face = elliptic_tube()
    fit = rcq.fit_face(face, samples=16, measure_samples=24)
    assert fit.result.patch.fold is not None
    assert 0.99 <= fit.hausdorff.max <= fit.error_bound <= 1.01, (fit.hausdorff.max, fit.error_bound)
    ends = float([n for n in fit.result.notes if "folded" in n][0].split("between its ends, ")[1].rstrip(")"))
    assert ends > 4.0 * fit.error_bound


@pytest.mark.slow
@pytest.mark.skipif(not os.path.exists(os.path.join(DATA, "asitus_BSplHelix.brep")), reason="helix file absent")
def test_the_helical_tube_folded_is_nearer_than_part_ruled_between_its_seam_and_itself():
    """The helix (a tube of radius 5 swept half a turn round a helix): rulings between its end circles were the
    result before, measured 26.5; Part Ruled between its seam edge and itself reversed (the seam's chords), 10-12;
    folded, within about the tube's radius of it (about half the chords' distance), measured by OCCT within its
    bound."""
    face = read_faces(os.path.join(DATA, "asitus_BSplHelix.brep"))[0]
    fit = rcq.fit_face(face, samples=16, measure_samples=16)
    assert fit.result.patch.fold is not None
    assert fit.hausdorff.max <= fit.error_bound <= 1.1 * 5.0, (fit.hausdorff.max, fit.error_bound)
    seam = [k for k, s in enumerate(fit.result.patch.region.seams) if s][0]
    chords = min(measure(face, s, 16) for s in part_ruled(face, [seam], [seam]))
    assert fit.hausdorff.max < 0.75 * chords, (fit.hausdorff.max, chords)
