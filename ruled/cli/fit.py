"""ruled faces, ruled fit (one face) and ruled demo."""

from __future__ import annotations

import os

from ruled.cli.common import check_measure_samples, cli_text, print_files_only, rails_text, with_bar
from ruled.cli.split import cmd_partition
from ruled.core.errors import RuledError, positive


def run_fit(*args, **kw) -> dict:
    """The face's job (ruled.jobs.face.run_fit), its warnings in the command line's terms."""
    from ruled.jobs.face import run_fit as job
    return job(*args, **{"text": cli_text, **kw})


def run_wall(*args, **kw) -> dict:
    """The wall's job (ruled.jobs.wall.run_wall), its warnings in the command line's terms."""
    from ruled.jobs.wall import run_wall as job
    return job(*args, **{"text": cli_text, **kw})


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
            holes = sum(w.role == "hole" for w in walls)
            role = ("outer wall" if r.role == "outer" else
                    f"inner wall, a hole's: --wall {r.name.replace(' ', ':') if holes > 1 else 'hole'}")
            print(f"wall {k}: {r.name}  faces {','.join(map(str, r.faces))}  ({role}; bottom contour {len(r.loops[0])} "
                  f"edges, top contour {len(r.loops[1])} edges)")
    return 0


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
    elif rg is not None and rg.get("fold"):
        where = rails_text(rg)
    elif rg is not None and rg["trimmed"]:
        where = f"{rails_text(rg)} of the trimmed face"
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


def cmd_fit_wall(args) -> int:
    """ruled fit INPUT --wall auto|K,L-M: the wall as one closed ruled surface (STEP, report)."""
    for flag, given in (("--tol", args.tol is not None), ("--replace", args.replace), ("--rails", args.rails),
                        ("--split-faces", args.split_faces), ("--plot", args.plot)):
        if given:
            raise RuledError(f"{flag} is for one face; a wall (--wall) is fitted whole: drop {flag}")
    if args.ends != "auto":
        raise RuledError(f"--ends {args.ends} is for one face: a wall's rulings run round the ring, which has no ends "
                         f"to pin or run past; drop --ends")
    rep = run_wall(args.input, args.wall, args.output, samples=args.samples, objective=args.objective,
                   max_error=args.max_error, refine=not args.no_refine, method=args.method,
                   elevations=args.elevations, step=args.step, metric=args.metric, memory_cap_mb=args.memory_cap,
                   report=args.report, measure_samples=args.measure_samples, quiet=args.quiet,
                   per_face=args.per_face)
    h = rep["hausdorff"]
    across = f"; rulings paired across {rep['crossed_corners']} of them" if rep.get("crossed_corners") else ""
    cut = (f", fitted in {rep['pieces']} pieces between the corners both contours share (C0 rulings there{across})"
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
    """The README's main job on a bundled face: fit it (STEP, report, plot), make the wire's XYUV G-code of the fit
    for the default post (LinuxCNC), check the file with LinuxCNC's own interpreter where it is installed, and
    replay the file against the design face."""
    from ruled.examples import demo_blade
    from ruled.occ.convert import container_to_face
    from ruled.occ.io import write_step

    out = os.path.abspath("ruled-demo")
    os.makedirs(out, exist_ok=True)
    src = os.path.join(out, "input.step")
    write_step(container_to_face(demo_blade()), src)
    print(f"demo: a drafted, bulged blade (a B-spline face 80 x 40 mm, not ruled) written to {src}; fitting face 0 "
          f"with 40 samples")
    paths = {k: os.path.join(out, n) for k, n in (("o", "result.step"), ("r", "report.json"), ("p", "plot.png"))}
    rep = run_fit(src, 0, paths["o"], samples=40, report=paths["r"], plot=paths["p"], quiet=args.quiet)
    _summary(rep, paths["o"], paths["r"], paths["p"])
    # the fit as machine data: synchronized XYUV contours for a 4-axis wire, upright along z
    from ruled.fit.options import FitOptions
    from ruled.jobs.machine import machine_job
    from ruled.jobs.replay import plot_of, replay_job
    from ruled.machine.output import plot_path, write_checked
    from ruled.machine.paths import MachineOptions
    from ruled.occ.io import get_face
    files = {k: os.path.join(out, n) for k, n in (("g", "wire.ngc"), ("c", "wire.csv"), ("p", "wire.png"),
                                                  ("j", "wire.json"), ("q", "replay.png"))}
    fm = with_bar(args.quiet, 0, lambda bar: machine_job(get_face(src, 0), MachineOptions(axis="z"),
                                                         FitOptions(samples=40), bar, 20))
    program = write_checked(fm.path, files["g"], None, "mm", fm.report.get("side"), files["c"])
    plot_path(fm.path, files["p"], "Ruled demo: the XYUV contours of the blade's ruled fit")
    m, c = fm.report["machine"], fm.report["cut"]
    check = program["check"]
    print(f"XYUV ({program['post']}): {m['sync_points']} synchronized pairs within {m['chord_tol']:.3g} of the "
          f"ruled surface, largest taper {m['max_taper_deg']:.3g} deg; "
          + ("LinuxCNC's interpreter is not installed here (Debian: apt-get install linuxcnc-uspace)" if check is None
             else f"LinuxCNC's interpreter reads it: {check['moves']} moves" if check["error"] is None
             else f"LinuxCNC's interpreter REFUSES it at {check['error']}"))
    rp, plot = replay_job(files["g"], src, face=0, measure_samples=20)
    plot_of(rp, plot, files["q"])
    rc = rp["cut"]
    print(f"replayed ({rp['reader']}) against the design face: overcut {rc['overcut']:.4g}, undercut "
          f"{rc['undercut']:.4g} (the machine's own measure: {c['overcut']:.4g}, {c['undercut']:.4g}; the fit's "
          f"bound {c['fit_bound']:.4g} + the chords {m['chord_tol']:.3g})")
    import json
    with open(files["j"], "w") as fh:
        json.dump({"machine": fm.report, "program": program, "replay": rp}, fh, indent=1, default=float)
    print_files_only((("G-code", files["g"]), ("CSV", files["c"]), ("plot", files["p"]), ("report", files["j"]),
                      ("replay", files["q"])))
    return 0 if check is None or check["error"] is None else 2
