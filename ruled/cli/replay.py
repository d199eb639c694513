"""ruled replay (a machine file read back and measured against the part) and ruled posts (the controllers)."""

from __future__ import annotations

import os
import sys

from ruled.cli.common import check_outputs, cli_text, print_files_only


def cmd_replay(args) -> int:
    from ruled.core.progress import Bar
    from ruled.fit.report import write_report
    from ruled.jobs.replay import plot_of, replay_job
    check_outputs(args.report, args.plot, inputs=(args.file, args.against))
    planes = None if args.planes is None else tuple(args.planes.split(","))
    bar = Bar(enabled=not args.quiet and sys.stderr.isatty())
    try:
        rep, plot = replay_job(args.file, args.against, args.face, args.wall, args.post, args.reader, args.axis,
                               planes, args.kerf, args.side, args.measure_samples, bar)
    finally:
        bar.done()
    rep["warnings"] = [cli_text(w) for w in rep["warnings"]]
    if args.plot:
        plot_of(rep, plot, args.plot)
    if args.report:
        write_report(rep, args.report)
    mv, c, m = rep["moves"], rep["cut"], rep["machine"]
    print(f"{os.path.basename(args.file)} ({rep['post']}, read by {rep['reader']}): {mv['points']} points, "
          f"{mv['feed']} feed moves, {mv['rapid']} rapid")
    if m["mode"] == "xyuv":
        sp = m["speeds"]
        print(f"against {rep['against']} of {os.path.basename(args.against)}, {c['against']}: overcut "
              f"{c['overcut']:.6g}, undercut {c['undercut']:.6g} (the face to the cut {c['design_to_cut']:.6g}, the "
              f"cut to the face {c['cut_to_design']:.6g}; {c['samples']} points)")
        speeds = "" if not sp.get("moves_timed") else (
            f"; guides: lower {sp['lower'][0]:.4g} to {sp['lower'][1]:.4g}, upper {sp['upper'][0]:.4g} to "
            f"{sp['upper'][1]:.4g} per minute, the faster {sp['faster'][0]:.4g} to {sp['faster'][1]:.4g}; "
            f"{sp['minutes']:.4g} minutes")
        print(f"largest taper {m['max_taper_deg']:.3g} deg{speeds}")
    else:
        w = rep["swept_tool"]
        print(f"against {rep['against']} of {os.path.basename(args.against)}: the face against the swept tool: "
              f"overcut {w['overcut']:.6g}, undercut {w['undercut']:.6g}; the axis turns at most "
              f"{w['axis_angle_max_deg']:.3g} degrees a move")
    for w in rep["warnings"]:
        print(f"ruled: warning: {w}", file=sys.stderr)
    print_files_only((("report", args.report), ("plot", args.plot)))
    return 0


def cmd_posts(args) -> int:
    from ruled.machine.posts import SHIPPED, load_post
    if args.name:
        post = load_post(args.name, None)
        with open(post.source) as fh:
            print(fh.read(), end="")
        return 0
    print("the posts 'ruled machine --post' takes (your own: a copy of one, changed, given by its path):")
    for name in SHIPPED:
        post = load_post(name, None)
        what = "flank" if post.machine == "flank" else "wire"
        print(f"  {name:9s} {what:5s} {post.extension:7s} {post.description}")
    print("'ruled posts NAME' prints a post's file; docs/posts/ has a page for each")
    return 0
