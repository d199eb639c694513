"""ruled machine."""

from __future__ import annotations

import os

from ruled import __version__
from ruled.cli.common import check_measure_samples, check_outputs, cli_text, print_files_only, rails_text, with_bar
from ruled.core.errors import RuledError


def run_machine(args) -> dict:
    """Read a face, fit it, make the machine path, measure it, write the G-code / APT, CSV, STEP."""
    from ruled.fit.options import FitOptions
    from ruled.fit.report import write_report
    from ruled.jobs.machine import machine_job
    from ruled.machine.output import plot_path, write_checked
    from ruled.machine.paths import MachineOptions
    from ruled.occ.io import get_face, write_step
    from ruled.occ.machine import cam_shapes

    planes = None
    if args.planes is not None:
        planes = args.planes.split(",")
    opts = MachineOptions("flank" if args.flank else "xyuv", args.chord_tol, planes, args.axis, args.margin,
                          args.kerf, args.tool_radius, args.taper, args.lead, args.feed, tip=args.tip,
                          positions=args.positions, gouge_tol=args.gouge_tol).checked()
    if args.flank and args.kerf:
        raise RuledError("--kerf is for --xyuv; a flank tool is offset by --tool-radius")
    if args.xyuv and args.tool_radius is not None:
        raise RuledError("--tool-radius is for --flank; a wire is offset by --kerf")
    if args.xyuv and (args.gouge_tol is not None or args.positions != "envelope"):
        raise RuledError("--gouge-tol and --positions are for --flank; a wire cuts its rulings")
    if args.flank and args.gouge_tol is not None and args.positions == "offset":
        raise RuledError("--gouge-tol holds the envelope's positions; --positions offset has none to hold")
    check_measure_samples(args.measure_samples, 4)
    settings = post_settings(args, opts.mode)
    if args.ruled and args.method != "2d":
        raise RuledError("--ruled machines the face as it is; --method chooses a fit: give one of them")
    if args.ruled and args.rails is not None:
        raise RuledError("--ruled machines the face as it is; --rails chooses a fit's rails: give one of them")
    fit_opts = FitOptions(samples=args.samples, method=args.method, ends=args.ends).checked()
    csv_path = args.csv or os.path.splitext(args.output)[0] + ".csv"
    check_outputs(args.output, csv_path, args.step, args.report, args.plot, inputs=(args.input,))
    side = 1.0 if args.side in (None, "outside") else -1.0
    if args.start is not None and args.wall is None:
        raise RuledError("--start places a wall's loop (--wall); a face's path starts at its own end")
    if args.wall is not None:
        fm, what, chosen = _machine_wall(args, opts)
    elif isinstance(args.face, int):
        face = get_face(args.input, args.face)
        fm = with_bar(args.quiet, args.face, lambda bar: machine_job(
            face, opts, fit_opts, bar, args.measure_samples, side, rails=args.rails, given=args.ruled))
        what, chosen = f"face {args.face}", args.face
    else:
        fm, what, chosen = _machine_patches(args, opts, side)
    title = f"{what} of {os.path.basename(args.input)}"
    program = write_checked(fm.path, args.output, settings, args.units, fm.report.get("side"), csv_path)
    if args.step:
        write_step(cam_shapes(fm.face, fm.surface, fm.path.u, args.rulings), args.step)
    rep = {"version": __version__, "input": os.path.abspath(args.input), "face": chosen,
           "output": os.path.abspath(args.output), "csv": os.path.abspath(csv_path), **fm.report, "program": program}
    rep["warnings"] = [cli_text(w) for w in rep.get("warnings", [])]
    if args.plot:
        plot_path(fm.path, args.plot, f"{title}: {opts.mode}", fm.report.get("swept_tool"))
    if args.report:
        write_report(rep, args.report)
    return rep


