"""ruled faces, ruled fit (one face) and ruled demo."""

from __future__ import annotations

import os
import sys
import time

from ruled import __version__
from ruled.cli.common import check_measure_samples, check_outputs, cli_text, print_files_only, with_bar
from ruled.cli.split import cmd_partition
from ruled.core.errors import RuledError, positive


def cmd_faces(args) -> int:
    from ruled.core.region import four_sides
    from ruled.occ.io import face_info, read_faces
    from ruled.occ.region import edge_lines, face_region, rect_area_ratio
    faces = read_faces(args.input)
    if not faces:
        raise RuledError(f"{args.input}: the file holds no faces")
    for i, face in enumerate(faces):
        info = face_info(i, face)
        extra = ""
        try:
            region = face_region(face)
            ratio = rect_area_ratio(face, region.surface, info.area)
            trim = "untrimmed" if region.is_rectangle() else f"trimmed {100 * ratio:.0f}%"
            extra = f"  {trim}  edges {region.size}  holes {len(region.holes)}"
            sides = four_sides(region) if args.edges and not region.is_rectangle() else None
        except RuledError as exc:
            extra, sides = f"  ({cli_text(exc)})", None
        print(info.line() + extra)
        if args.edges:
            for line in edge_lines(face):
                print(line)
            if sides is not None:
                print("    sides: " + "  ".join(f"{k}: [{','.join(map(str, sides.edges(k))) or 'point'}]"
                                               for k in range(4)) + f"  ({sides.how})")
    if args.walls:
        from ruled.occ.io import read_shape
        from ruled.occ.ring import find_walls
        walls = find_walls(read_shape(args.input))
        if not walls:
            print("walls: none (no ring of faces between two planar caps); give a wall's faces with --wall K,L-M")
        for k, r in enumerate(walls):
            print(f"wall {k}: faces {','.join(map(str, r.faces))}  (bottom contour {len(r.loops[0])} edges, "
                  f"top contour {len(r.loops[1])} edges)")
    return 0


def run_fit(input_path: str, face_index: int, output: str, *, samples=40, objective="sum", max_error=None,
            direction="auto", refine=True, report=None, plot=None, measure_samples=40, quiet=False, method="2d",
            elevations=None, step=None, metric="lsad", memory_cap_mb=None, rails=None, face=None, say=True,
            text=cli_text, face_timeout=None, ends="auto", replace=False) -> dict:
    """The whole job: read, fit, build, measure, write. Returns the report dict.  face: the face, read
    already (the batch's workers keep the files they have read); say: print the warnings and notes
    (the batch keeps them in the reports); text: how the warnings name options (the command's terms);
    face_timeout: seconds the fit and the measure may take (None: no limit; the batch has its own);
    replace: output holds the whole part, the face replaced by its result (ruled.occ.replace)."""
    from ruled.fit.options import FitOptions
    opts = FitOptions(samples=samples, objective=objective, max_error=max_error, direction=direction,
                      refine=refine, method=method, elevations=elevations, step=step, metric=metric,
                      memory_cap=None if memory_cap_mb is None else memory_cap_mb * 2.0 ** 20, ends=ends).checked()
    check_outputs(output, report, plot, inputs=(input_path,))
    check_measure_samples(measure_samples)
    if face_timeout is not None:
        positive("face_timeout", face_timeout, "seconds")
    # the face before the engine: a wrong --face is answered without loading it
    from ruled.occ.io import face_area, get_face, read_shape
    t0 = time.perf_counter()
    part = read_shape(input_path) if replace else None      # (read once: the face from it, then the part)
    face = get_face(input_path, face_index, part) if face is None else face
    t_read = time.perf_counter() - t0
    from ruled.core.progress import Bar, TimeLimit
    from ruled.fit.facefit import first_consistent
    from ruled.fit.report import plot as make_plot
    from ruled.fit.report import write_report
    from ruled.occ.region import fit_face
    bar = Bar(enabled=not quiet and sys.stderr.isatty())
    limit = TimeLimit(face_timeout, bar, f"face {face_index}",
                      "; give it more time («face_timeout»), or fewer «samples»")
    with limit:
        t_fit = time.perf_counter()
        try:
            res, slack = fit_face(face, opts, limit, rails)
        finally:
            bar.done()
        t_fit = time.perf_counter() - t_fit
        area = face_area(face, 1e-6)          # once: each candidate tried is compared with it
        built: dict = {}
        res, rep, more = first_consistent(res, lambda r: _built_and_measured(
            r, slack, face, area, face_index, output, input_path, method, measure_samples, quiet, limit, text,
            {"read": t_read, "fit": t_fit}, built))
        if replace:
            rep["replace"] = _replaced(part if part is not None else read_shape(input_path), face_index,
                                       built["face"], rep["error_bound"], output)
    warnings = [text(w) for w in res.patch.warnings]
    for w in warnings + more if say else ():
        print(f"ruled: warning: face {face_index}: {w}", file=sys.stderr)
    rep["warnings"] = warnings + more
    for note in res.notes if say else ():
        print(f"ruled: {note}", file=sys.stderr)
    if report:
        write_report(rep, report)
    if plot:
        make_plot(res, plot, rep["hausdorff"]["max"])
    return rep


