"""A wall's closed ruled result in one piece per input face (``ruled fit --wall --per-face``): the result
trimmed between the images on it of the faces' joints (each joint edge projected onto the result, a
polyline in its (s, t) from the bottom rail to the top), the pieces sewn into one shell.  Where a joint is
a corner line both contours share, it is a ruling of the result and the cut is exact; elsewhere the rulings
cross it and the cut follows its projection."""

from __future__ import annotations

from ruled.core.errors import BadInputError, RuledError
from ruled.occ.ring import _edge_points
from ruled.occ.wall import WallFit


def _joints(fit: WallFit) -> list:
    """Per kept face (slivers are part of their neighbours' joints) in ring order: the edge after it."""
    ring, faces = fit.wall.ring, fit.wall.faces
    keep = ring.kept
    out = []
    for i, k in enumerate(keep):
        nxt = keep[(i + 1) % len(keep)]
        j = (nxt - 1) % len(faces)         # the joint just before the next kept face
        out.append((k, ring.joints[j]))
    return out


def per_face(fit: WallFit) -> tuple:
    """(pieces, the sewn shell): per kept face of the wall (ring order), the result between its joints."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_Sewing

    from ruled.fit.wall.pieces import JOINT_SAMPLES, piece_trims
    from ruled.occ.convert import container_to_bspline
    from ruled.occ.trimmed import trimmed_face
    R = fit.surface
    joints = _joints(fit)
    if len(joints) < 2:
        return [fit.face], fit.face
    surf = container_to_bspline(R)
    surf.SetUPeriodic()
    pieces = []
    for i, trim in enumerate(piece_trims(R, [_edge_points(e, JOINT_SAMPLES) for _, e in joints])):
        try:
            face = trimmed_face(R, trim, surf)
        except RuledError as exc:       # (its advice is a face's: a wall has no ends to pin)
            k = fit.wall.ring.faces[fit.wall.ring.kept[i]] if i < len(fit.wall.ring.kept) else i
            raise type(exc)(f"the wall's piece over its face {k} is not a valid face ({exc.problem}); write the "
                            f"wall whole (drop «per_face»)") from None
        pieces.append(face)
    sew = BRepBuilderAPI_Sewing(1e-6 * fit.wall.size)
    for f in pieces:
        sew.Add(f)
    sew.Perform()
    shell = sew.SewedShape()
    if shell is None or shell.IsNull():
        raise BadInputError("the wall's pieces could not be sewn (please report the part); write it whole")
    return pieces, shell


__all__ = ["per_face"]
