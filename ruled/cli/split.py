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
                        fit=FitOptions.of(samples=fit_samples, objective=objective).checked(),
                        max_strips=getattr(args, "max_strips", 16), dims=getattr(args, "dims", 4),
                        levels=getattr(args, "elevations", None) or 2, step=getattr(args, "split_step", None),
                        memory_cap=None if args.memory_cap is None else args.memory_cap * 2.0 ** 20).checked()


def run_split(args) -> dict:
    """Read a face, split it (optimal, best iso, middle), build, fit, measure, write."""
    from ruled.fit.report import write_report
    from ruled.jobs.split import split_job
    from ruled.occ.io import get_face, write_step
    from ruled.split.report import plot_split, split_report

    check_measure_samples(args.measure_samples, 4)
    args.split_samples, args.split_objective, args.split_step = args.samples, args.objective, args.step
    opts = _split_options(args, args.fit_samples)
    check_outputs(args.output, args.report, args.plot, args.split_faces, inputs=(args.input,))
    t0 = time.perf_counter()
    face = get_face(args.input, args.face)
    job = with_bar(args.quiet, args.face, lambda bar: _Warned(split_job(face, opts, bar, args.measure_samples)))
    fs, whole = job.split, job.whole
    # the split's fits, or, where not splitting is better, the face's own fit (and the face itself unsplit)
    write_step(fs.fits[fs.chosen] if job.kept else [whole.face], args.output)
    if args.split_faces:
        write_step(fs.faces[fs.chosen].faces if job.kept else [face], args.split_faces)
    rep = {"version": __version__, "input": os.path.abspath(args.input), "face": args.face, "dims": args.dims,
           "samples": opts.samples, "interior": opts.interior, "objective": opts.objective,
           **split_report(fs.result, fs.measured, fs.chosen, fs.edge_bounds()),
           "checks": {k: check_json(c) for k, c in fs.checks.items()},
           "surface_deviation": fs.deviation, "split_bound": job.bound, "kept": job.kept,
           "face_fit": {"error_bound": whole.bound, "measured": whole.measured, "trimmed": whole.trimmed}}
    if not job.kept:
        rep["verdict"] = job.verdict
    rep["timings"] = {**fs.timings, "total": time.perf_counter() - t0}
    if args.plot:
        plot_split(fs.result, args.plot, fs.measured)
    if args.report:
        write_report(rep, args.report)
    return rep


class _Warned:
    """A split job with the warnings of its split (what with_bar prints)."""

    def __init__(self, job):
        self.job, self.warnings = job, job.split.warnings

    def __getattr__(self, name):
        return getattr(self.job, name)


def cmd_split(args) -> int:
    rep = run_split(args)
    f, dev = rep["face_fit"], rep["surface_deviation"]
    print(f"face {rep['face']}: its fit ('ruled fit'), error bound {f['error_bound']:.6g}"
          f"{' (trimmed by its edges)' if f['trimmed'] else ''}; one ruled strip of the surface split, "
          f"{rep['whole']['error_bound'] + dev:.6g}; split along {'v' if rep['direction'] == 'u' else 'u'} "
          f"(rulings along {rep['direction']}):")
    for name, c in rep["candidates"].items():
        mark = "  <- chosen" if name == rep["chosen"] else ""
        print(f"  {name:9s} error bound {c['error_bound'] + dev:.6g}   measured Hausdorff {c['hausdorff']:.6g}{mark}")
    if not rep["kept"]:
        print(f"{rep['verdict']}: written unsplit")
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