def _built_and_measured(res, slack, face, area, face_index, output, input_path, method, measure_samples, quiet,
                        limit, text, timings, built: dict) -> tuple:
    """The result built, written and measured: (its report, the measure's warnings); area: the face's (OCCT's,
    adaptive).  A result whose figures contradict each other is refused (the STEP removed), naming the face."""
    from ruled.core.errors import FiguresError
    from ruled.fit.facefit import area_ratio, measured_warnings
    from ruled.fit.report import report_dict
    from ruled.occ.io import face_area, write_step
    from ruled.occ.measure import hausdorff
    from ruled.occ.trimmed import built_slack, result_face
    t1 = time.perf_counter()
    out_face = built["face"] = result_face(res)
    slack += built_slack(out_face, res)
    write_step(out_face, output)
    t_write = time.perf_counter() - t1
    t2 = time.perf_counter()
    if not quiet and sys.stderr.isatty():
        print(f"  measuring the Hausdorff distance with OCCT ({measure_samples}x{measure_samples} samples per face)",
              file=sys.stderr)
    limit.stage = "the measure"
    h = hausdorff(face, out_face, measure_samples)
    t_meas = time.perf_counter() - t2
    rep = report_dict(res, input_path=input_path, face=face_index, method=method,
                      hausdorff={"max": h.max, "mean": h.mean, "input_to_result": h.max_a_to_b,
                                 "result_to_input": h.max_b_to_a, "samples": h.samples,
                                 "resolution": h.resolution},
                      timings={**timings, "build_and_write": t_write, "measure": t_meas}, version=__version__,
                      conversion_slack=slack)
    result_area = face_area(out_face, 1e-6)
    rep["area"] = {"face": area, "result": result_area, "ratio": area_ratio(res, area, result_area)}
    if res.best.trim is not None:
        rep["trim"] = {"ends": "trimmed", "trim_eps": res.best.trim.eps, "trim_bound": res.best.trim.added,
                       **(res.patch.extension or {})}
    try:
        more = [text(w) for w in measured_warnings(res, rep["error_bound"], h.max, res.patch.face_size,
                                                   rep["area"]["ratio"])]
    except FiguresError as exc:
        os.unlink(output)              # never a result that contradicts its own figures on disk
        raise FiguresError(f"face {face_index}: {exc.template}") from None
    return rep, more


def _replaced(shape, index: int, face, bound: float, output: str) -> dict:
    """The whole part (shape, as read) written to output, its face ``index`` replaced by the result face and
    sewn; returns the report's ``replace`` section.  A part that cannot be sewn is refused (output removed)."""
    from ruled.occ.io import faces_of, write_step
    from ruled.occ.replace import replaced_part, sewing_tolerance
    t0 = time.perf_counter()
    try:
        part = replaced_part(shape, index, face, sewing_tolerance(bound, faces_of(shape)[index], face))
    except RuledError:
        os.unlink(output)              # the face alone is not what was asked for
        raise
    write_step(part.shape, output)
    return {**part.report(), "seconds": time.perf_counter() - t0}


def _summary(rep: dict, output: str, report=None, plot=None) -> None:
    h = rep["hausdorff"]
    rg = rep.get("region")
    where = f"along {rep['direction']}"
    if rg is not None and rg.get("own"):
        where = "along the iso lines of the face's own surface (it is ruled; the result is trimmed by its edges)"
    elif rg is not None and rg.get("box"):
        where = ("between the iso lines bounding the face's own surface (the face has no four-sided map; the "
                 "result is trimmed by its edges)")
    elif rep.get("trim"):
        where = "crossing the face's end edges (the rails run past the face; the result is trimmed by its edges)"
    elif rg is not None and rg["trimmed"]:
        where = f"between edges {','.join(map(str, rg['rails'][0])) or 'a point'} and " \
                f"{','.join(map(str, rg['rails'][1])) or 'a point'} of the trimmed face"
    print(f"face {rep['face']}: rulings {where}{' (closed)' if rep['closed'] else ''}, "
          f"{len(rep['pairs'])} DP rulings, result {rep['result']['poles'][0]}x{rep['result']['poles'][1]} poles "
          f"degree {rep['result']['degree'][0]}x{rep['result']['degree'][1]}")
    if rep["method"] == "4d":
        e = rep["elevation"]
        if e["step"] is None:
            print("4d: no elevation tried; " + "; ".join(rep["notes"]))
        else:
            print(f"4d: {e['levels'] * 2 + 1} elevation levels of {e['step']:.4g} ({e['metric']}); result from "
                  f"the {rep['result_method']} fit")
    print(f"error bound {rep['error_bound']:.6g}   measured Hausdorff max {h['max']:.6g} mean {h['mean']:.6g}"
          + (f"   area {rep['area']['ratio']:.4g} x the face's" if rep.get("area", {}).get("ratio") else ""))
    if rep.get("replace"):
        r = rep["replace"]
        print(f"part:   face {r['face']} replaced, sewn within {r['sewing_tolerance']:.3g}: {r['faces']} faces, "
              + ("a valid closed solid" if r["closed_solid"] else f"{r['free_edges']} free edges as before"))
    print(f"STEP:   {os.path.abspath(output)}")
    if report:
        print(f"report: {os.path.abspath(report)}")
    if plot:
        print(f"plot:   {os.path.abspath(plot)}")


