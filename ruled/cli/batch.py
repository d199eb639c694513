"""ruled batch: every selected face of many files, on a process pool or a Dask cluster."""

from __future__ import annotations

import os
import sys

from ruled.batch.batch import run_batch
from ruled.cli.common import batch_text, check_measure_samples


def options_dict(args) -> dict:
    return {"samples": args.samples, "objective": args.objective, "max_error": args.max_error,
            "direction": args.direction, "method": args.method, "measure_samples": args.measure_samples,
            "plots": not args.no_plots, **({"walls": True} if args.walls else {}),
            **({"post": args.post} if args.post else {})}


def main_batch(args) -> int:
    from ruled.core.progress import Bar
    from ruled.fit.options import FitOptions
    FitOptions(samples=args.samples, objective=args.objective, max_error=args.max_error, direction=args.direction,
               method=args.method).checked()
    check_measure_samples(args.measure_samples)
    if args.post:           # (a post that cannot be written is refused before any face is fitted)
        from ruled.machine.program import PostSettings
        PostSettings(post=args.post).resolved("xyuv")
    bar = Bar(enabled=not args.quiet and sys.stderr.isatty())
    try:
        out = run_batch(args.inputs, args.output, faces=args.faces, fraction=args.candidate_fraction,
                        options=options_dict(args), jobs=args.jobs, scheduler=args.scheduler, resume=args.resume,
                        face_timeout=args.face_timeout, memory_cap_mb=args.memory_cap, progress=bar,
                        text=batch_text)
    finally:
        bar.done()
    from ruled.batch.batch import NO_WALL
    bare = sorted(r["file"] for r in out["rows"] if r["face"] == NO_WALL)
    rows = [r for r in out["rows"] if r["face"] != NO_WALL]
    n = {s: sum(r["status"] == s for r in rows) for s in ("ok", "refused", "failed")}
    what = "walls" if args.walls else "faces"
    print(f"{len(rows)} of {out['total'] - len(bare)} {what}: {n['ok']} fitted, {n['refused']} refused, "
          f"{n['failed']} failed" + (f"; {len(bare)} file{'s' if len(bare) > 1 else ''} with no wall: "
                                     + ", ".join(bare) if bare else ""))
    worst = [r for r in rows if r["status"] == "ok"][:3]
    for r in worst:
        name = r["face"] if args.walls else f"face {r['face']}"
        print(f"  {r['file']} {name}: error bound {r['error_bound']:.6g}, measured {r['hausdorff']:.6g}")
    for k in ("csv", "json", "html"):
        print(f"summary: {os.path.abspath(out['paths'][k])}")
    if out["interrupted"]:
        print("ruled: interrupted; the summary holds the faces that finished (--resume continues)", file=sys.stderr)
        return 130
    return 0
