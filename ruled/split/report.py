"""Report and plot of a split and of a partition (no CAD host needed)."""

from __future__ import annotations

from typing import Optional

import numpy as np

from ruled.core.distance import project_points
from ruled.core.nurbs import Curve, Surface
from ruled.split.partition import Partition, SplitResult, StripFit
from ruled.split.strips import input_curve


def _curve_json(c: Curve, transposed: bool) -> dict:
    c = input_curve(c, transposed)
    return {"degree": c.degree, "knots": c.knots.tolist(), "points": c.poles.tolist()}


def _strip_json(sf: StripFit, measured: Optional[dict]) -> dict:
    R = sf.fit.surface
    return {"error_bound": sf.bound, "fit_bound": sf.fit.error_bound, "side_surface_deviation": sf.side.deviation,
            "result_poles": list(R.poles.shape[:2]), "result_degree": [R.degree_u, R.degree_v],
            "hausdorff": measured}


def split_report(res: SplitResult, measured: dict, chosen: str, edge_bounds: Optional[dict] = None) -> dict:
    """measured: candidate name -> [per side Hausdorff dicts]; edge_bounds: name -> how far the built split
    faces' edge (the split curve on the surface, certified) is from the exact split curve.  A candidate's
    error_bound is between its fits and its split faces: the larger side's bound plus that."""
    cands = {}
    for name, c in res.candidates.items():
        m = measured.get(name)
        e = (edge_bounds or {}).get(name, 0.0)
        cands[name] = {"error_bound": c.bound + e, "fit_bound": c.bound, "split_edge_bound": e,
                       "dp_score": c.dp_score, "t": c.t,
                       "hausdorff": None if m is None else max(x["max"] for x in m),
                       "sides": [_strip_json(s, None if m is None else m[k]) for k, s in enumerate(c.sides)],
                       "curve_uv": _curve_json(c.curve, res.transposed)}
    mp = res.m_points[:, ::-1] if res.transposed else res.m_points
    return {"direction": "u" if res.transposed else "v", "whole": {"error_bound": res.whole.bound},
            "m_points_uv": mp.tolist(), "candidates": cands, "chosen": chosen,
            "timings": res.timings}


def partition_report(p: Partition, measured: list, edge_bound: float = 0.0) -> dict:
    """edge_bound: how far the built strips' split edges are from the exact split curves (see split_report)."""
    return {"tol": p.tol, "strips": len(p.strips), "greedy_strips": p.greedy_count,
            "uniform_strips": p.uniform_count, "used": p.used,
            "direction": "u" if p.transposed else "v",
            "strip_detail": [_strip_json(s, m) for s, m in zip(p.strips, measured)],
            "max_error_bound": max(p.bounds) + edge_bound, "max_fit_bound": max(p.bounds),
            "split_edge_bound": edge_bound, "max_hausdorff": max(m["max"] for m in measured) if measured else None,
            "history": [{"strip": k, "split": name, "bound": b} for k, name, b in p.history],
            "timings": p.timings}


def error_map(So: Surface, R: Surface, n: int = 60):
    """Distance from the oriented surface to a ruled result over an n x n grid of its domain."""
    from scipy.spatial import cKDTree
    u0, u1, v0, v1 = So.domain
    us, vs = np.linspace(u0, u1, n), np.linspace(v0, v1, n)
    uu, vv = np.meshgrid(us, vs, indexing="ij")
    X = So(uu.ravel(), vv.ravel())
    a0, a1, b0, b1 = R.domain
    g = 4 * n
    su, sv = np.meshgrid(np.linspace(a0, a1, g), np.linspace(b0, b1, g), indexing="ij")
    Y = R(su.ravel(), sv.ravel())
    _, idx = cKDTree(Y).query(X)
    uv0 = np.stack([su.ravel()[idx], sv.ravel()[idx]], axis=1)
    _, d = project_points(R, X, uv0, 6)
    return us, vs, d.reshape(n, n)


def plot_split(res: SplitResult, path: str, measured: dict) -> None:
    """The M-curve over the whole-face fit's error map in the (oriented) parameter domain, as the paper's
    Fig. 6, with the iso-parametric splits; and the errors of the three splits (Fig. 12)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    So = res.oriented
    us, vs, E = error_map(So, res.whole.fit.surface)
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(13, 5.2))
    im = ax1.pcolormesh(us, vs, E.T, shading="auto", cmap="viridis")
    fig.colorbar(im, ax=ax1, label="distance to the one-strip ruled fit")
    ax1.plot(res.m_points[:, 0], res.m_points[:, 1], "w.", ms=5, label="M-points (split DP)")
    x = np.linspace(So.domain[0], So.domain[1], 300)
    styles = {"optimal": ("r-", 2.0), "best-iso": ("w--", 1.2), "iso-0.5": ("w:", 1.2)}
    for name, c in res.candidates.items():
        st, lw = styles.get(name, ("k-", 1))
        ax1.plot(x, c.curve(x)[:, 1], st, lw=lw, label=f"{name} split")
    lab = ("v", "u") if res.transposed else ("u", "v")
    ax1.set_xlabel(f"{lab[0]} (along the split)")
    ax1.set_ylabel(f"{lab[1]} (across, the rulings' direction)")
    ax1.set_title("split curves over the error of a single ruled fit")
    ax1.legend(loc="best", fontsize=8)
    names = list(res.candidates)
    xb = np.arange(len(names))
    ax2.bar(xb - 0.2, [res.candidates[k].bound for k in names], 0.4, label="certified bound", color="0.6")
    ax2.bar(xb + 0.2, [max(m["max"] for m in measured[k]) if k in measured else 0 for k in names], 0.4,
            label="measured Hausdorff (OCCT)", color="C3")
    ax2.axhline(res.whole.bound, color="k", ls=":", lw=1, label=f"one strip: {res.whole.bound:.4g}")
    ax2.set_xticks(xb, names)
    ax2.set_ylabel("error of the two fitted sides")
    ax2.set_title("optimal vs iso-parametric splits")
    ax2.legend(loc="best", fontsize=8)
    fig.tight_layout()
    from ruled.core.outputs import atomic
    with atomic(path) as tmp:
        fig.savefig(tmp, dpi=110)
    plt.close(fig)