def cmd_fit(args) -> int:
    check_measure_samples(args.measure_samples)
    if args.wall is not None:
        return cmd_fit_wall(args)
    if args.per_face:
        raise RuledError("--per-face cuts a wall's result into its faces' pieces: give --wall, or drop --per-face")
    if args.tol is not None:
        if args.replace and (args.ends == "pinned" or args.split_faces or args.method != "2d"):
            raise RuledError("--replace puts one ruled face back into the part, and --tol with --ends pinned, "
                             "--split-faces or --method 4d makes strips; drop one of them")
        if args.ends != "pinned" and not args.split_faces and args.method == "2d":
            # the whole face first: with its rails past the face, one ruled face may hold the tolerance
            positive("tol", args.tol)
            rep = run_fit(args.input, args.face, args.output, samples=args.samples, objective=args.objective,
                          direction=args.direction, refine=not args.no_refine, report=args.report,
                          measure_samples=args.measure_samples, quiet=args.quiet, rails=args.rails,
                          face_timeout=args.face_timeout, ends=args.ends, say=False, replace=args.replace)
            if rep["error_bound"] <= args.tol and rep["hausdorff"]["max"] <= args.tol:
                print(f"face {args.face}: one ruled face within {args.tol:.6g}: no strips needed")
                _summary(rep, args.output, args.report)
                return 0
            if args.replace:
                os.unlink(args.output)
                raise RuledError(f"--replace puts one ruled face back into the part, and face {args.face}'s best is "
                                 f"{max(rep['error_bound'], rep['hausdorff']['max']):.4g} from it (bound or measure), "
                                 f"above --tol {args.tol:.4g}; drop --replace to write its strips, or raise --tol")
        return cmd_partition(args)
    if args.split_faces:
        raise RuledError("--split-faces needs --tol (the partition); for one split use 'ruled split'")
    rep = run_fit(args.input, args.face, args.output, samples=args.samples, objective=args.objective,
                  max_error=args.max_error, direction=args.direction, refine=not args.no_refine,
                  report=args.report, plot=args.plot, measure_samples=args.measure_samples, quiet=args.quiet,
                  method=args.method, elevations=args.elevations, step=args.step, metric=args.metric,
                  memory_cap_mb=args.memory_cap, rails=args.rails, face_timeout=args.face_timeout,
                  ends=args.ends, replace=args.replace)
    _summary(rep, args.output, args.report, args.plot)
    return 0


def run_wall(input_path: str, wall_spec, output: str, *, samples=40, objective="sum", max_error=None,
             refine=True, method="2d", elevations=None, step=None, metric="lsad", memory_cap_mb=None,
             report=None, measure_samples=40, quiet=False, shape=None, per_face=False) -> dict:
    """A wall's whole job (read, join, fit, measure, write): the report dict.  wall_spec: 'auto', 'K,L-M' or
    a list of face indices; samples: per face; shape: the part, read already; per_face: write the result
    in one piece per input face, sewn (ruled.occ.wallfaces), each measured against its face."""
    from dataclasses import replace

    from ruled.fit.options import FitOptions
    from ruled.fit.report import write_report
    from ruled.occ.io import read_shape, write_step
    from ruled.occ.wall import fit_wall, wall_of
    opts = FitOptions(samples=samples, objective=objective, max_error=max_error, refine=refine, method=method,
                      elevations=elevations, step=step, metric=metric,
                      memory_cap=None if memory_cap_mb is None else memory_cap_mb * 2.0 ** 20).checked()
    check_outputs(output, report, None, inputs=(input_path,))
    check_measure_samples(measure_samples)
    t0 = time.perf_counter()
    wall = wall_of(read_shape(input_path) if shape is None else shape, wall_spec)
    # samples per face: the ring's grow with its faces
    opts = replace(opts, samples=samples * len(wall.faces)).checked()
    wf = with_bar(quiet, "the wall", lambda bar: fit_wall(wall, opts, bar, measure_samples=measure_samples))
    rep = {**wf.report(), "input": input_path, "samples": opts.samples, "version": __version__}
    if per_face:
        from ruled.occ.measure import hausdorff
        from ruled.occ.wallfaces import per_face as pieces_of
        pieces, shell = pieces_of(wf)
        kept = [(wall.ring.faces[k], wall.faces[k]) for k in wall.ring.kept]
        rep["per_face"] = [{"face": i, "measured": hausdorff(f, p, measure_samples).max}
                           for (i, f), p in zip(kept, pieces)]
        write_step(shell, output)
    else:
        write_step(wf.face, output)
    rep["seconds"] = time.perf_counter() - t0
    if report:
        write_report(rep, report)
    return rep