def post_settings(args, mode: str):
    """The post and its settings from the command line, checked against each other before any work."""
    from ruled.machine.program import PostSettings
    s = PostSettings(post=args.post, feed_mode=args.feed_mode, power=args.power, dwell=args.dwell,
                     letters=args.letters, home=args.home, origin=args.origin, compensation=args.compensation,
                     corner_radius=args.corner_radius)
    post, _ = s.resolved(mode)
    if getattr(args, "kerf", 0) and args.compensation is not None:
        raise RuledError("--compensation lets the controller offset the wire by its D register; --kerf offsets it "
                         "in the path: give one of them")
    if mode == "flank" and any(x not in (None, False) for x in (args.feed_mode, args.power, args.dwell,
                                                                 args.letters, args.compensation)):
        raise RuledError("--feed-mode, --wire-power, --dwell, --letters and --compensation are a wire's; a flank "
                         "path is APT CL data (--post apt)")
    if mode == "xyuv" and args.corner_radius:
        raise RuledError("--corner-radius is a flank tool's (APT's CUTTER); a wire has none")
    return s


def _machine_wall(args, opts):
    """'ruled machine --wall auto|K,L-M': the wall fitted as one closed ruled surface, one closed path."""
    from dataclasses import replace

    from ruled.fit.options import FitOptions
    from ruled.occ.io import read_shape
    from ruled.occ.wall import fit_wall, wall_of
    from ruled.occ.wallmachine import machine_of_wall
    for flag, given in (("--ruled", args.ruled), ("--rails", args.rails is not None)):
        if given:
            raise RuledError(f"{flag} is for one face; a wall (--wall) is fitted whole: drop {flag}")
    wall = wall_of(read_shape(args.input), args.wall)
    fit_opts = replace(FitOptions(samples=args.samples, method=args.method), samples=args.samples * len(wall.faces))

    def work(bar):
        fit = fit_wall(wall, fit_opts.checked(), bar, measure=False)     # (measured with the path it cuts)
        return machine_of_wall(fit, opts, args.side, args.start, args.measure_samples, bar)
    fm = with_bar(args.quiet, "the wall", work)
    what = f"the wall (faces {_face_text(list(wall.ring.faces))})"
    return fm, what, list(wall.ring.faces)


def _machine_patches(args, opts, side):
    """'ruled machine --face all|K,L-M --ruled': the patches joined and machined as one."""
    from ruled.occ.io import read_faces
    from ruled.occ.machine import machine_of_patches
    if not args.ruled:
        raise RuledError(f"--face {_face_text(args.face)} machines several faces as one, which only patches of a "
                         f"ruled result can be (add --ruled); fit the faces one at a time")
    faces = read_faces(args.input)
    idx = list(range(len(faces))) if args.face == "all" else args.face
    bad = [i for i in idx if i >= len(faces)]
    if bad:
        raise RuledError(f"--face {_face_text(args.face)}: {args.input} has {len(faces)} faces (0 to "
                         f"{len(faces) - 1}); see 'ruled faces {args.input}'")
    what = f"face {idx[0]}" if len(idx) == 1 else f"faces {_face_text(idx)}"
    fm = with_bar(args.quiet, what, lambda bar: machine_of_patches(
        [faces[i] for i in idx], [f"face {i}" for i in idx], opts, bar, args.measure_samples, side))
    return fm, what, idx


def _face_text(face) -> str:
    if face == "all":
        return "all"
    runs, start = [], face[0]
    for a, b in zip(face, face[1:] + [None]):
        if b != a + 1:
            runs.append(str(start) if start == a else f"{start}-{a}")
            start = b
    return ",".join(runs)


