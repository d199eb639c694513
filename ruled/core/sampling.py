"""Boundary samples, their elevations along the surface normal, and the per-patch terms of the 4D-DP.

Wang & Elber, §2 eqs. (1)–(3): n samples P_i = C0(u_i), Q_j = C1(u_j) on the
two boundaries of the oriented surface S(u, v) (rulings run along v), and the
elevated points P_{i,k} = P_i + k tau nP_i, Q_{j,l} = Q_j + l tau nQ_j,
k, l in [-m, m], with nP, nQ the unit normals of S.

Indices: the DP works on level indices K = k + m in [0, 2m].  A move ends at
ruling (i, j) and comes from (i - di, j - dj) with pattern
``PQ`` (di, dj) = (1, 1), ``P`` (1, 0) or ``Q`` (0, 1); per-pattern tables are
indexed [pattern, i, j] by the ruling the move ends at (wrapped indices on a
closed boundary, where i - 1 of i = 0 is n - 1).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ruled.core.nurbs import Surface

PATTERNS = ((1, 1), (1, 0), (0, 1))  # (di, dj) of the patterns PQ, P, Q


@dataclass(frozen=True)
class Elevated:
    """Samples of both boundaries and the elevation levels (oriented surface, see module doc)."""

    closed: bool
    x: np.ndarray       # (n,) normalized sample parameters (u = u0 + L x)
    u: np.ndarray       # (n,) sample parameters
    P: np.ndarray       # (n, 3) C0(u_i)
    Q: np.ndarray       # (n, 3) C1(u_j)
    nP: np.ndarray      # (n, 3) unit normals at P
    nQ: np.ndarray      # (n, 3) unit normals at Q
    levels: np.ndarray  # (2m + 1,) elevations k tau, k = -m..m
    tau: float

    @property
    def n(self) -> int:
        return self.u.shape[0]

    @property
    def m(self) -> int:
        return (self.levels.shape[0] - 1) // 2

    def points(self, side: str, idx, level) -> np.ndarray:
        """Elevated points of one side ('P' or 'Q') at sample indices idx and level indices level."""
        base, nrm = (self.P, self.nP) if side == "P" else (self.Q, self.nQ)
        idx = np.asarray(idx) % self.n
        return base[idx] + self.levels[np.asarray(level)][..., None] * nrm[idx]

    def partner_x(self, i, j) -> np.ndarray:
        """Normalized parameter of sample j as seen from sample i: on a closed boundary the
        parameter line of a ruling takes the shorter way around."""
        xi, xj = self.x[np.asarray(i) % self.n], self.x[np.asarray(j) % self.n]
        if not self.closed:
            return xj
        return xi + (np.mod(xj - xi + 0.5, 1.0) - 0.5)


def unit_normals(S: Surface, u: np.ndarray, v: float, inward: float) -> np.ndarray:
    """Unit normals of S along the iso-line v; where S is singular there (a collapsed edge), the
    normal a little inside (v + inward) is used."""
    N = S.normals(u, np.full(u.shape, v))
    bad = np.linalg.norm(N, axis=1) < 0.5
    for step in (1e-6, 1e-4, 1e-2):
        if not bad.any():
            break
        N[bad] = S.normals(u[bad], np.full(int(bad.sum()), v + step * inward))
        bad = np.linalg.norm(N, axis=1) < 0.5
    return N


def elevated_samples(S: Surface, n: int, m: int, tau: float, closed: bool) -> Elevated:
    """Eqs. (1)–(3) on the oriented surface S (rulings along v)."""
    u0, u1, v0, v1 = S.domain
    x = np.arange(n) / (n if closed else n - 1)
    u = u0 + (u1 - u0) * x
    P = S(u, np.full(n, v0))
    Q = S(u, np.full(n, v1))
    nP = unit_normals(S, u, v0, v1 - v0)
    nQ = unit_normals(S, u, v1, v0 - v1)
    levels = tau * np.arange(-m, m + 1, dtype=float)
    return Elevated(closed, x, u, P, Q, nP, nQ, levels, float(tau))
