"""Distances to a set of faces (a cone spline's patches, a split's sides): candidate faces by their own
sampling resolution, exact OCCT projection on each; points along lines."""

from __future__ import annotations

import numpy as np

from ruled.core.distance import _golden_min, to_lines  # noqa: F401  (to_lines: its home was here)
from ruled.core.hostform import screened
from ruled.occ.measure import _Projector, face_points, face_samples


# ------------------------------------------------------------------------------ several faces
class FaceSet:
    """Distances from points to the nearest of several faces: each face's projector, tried on the faces
    that can be the nearest one by their coarse sample clouds."""

    def __init__(self, faces, n: int = 24):
        from scipy.spatial import cKDTree

        self.proj = [_Projector(f) for f in faces]
        samples = [face_samples(f, n, resolution=True) for f in faces]
        self.trees = [cKDTree(c) for c, _ in samples]
        # per face, how far a point of it can be from its cloud: the face can be this much nearer to a
        # point than its cloud is
        self.slack = np.array([r for _, r in samples])

    def _candidates(self, X: np.ndarray, chunk: int = 4096) -> np.ndarray:
        """(N, faces) booleans: the faces that can be the nearest to each point.  A face's cloud lies on
        it, so the nearest face is at most the nearest cloud's distance away; a face whose cloud is
        farther than that by more than its slack cannot be the nearest."""
        out = np.zeros((len(X), len(self.proj)), bool)
        for lo in range(0, len(X), chunk):
            D = np.column_stack([t.query(X[lo:lo + chunk])[0] for t in self.trees])
            out[lo:lo + chunk] = D - self.slack[None, :] <= D.min(axis=1, keepdims=True)
        return out

    def distance(self, x) -> float:
        cand = np.nonzero(self._candidates(np.asarray(x, float).reshape(1, 3))[0])[0]
        return min(self.proj[i].distance(x) for i in cand)

    def upper(self, X: np.ndarray) -> np.ndarray:
        X = np.asarray(X, float).reshape(-1, 3)
        cand = self._candidates(X)
        ub = np.full(len(X), np.inf)
        for i, p in enumerate(self.proj):
            m = cand[:, i]
            if m.any():
                ub[m] = np.minimum(ub[m], p.upper(X[m]))
        return ub

    def distances(self, X: np.ndarray) -> np.ndarray:
        return screened(self, X)


def sample_faces(faces, n: int) -> np.ndarray:
    """About n x n samples of each face as bounded by its edges (OCCT evaluation), stacked."""
    return np.concatenate([face_points(f, n) for f in faces])


