"""The reverse certificate: a bound on how far the face lies from the fit (every point of the face to
the ruled surface), over a grid refined where the bound is loose."""

from __future__ import annotations

import numpy as np

from ruled.core.basis import SpanRangeMax
from ruled.core.nurbs import Surface
from ruled.fit.certify.bounds import _crease_term, _curve_feet, _knot_grid, _nodes_of, _range_max, _twin, crease_jumps
from ruled.fit.certify.cells import FLOOR, Certificate, _cells_to_split, _corner_max
from ruled.fit.dp.pairing import Pairing


def certify_reverse(S: Surface, pairing: Pairing, R: Surface, target_s: int = 240, target_t: int = 40,
                    rounds: int = 3) -> Certificate:
    """Certified bound of H(S, R) from the other side: phi maps R's domain (s, t) into S's
    (closest points on S, seeded by the pairing's correspondence), sides to sides, so

        H(S, R) <= sup |f|,  f = R - S o phi,

    and on each grid cell (aligned with R's knot spans, so R is smooth inside; phi bilinear)

        sup_cell |f| <= max_corners |f| + (h_s^2 |R_ss| + q(du_s, dv_s) + q(du_t, dv_t)) / 8,

    q(du, dv) = Muu du^2 + 2 Muv |du dv| + Mvv dv^2 with S's second-derivative bounds over the
    cell's u-range and du, dv the largest parameter change of phi along the cell's edges (R_tt = 0).
    The closest-point map onto the smooth input is continuous where R folds (fans, lifted ends),
    which is where the forward map of ``certify`` loses its tightness."""
    from ruled.core.distance import project_points
    closed = pairing.closed
    u0, u1, v0, v1 = S.domain
    L, V = u1 - u0, v1 - v0
    Sb, Rb = _twin(S), _twin(R, ruled=True)
    bS = Sb.derivative_bounds()
    M = {k: SpanRangeMax(Sb.knots_u, Sb.degree_u, bS[k].max(axis=1)) for k in ("Suu", "Suv", "Svv")}
    Rss_span = Rb.derivative_bounds()["Suu"][:, 0]
    creases = (crease_jumps(S, 0, closed), crease_jumps(S, 1))
    extra_s = np.zeros(0)
    tt = np.linspace(0.0, 1.0, target_t + 1)
    best = prev = None
    for rnd in range(rounds + 1):
        ss, span_s = _knot_grid(R, "u", target_s, extra_s, Rb)
        ns, nt = ss.size, tt.size
        SS, TT = np.meshgrid(ss, tt, indexing="ij")
        Y = R(SS.ravel(), TT.ravel()).reshape(ns, nt, 3)
        a, b = pairing.ab(ss)
        xs = (1 - TT) * a[:, None] + TT * b[:, None]
        useed = u0 + L * (xs if closed else np.clip(xs, 0.0, 1.0))
        vseed = v0 + V * TT
        seeds = np.stack([useed, vseed], axis=2)
        uv = np.empty((ns, nt, 2))
        new = np.ones((ns, nt), bool)
        if prev is not None:      # the nodes of the last round's grid keep their closest points (the same
            new = ~_nodes_of(prev, ss, tt, uv)      # point from the same seed: the same projection)
        uv[new] = project_points(S, Y[new], seeds[new], 8, closed)[0]
        prev = (ss, tt, uv)
        U = uv[:, :, 0].copy()
        W = uv[:, :, 1].copy()
        if closed:  # continuous (unwrapped) u
            U = useed + (np.mod(U - useed + 0.5 * L, L) - 0.5 * L)
        # sides to sides
        U[:, 0] = _curve_feet(S, Y[:, 0], useed[:, 0], v0, closed)
        U[:, -1] = _curve_feet(S, Y[:, -1], useed[:, -1], v1, closed)
        W[:, 0], W[:, -1] = v0, v1
        if closed:
            for col in (0, -1):
                U[:, col] = useed[:, col] + (np.mod(U[:, col] - useed[:, col] + 0.5 * L, L) - 0.5 * L)
        else:
            St = S.transposed()
            for row, uu in ((0, u0), (-1, u1)):
                W[row, 1:-1] = _curve_feet(St, Y[row, 1:-1], W[row, 1:-1], uu, False)
                U[row, :] = uu
            W[:, 0], W[:, -1] = v0, v1
        f, rs, rt = _reverse_cells(S, Y, ss, span_s, tt, U, W, closed, M, Rss_span, creases)
        rem = rs + rt
        cell = _corner_max(f) + rem
        cert = Certificate(float(cell.max()), float(f.max()), float(rem.max()), (ns, nt))
        if best is None or cert.bound < best.bound:
            best = cert
        split = _cells_to_split(cert, cell, (rs, rt), FLOOR * S.diagonal())
        if rnd == rounds or split is None:
            break
        iu, iv = split
        extra_s = np.concatenate([extra_s, 0.5 * (ss[iu] + ss[iu + 1])])
        if np.unique(iv).size > 0 and nt < 8 * target_t:
            tt = np.unique(np.concatenate([tt, 0.5 * (tt[iv] + tt[iv + 1])]))
    return best


