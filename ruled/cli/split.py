"""ruled split (one optimal cut) and ruled fit --tol (the partition into strips)."""

from __future__ import annotations

import os
import time

from ruled import __version__
from ruled.cli.common import check_json, check_measure_samples, check_outputs, print_files, with_bar
from ruled.core.errors import RuledError


def _split_options(args, fit_samples: int = 40, objective: str = "sum"):
    from ruled.fit.options import FitOptions
    from ruled.split.partition import SplitOptions
    return SplitOptions(samples=getattr(args, "split_samples", None) or 30, interior=getattr(args, "interior", 10),
                        objective=getattr(args, "split_objective", "max"),
                        fit=FitOptions(samples=fit_samples, objective=objective).checked(),
                        max_strips=getattr(args, "max_strips", 16), dims=getattr(args, "dims", 4),
                        levels=getattr(args, "elevations", None) or 2, step=getattr(args, "split_step", None),
                        memory_cap=None if args.memory_cap is None else args.memory_cap * 2.0 ** 20).checked()


def run_split(args) -> dict:
    """Read a face, split it (optimal, best iso, middle), build, fit, measure, write."""
    from ruled.fit.report import write_report
    from ruled.occ.io import get_face, write_step
    from ruled.occ.split import split_of_face
    from ruled.split.report import plot_split, split_report

    check_measure_samples(args.measure_samples, 4)
    args.split_samples, args.split_objective, args.split_step = args.samples, args.objective, args.step
    opts = _split_options(args, args.fit_samples)
    check_outputs(args.output, args.report, args.plot, args.split_faces, inputs=(args.input,))
    t0 = time.perf_counter()
    face = get_face(args.input, args.face)
    fs = with_bar(args.quiet, args.face, lambda bar: split_of_face(face, opts, bar, args.measure_samples))
    write_step(fs.fits[fs.chosen], args.output)
    if args.split_faces:
        write_step(fs.faces[fs.chosen].faces, args.split_faces)
    rep = {"version": __version__, "input": os.path.abspath(args.input), "face": args.face, "dims": args.dims,
           "samples": opts.samples, "interior": opts.interior, "objective": opts.objective,
           **split_report(fs.result, fs.measured, fs.chosen, fs.edge_bounds()),
           "checks": {k: check_json(c) for k, c in fs.checks.items()}}
    rep["timings"] = {**fs.timings, "total": time.perf_counter() - t0}
    if args.plot:
        plot_split(fs.result, args.plot, fs.measured)
    if args.report:
        write_report(rep, args.report)
    return rep


def cmd_split(args) -> int:
    rep = run_split(args)
    print(f"face {rep['face']}: one ruled strip, error bound {rep['whole']['error_bound']:.6g}; split along "
          f"{'v' if rep['direction'] == 'u' else 'u'} (rulings along {rep['direction']}):")
    for name, c in rep["candidates"].items():
        mark = "  <- chosen" if name == rep["chosen"] else ""
        print(f"  {name:9s} error bound {c['error_bound']:.6g}   measured Hausdorff {c['hausdorff']:.6g}{mark}")
    print_files(args.output, (("faces", args.split_faces), ("report", args.report), ("plot", args.plot)))
    return 0


def cmd_partition(args) -> int:
    """ruled fit --tol: strips until every ruled fit is within the tolerance."""
    from ruled.fit.report import write_report
    from ruled.occ.io import get_face, write_step
    from ruled.occ.split import edge_bound, partition_of_face
    from ruled.split.report import partition_report

    if args.method != "2d":
        raise RuledError("--tol partitions with 2d fits; drop --method 4d")
    check_outputs(args.output, args.report, args.split_faces, inputs=(args.input,))
    opts = _split_options(args, args.samples, args.objective)
    t0 = time.perf_counter()
    face = get_face(args.input, args.face)
    fp = with_bar(args.quiet, args.face, lambda bar: partition_of_face(face, args.tol, opts, bar,
                                                                        args.measure_samples))
    write_step(fp.fits, args.output)
    if args.split_faces:
        write_step(fp.faces.faces, args.split_faces)
    rep = {"version": __version__, "input": os.path.abspath(args.input), "face": args.face,
           **partition_report(fp.partition, fp.measured, edge_bound(fp.faces)), "checks": check_json(fp.check)}
    rep["tol"], rep["fit_tol"] = args.tol, fp.partition.tol     # the fits aim inside tol by the edges' allowance
    rep["timings"]["total"] = time.perf_counter() - t0
    if args.report:
        write_report(rep, args.report)
    print(f"face {rep['face']}: {rep['strips']} strips within {args.tol:.6g} ({rep['used']}; optimal splitting "
          f"{rep['greedy_strips']}, uniform iso-parametric {rep['uniform_strips'] or '>' + str(opts.max_strips)})")
    print(f"largest error bound {rep['max_error_bound']:.6g}   largest measured Hausdorff {rep['max_hausdorff']:.6g}")
    print_files(args.output, (("faces", args.split_faces), ("report", args.report)))
    return 0
