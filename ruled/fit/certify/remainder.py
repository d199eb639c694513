"""The interpolation remainders of the forward certificate (ruled.fit.certify.forward): per grid cell, how far
|S - R o psi| can rise between the cell's corners, to first order (second-derivative bounds of S and R from their
control nets, psi's steps along the cell's edges, the slope jumps of R's kinks the cell's image crosses) and to
second order (f's second derivatives at the corners, third-derivative bounds for the rest)."""

from __future__ import annotations

import numpy as np

from ruled.core.nurbs import Curve
from ruled.fit.certify.bounds import (
    _contains,
    _crossing,
    _joint_jumps,
    _local_net_max,
    _rail,
    _range_max,
    _soft_knots,
    _spanmax,
)

# the second-order remainder's corner values are taken this fraction of the cell inside each corner
NUDGE = 1e-6


def _s_range(s, closed) -> tuple:
    """Per cell, the range of s over its corners (unwrapped round a closed result's seam)."""
    cs = np.stack([s[:-1, :-1], s[1:, :-1], s[:-1, 1:], s[1:, 1:]])
    if closed:
        cs = cs[0][None] + (cs - cs[0][None] - np.round(cs - cs[0][None]))
    return cs.min(axis=0), cs.max(axis=0)


def _first_order(S, b, us, vs, span_u, span_v, s, t, bd, R, tw, closed) -> tuple:
    """Per cell, the first-order remainder of the module doc, its u and v parts: S's and R's second derivatives
    over the cell and psi's steps along its edges, and the slope jumps of R's kinks the cell's image crosses."""
    Suu = _range_max(_range_max(b["Suu"], span_u, 0), span_v, 1)
    Svv = _range_max(_range_max(b["Svv"], span_u, 0), span_v, 1)
    hu = np.diff(us)[:, None]
    hv = np.diff(vs)[None, :]

    def rel(q):
        if not closed:
            return q
        return q - np.round(q)

    s00, s10, s01, s11 = s[:-1, :-1], s[1:, :-1], s[:-1, 1:], s[1:, 1:]
    dsu = np.maximum(np.abs(rel(s10 - s00)), np.abs(rel(s11 - s01)))
    dsv = np.maximum(np.abs(rel(s01 - s00)), np.abs(rel(s11 - s10)))
    t00, t10, t01, t11 = t[:-1, :-1], t[1:, :-1], t[:-1, 1:], t[1:, 1:]
    dtu = np.maximum(np.abs(t10 - t00), np.abs(t11 - t01))
    dtv = np.maximum(np.abs(t01 - t00), np.abs(t11 - t10))
    slo, shi = _s_range(s, closed)
    ct = np.stack([t00, t10, t01, t11])
    tlo, thi = ct.min(axis=0), ct.max(axis=0)
    Rb = tw[1]
    if R.rational:  # quotient-rule bounds of the rational ruled surface, per span in s
        rb = Rb.derivative_bounds()
        Rss = _spanmax(Rb, rb["Suu"][:, 0], slo, shi)
        Rst = _spanmax(Rb, rb["Suv"][:, 0], slo, shi)
    else:
        Ab, Bb = _rail(Rb, 0), _rail(Rb, 1)
        diff = Curve(Bb.poles - Ab.poles, Ab.knots, Ab.degree)
        A2 = _spanmax(Rb, _local_net_max(Ab, 2), slo, shi)
        B2 = _spanmax(Rb, _local_net_max(Bb, 2), slo, shi)
        Rst = _spanmax(Rb, _local_net_max(diff, 1), slo, shi)
        Rss = (1.0 - tlo) * A2 + thi * B2
    ru = (Suu * hu ** 2 + Rss * dsu ** 2 + 2 * Rst * dsu * dtu) / 8.0
    rv = (Svv * hv ** 2 + Rss * dsv ** 2 + 2 * Rst * dsv * dtv) / 8.0
    # R's kinks, and for a closed result its seam (s = 0, where R_s jumps when the face's boundary has a
    # corner there: a degree-1 tube's seam is one; a smooth seam adds only its round-off jump)
    kinks = bd.kinks if not closed or np.any(bd.kinks == 0.0) else np.concatenate([[0.0], bd.kinks])
    for sk in kinks:
        hit = _crossing(slo, shi, sk, closed)
        if hit.any():
            J = _joint_jumps(R, sk)[0]
            ru = ru + np.where(hit, J * dsu / 4.0, 0.0)
            rv = rv + np.where(hit, J * dsv / 4.0, 0.0)
    return ru, rv


