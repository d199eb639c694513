"""ruled cone."""

from __future__ import annotations

import os
import time

from ruled import __version__
from ruled.cli.common import check_measure_samples, check_outputs, print_files, with_bar


def run_cone(input_path: str, face_index: int, output: str, *, tol: float, step: float = 0.1, fit: bool = False,
             direction: str = "auto", paper_search: bool = False, allow_creases: bool = False, report=None,
             plot=None, measure_samples=24, quiet=False) -> dict:
    """Read a face, build its cone spline, sew and write the patches, measure them with OCCT."""
    from ruled.cone.report import cone_report
    from ruled.cone.report import plot as cone_plot
    from ruled.fit.report import write_report
    from ruled.occ.conespline import check_tolerance, cone_of_face
    from ruled.occ.io import get_face, write_step

    tol = check_tolerance(tol)
    check_measure_samples(measure_samples, 4)
    check_outputs(output, report, plot, inputs=(input_path,))
    t0 = time.perf_counter()
    face = get_face(input_path, face_index)
    fc = with_bar(quiet, face_index, lambda bar: cone_of_face(
        face, tol, step, direction=direction, fit=fit, progress=bar, measure_samples=measure_samples,
        search="paper" if paper_search else "longest", allow_creases=allow_creases))
    t1 = time.perf_counter()
    write_step([fc.shell], output)
    rep = {"version": __version__, "input": os.path.abspath(input_path), "face": face_index,
           **cone_report(fc.result), "measure": fc.measure,
           "hausdorff": fc.measure["hausdorff"] if fc.measure else None,
           "fit": None if fc.fit is None else {"error_bound": fc.fit.error_bound, "direction": fc.fit.direction},
           "timings": {"total": time.perf_counter() - t0, **fc.timings, "write": time.perf_counter() - t1},
           "warnings": fc.warnings}
    if plot:
        cone_plot(fc.result, plot)
    if report:
        write_report(rep, report)
    return rep


def cmd_cone(args) -> int:
    rep = run_cone(args.input, args.face, args.output, tol=args.tol, step=args.step, fit=args.fit,
                   direction=args.direction, paper_search=args.paper_search, allow_creases=args.allow_creases,
                   report=args.report, plot=args.plot,
                   measure_samples=args.measure_samples, quiet=args.quiet)
    kinds = sorted({p["kind"] for p in rep["patch_detail"]})
    print(f"face {rep['face']}: {rep['patches']} {'/'.join(kinds)} patches in {len(rep['pieces'])} piece(s), "
          f"all developable: {rep['all_developable']}, largest G1 angle {rep['max_g1_angle_deg']:.2g} deg"
          + (f" inside a piece; the pieces meet at creases of up to {rep['max_crease_between_pieces_deg']:.3g} deg"
             if len(rep["pieces"]) > 1 else ""))
    m = rep["measure"]
    meas = "" if m is None else (f"   measured: design to cone {m['design_to_cone']:.6g}, cone to ruled surface "
                                 f"{m['cone_to_ruled']:.6g}")
    print(f"error bound (eq. 9) {rep['error_bound']:.6g} (tolerance {rep['tol']:.6g}){meas}")
    print_files(args.output, (("report", args.report), ("plot", args.plot)))
    print(f"to cut it: ruled machine {args.output} --face all --ruled --xyuv -o "
          f"{os.path.splitext(args.output)[0]}.ngc (all its patches as one wire path, the taper of each)")
    return 0
