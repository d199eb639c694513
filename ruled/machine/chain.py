"""Ruled patches that follow one another (a cone spline's patches, a split's strips along the rulings)
joined into one ruled surface, so that one wire or tool path runs over them all; and, per patch, the
figures a machinist checks: the taper of the lines against the machine axis and their twist (the turn
of the surface's normal along a line: 0 on a developable patch, whose tangent plane is constant along
each ruling).

Each patch is R_k(u, t), linear in t (its rulings run along t).  Patch k+1 must start on the ruling
where patch k ends (either may be reversed; they are turned to follow one another).  The joined
surface has degree p in u, knots of multiplicity p at the joints (C0 in its parameter there, however
smooth in space), patch k on u in [k, k+1]; its weights are patch k+1's scaled to meet patch k's at
the joint, which keeps each patch exactly.
"""

from __future__ import annotations

import math

import numpy as np

from ruled.core.errors import BadInputError
from ruled.core.nurbs import Surface
from ruled.machine.paths import reversed_t

JOIN_TOL = 1e-7           # of the patches' diagonal: rulings farther apart do not meet


def _flip_u(R: Surface) -> Surface:
    ku = R.knots_u[0] + R.knots_u[-1] - R.knots_u[::-1]
    W = None if R.weights is None else R.weights[::-1].copy()
    return Surface(R.poles[::-1].copy(), ku, R.knots_v, R.degree_u, R.degree_v, W)


def _weights(R: Surface) -> np.ndarray:
    return np.ones(R.poles.shape[:2]) if R.weights is None else R.weights


def _gap(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.linalg.norm(a - b, axis=-1).max())


def _orient(prev: Surface, nxt: Surface, tol: float) -> tuple[Surface, float]:
    """nxt turned (in u and/or t) so that it starts on prev's last ruling; and the gap left."""
    best, gap = nxt, math.inf
    for fu in (False, True):
        for ft in (False, True):
            cand = nxt
            if fu:
                cand = _flip_u(cand)
            if ft:
                cand = reversed_t(cand)
            g = _gap(prev.poles[-1], cand.poles[0])
            if g < gap:
                best, gap = cand, g
            if g <= tol:
                return cand, g
    return best, gap


def join_patches(patches: list[Surface], names: list[str] | None = None) -> tuple[Surface, float]:
    """One ruled surface (rulings along v) through the ruled patches (each of degree 1 in v), in the
    order given, and +1 when its normal is the first patch's own (-1: that patch was run backwards).
    Refuses patches that are not ruled, not of one degree, or do not follow one another."""
    if not patches:
        raise BadInputError("no patches to join")
    names = names or [f"patch {k}" for k in range(len(patches))]
    for R, nm in zip(patches, names):
        if R.degree_v != 1 or R.poles.shape[1] != 2:
            raise BadInputError(f"{nm} is not a ruled patch (degree {R.degree_v} along its rulings, "
                                f"{R.poles.shape[1]} poles across; a patch of 'ruled cone' or 'ruled fit' has 1 and 2)")
        if R.periodic_u and len(patches) > 1:
            raise BadInputError(f"{nm} is closed around: a closed ruled face is machined on its own, not joined")
    p = max(R.degree_u for R in patches)
    if any(R.degree_u != p for R in patches):
        raise BadInputError(f"the patches have different degrees along their boundaries "
                            f"({sorted({R.degree_u for R in patches})}): join patches of one 'ruled cone' or "
                            f"'ruled fit' result")
    if len(patches) == 1:
        return patches[0], 1.0
    size = max(R.diagonal() for R in patches)
    tol = JOIN_TOL * size
    chain = list(patches)
    # the first patch may run either way: take the way that meets the second
    gaps = [_orient(c, chain[1], tol)[1] for c in (chain[0], _flip_u(chain[0]))]
    sign = 1.0 if gaps[0] <= gaps[1] else -1.0
    if sign < 0:
        chain[0] = _flip_u(chain[0])
    for k in range(1, len(chain)):
        chain[k], g = _orient(chain[k - 1], chain[k], tol)
        if g > tol:
            raise BadInputError(
                f"{names[k]} does not start where {names[k - 1]} ends (its nearest ruling is {g:.3g} away, more than "
                f"{tol:.3g}): join only patches that follow one another, in their order (as 'ruled cone' writes "
                f"them), or machine them one at a time")
    poles: list = []
    weights: list = []
    knots = [0.0] * (p + 1)
    for k, R in enumerate(chain):
        W = _weights(R)
        if k:
            prev_w = weights[-1]
            ratio = prev_w / W[0]
            if np.ptp(ratio) > 1e-9 * ratio.max():
                raise BadInputError(f"{names[k]} meets {names[k - 1]} with weights that cannot be matched along "
                                    f"the joint ruling: machine them one at a time")
            scale = float(ratio.mean())
        else:
            scale = 1.0
        W = W * scale
        start = 1 if k else 0
        poles.extend(R.poles[start:])
        weights.extend(W[start:])
        ku = R.knots_u
        inner = (ku[p + 1:-p - 1] - ku[p]) / (ku[-p - 1] - ku[p])
        knots.extend((k + inner).tolist())
        knots.extend([float(k + 1)] * (p if k < len(chain) - 1 else p + 1))
    return Surface(np.array(poles), np.array(knots), chain[0].knots_v, p, 1, np.array(weights)), sign


def patch_figures(R: Surface, axis: np.ndarray, count: int, n: int = 33) -> list[dict]:
    """Per patch k (u in [k, k+1] of a joined surface; count patches): the lines' taper against the
    machine axis (smallest and largest, degrees) and their twist: the largest angle between the
    surface's normals at the two ends of a line (degrees; 0 on a developable patch)."""
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    u0, u1, t0, t1 = R.domain
    out = []
    for k in range(count):
        a, b = (u0, u1) if count == 1 else (float(k), float(k + 1))
        u = np.linspace(a, b, n)
        u[0], u[-1] = a + 1e-9 * (b - a), b - 1e-9 * (b - a)     # inside the patch, not on its joints
        A, B = R(u, np.full(n, t0)), R(u, np.full(n, t1))
        d = B - A
        cos = np.abs(d @ axis) / np.linalg.norm(d, axis=1)
        taper = np.degrees(np.arccos(np.clip(cos, 0.0, 1.0)))
        n0, n1 = R.normals(u, np.full(n, t0)), R.normals(u, np.full(n, t1))
        twist = np.degrees(np.arctan2(np.linalg.norm(np.cross(n0, n1), axis=1), np.einsum("ij,ij->i", n0, n1)))
        out.append({"patch": k, "taper_min_deg": float(taper.min()), "taper_max_deg": float(taper.max()),
                    "twist_deg": float(twist.max())})
    return out