def cmd_fit_wall(args) -> int:
    """ruled fit INPUT --wall auto|K,L-M: the wall as one closed ruled surface (STEP, report)."""
    for flag, given in (("--tol", args.tol is not None), ("--replace", args.replace), ("--rails", args.rails),
                        ("--split-faces", args.split_faces), ("--plot", args.plot)):
        if given:
            raise RuledError(f"{flag} is for one face; a wall (--wall) is fitted whole: drop {flag}")
    rep = run_wall(args.input, args.wall, args.output, samples=args.samples, objective=args.objective,
                   max_error=args.max_error, refine=not args.no_refine, method=args.method,
                   elevations=args.elevations, step=args.step, metric=args.metric, memory_cap_mb=args.memory_cap,
                   report=args.report, measure_samples=args.measure_samples, quiet=args.quiet,
                   per_face=args.per_face)
    h = rep["hausdorff"]
    cut = (f", fitted in {rep['pieces']} pieces between the corners both contours share (C0 rulings there)"
           if rep["pieces"] > 1 else ", fitted from the one corner both contours share round to it (a C0 ruling "
           "there)" if rep["corners"] else ", one periodic fit (its rulings cross the faces' joints)")
    print(f"wall: faces {','.join(map(str, rep['faces']))} as one closed ruled surface, "
          f"{rep['result']['poles'][0]}x{rep['result']['poles'][1]} poles degree "
          f"{rep['result']['degree'][0]}x{rep['result']['degree'][1]}{cut}")
    print(f"error bound {rep['error_bound']:.6g}   measured Hausdorff max {h['max']:.6g} mean {h['mean']:.6g} "
          f"(against the wall's faces, both ways)")
    if rep.get("per_face"):
        print(f"per face: {len(rep['per_face'])} pieces sewn into one shell, each against its face: "
              + ", ".join(f"face {p['face']} {p['measured']:.3g}" for p in rep["per_face"]))
    print_files_only((("STEP", args.output), ("report", args.report)))
    return 0


def cmd_demo(args) -> int:
    from ruled.examples import elber_ex2
    from ruled.occ.convert import container_to_face
    from ruled.occ.io import write_step

    out = os.path.abspath("ruled-demo")
    os.makedirs(out, exist_ok=True)
    src = os.path.join(out, "input.step")
    write_step(container_to_face(elber_ex2()), src)
    print(f"demo: Elber's B-spline example (ex2) written to {src}; fitting face 0 with 40 samples")
    paths = {k: os.path.join(out, n) for k, n in (("o", "result.step"), ("r", "report.json"), ("p", "plot.png"))}
    rep = run_fit(src, 0, paths["o"], samples=40, report=paths["r"], plot=paths["p"], quiet=args.quiet)
    _summary(rep, paths["o"], paths["r"], paths["p"])
    # the result as machine data: synchronized XYUV contours for a 4-axis wire
    from ruled.machine.output import plot_path, write_machine
    from ruled.machine.paths import MachineOptions
    from ruled.occ.io import get_face
    from ruled.occ.machine import machine_of_face
    fm = with_bar(args.quiet, 0, lambda bar: machine_of_face(get_face(paths["o"], 0), MachineOptions(),
                                                               progress=bar, measure_samples=20, given=True))
    files = {k: os.path.join(out, n) for k, n in (("g", "wire.ngc"), ("c", "wire.csv"), ("p", "wire.png"))}
    write_machine(fm.path, files["g"], "Ruled demo: the ruled fit of Elber's ex2", files["c"])
    plot_path(fm.path, files["p"], "Ruled demo: XYUV contours of the ruled fit")
    m, c = fm.report["machine"], fm.report["cut"]
    print(f"XYUV: {m['sync_points']} synchronized pairs within {m['chord_tol']:.3g} of the ruled surface "
          f"(measured {c['max']:.3g}), largest taper {m['max_taper_deg']:.3g} deg")
    print_files_only((("G-code", files["g"]), ("CSV", files["c"]), ("plot", files["p"])))
    return 0
