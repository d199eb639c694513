"""JSON report and plot of a fit (no CAD host needed)."""

from __future__ import annotations

import json
from typing import Optional

import numpy as np

from ruled.fit.fit2d import FitResult


def report_dict(res: FitResult, *, input_path: str, face: int, method: str = "2d",
                hausdorff: Optional[dict] = None, timings: Optional[dict] = None, version: str = "",
                conversion_slack: float = 0.0) -> dict:
    """The JSON report; error_bound includes the face-to-surface conversion slack."""
    b = res.best
    R = b.surface
    out = {
        "input": input_path,
        "face": face,
        "method": method,
        "result_method": b.method,
        "direction": b.direction,
        "closed": b.closed,
        "samples": res.options.samples,
        "objective": res.options.objective.value,
        "max_error": res.options.max_error,
        "pairs": b.pairs.tolist(),
        "rulings": b.rulings.tolist(),
        "ruling_distance": b.ruling_costs.tolist(),
        "error_bound": b.error_bound + conversion_slack,
        "hausdorff": hausdorff,
        "result": {
            "degree": [R.degree_u, R.degree_v],
            "poles": [int(R.poles.shape[0]), int(R.poles.shape[1])],
            "periodic_u": R.periodic_u,
            "boundary_fit_error": b.boundary_fit_error,
            "max_refined_ruling_distance": float(np.max(b.refined[2])),
        },
        "certificate": {"bound": b.certificate.bound, "conversion_slack": conversion_slack,
                        "node_max": b.certificate.node_max, "remainder": b.certificate.remainder,
                        "grid": list(b.certificate.nodes),
                        # the rails compacted (ruled.fit.rails.compact_fit): how far that moved the bound, and
                        # the poles per rail before it
                        "compaction": b.certificate.compaction, "compacted_from": b.certificate.compacted_from},
        "candidates": {d: (c if isinstance(c, str) else {"error_bound": c.error_bound, "closed": c.closed})
                       for d, c in res.candidates.items()},
        "timings": {**{f"{d}.{k}": v for d, c in res.candidates.items() if not isinstance(c, str)
                       for k, v in c.timings.items()}, **(timings or {})},
        "version": version,
        "notes": list(res.notes),
    }
    if res.patch is not None:
        out["region"] = region_report(res)
    if method == "4d":
        fit4 = b if b.method == "4d" else (res.other if res.other is not None and res.other.method == "4d" else None)
        out["elevation"] = {"levels": fit4.lift["levels"] if fit4 is not None else res.options.elevations,
                            "step": fit4.lift["step"] if fit4 is not None else None,
                            "metric": res.options.metric.value,
                            "end_elevations": None if b.elevations is None else b.elevations.tolist(),
                            "details": None if fit4 is None else {k: v for k, v in fit4.lift.items()
                                                                  if k not in ("levels", "step", "metric",
                                                                               "refined_lifts")}}
        out["comparison"] = {f.method: {"measured_sampled": f.measured, "error_bound": f.error_bound,
                                        "poles": list(f.surface.poles.shape[:2])}
                             for f in (b, res.other) if f is not None}
    return out


def region_report(res: FitResult) -> dict:
    """The face as fitted: whether it is trimmed, its sides (loop edge indices, as 'ruled faces --edges'
    lists them), the rails, and the deviation of its patch (in the bound)."""
    p = res.patch
    ra, rb = p.rails(res.direction)
    d = {"trimmed": not p.identity, "own": p.own, "box": p.box, "how": p.how, "edges": p.region.size,
         "holes": len(p.region.holes),
         "rails": [list(ra), list(rb)], "patch_deviation": p.deviation, "edge_gap": p.edge_gap,
         "hole_span": p.hole_span, "patch_spans": list(p.spans), "face_size": p.face_size}
    if p.sides is not None:
        d["sides"] = [list(p.sides.edges(i)) for i in range(4)]
    if p.fold is not None:
        d["fold"] = {"axis": "uv"[p.fold[0]], "lines": [p.fold[1], p.fold[2]]}
    return d


