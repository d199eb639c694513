"""A certificate (the bound, where it is reached, how it was made) and the grid cells a certificate refines
where its bound is loose."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np

# bounds below this fraction of the face's size are not refined further (no machine holds less)
FLOOR = 1e-6
# psi's Jacobian below -this of its median on a cell of the face: a fold (ruled.fit.face.trim)
FOLD_TOL = 1e-3
# a cell whose corners map this near a rail of R lies along it (ruled.fit.face.trim)
RAIL_T = 1e-3


@dataclass(frozen=True)
class Certificate:
    bound: float        # certified upper bound of H(S, R)
    node_max: float     # largest |S - R o psi| at the grid nodes (a sampled estimate)
    remainder: float    # largest per-cell remainder term
    nodes: tuple        # grid size (nu, nv)
    map_deviation: float = 0.0   # included in bound: the fitted patch's deviation from the bounded face
    rounding: float = 0.0        # included in bound: double precision's round-off in the evaluations
    compaction: float = 0.0      # included in bound: how far the compacted rails moved the result (ruled.fit.rails)
    compacted_from: int = 0      # the result's poles per rail before its compaction (0: not compacted)
    psi: Optional[tuple] = None  # a masked (trimmed) certificate's map: (us, vs, s, t), R's (s, t) at the grid's nodes
    alternatives: tuple = ()     # a masked certificate's other maps that keep their orientation (certificates too)


def _corner_max(f: np.ndarray) -> np.ndarray:
    """Per grid cell, the largest of the node values at its four corners."""
    return np.maximum(np.maximum(f[:-1, :-1], f[1:, :-1]), np.maximum(f[:-1, 1:], f[1:, 1:]))


def _cells_to_split(cert: Certificate, cell: np.ndarray, rem: tuple, floor: float, uniform: bool = False):
    """Grid intervals to halve in the next round, (iu, iv): those of the cells near the worst and
    dominated by their remainder, in the directions whose part of the remainder (rem = (u part,
    v part)) matters; None when the bound is tight, or when most cells qualify (the grid is coarse
    everywhere: local refinement would not pay) unless ``uniform`` (then the whole grid is halved in
    the directions that dominate: an exact fit, whose bound is all remainder); None too when the
    bound is below ``floor`` (no CAD tolerance asks for less)."""
    ru, rv = rem
    tot = ru + rv
    cut = cert.node_max + 0.5 * (cert.bound - cert.node_max)
    bad = (cell > cut) & (tot > 0.25 * cell)
    if (not bad.any() or cert.bound <= max(1.02 * cert.node_max, floor)
            or (bad.mean() > 0.05 and not uniform)):
        return None
    iu = np.unique(np.nonzero(bad & (ru >= 0.25 * tot))[0])
    iv = np.unique(np.nonzero(bad & (rv >= 0.25 * tot))[1])
    return iu, iv


def folds(psi: tuple, cells: np.ndarray) -> bool:
    """Whether psi fails to keep its orientation on a cell of the mask: its bilinear Jacobian, at each
    corner of each such cell, below -FOLD_TOL of its median somewhere (the grid's rows next to R's rails
    are a hair high, and their nodes go to the rails' closest points: a corner there may come out flat,
    or negative at round-off's scale, without folding anything)."""
    us, vs, S, T = psi
    hu, hv = np.diff(us)[:, None], np.diff(vs)[None, :]

    def edge(F, axis, k):
        # the cell's edge difference along axis at its side k (0 or 1)
        if axis == 0:
            return (F[1:, k:F.shape[1] - 1 + k] - F[:-1, k:F.shape[1] - 1 + k]) / hu
        return (F[k:F.shape[0] - 1 + k, 1:] - F[k:F.shape[0] - 1 + k, :-1]) / hv
    dets = [(edge(S, 0, j0) * edge(T, 1, i0) - edge(S, 1, i0) * edge(T, 0, j0))[cells]
            for j0 in (0, 1) for i0 in (0, 1)]
    d = np.concatenate(dets)
    med = float(np.median(d)) if d.size else 0.0
    return not (med > 0 and d.min() > -FOLD_TOL * med)