def _remainder2(S, us, vs, span_u, span_v, s, t, slo, shi, closed, R, bd, tw, need) -> tuple:
    """Per cell, the interpolation remainder (h_u^2 sup|f_uu| + h_v^2 sup|f_vv|) / 8 with sup|f_uu|
    bounded from its values at the cell's corners and third-derivative bounds:

        sup|f_uu| <= max_corners |f_uu| + (h_u sup|f_uuu| + h_v sup|f_uuv|) / 2   (+ jumps),

    f_uu = S_uu - (R_ss s_u^2 + 2 R_st s_u t_u) at a corner (just inside the cell: see NUDGE), with
    the cell's own (bilinear) slopes there; f_uuu and f_uuv by the chain rule (psi bilinear: s_uu = 0; R linear in
    t: R_tt = R_stt = 0) from the control-net bounds of S and R.  Where S o psi is exactly R o psi up
    to the bilinear map's own error, f_uu is that error's second derivative: the bound follows the
    fit down to round-off, where the first-order remainder stays at h^2 |S_uu| / 8.  f_uu jumps where
    R's second derivative does (knots of multiplicity p - 1): each crossing adds the jump (a straight
    path crosses such a line at most twice in a bilinear cell).  Cells where this does not hold (S
    less than C2 inside, R less than C1) get infinity."""
    nu, nv = us.size, vs.size
    hu = np.diff(us)[:, None]
    hv = np.diff(vs)[None, :]

    def rel(q):
        return q - np.round(q) if closed else q

    su_b, su_t = rel(s[1:, :-1] - s[:-1, :-1]) / hu, rel(s[1:, 1:] - s[:-1, 1:]) / hu
    tu_b, tu_t = (t[1:, :-1] - t[:-1, :-1]) / hu, (t[1:, 1:] - t[:-1, 1:]) / hu
    sv_l, sv_r = rel(s[:-1, 1:] - s[:-1, :-1]) / hv, rel(s[1:, 1:] - s[1:, :-1]) / hv
    tv_l, tv_r = (t[:-1, 1:] - t[:-1, :-1]) / hv, (t[1:, 1:] - t[1:, :-1]) / hv
    s_uv = np.abs(su_t - su_b) / hv
    t_uv = np.abs(tu_t - tu_b) / hv
    # f_uu and f_vv at a point just inside each corner (NUDGE of the cell inward): on the cell's side
    # of any knot line through the corner (S's creases are grid lines, R's knots may pass through
    # nodes), where a node's own value would be the neighbour's
    s00, t00 = s[:-1, :-1], t[:-1, :-1]
    du_s, dv_s = rel(s[1:, :-1] - s00), rel(s[:-1, 1:] - s00)
    dd_s = rel(s[1:, 1:] - s00) - du_s - dv_s
    du_t, dv_t = t[1:, :-1] - t00, t[:-1, 1:] - t00
    dd_t = t[1:, 1:] - t00 - du_t - dv_t
    # the cells asked for (need), each a row of the evaluations; the others get infinity (not used)
    sel = need
    m = int(np.count_nonzero(sel))
    Fuu, Fvv = np.full((nu - 1, nv - 1), np.inf), np.full((nu - 1, nv - 1), np.inf)
    if m:
        P = [(lu, lv) for lu in (NUDGE, 1.0 - NUDGE) for lv in (NUDGE, 1.0 - NUDGE)]
        uq = np.concatenate([np.broadcast_to(us[:-1, None] + lu * hu, (nu - 1, nv - 1))[sel] for lu, lv in P])
        vq = np.concatenate([np.broadcast_to(vs[None, :-1] + lv * hv, (nu - 1, nv - 1))[sel] for lu, lv in P])
        sq = np.concatenate([(s00 + lu * du_s + lv * dv_s + lu * lv * dd_s)[sel] for lu, lv in P])
        tq = np.concatenate([(t00 + lu * du_t + lv * dv_t + lu * lv * dd_t)[sel] for lu, lv in P])
        Dq = S.evaluate(uq, vq, 2)
        Rq = R.evaluate(np.mod(sq, 1.0) if closed else np.clip(sq, 0.0, 1.0), np.clip(tq, 0.0, 1.0), 2)
        fuu = fvv = 0.0
        for k, (lu, lv) in enumerate(P):
            sl = slice(k * m, (k + 1) * m)
            a_s, a_t = ((du_s + lv * dd_s) / hu)[sel], ((du_t + lv * dd_t) / hu)[sel]   # psi_u there
            c_s, c_t = ((dv_s + lu * dd_s) / hv)[sel], ((dv_t + lu * dd_t) / hv)[sel]   # psi_v there
            Rss, Rst = Rq.Suu[sl], Rq.Suv[sl]
            guu = Dq.Suu[sl] - (Rss * (a_s * a_s)[:, None] + 2.0 * Rst * (a_s * a_t)[:, None])
            gvv = Dq.Svv[sl] - (Rss * (c_s * c_s)[:, None] + 2.0 * Rst * (c_s * c_t)[:, None])
            fuu = np.maximum(fuu, np.linalg.norm(guu, axis=1))
            fvv = np.maximum(fvv, np.linalg.norm(gvv, axis=1))
        Fuu[sel], Fvv[sel] = fuu, fvv
    a_u, b_u = np.maximum(np.abs(su_b), np.abs(su_t)), np.maximum(np.abs(tu_b), np.abs(tu_t))
    a_v, b_v = np.maximum(np.abs(sv_l), np.abs(sv_r)), np.maximum(np.abs(tv_l), np.abs(tv_r))
    # S's third derivatives over the cell's spans
    Sb, Rb = tw
    b3 = Sb.third_derivative_bounds()
    M3 = {k: _range_max(_range_max(b3[k], span_u, 0), span_v, 1) for k in ("Suuu", "Suuv", "Suvv", "Svvv")}
    # R's second and third derivatives over the cell's s-range
    rb, rb3 = Rb.derivative_bounds(), Rb.third_derivative_bounds()
    Mss = _spanmax(Rb, rb["Suu"][:, 0], slo, shi)
    Mst = _spanmax(Rb, rb["Suv"][:, 0], slo, shi)
    Msss = _spanmax(Rb, rb3["Suuu"][:, 0], slo, shi)
    Msst = _spanmax(Rb, rb3["Suuv"][:, 0], slo, shi)
    r_uuu = Msss * a_u ** 3 + 3 * Msst * a_u ** 2 * b_u
    r_vvv = Msss * a_v ** 3 + 3 * Msst * a_v ** 2 * b_v
    r_uuv = ((Msss * a_v + Msst * b_v) * a_u ** 2 + 2 * Mss * a_u * s_uv + 2 * Msst * a_v * a_u * b_u
             + 2 * Mst * (s_uv * b_u + a_u * t_uv))
    r_vvu = ((Msss * a_u + Msst * b_u) * a_v ** 2 + 2 * Mss * a_v * s_uv + 2 * Msst * a_u * a_v * b_v
             + 2 * Mst * (s_uv * b_v + a_v * t_uv))
    half = 0.5 + NUDGE      # the nudged corners are a little farther from the cell's points
    Guu = Fuu + half * hu * (M3["Suuu"] + r_uuu) + half * hv * (M3["Suuv"] + r_uuv)
    Gvv = Fvv + half * hv * (M3["Svvv"] + r_vvv) + half * hu * (M3["Suvv"] + r_vvu)
    bad = np.zeros(Guu.shape, bool)
    # S less than C2 inside a cell (creases, multiplicity >= p, are grid lines already)
    u0, u1, v0, v1 = S.domain
    ku, _ = _soft_knots(S.knots_u, S.degree_u, u0, u1)
    kv, _ = _soft_knots(S.knots_v, S.degree_v, v0, v1)
    bad |= _contains(ku, us[:-1], us[1:])[:, None] | _contains(kv, vs[:-1], vs[1:])[None, :]
    # R's knots where R_ss jumps, inside a cell's s-range
    kr, mr = _soft_knots(bd.A.knots, bd.A.degree, 0.0, 1.0)
    if closed:     # the seam of a periodic result is a knot too
        kr, mr = np.concatenate([[0.0], kr]), np.concatenate([[bd.A.degree], mr])
    for sk, m in zip(kr, mr):
        _, J2, kink = _joint_jumps(R, sk)
        hit = _crossing(slo, shi, sk, closed, strict=True)   # touching cells evaluated on their side
        if m >= bd.A.degree and kink:
            bad |= hit      # a kink of R: the first-order remainder's kink term handles it
            continue
        Guu = Guu + np.where(hit, 2.0 * J2 * a_u ** 2, 0.0)
        Gvv = Gvv + np.where(hit, 2.0 * J2 * a_v ** 2, 0.0)
    return np.where(bad, np.inf, hu ** 2 * Guu / 8.0), np.where(bad, np.inf, hv ** 2 * Gvv / 8.0)
