"""A pairing that follows (nearly) exact refined rulings to round-off: the rulings searched again, the
smooth pairing's knots where the boundary curves' own kinks make the rulings' pairing kink, and its spans
halved where it misses them."""

from __future__ import annotations

import numpy as np

from ruled.core.nearest import GOLD, golden
from ruled.core.nurbs import Surface
from ruled.fit.dp.pairing import MAX_DELTA_COEFS, refine_pairing, smooth_pairing
from ruled.fit.face.cost import over_face, ruling_cost
from ruled.fit.reparam import _mapped_knots, _merge

# rulings at most this fraction of the size from the face count as exact (the pairing then follows them)
EXACT_RULINGS = 1e-4


def follow_exact(So: Surface, closed: bool, h: float, refined: tuple, pairing,
                  rounds: int = 6):
    """Where the refined rulings are (nearly) exact, a smooth pairing that follows them: while the
    cubic delta(sigma) misses them (its rulings' distances, checked between the refined samples too,
    above twice the refined ones), the knot spans where it misses are halved, each new span pinned
    by refined samples of its own.  Elsewhere the pairing as it is.  Returns (pairing, sigma, delta,
    cost)."""
    sig, dlt, rc = refined
    u0, u1, v0, v1 = So.domain
    L = u1 - u0
    diag = So.diagonal()
    if float(np.max(rc)) > EXACT_RULINGS * diag:
        return pairing, sig, dlt, rc
    if So.weights is not None:
        # a rational face (a conic's surface of revolution): its rulings to round-off, for its rails to be
        # exact (on a polynomial one the search's own precision has served, and a search again wanders
        # along the flat valleys of a fan of rulings at a corner, bending the pairing)
        dlt, rc = _polished(So, closed, sig, dlt, rc, 4.0 * h * GOLD ** 18)

    def misses(pr, rc):
        """(knots, check sigmas, whether the pairing's ruling there misses, the largest miss) over the face."""
        br = np.unique(pr.delta.knots)         # absolute sigma, over the pairing's span
        chk = np.unique(np.concatenate([np.linspace(br[i], br[i + 1], 9) for i in range(br.size - 1)]))
        a, b = pr.ab((chk - pr.sigma0) / pr.span)
        miss = ruling_cost(So, u0 + L * a, u0 + L * b, 15, 4, closed)
        # (on a face's extended patch, where a ruling crosses the face: near its end edges a ruling's few
        # samples over the face leave its pairing loose, and spans halved there only bend the rails)
        over = over_face(So, u0 + L * a, u0 + L * b, every=True)
        return br, chk, (miss > 2.0 * float(np.max(rc)) + 1e-7 * diag) & over, float(np.max(miss[over], initial=0.0))

    own = np.unique(pairing.delta.knots)[1:-1]
    start = (sig, dlt, rc)

    def follow(ks, km):
        """The loop below from the refined rulings, with the knots ks (multiplicities km) kept throughout:
        (pairing, sigma, delta, cost, its worst miss)."""
        def knotted(interior):
            interior = np.unique(interior)
            near = np.abs(interior[:, None] - ks[None, :]).min(axis=1, initial=np.inf)
            return np.concatenate([interior[near > 1e-9], np.repeat(ks, km)])
        sig, dlt, rc = start
        pr = smooth_pairing(So, sig, dlt, closed, 0, interior=knotted(own))
        got = misses(pr, rc)
        for _ in range(rounds):
            br, chk, bad, _worst = got
            if not bad.any() or br.size - 1 >= 4 * MAX_DELTA_COEFS:
                break
            span = np.unique(np.clip(np.searchsorted(br, chk[bad], side="right") - 1, 0, br.size - 2))
            mids = 0.5 * (br[span] + br[span + 1])
            new = np.concatenate([np.linspace(br[i], br[i + 1], 6)[1:-1] for i in span])
            # each new ruling searched next to the refined ones' family (pairing.refine_pairing: a bracket of
            # a whole sample may hold the other family of a doubly ruled face)
            s2, d2, c2 = refine_pairing(So, u0, L, closed, np.stack([sig - dlt, sig + dlt], axis=1), h / 64, 0,
                                        at=new)
            order = np.argsort(np.concatenate([sig, s2]), kind="stable")
            sig, dlt, rc = (np.concatenate([sig, s2])[order], np.concatenate([dlt, d2])[order],
                            np.concatenate([rc, c2])[order])
            pr = smooth_pairing(So, sig, dlt, closed, 0, interior=knotted(np.concatenate([br[1:-1], mids])))
            got = misses(pr, rc)
        return pr, sig, dlt, rc, got[3]

    best = follow(np.zeros(0), np.zeros(0, int))
    # the boundary curves' kinks, kept where the pairing then follows the rulings closer
    ks, km = _boundary_kinks(So, best[0])
    if ks.size:
        other = follow(ks, km)
        if other[4] < best[4]:
            best = other
    return best[:4]


def _boundary_kinks(So: Surface, pairing) -> tuple[np.ndarray, np.ndarray]:
    """(sigma, multiplicity): where a ruling of the pairing ends at a knot of a boundary curve at which the
    curve is less than twice differentiable, the pairing of exact rulings is too (a conic's rational
    arcs meet with a jump of curvature of their parametrization): a cubic delta follows it with a knot
    of this multiplicity there."""
    u0, u1, v0, v1 = So.domain
    found = [_mapped_knots(So.iso_curve("u", v), u0, u1 - u0, pairing, which, 3)
             for v, which in ((v0, "a"), (v1, "b"))]
    s = np.concatenate([f[0] for f in found])
    m = np.concatenate([f[1] for f in found])
    keep = (m >= 2) & (s > 1e-6) & (s < 1.0 - 1e-6)
    if not keep.any():
        return np.zeros(0), np.zeros(0, int)
    sig, m = _merge(pairing.sigma0 + pairing.span * s[keep], m[keep], 1e-6)
    return sig, np.minimum(m, 3)


def _polished(So: Surface, closed: bool, sig: np.ndarray, dlt: np.ndarray, rc: np.ndarray, width: float,
              rounds: int = 30) -> tuple:
    """(delta, cost) of near-exact refined rulings searched again within width of theirs, to round-off
    (the refinement's search stops at a fraction of a sample step: on an exactly ruled face that is
    1e-6 of its size, and every rail composed through them inherits it), kept where closer."""
    u0, u1 = So.domain[:2]
    L = u1 - u0
    x, f = golden(lambda d: ruling_cost(So, u0 + L * (sig - d), u0 + L * (sig + d), 11, 6, closed),
                   dlt - width, dlt + width, rounds)
    # only a real gain: exact ones (iso-lines) stay, and so do those in a flat valley (a fan of rulings at a
    # corner, where a search wanders along it and bends the pairing for nothing)
    better = (f < 0.1 * rc) & (rc > 1e-12 * So.diagonal())
    return np.where(better, x, dlt), np.where(better, f, rc)