def _plain(o):
    """numpy scalars and arrays as JSON values."""
    if isinstance(o, np.generic):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    raise TypeError(f"{type(o).__name__} is not JSON serializable")


def write_report(d: dict, path: str) -> None:
    from ruled.core.outputs import write_text
    write_text(path, json.dumps(d, indent=1, default=_plain))


def plot(res: FitResult, path: str, measured: Optional[float] = None) -> None:
    """Pairing function (DP path and fitted reparametrization, as Elber's Fig. 5) and error per ruling;
    ``measured`` (the independent Hausdorff distance) is drawn beside the certified bound."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    b = res.best
    n = res.options.samples
    h = 1.0 / (n if b.closed else n - 1)
    ab = b.pairs[:, :2] * h
    s = np.linspace(0, 1, 400)
    a, bb = b.pairing.ab(s)
    lifted = b.elevations is not None
    fig, axes = plt.subplots(1, 3 if lifted else 2, figsize=(16 if lifted else 11, 5))
    ax1, ax2 = axes[0], axes[1]
    ax1.plot(ab[:, 0], ab[:, 1], color="0.6", lw=4, label="DP path (samples)")
    ax1.plot(a, bb, "k-", lw=1.2, label="fitted reparametrization")
    ax1.plot([0, 1], [0, 1], ":", color="0.3", lw=0.8, label="iso-parametric")
    ax1.set_xlabel("normalized parameter on first boundary")
    ax1.set_ylabel("normalized parameter on second boundary")
    ax1.set_aspect("equal")
    ax1.set_title(f"pairing ({'closed, ' if b.closed else ''}rulings along {b.direction})")
    ax1.legend(loc="best", fontsize=8)
    sig, _, rc = b.refined
    ax2.plot(np.arange(len(b.ruling_costs)), b.ruling_costs, ".-", color="0.5", label="DP rulings")
    ax2.plot((sig - sig[0]) * (len(b.ruling_costs) - 1), rc, "k-", lw=1, label="refined rulings")
    ax2.axhline(b.error_bound, color="r", ls="--", lw=1, label=f"certified bound {b.error_bound:.4g}")
    if measured is not None:
        ax2.axhline(measured, color="g", ls=":", lw=1.2, label=f"measured Hausdorff {measured:.4g}")
    ax2.set_xlabel("ruling index along the path")
    ax2.set_ylabel("line–surface distance")
    ax2.set_title("error per ruling" + (" (4d: move cost)" if lifted else ""))
    ax2.legend(loc="best", fontsize=8)
    if lifted:
        ax3 = axes[2]
        idx = np.arange(len(b.elevations))
        ax3.step(idx, b.elevations[:, 0], where="mid", color="C0", alpha=0.5, label="DP, first boundary end (P)")
        ax3.step(idx, b.elevations[:, 1], where="mid", color="C1", alpha=0.5, label="DP, second boundary end (Q)")
        if b.lift.get("refined_lifts") is not None:
            sg, eA, eB = b.lift["refined_lifts"]
            x = (sg - sg[0]) * (len(idx) - 1)
            ax3.plot(x, eA, color="C0", lw=1.4, label="refined, P end")
            ax3.plot(x, eB, color="C1", lw=1.4, label="refined, Q end")
        ax3.axhline(0.0, color="0.3", lw=0.8, ls=":")
        ax3.set_xlabel("ruling index along the path")
        ax3.set_ylabel("elevation along the surface normal")
        ax3.set_title(f"elevations ({2 * b.lift['levels'] + 1} levels of {b.lift['step']:.3g})")
        ax3.legend(loc="best", fontsize=8)
    fig.tight_layout()
    from ruled.core.outputs import atomic
    with atomic(path) as tmp:
        fig.savefig(tmp, dpi=110)
    plt.close(fig)
