"""Report and plot of a cone spline: per patch the weight, the apex (or the cylinder's direction) and
the development; the plot shows the fat curve and the fitted fat conic spline as the paper's figures."""

from __future__ import annotations

from typing import Optional

import numpy as np

from ruled.cone.conespline import ConeSpline
from ruled.cone.conic import conic


def _vec(x) -> Optional[list]:
    return None if x is None else [float(c) for c in x]


def cone_report(res: ConeSpline) -> dict:
    patches = []
    for i, p in enumerate(res.patches):
        d = {"index": i, "piece": p.piece, "kind": p.kind, "weight": p.weight, "error_bound": p.bound,
             "developable": p.developable, "v": list(p.v), "v_other": list(p.vb)}
        if p.kind == "cone":
            d["apex"] = _vec(p.apex)
            d["development_angle_deg"] = p.development
        else:
            d["direction"] = _vec(p.direction)
            d["development_width"] = p.development
        patches.append(d)
    pieces = [{"v_range": list(q.v_range), "origin": _vec(q.origin), "normal": _vec(q.axes[2]),
               "heights": list(q.heights), "fit_heights": list(q.fit_heights),
               "boundaries_in_planes": q.planar_boundaries, "arcs": len(q.arcs),
               "collapsed_sides": int(sum(np.ptp(a.A, axis=0).max() == 0 or np.ptp(a.B, axis=0).max() == 0
                                          for a in q.arcs))} for q in res.pieces]
    return {"tol": res.tol, "step": res.step, "patches": len(res.patches), "error_bound": res.bound,
            "max_g1_angle_deg": res.max_g1_deg, "max_crease_between_pieces_deg": res.max_crease_deg,
            "all_developable": all(p.developable for p in res.patches),
            "pieces": pieces, "patch_detail": patches, "notes": res.notes}


def plot(res: ConeSpline, path: str) -> None:
    """For each piece, in its planes' frame: the extended fat curve (light), the surface's own
    boundaries (dashed), the fitted conic arcs (dark) with their control polygons and the
    interpolating parallel chords."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    k = len(res.pieces)
    cols = min(k, 3)
    rows = -(-k // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(6.5 * cols, 5.5 * rows), squeeze=False)
    for ax in axes.flat[k:]:
        ax.set_visible(False)
    v = np.linspace(0.0, 1.0, 600)
    t = np.linspace(0.0, 1.0, 80)
    for n, (ax, q) in enumerate(zip(axes.flat, res.pieces)):
        for f, lab in ((q.c0, "extended boundaries"), (q.c1, None)):
            P = f(v)
            ax.plot(P[:, 0], P[:, 1], color="#9ecae1", lw=4, label=lab)
        for f, lab in ((q.orig0, "the surface's boundaries"), (q.orig1, None)):
            P = f(v)
            ax.plot(P[:, 0], P[:, 1], "--", color="#e6550d", lw=1, label=lab)
        for i, a in enumerate(q.arcs):
            for tri in (a.A, a.B):
                X = conic(tri[0], tri[1], tri[2], a.w, t)
                ax.plot(X[:, 0], X[:, 1], color="#08306b", lw=1.4, label="fat conic spline" if i == 0 and
                        tri is a.A else None)
                ax.plot(tri[:, 0], tri[:, 1], ":", color="0.45", lw=0.8,
                        label="control polygons" if i == 0 and tri is a.A else None)
            ax.plot([a.A[0, 0], a.B[0, 0]], [a.A[0, 1], a.B[0, 1]], color="0.6", lw=0.6)
            ax.plot([a.A[0, 0], a.A[2, 0]], [a.A[0, 1], a.A[2, 1]], color="#31a354", lw=0.8,
                    label="parallel chords" if i == 0 else None)
            ax.plot([a.B[0, 0], a.B[2, 0]], [a.B[0, 1], a.B[2, 1]], color="#31a354", lw=0.8)
        ax.set_aspect("equal", adjustable="datalim")
        h0, h1, H0, H1 = (0.0 if abs(x) <= 1e-12 * (abs(q.heights[1] - q.heights[0]) + 1e-300) else x
                          for x in (*q.heights, *q.fit_heights))
        ax.set_title(f"{'piece %d (v %.3g .. %.3g): ' % (n, *q.v_range) if k > 1 else ''}"
                     f"{len(q.arcs)} fat conic arcs\nplanes {h0:.4g} .. {h1:.4g} (fitted on {H0:.4g} .. {H1:.4g}), "
                     f"{'the boundaries' if q.planar_boundaries else 'rulings extended'}", fontsize=9)
        ax.set_xlabel("frame x")
        ax.set_ylabel("frame y")
        if n == 0:
            ax.legend(loc="best", fontsize=7)
    fig.suptitle(f"cone spline: {len(res.patches)} patches, tolerance {res.tol:g}, bound (eq. 9) {res.bound:.4g}")
    fig.tight_layout()
    from ruled.core.outputs import atomic
    with atomic(path) as tmp:
        fig.savefig(tmp, dpi=110)
    plt.close(fig)


def to_ruled(res, per: list, patch_of=None) -> tuple:
    """(the points, their exact distances to the ruled surface between the planes): per, samples of each
    patch of the cone spline res (a host's, of its faces; patch_of: each face's patch, when they are not the
    patches one to one, trimmed by a face's edges); each point to its own piece's rulings, then,
    from the farthest down while above the largest distance found, to the other pieces' too (the nearest
    point may lie across a piece's end)."""
    from ruled.core.distance import to_lines
    pts = np.concatenate(per)
    patches = res.patches if patch_of is None else [res.patches[i] for i in patch_of]
    own = np.concatenate([np.full(len(c), q.piece) for c, q in zip(per, patches)])
    d = np.empty(len(pts))
    for k, piece in enumerate(res.pieces):
        m = own == k
        if m.any():
            d[m] = to_lines(pts[m], piece.rulings)
    if len(res.pieces) > 1:
        top, order = 0.0, np.argsort(-d, kind="stable")
        for lo in range(0, len(order), 64):
            idx = order[lo:lo + 64]
            idx = idx[d[idx] > top]
            if not idx.size:
                break
            for k, piece in enumerate(res.pieces):
                sel = idx[own[idx] != k]
                if sel.size:
                    d[sel] = np.minimum(d[sel], to_lines(pts[sel], piece.rulings))
            top = max(top, float(d[idx].max()))
    return pts, d
