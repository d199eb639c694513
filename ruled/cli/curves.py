"""ruled curve-on-surface."""

from __future__ import annotations

import os
import sys
import time

from ruled import __version__
from ruled.cli.common import check_outputs, with_bar
from ruled.core.errors import RuledError


def _load_domain_curve(uv, uv_curve):
    import json

    from ruled.curves.domain import domain_curve_from_json, parse_uv
    if uv is not None:
        return parse_uv(uv), {"kind": "polyline", "text": uv}
    if not os.path.isfile(uv_curve):
        raise RuledError(f"{uv_curve}: no such file; give a JSON curve file")
    try:
        with open(uv_curve) as f:
            d = json.load(f)
    except (OSError, ValueError) as exc:
        raise RuledError(f"{uv_curve}: cannot read it as JSON ({exc})") from None
    return domain_curve_from_json(d), {"kind": "bspline", "file": os.path.abspath(uv_curve)}


def run_curve_on_surface(input_path: str, face_index: int, output: str, *, uv=None, uv_curve=None, tol=1e-3,
                         angle=1.0, bound="local", report=None, measure_samples=2000, quiet=False) -> dict:
    """Read a face, approximate the image of a (u, v) curve by a curve lying on it exactly, build
    the edge (3D curve and pcurve), measure it with OCCT, write STEP. Returns the report dict."""
    from ruled.fit.report import write_report
    from ruled.occ.cos import curve_on_face
    from ruled.occ.io import get_face, write_step

    if measure_samples < 2:
        raise RuledError("--measure-samples must be at least 2")
    check_outputs(output, report, inputs=(input_path,))
    D, dom = _load_domain_curve(uv, uv_curve)
    t0 = time.perf_counter()
    face = get_face(input_path, face_index)
    fc = with_bar(quiet, face_index, lambda bar: curve_on_face(face, D, tol, angle, bound=bound, progress=bar,
                                                                 measure_samples=measure_samples))
    t1 = time.perf_counter()
    write_step([fc.edge], output)
    res, m = fc.result, fc.measure
    t_write = time.perf_counter() - t1
    rep = {
        "version": __version__, "input": os.path.abspath(input_path), "face": face_index, "domain_curve": dom,
        "tol": res.tol, "angle_deg": res.angle_deg, "bound_rule": res.bound_rule,
        "segments": res.segments, "segments_after_distance": res.distance_segments, "degree": res.degree,
        "control_points": res.control_points, "closed": res.closed,
        "error_bound": res.error_bound, "hausdorff": m.hausdorff,
        "hausdorff_detail": {"result_to_exact": m.result_to_exact, "exact_to_result": m.exact_to_result,
                             "samples": m.samples, "engine_sampled": fc.engine_hausdorff},
        "max_distance_to_surface": m.on_surface, "max_joint_angle_deg": m.max_joint_angle_deg(res.angle_deg),
        "engine_max_joint_angle_deg": res.max_joint_angle_deg,
        "corners": [{"t": t, "angle_deg": a, "exact_image_angle_deg": e} for t, a, e in m.corners(res.angle_deg)],
        "timings": {"total": time.perf_counter() - t0, **fc.timings, "write": t_write},
        "notes": res.notes, "warnings": fc.warnings,
    }
    for note in res.notes:
        print(f"ruled: {note}", file=sys.stderr)
    if report:
        write_report(rep, report)
    return rep


def cmd_curve_on_surface(args) -> int:
    rep = run_curve_on_surface(args.input, args.face, args.output, uv=args.uv, uv_curve=args.uv_curve, tol=args.tol,
                               angle=args.angle, bound=args.bound, report=args.report,
                               measure_samples=args.measure_samples, quiet=args.quiet)
    print(f"face {rep['face']}: {rep['segments']} segments of degree {rep['degree']} "
          f"({rep['control_points']} control points){' closed' if rep['closed'] else ''}, on the surface to "
          f"{rep['max_distance_to_surface']:.2g}")
    print(f"error bound {rep['error_bound']:.6g} (tolerance {rep['tol']:.6g})   measured Hausdorff to the exact image "
          f"{rep['hausdorff']:.6g}   largest joint angle {rep['max_joint_angle_deg']:.3g} deg")
    print(f"STEP:   {os.path.abspath(args.output)}")
    if args.report:
        print(f"report: {os.path.abspath(args.report)}")
    return 0
