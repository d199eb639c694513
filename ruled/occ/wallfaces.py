"""A wall's closed ruled result in one piece per input face (``ruled fit --wall --per-face``): the result
trimmed between the images on it of the faces' joints (each joint edge projected onto the result, a
polyline in its (s, t) from the bottom rail to the top), the pieces sewn into one shell.  Where a joint is
a corner line both contours share, it is a ruling of the result and the cut is exact; elsewhere the rulings
cross it and the cut follows its projection."""

from __future__ import annotations

import numpy as np

from ruled.core.errors import BadInputError, RuledError
from ruled.core.nurbs import Curve
from ruled.occ.ring import _edge_points, _ends
from ruled.occ.wall import WallFit

JOINT_SAMPLES = 65     # points of each joint edge projected onto the result


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


def _on_result(R, edge, bottom: np.ndarray) -> np.ndarray:
    """(m, 2): the joint edge's points projected onto R, from its end on the bottom contour (t = t0) up."""
    from ruled.core.distance import project_points
    X = _edge_points(edge, JOINT_SAMPLES)
    if np.linalg.norm(X[0] - bottom) > np.linalg.norm(X[-1] - bottom):
        X = X[::-1]
    u0, u1, t0, t1 = R.domain
    gu, gt = np.meshgrid(np.linspace(u0, u1, 801), np.linspace(t0, t1, 17), indexing="ij")
    G = R(gu.ravel(), gt.ravel())
    k = np.argmin(np.linalg.norm(X[:, None, :] - G[None], axis=2), axis=1)
    uv, d = project_points(R, X, np.stack([gu.ravel()[k], gt.ravel()[k]], axis=1), iters=30, closed_u=True)
    uv[0, 1], uv[-1, 1] = t0, t1
    # one sheet: s continuous along the joint (across the seam)
    L = u1 - u0
    uv[:, 0] = uv[0, 0] + np.concatenate([[0.0], np.cumsum((np.diff(uv[:, 0]) + 0.5 * L) % L - 0.5 * L)])
    return uv


def _line(p, q) -> Curve:
    return Curve(np.array([p, q], float), np.array([0.0, 0.0, 1.0, 1.0]), 1)


def _polyline(P: np.ndarray) -> Curve:
    m = len(P)
    return Curve(np.asarray(P, float), np.concatenate([[0.0], np.linspace(0.0, 1.0, m), [1.0]]), 1)


def per_face(fit: WallFit) -> tuple:
    """(pieces, the sewn shell): per kept face of the wall (ring order), the result between its joints."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_Sewing

    from ruled.fit.trim import Trim
    from ruled.occ.convert import container_to_bspline
    from ruled.occ.trimmed import trimmed_face
    R = fit.surface
    joints = _joints(fit)
    if len(joints) < 2:
        return [fit.face], fit.face
    surf = container_to_bspline(R)
    surf.SetUPeriodic()
    u0, u1, t0, t1 = R.domain
    L = u1 - u0
    s = np.linspace(u0, u1, 2001)
    rail = R(s, np.full(s.size, t0))
    curves = []
    for _, e in joints:
        # the joint's end on the bottom contour: the one nearer the result's bottom rail
        ends = _ends(e)
        near = min(ends, key=lambda p: float(np.min(np.linalg.norm(rail - p, axis=1))))
        curves.append(_on_result(R, e, near))
    pieces = []
    for i in range(len(joints)):
        left, right = curves[i - 1], curves[i].copy()
        # the right joint after the left one round the ring (by less than a period)
        shift = np.floor((right[0, 0] - left[0, 0]) / L)
        right[:, 0] -= shift * L
        if right[0, 0] <= left[0, 0]:
            right[:, 0] += L
        loop = (_line(left[0], right[0]), _polyline(right), _line(right[-1], left[-1]), _polyline(left[::-1]))
        try:
            face = trimmed_face(R, Trim(loop), surf)
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
