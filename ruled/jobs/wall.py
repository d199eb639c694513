"""A wall's whole job (``ruled fit --wall``, the batch's walls): read the part, find or take the ring of faces,
join it, fit it as one closed ruled surface, measure it against the wall's faces, write the STEP and report."""

from __future__ import annotations

import sys
import time
from typing import Callable, Optional

from ruled import __version__
from ruled.core.outputs import check_measure_samples, check_outputs


def run_wall(input_path: str, wall_spec, output: str, *, samples=40, objective="sum", max_error=None,
             refine=True, method="2d", elevations=None, step=None, metric="lsad", memory_cap_mb=None,
             report=None, measure_samples=40, quiet=False, shape=None, per_face=False,
             text: Callable = str, say: bool = True, after: Optional[Callable] = None) -> dict:
    """A wall's whole job (read, join, fit, measure, write): the report dict.  wall_spec: 'auto', 'K,L-M' or
    a list of face indices; samples: per face; shape: the part, read already; per_face: write the result
    in one piece per input face, sewn (ruled.occ.wallfaces), each measured against its face; text, say: how
    the warnings name options and whether they are printed (as run_fit's)."""
    from dataclasses import replace

    from ruled.core.progress import Bar
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
    bar = Bar(enabled=not quiet and sys.stderr.isatty())
    try:
        wf = fit_wall(wall, opts, bar, measure_samples=measure_samples)
    finally:
        bar.done()
    for w in wf.warnings if say else ():
        print(f"ruled: warning: the wall: {text(w)}", file=sys.stderr)
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
    if after is not None:
        rep.update(after(wf))
    rep["seconds"] = time.perf_counter() - t0
    if report:
        write_report(rep, report)
    return rep


__all__ = ["run_wall"]
