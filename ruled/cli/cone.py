"""ruled cone."""

from __future__ import annotations

import os
import time

from ruled import __version__
from ruled.cli.common import check_measure_samples, check_outputs, cli_text, print_files, with_bar


def run_cone(input_path: str, face_index: int, output: str, *, tol: float, step: float = 0.1, fit: bool = False,
             direction: str = "auto", paper_search: bool = False, allow_creases: bool = False, report=None,
             plot=None, measure_samples=24, quiet=False) -> dict:
    """Read a face, build its cone spline, sew and write the patches, measure them with OCCT."""
    from ruled.cone.report import cone_report
    from ruled.cone.report import plot as cone_plot
    from ruled.fit.report import write_report
    from ruled.jobs.cone import cone_job
    from ruled.occ.conespline import check_tolerance
    from ruled.occ.io import face_area, get_face, write_step

    tol = check_tolerance(tol)
    check_measure_samples(measure_samples, 4)
    check_outputs(output, report, plot, inputs=(input_path,))
    t0 = time.perf_counter()
    face = get_face(input_path, face_index)
    fc = with_bar(quiet, face_index, lambda bar: cone_job(
        face, tol, step, direction=direction, fit=fit, progress=bar, measure_samples=measure_samples,
        search="paper" if paper_search else "longest", allow_creases=allow_creases))
    t1 = time.perf_counter()
    write_step([fc.shell], output)
    ff = fc.fitted
    rep = {"version": __version__, "input": os.path.abspath(input_path), "face": face_index,
           **cone_report(fc.result), "measure": fc.measure,
           "hausdorff": fc.measure["hausdorff"] if fc.measure else None,
           "fit": None if ff is None else {"error_bound": ff.bound, "measured": ff.measured,
                                           "direction": ff.fit.direction, "trimmed": ff.trimmed},
           "bound": fc.bound,
           "timings": {"total": time.perf_counter() - t0, **fc.timings, "write": time.perf_counter() - t1},
           "warnings": [cli_text(w) for w in fc.warnings]}
    if ff is not None and ff.trimmed:
        a, b = face_area(face, 1e-6), sum(face_area(f, 1e-6) for f in fc.faces)
        rep["area"] = {"face": a, "patches": b, "ratio": b / a if a > 0 else None}
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
    if rep["fit"] is None:
        print(f"error bound (eq. 9) {rep['error_bound']:.6g} (tolerance {rep['tol']:.6g}){meas}")
    else:
        f = rep["fit"]
        both = m is not None and m.get("cone_to_design") is not None
        how = "trimmed by the face's edges, like the patches" if f["trimmed"] else "pinned"
        print(f"error bound {rep['bound']:.6g}: cone (eq. 9) {rep['error_bound']:.6g} + the fit's "
              f"{f['error_bound']:.6g} ({how})"
              + ("" if m is None else f"   measured {m['hausdorff']:.6g} "
                 + ("(the face and the patches, both ways)" if both else "(the face to the patches; the patches to "
                                                                        "the fit's ruled surface)"))
              + (f"   area {rep['area']['ratio']:.4g} x the face's" if rep.get("area") else ""))
    print_files(args.output, (("report", args.report), ("plot", args.plot)))
    print(f"to cut it: ruled machine {args.output} --face all --ruled --xyuv -o "
          f"{os.path.splitext(args.output)[0]}.ngc (all its patches as one wire path, the taper of each)")
    return 0