def _reverse_cells(S, Y, ss, span_s, tt, U, W, closed, M, Rss_span, creases) -> tuple:
    """For phi given at the nodes (U, W: S's parameters of R's grid points Y), the node distances f and per cell
    the remainder's s and t parts (the module doc's bound on each cell is the corner maximum of f plus both)."""
    u0, u1 = S.domain[:2]
    L = u1 - u0
    ns, nt = ss.size, tt.size
    F = S((u0 + np.mod(U - u0, L) if closed else U).ravel(), W.ravel()).reshape(ns, nt, 3)
    f = np.linalg.norm(Y - F, axis=2)
    hs = np.diff(ss)[:, None]
    du_s = np.maximum(np.abs(np.diff(U, axis=0)[:, :-1]), np.abs(np.diff(U, axis=0)[:, 1:]))
    dv_s = np.maximum(np.abs(np.diff(W, axis=0)[:, :-1]), np.abs(np.diff(W, axis=0)[:, 1:]))
    du_t = np.maximum(np.abs(np.diff(U, axis=1)[:-1]), np.abs(np.diff(U, axis=1)[1:]))
    dv_t = np.maximum(np.abs(np.diff(W, axis=1)[:-1]), np.abs(np.diff(W, axis=1)[1:]))
    cu = np.stack([U[:-1, :-1], U[1:, :-1], U[:-1, 1:], U[1:, 1:]])
    lo, hi = cu.min(axis=0), cu.max(axis=0)
    if closed:
        sh = L * np.floor((lo - u0) / L)
        lo, hi = lo - sh, hi - sh
    Muu, Muv, Mvv = M["Suu"](lo, hi), M["Suv"](lo, hi), M["Svv"](lo, hi)
    rs = (hs ** 2 * _range_max(Rss_span, span_s)[:, None] + Muu * du_s ** 2 + 2 * Muv * du_s * dv_s
          + Mvv * dv_s ** 2) / 8.0
    rt = (Muu * du_t ** 2 + 2 * Muv * du_t * dv_t + Mvv * dv_t ** 2) / 8.0
    if creases[0][0].size or creases[1][0].size:
        # S o phi has a kink where phi crosses a crease of S: linear interpolation across a kink of
        # slope jump J along an edge of parameter change d errs by up to J d / 4 more
        cv = np.stack([W[:-1, :-1], W[1:, :-1], W[:-1, 1:], W[1:, 1:]])
        Ju = _crease_term(creases[0], lo, hi, L if closed else 0.0)
        Jv = _crease_term(creases[1], cv.min(axis=0), cv.max(axis=0))
        rs = rs + (Ju * du_s + Jv * dv_s) / 4.0
        rt = rt + (Ju * du_t + Jv * dv_t) / 4.0
    return f, rs, rt
