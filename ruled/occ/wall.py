"""A part's wall: a ring of faces joined edge to edge into a band between two closed contours (the bottom
and the top), as one closed B-spline surface for the engine's periodic fit (Elber 2011 §3.3).

A face of the ring is taken as a four-sided patch, its bottom and top contour edges as two opposite
sides and its two joints with its neighbours as the other two: the face's own surface where those are
iso-curves of it (a cone between two arcs, a loft's face), or the ruled patch between its bottom and
top edges where the face is planar and its joints straight (a tapered extrusion's flank).  Either is
the face exactly.  The patches, made compatible along the rulings' direction (common degree and
knots: exact), are joined with full-multiplicity knots at the joints, so that the contours' corners
stay corners, into one surface closed round the ring; the DP's rulings then cross the faces' joints
freely.  A wall whose faces cannot be joined exactly is refused in one line naming the faces.

This module reads the faces with OCCT; the work is the engine's, on plain arrays: ruled.fit.wall.ring (the
ring's topology), ruled.fit.wall.join (the patches joined), ruled.fit.wall.fit (the fit), so that another host's
adapter (FreeCAD's) gives the same walls.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Optional

import numpy as np
from OCP.BRep import BRep_Tool
from OCP.BRepAdaptor import BRepAdaptor_Curve
from OCP.Geom import Geom_TrimmedCurve
from OCP.GeomAbs import GeomAbs_CurveType
from OCP.GeomConvert import GeomConvert

from ruled.core.errors import BadInputError
from ruled.core.nurbs import Surface
from ruled.occ.convert import face_to_bspline
from ruled.occ.io import faces_of
from ruled.occ.ring import (
    Ring,
    _edge_points,
    _ends,
    _face_edges,
    _length,
    _planar_normal,
    find_walls,
    ring_of,
)


# ------------------------------------------------------------------------------------- the joined surface
def _is_line(edge, tol: float) -> bool:
    """The edge is straight: a line, or a curve within tol of its chord."""
    from ruled.fit.wall.ring import is_straight
    if BRepAdaptor_Curve(edge).GetType() == GeomAbs_CurveType.GeomAbs_Line:
        return True
    return is_straight(_edge_points(edge, 65), tol)


def contour_edge(edge, size: float):
    """The edge as the engine's RingEdge with its 3D curve (a B-spline from end to end) and whether it is
    straight (for a face's patch and a loop's start)."""
    from ruled.fit.wall.ring import RingEdge
    from ruled.occ.region import _kernel_curve
    a, b = _ends(edge)
    ad = BRepAdaptor_Curve(edge)
    c3 = BRep_Tool.Curve_s(edge, 0.0, 0.0)
    bs = GeomConvert.CurveToBSplineCurve_s(Geom_TrimmedCurve(c3, ad.FirstParameter(), ad.LastParameter()))
    pts = _edge_points(edge)
    return RingEdge(a, b, pts, _length(edge), curve=_kernel_curve(bs, False), straight=_is_line(edge, 1e-6 * size))


def _clamped(bs):
    """bs non-periodic and clamped (OCCT's non-periodic form of a periodic surface is not: segmented to its
    range, it is)."""
    bs = bs.Copy()
    if bs.IsUPeriodic():
        bs.SetUNotPeriodic()
    if bs.IsVPeriodic():
        bs.SetVNotPeriodic()
    um = [bs.UMultiplicity(i) for i in (1, bs.NbUKnots())]
    vm = [bs.VMultiplicity(i) for i in (1, bs.NbVKnots())]
    if any(m != bs.UDegree() + 1 for m in um) or any(m != bs.VDegree() + 1 for m in vm):
        bs.Segment(*bs.Bounds())
    return bs


def _patch(face, index: int, bottom: tuple, top: tuple, before, after, size: float) -> tuple:
    """(the face as a four-sided patch, its contours' mean length, its deviation): ruled.fit.wall.join.wall_patch on
    its surface (None for a plane) and its edges (before, after: its joints, read already by contour_edge),
    with its Coons patch (ruled.fit.wall.patch) where it is no exact one."""
    from ruled.fit.wall.join import wall_patch
    from ruled.occ.convert import bspline_surface_to_container
    S = None if _planar_normal(face) is not None else bspline_surface_to_container(_clamped(face_to_bspline(face)))
    edge_tol = max((BRep_Tool.Tolerance_s(e) for e in bottom + top), default=0.0)
    ce = [[contour_edge(e, size) for e in c] for c in (bottom, top)]

    def loose():
        from ruled.fit.wall.patch import contour_patch
        from ruled.occ.region import face_region, outer_edges
        loop = outer_edges(face)
        ids = [[k for k, g in enumerate(loop) if any(g.IsSame(e) for e in c)] for c in (bottom, top)]
        return contour_patch(face_region(face), ids[0], ids[1], index)
    return wall_patch(index, S, ce[0], ce[1], before, after, size, edge_tol, loose)


@dataclass
class Wall:
    """A wall: its ring, its faces (TopoDS, ring order) and the joined closed surface (u round the ring, the
    faces' shares in ``breaks``; v from the bottom contour to the top)."""

    ring: Ring
    faces: tuple
    surface: Surface
    breaks: np.ndarray
    corners: list             # the joints (indices into breaks) where both contours have a corner
    slack: float = 0.0        # the faces' distance from the joined surface, at most (see _slack)

    @property
    def size(self) -> float:
        return self.ring.size


def joined_surface(ring: Ring, faces: tuple) -> tuple:
    """(Surface, breaks, corners, slack): the ring's faces (slivers left out) as one B-spline surface closed round
    the ring (ruled.fit.wall.join.joined)."""
    from ruled.fit.wall.join import joined
    n = len(faces)
    keep = ring.kept
    joints = [None if e is None else contour_edge(e, ring.size) for e in ring.joints]   # (each borders two faces)
    got = [_patch(faces[k], ring.faces[k], ring.bottom[k], ring.top[k], joints[k - 1] if n > 1 else None,
                  joints[k] if n > 1 else None, ring.size) for k in keep]
    return joined([g[0] for g in got], [g[1] for g in got], [ring.faces[k] for k in keep], ring.size,
                  [g[2] for g in got])


def wall_of(shape, indices="auto", faces: Optional[list] = None) -> Wall:
    """The wall of the part ``shape``: the faces ``indices`` (a list, or 'K,L-M'), or a word: 'auto' (the
    part's only wall), 'outer', 'hole', 'hole:K' (ruled.fit.wall.ring.pick_wall; find_walls names them).  faces:
    the faces themselves instead of a part (indices then index them)."""
    from ruled.core.errors import parse_faces
    from ruled.fit.wall.ring import WALL_WORDS, is_wall_word, pick_wall
    if faces is None:
        faces = faces_of(shape)
    if isinstance(indices, str) and not is_wall_word(indices):
        indices = parse_faces(indices, "«wall»", WALL_WORDS + ("hole:K",))
    if is_wall_word(indices):
        walls = find_walls(shape)
        if not walls:
            raise BadInputError("the part has no wall (a ring of faces between two planar caps); give its faces "
                                "with «wall=K,L-M»")
        ring = walls[pick_wall(indices, [r.name for r in walls], [r.role for r in walls],
                               [list(r.faces) for r in walls])]
    else:
        from dataclasses import replace

        from ruled.occ.ring import ring_role
        ring = ring_of(faces, indices)
        ring = replace(ring, role=ring_role(ring, faces))
    tfaces = tuple(faces[i] for i in ring.faces)
    S, breaks, corners, slack = joined_surface(ring, tfaces)
    return Wall(ring, tfaces, S, breaks, corners, _slack(ring, tfaces, S) + slack)


def _slack(ring: Ring, faces: tuple, S=None) -> float:
    """How far the wall's faces, as bounded by their edges, can be from the joined surface: their edges'
    tolerances (an edge's 3D curve lies that close to its faces' surfaces), or where larger, their edges'
    distance from the joined surface S as bounded by the contours (EDGE_SAMPLES along each: a file's edge may
    lie farther off than its tolerance says, or off along the surface, past the contour the joined surface
    ends at; measured, and so the measure's CORNERS x n along them are within it), and a sliver's largest
    distance from the faces kept, sampled densely (a sliver is a crease thinner than its samples' spacing, so
    this term is measured, not certified)."""
    from ruled.core.edgerows import EDGE_SAMPLES
    from ruled.occ.convert import container_to_face
    from ruled.occ.faceset import FaceSet
    from ruled.occ.measure import _edge_polylines, _Projector, face_samples
    tol = max((BRep_Tool.Tolerance_s(e) for f in faces for e in _face_edges(f)), default=0.0)
    if S is not None and tol > 0.0:
        E = np.concatenate([e for f in faces for e in _edge_polylines(f, EDGE_SAMPLES)])
        tol = max(tol, float(_Projector(container_to_face(S)).distances(E).max()))
    slivers = [f for f, s in zip(faces, ring.slivers) if s]
    if not slivers:
        return float(tol)
    kept = FaceSet([faces[k] for k in ring.kept])
    worst = 0.0
    for f in slivers:
        worst = max(worst, float(kept.distances(face_samples(f, 80)[0]).max()))
    return float(max(tol, worst))




# ------------------------------------------------------------------------------------------------ the fit
@dataclass
class WallFit:
    """A wall's closed ruled result: the fit (ruled.fit.fit2d.FitResult), the result face, its certified
    bound from the joined surface (which is the wall's faces exactly) and the measure against the wall's
    faces as bounded by their edges, both ways (ruled.core.hostform.Hausdorff)."""

    wall: Wall
    result: Any
    face: Any
    error_bound: float
    hausdorff: Any
    area_ratio: Optional[float] = None     # the result's area over the wall faces'
    warnings: tuple = ()
    surface: Optional[Surface] = None      # the closed ruled result (plain arrays)
    crossed: int = 0                       # corners whose rulings were paired anew across them
    plain: Optional[tuple] = None          # then (surface, bound) of the result with the corners' own rulings

    def report(self) -> dict:
        r = self.surface
        h = self.hausdorff
        return {"faces": list(self.wall.ring.faces), "closed": True, "pieces": len(self.result),
                "crossed_corners": self.crossed,
                "corners": [float(self.wall.breaks[k]) for k in self.wall.corners],
                "method": self.result[0].best.method, "error_bound": self.error_bound,
                "hausdorff": None if h is None else {"max": h.max, "mean": h.mean, "wall_to_result": h.max_a_to_b,
                                                     "result_to_wall": h.max_b_to_a, "samples": h.samples,
                                                     "resolution": h.resolution},
                "size": self.wall.size, "result": {"poles": list(r.poles.shape[:2]),
                                                   "degree": [r.degree_u, r.degree_v],
                                                   "rational": r.weights is not None},
                "contours": {"bottom_edges": len(self.wall.ring.loops[0]), "top_edges": len(self.wall.ring.loops[1])},
                "breaks": [float(x) for x in self.wall.breaks], "area_ratio": self.area_ratio,
                "slack": self.wall.slack, "warnings": [str(w) for w in self.warnings]}


def measure_wall(faces, out_face, n: int = 40):
    """The two-sided measure between the wall's faces (their union, each bounded by its edges) and a face: about
    n x n points of each face and n along every edge, and CORNERS times as many along the wall's edges (its
    joints and corners) and along the result's rulings where it has a corner (ruled.core.edgerows.corner_rulings:
    a corner's ruling is where a ruled surface through a bowed joint lies farthest from it)."""
    from dataclasses import replace as _replace

    from ruled.core.edgerows import CORNERS
    from ruled.occ.faceset import FaceSet
    from ruled.occ.measure import _edge_polylines, _Projector, corner_points, face_samples, two_sided
    to_wall, to_out = FaceSet(list(faces)), _Projector(out_face)
    got = [face_samples(f, n, resolution=True) for f in faces]
    pa = np.concatenate([p for p, _ in got] + [e for f in faces for e in _edge_polylines(f, CORNERS * n)])
    pb, rb = face_samples(out_face, n, to_out.inside, resolution=True)
    pb = np.concatenate([pb, corner_points(out_face, CORNERS * n)])
    return _replace(two_sided(pa, pb, to_wall, to_out), resolution=max([rb] + [r for _, r in got]))


def fit_wall(wall: Wall, options, progress=None, measure: bool = True, measure_samples: int = 40) -> WallFit:
    """The wall's one closed ruled surface (ruled.fit.wall.fit.fit_ring on the joined surface), built as one face
    and measured against the wall's faces, both ways."""
    from ruled.fit.wall.fit import fit_ring
    from ruled.occ.convert import container_to_face
    from ruled.occ.trimmed import built_slack, result_face
    ring = fit_ring(wall.surface, wall.breaks, wall.corners, options, wall.size, progress)
    results, surface, bound = ring.results, ring.surface, ring.bound
    if ring.periodic:
        out = result_face(results[0])
        bound += built_slack(out, results[0])
    else:
        out = container_to_face(surface)
    bound += wall.slack
    plain = None if ring.plain is None else (ring.plain[0], ring.plain[1] + wall.slack)
    fit = WallFit(wall, results, out, bound, None, surface=surface, crossed=ring.crossed, plain=plain)
    return measured(fit, measure_samples) if measure else fit


def measured(fit: WallFit, measure_samples: int = 40) -> WallFit:
    """The wall's fit with its result measured against the wall's faces (measure_wall), its area ratio and the
    warnings the measure gives."""
    from dataclasses import replace as _replace

    from ruled.fit.face.verdict import measured_warnings
    from ruled.occ.io import face_area
    wall, face = fit.wall, getattr(fit.face, "wrapped", fit.face)         # (a CadQuery face: its OCCT one)
    h = measure_wall(wall.faces, face, measure_samples)
    ratio = face_area(face, 1e-6) / sum(face_area(f, 1e-6) for f in wall.faces)
    return _replace(fit, hausdorff=h, area_ratio=ratio,
                    warnings=measured_warnings(fit.result[0], fit.error_bound, h.max, wall.size, ratio))


__all__ = ["Ring", "Wall", "WallFit", "ring_of", "find_walls", "joined_surface", "wall_of", "fit_wall", "measured",
           "measure_wall"]