def cmd_machine(args) -> int:
    rep = run_machine(args)
    m, f = rep["machine"], rep["fit"]
    meas = f" (measured {f['measured']:.6g})" if "measured" in f else ""
    if "wall" in rep:
        w = rep["wall"]
        print(f"wall: faces {_face_text(w['faces'])} as one closed ruled surface ({w['pieces']} "
              f"piece{'s' if w['pieces'] > 1 else ''}), fit bound {f['error_bound']:.6g}{meas}; the loop starts at "
              f"({w['start'][0]:.6g}, {w['start'][1]:.6g}, {w['start'][2]:.6g})")
        if w.get("corners_note"):
            print(f"  {w['corners_note']}")
    elif "patches" in rep:
        print(f"faces {_face_text(rep['face'])}: {len(rep['patches'])} ruled patches machined as one"
              if len(rep["patches"]) > 1 else f"face {rep['face'][0]}: a ruled result, rulings along {f['direction']}")
        for p in rep["patches"]:
            print(f"  {p['face']}: taper {p['taper_min_deg']:.3g} to {p['taper_max_deg']:.3g} deg, twist along the "
                  f"line {p['twist_deg']:.2g} deg")
    elif args.ruled:
        print(f"face {rep['face']}: a ruled result, rulings along {f['direction']}")
    else:
        rg = f.get("region")
        where = rails_text(rg) if rg and rg["trimmed"] else f"along {f['direction']}"
        if m.get("trimmed"):
            where += " (they cross the face's end edges: the result is trimmed by its edges)"
        print(f"face {rep['face']}: ruled fit bound {f['error_bound']:.6g}{meas}, rulings {where}")
    if m["mode"] == "xyuv":
        print(f"XYUV: {m['sync_points']} synchronized points, XY path {m['length_xy']:.6g}, UV path "
              f"{m['length_uv']:.6g}, largest taper {m['max_taper_deg']:.3g} deg, planes at "
              f"{m['plane_heights'][0]:.6g} and {m['plane_heights'][1]:.6g} along "
              f"{tuple(round(x, 6) for x in m['axis'])}")
        if "cut" in rep:
            c = rep["cut"]
            fillet = c.get("inside_corner_fillet") or 0.0
            print(f"what the wire cuts, against {c['against']}: {c['max']:.6g} (bound {c['bound']:.6g}: the fit's "
                  f"{max(c['fit_bound'], c['fit_error']):.6g} + {m['cut_bound_beyond_fit']:.6g}, the chord tolerance"
                  f"{'' if m['cut_bound_beyond_fit'] == m['chord_tol'] else ' and the kerf offset deviation'}"
                  f"{f' + {fillet:.6g}, the round the wire leaves in inside corners' if fillet else ''})")
    else:
        print(f"flank: {m['cl_points']} CL points, tool radius {m['tool_radius']:.6g}"
              f"{', taper %.3g deg' % m['taper_deg'] if m['taper_deg'] else ''}, tool-envelope deviation "
              f"{m['envelope_deviation']:.3g}")
        pos = m.get("positions", {})
        if "after" in pos:
            print(f"tool positions fitted to the face's envelope ({pos['rounds']} rounds, {pos['points']} points): "
                  f"overcut {pos['before']['overcut']:.3g} -> {pos['after']['overcut']:.3g}, undercut "
                  f"{pos['before']['undercut']:.3g} -> {pos['after']['undercut']:.3g}; gouge tolerance "
                  f"{pos['gouge_tol']:.3g}, chord tolerance {m['chord_tol']:.3g}")
        if "tool_envelope" in rep:
            e = rep["tool_envelope"]
            print(f"{'against ' + e['against'].split(' (')[0] + ', ' if 'against' in e else ''}"
                  f"at the CL points: overcut {e['cl_positions']['overcut']:.6g}, undercut "
                  f"{e['cl_positions']['undercut']:.6g}; with the moves between: overcut "
                  f"{e['with_moves']['overcut']:.6g}, undercut {e['with_moves']['undercut']:.6g}")
        if "swept_tool" in rep:
            w = rep["swept_tool"]
            past = f" ({w['unreached']} of its points past the tool's ends)" if w["unreached"] else ""
            print(f"the face against the swept tool: overcut {w['overcut']:.6g}, undercut {w['undercut']:.6g}{past}; "
                  f"the axis turns by at most {w['axis_angle_max_deg']:.3g} degrees from one CL point to the next")
        oc = rep.get("overcut")
        if oc and not oc["agree"]:
            print(f"the two measures' overcuts differ by more than 10 %: the larger, {oc['larger']:.6g}, is the figure")
    pr = rep["program"]
    check = pr.get("check")
    what_file = "G-code" if m["mode"] == "xyuv" and not pr["post"].startswith("apt") else "APT"
    print(f"{what_file} ({pr['post']}): {rep['output']}" + (
        "" if check is None else f"; LinuxCNC's interpreter reads it: {check['moves']} moves" if check["error"] is None
        else f"; LinuxCNC's interpreter REFUSES it at {check['error']}"))
    print_files_only((("CSV", rep["csv"]), ("STEP", args.step), ("report", args.report), ("plot", args.plot)))
    return 0
