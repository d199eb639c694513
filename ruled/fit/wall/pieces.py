"""A wall's closed ruled result cut into one piece per input face, on plain arrays: each joint between two of
the wall's faces (its points, from a host) projected onto the result, a polyline in its (s, t) from the bottom
rail to the top, and per face the loop in (s, t) between its two joints (ruled.fit.face.trim.Trim), which the hosts
build as trimmed faces and sew (ruled.occ.wallfaces, the workbench's RuledWall).  Where a joint is a corner
line both contours share, it is a ruling of the result and the cut is exact; elsewhere the rulings cross it
and the cut follows its projection."""

from __future__ import annotations

import numpy as np

from ruled.core.nurbs import Curve, Surface

JOINT_SAMPLES = 65     # points of each joint edge projected onto the result


def on_result(R: Surface, X: np.ndarray) -> np.ndarray:
    """(m, 2): the joint's points X (from its end on the bottom rail up) projected onto R, one sheet (s
    continuous along the joint, across the seam), its ends on the rails."""
    from ruled.core.distance import project_points
    u0, u1, t0, t1 = R.domain
    gu, gt = np.meshgrid(np.linspace(u0, u1, 801), np.linspace(t0, t1, 17), indexing="ij")
    G = R(gu.ravel(), gt.ravel())
    k = np.argmin(np.linalg.norm(X[:, None, :] - G[None], axis=2), axis=1)
    uv, _ = project_points(R, X, np.stack([gu.ravel()[k], gt.ravel()[k]], axis=1), iters=30, closed_u=True)
    uv[0, 1], uv[-1, 1] = t0, t1
    L = u1 - u0
    uv[:, 0] = uv[0, 0] + np.concatenate([[0.0], np.cumsum((np.diff(uv[:, 0]) + 0.5 * L) % L - 0.5 * L)])
    return uv


def _line(p, q) -> Curve:
    return Curve(np.array([p, q], float), np.array([0.0, 0.0, 1.0, 1.0]), 1)


def _polyline(P: np.ndarray) -> Curve:
    m = len(P)
    return Curve(np.asarray(P, float), np.concatenate([[0.0], np.linspace(0.0, 1.0, m), [1.0]]), 1)


def piece_trims(R: Surface, joints: list) -> list:
    """Per face of the wall (ring order), the Trim of the result between the joint before it and the joint
    after it; joints: per face, the points of the joint after it (either way round)."""
    from ruled.fit.face.trim import Trim
    u0, u1, t0, t1 = R.domain
    L = u1 - u0
    s = np.linspace(u0, u1, 2001)
    rail = R(s, np.full(s.size, t0))
    curves = []
    for X in joints:
        X = np.asarray(X, float)
        # from its end on the bottom contour: the one nearer the result's bottom rail
        near = [float(np.min(np.linalg.norm(rail - p, axis=1))) for p in (X[0], X[-1])]
        curves.append(on_result(R, X if near[0] <= near[1] else X[::-1]))
    trims = []
    for i in range(len(joints)):
        left, right = curves[i - 1], curves[i].copy()
        # the right joint after the left one round the ring (by less than a period)
        right[:, 0] -= np.floor((right[0, 0] - left[0, 0]) / L) * L
        if right[0, 0] <= left[0, 0]:
            right[:, 0] += L
        trims.append(Trim((_line(left[0], right[0]), _polyline(right), _line(right[-1], left[-1]),
                           _polyline(left[::-1]))))
    return trims


__all__ = ["JOINT_SAMPLES", "on_result", "piece_trims"]
