"""The ``ruled`` command line.

    ruled faces INPUT
    ruled fit INPUT --face K [--method 2d|4d] [--samples N] [--objective sum|max]
              [--max-error E] [--direction auto|u|v] [--elevations M] [--step TAU]
              [--metric lsad|sshb] [--memory-cap MB] -o OUTPUT.step [--report R.json] [--plot P.png]
    ruled curve-on-surface INPUT --face K (--uv "u0,v0;u1,v1;..." | --uv-curve CURVE.json)
              [--tol EPS] [--angle DEG] -o OUTPUT.step [--report R.json]
    ruled cone INPUT --face K --tol T [--step D] [--fit] [--direction auto|u|v] [--allow-creases] -o OUTPUT.step
              [--report R.json] [--plot P.png]
    ruled split INPUT --face K [--dims 4|5|7] [--elevations M] [--step TAU] [--samples N] [--interior D]
              [--objective max|sum] -o OUTPUT.step
              [--split-faces FACES.step] [--report R.json] [--plot P.png]
    ruled fit INPUT --face K --tol T [--max-strips N] -o OUTPUT.step [--split-faces FACES.step] [--report R.json]
    ruled machine INPUT --face K (--xyuv [--planes a,b] [--kerf k] | --flank --tool-radius r [--taper deg] [--tip T])
              [--chord-tol t] [--units mm|inch] [--method 2d|4d | --ruled] -o OUTPUT.ngc|.apt [--csv C.csv]
              [--step CAM.step [--rulings]]
              [--report R.json] [--plot P.png]
    ruled batch INPUT... [--faces all|bspline|ruled-candidates|K,L-M] [fit options] [--jobs N]
              [--scheduler tcp://HOST:PORT] [--resume] [--face-timeout S] -o OUTDIR
    ruled demo

Every error a user can cause ends in one line on stderr and exit code 2.
"""

from __future__ import annotations

import signal
import sys

# Ctrl-C while the command line starts: noted, acted on (exit 130, quietly) once main() runs
_SIGINT = []
if (__name__ == "__main__" or (sys.argv and sys.argv[0].replace("\\", "/").split("/")[-1] in ("ruled", "ruled.exe"))) \
        and signal.getsignal(signal.SIGINT) is signal.default_int_handler:
    signal.signal(signal.SIGINT, lambda *_: _SIGINT.append("early"))

import argparse  # noqa: E402
import os  # noqa: E402
import time  # noqa: E402

from . import __version__  # noqa: E402
from .errors import RuledError  # noqa: E402

# the engine's matrices are small: a multi-threaded BLAS only spins (measured: twice the CPU time of
# a fit, and slower); set before numpy loads (the imports above do not load it), in the command
# line's own process only
for _var in ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors (exit code 2)."""

    def error(self, message):
        self.exit(2, f"ruled: error: {message}; see '{self.prog} --help'\n")


def _parser() -> argparse.ArgumentParser:
    p = _Parser(prog="ruled", description="Optimal ruled-surface fitting for CAD faces "
                                "(wire EDM, flank milling, hot-wire cutting).")
    p.add_argument("--version", action="version", version=f"ruled {__version__}")
    sub = p.add_subparsers(dest="cmd", required=True, parser_class=_Parser,
                           metavar="{faces,fit,split,curve-on-surface,cone,machine,batch,demo}")
    f = sub.add_parser("faces", help="list the faces of a STEP/BREP file (trimmed or not, edges, sides, holes)")
    f.add_argument("input")
    f.add_argument("--edges", action="store_true",
                   help="also list each face's outer-wire edges (the indices --rails takes) and its four sides")
    g = sub.add_parser("fit", help="fit the best ruled surface to one face")
    g.add_argument("input", help="STEP (.step/.stp) or BREP (.brep) file")
    g.add_argument("--face", type=int, required=True, help="face index (0-based, as 'ruled faces' lists)")
    g.add_argument("--method", choices=["2d", "4d"], default="2d",
                   help="2d: rulings between boundary samples (Elber); 4d: their ends also lifted along the "
                        "surface normal (Wang & Elber), never worse than 2d")
    g.add_argument("--elevations", type=int, default=None,
                   help="4d: elevation levels on each side of the surface (default 10, i.e. 21 levels)")
    g.add_argument("--step", type=float, default=None,
                   help="4d: elevation step in model units (default: the 2d result's distance / elevations)")
    g.add_argument("--metric", choices=["lsad", "sshb"], default="lsad",
                   help="4d cost: lsad, the line-surface distance of each ruling (default, faster); sshb, the "
                        "certified surface-bilinear bound of each patch")
    g.add_argument("--memory-cap", type=float, default=None,
                   help="refuse tables larger than this many MiB (default: 80%% of the free memory)")
    g.add_argument("--samples", type=int, default=40, help="samples per boundary (default 40)")
    g.add_argument("--objective", choices=["sum", "max"], default="sum",
                   help="sum of ruling distances (Elber) or the largest one (minimax)")
    g.add_argument("--max-error", type=float, default=None, help="forbid rulings farther than this from the face")
    g.add_argument("--direction", choices=["auto", "u", "v"], default="auto",
                   help="which pair of opposite sides the rulings join: v, sides 0 and 2 of the face (the v-min and "
                        "v-max boundaries of an untrimmed face); u, sides 1 and 3; auto: the better")
    g.add_argument("--rails", type=_rails, default=None, metavar="A,B",
                   help="the two opposite edges the rulings join (indices as 'ruled faces INPUT --edges' lists them)")
    g.add_argument("--no-refine", action="store_true", help="keep the DP pairing (no continuous refinement)")
    g.add_argument("-o", "--output", required=True, help="STEP file for the ruled face")
    g.add_argument("--report", help="JSON report")
    g.add_argument("--plot", help="PNG plot of the pairing and the error per ruling")
    g.add_argument("--measure-samples", type=int, default=40, help="n x n samples per face for the measure")
    g.add_argument("--quiet", action="store_true", help="no progress bars")
    g.add_argument("--tol", type=float, default=None,
                   help="partition the face into strips until every strip's ruled fit is within this distance "
                        "(splits at optimal curves, Wang & Elber); OUTPUT.step then holds every strip's fit")
    g.add_argument("--max-strips", type=int, default=16, help="with --tol: refuse beyond this many strips")
    g.add_argument("--split-faces", help="with --tol: STEP file for the strips of the face itself")
    s = sub.add_parser("split", help="the best curve to cut a face in two for ruling (Wang & Elber), the two "
                       "faces and their ruled fits, compared with iso-parametric splits")
    s.add_argument("input", help="STEP (.step/.stp) or BREP (.brep) file")
    s.add_argument("--face", type=int, required=True, help="face index (0-based, as 'ruled faces' lists)")
    s.add_argument("--dims", type=int, choices=[4, 5, 7], default=4,
                   help="split DP dimension: 4 (nothing elevated, default), 5 (M-points lifted along the normal) "
                        "or 7 (P-, Q- and M-points lifted)")
    s.add_argument("--elevations", type=int, default=2,
                   help="5d/7d: lift levels on each side of the surface (default 2, i.e. 5 levels)")
    s.add_argument("--step", type=float, default=None,
                   help="5d/7d: lift per level in model units (default: the one-strip fit's bound / "
                        "(2 elevations + 1))")
    s.add_argument("--samples", type=int, default=30, help="P-, Q- and M-columns of the split DP (default 30)")
    s.add_argument("--interior", type=int, default=10, help="interior M-rows of the split DP (default 10)")
    s.add_argument("--objective", choices=["max", "sum"], default="max",
                   help="split DP objective over the pairs of rulings: the largest (default, as the paper) or "
                        "the sum")
    s.add_argument("--fit-samples", type=int, default=40, help="samples per boundary of each side's fit")
    s.add_argument("--memory-cap", type=float, default=None,
                   help="refuse tables larger than this many MiB (default: 80%% of the free memory)")
    s.add_argument("-o", "--output", required=True, help="STEP file for the ruled fits, one face per side")
    s.add_argument("--split-faces", help="STEP file for the two faces of the split face")
    s.add_argument("--report", help="JSON report")
    s.add_argument("--plot", help="PNG: the split curves over the error map, and the errors compared")
    s.add_argument("--measure-samples", type=int, default=30, help="n x n samples per face for the measure")
    s.add_argument("--quiet", action="store_true", help="no progress bars")
    c = sub.add_parser("curve-on-surface", help="a low-degree curve lying exactly on a face, within a tolerance "
                       "of the image of a (u, v) curve (Yang et al.)")
    c.add_argument("input", help="STEP (.step/.stp) or BREP (.brep) file")
    c.add_argument("--face", type=int, required=True, help="face index (0-based, as 'ruled faces' lists)")
    src = c.add_mutually_exclusive_group(required=True)
    src.add_argument("--uv", help='a polyline in the face\'s (u, v): "u0,v0;u1,v1;..."')
    src.add_argument("--uv-curve", help='JSON B-spline in (u, v): {"degree": p, "knots": [...], "points": '
                     '[[u, v], ...], "weights": [optional]}')
    c.add_argument("--tol", type=float, default=1e-3,
                   help="distance tolerance to the exact image, model units (default 0.001)")
    c.add_argument("--angle", type=float, default=1.0, help="angle tolerance at the joints, degrees (default 1)")
    c.add_argument("--bound", choices=["local", "span"], default="local",
                   help="2D tolerance rule: local (derivative bounds over each piece's box, default) or span "
                        "(the paper's eq. 12 over the whole knot span)")
    c.add_argument("-o", "--output", required=True, help="STEP file for the curve (one edge)")
    c.add_argument("--report", help="JSON report")
    c.add_argument("--measure-samples", type=int, default=2000, help="samples of each curve for the measure")
    c.add_argument("--quiet", action="store_true", help="no progress bars")
    k = sub.add_parser("cone", help="a tangent-smooth cone spline (developable) within a tolerance of a ruled "
                       "face (Yang & Yang)")
    k.add_argument("input", help="STEP (.step/.stp) or BREP (.brep) file")
    k.add_argument("--face", type=int, required=True, help="face index (0-based, as 'ruled faces' lists)")
    k.add_argument("--tol", type=float, required=True, help="distance tolerance, model units")
    k.add_argument("--step", type=float, default=0.1,
                   help="first forward step along the boundaries, a fraction of their parameter (default 0.1)")
    k.add_argument("--fit", action="store_true",
                   help="fit the face by a ruled surface first ('ruled fit' defaults), then cone-spline that")
    k.add_argument("--direction", choices=["auto", "u", "v"], default="auto",
                   help="which parameter runs across the rulings' ends (auto: the linear one)")
    k.add_argument("--allow-creases", action="store_true",
                   help="keep a result whose neighbouring patches are not tangent continuous (strongly twisted "
                        "faces); without it such a face is refused")
    k.add_argument("--paper-search", action="store_true",
                   help="the paper's step search only (shrink by 0.9 until accepted; more patches)")
    k.add_argument("-o", "--output", required=True, help="STEP file for the patches (one sewn shell)")
    k.add_argument("--report", help="JSON report")
    k.add_argument("--plot", help="PNG plot of the fat curve and the fitted fat conic spline")
    k.add_argument("--measure-samples", type=int, default=24, help="n x n samples per face for the measure")
    k.add_argument("--quiet", action="store_true", help="no progress bars")
    _machine_parser(sub)
    _batch_parser(sub)
    d = sub.add_parser("demo", help="fit a bundled example; files go to ./ruled-demo/")
    d.add_argument("--quiet", action="store_true")
    return p


def _batch_parser(sub) -> None:
    b = sub.add_parser("batch", help="fit every selected face of many files (a process pool or a Dask cluster), "
                       "with a summary (CSV, JSON, HTML)")
    b.add_argument("inputs", nargs="+", metavar="INPUT", help="STEP (.step/.stp) or BREP (.brep) files")
    b.add_argument("--faces", default="all",
                   help="all, bspline (the B-spline faces), ruled-candidates (faces whose iso-parametric ruled "
                        "surface is already within --candidate-fraction of their size) or indices K,L-M "
                        "(default all)")
    b.add_argument("--candidate-fraction", type=float, default=0.01,
                   help="--faces ruled-candidates: the fraction of a face's size (default 0.01)")
    b.add_argument("--method", choices=["2d", "4d"], default="2d", help="the fit ('ruled fit --method')")
    b.add_argument("--samples", type=int, default=40, help="samples per boundary (default 40)")
    b.add_argument("--objective", choices=["sum", "max"], default="sum", help="as 'ruled fit --objective'")
    b.add_argument("--max-error", type=float, default=None, help="as 'ruled fit --max-error'")
    b.add_argument("--direction", choices=["auto", "u", "v"], default="auto", help="as 'ruled fit --direction'")
    b.add_argument("--measure-samples", type=int, default=40, help="n x n samples per face for the measure")
    b.add_argument("--no-plots", action="store_true",
                   help="no plot per face (faster on thousands of faces; the summary page then has no thumbnails)")
    b.add_argument("--jobs", type=int, default=None, help="worker processes (default: the number of cores)")
    b.add_argument("--scheduler", default=None, metavar="tcp://HOST:PORT",
                   help="run the faces on this Dask distributed cluster instead (pip install 'ruled[dask]')")
    b.add_argument("--resume", action="store_true",
                   help="skip the faces whose report exists for the same input file, face and options")
    b.add_argument("--face-timeout", type=float, default=600.0,
                   help="seconds a face may take before it is recorded as failed (default 600)")
    b.add_argument("--memory-cap", type=float, default=None,
                   help="MiB for the whole batch, divided among the workers (default: 80%% of the free memory)")
    b.add_argument("-o", "--output", required=True, help="output folder: one folder per input file, summary.*")
    b.add_argument("--quiet", action="store_true", help="no progress bar")


def _machine_parser(sub) -> None:
    m = sub.add_parser("machine", help="machine data for the ruled fit of a face: synchronized XYUV contours "
                       "(4-axis wire EDM, hot wire) or flank-milling tool axes")
    m.add_argument("input", help="STEP (.step/.stp) or BREP (.brep) file")
    m.add_argument("--face", type=_face_or_patches, required=True,
                   help="face index (0-based, as 'ruled faces' lists); with --ruled also all or K,L-M: ruled "
                        "patches that follow one another (the patches 'ruled cone' writes), machined as one")
    kind = m.add_mutually_exclusive_group(required=True)
    kind.add_argument("--xyuv", action="store_true", help="XYUV G-code (lower guide XY, upper guide UV) and CSV")
    kind.add_argument("--flank", action="store_true", help="flank-milling CL data: APT GOTO/x,y,z,i,j,k and CSV")
    m.add_argument("--planes", help="xyuv: the two plane heights a,b along the axis (default: just outside the "
                   "part; write --planes=-5,20 when a starts with a minus)")
    m.add_argument("--axis", default="auto",
                   help="xyuv: the machine axis, normal to the planes: auto (the mean ruling direction, snapped to "
                        "x, y or z within 0.5 degree), x, y, z or ax,ay,az")
    m.add_argument("--margin", type=float, default=None,
                   help="xyuv: default planes this far outside the part (default 2%% of its diagonal)")
    m.add_argument("--kerf", type=float, default=0.0,
                   help="xyuv: wire radius plus spark gap; the wire runs offset by it to the outside (default 0)")
    m.add_argument("--lead", type=float, default=None,
                   help="xyuv: lead-in and lead-out length (default 5%% of the diagonal; 0: none)")
    m.add_argument("--tool-radius", type=float, default=None, help="flank: tool radius (at the tip for --taper)")
    m.add_argument("--taper", type=float, default=0.0, help="flank: half angle of a conical tool, degrees")
    m.add_argument("--tip", choices=["auto", "first", "second"], default="auto",
                   help="flank: the tool tip at the rulings' first or second end (the fit's boundaries), or auto: "
                        "the end lower in z (default)")
    m.add_argument("--side", choices=["outside", "inside"], default="outside",
                   help="the side of the face the wire offset or the tool is on (outside: the face's normal)")
    m.add_argument("--chord-tol", type=float, default=None,
                   help="largest distance between a straight move and the contours (default 1e-4 of the diagonal)")
    m.add_argument("--feed", type=float, default=100.0,
                   help="feed rate, output units per minute (default 100)")
    m.add_argument("--units", choices=["mm", "inch"], default="mm",
                   help="units of the G-code / APT / CSV coordinates (the model's are mm; default mm)")
    m.add_argument("--method", choices=["2d", "4d"], default="2d", help="the ruled fit ('ruled fit --method')")
    m.add_argument("--ruled", action="store_true",
                   help="the face is a ruled result already (from 'ruled fit', 'ruled split', 'ruled fit --tol'): "
                        "use it as it is, no fit")
    m.add_argument("--samples", type=int, default=40, help="samples per boundary of the fit (default 40)")
    m.add_argument("--rails", type=_rails, default=None, metavar="A,B",
                   help="the two opposite edges the fit's rulings join ('ruled faces INPUT --edges')")
    m.add_argument("-o", "--output", required=True,
                   help="G-code (.ngc) for --xyuv, APT CL data (.apt) for --flank")
    m.add_argument("--csv", help="CSV of the synchronized pairs or CL points (default: OUTPUT with .csv)")
    m.add_argument("--step", help="STEP for CAM: the ruled result face")
    m.add_argument("--rulings", action="store_true", help="with --step: the rulings at the sync points as edges")
    m.add_argument("--report", help="JSON report")
    m.add_argument("--plot", help="PNG: the two contours with their synchronisation links")
    m.add_argument("--measure-samples", type=int, default=30, help="n x n samples per face for the measure")
    m.add_argument("--quiet", action="store_true", help="no progress bars")


def _face_or_patches(text: str):
    """--face of 'ruled machine': an index, or (for --ruled) 'all' or indices 'K,L-M' in their order."""
    try:
        return int(text)
    except ValueError:
        pass
    if text == "all":
        return text
    from .batch import parse_faces
    try:
        return parse_faces(text)
    except RuledError:
        raise argparse.ArgumentTypeError(f"--face {text!r}: give a face index, or with --ruled all or indices "
                                         f"like 0-6 (patches that follow one another)") from None


def _rails(text: str) -> tuple:
    try:
        a, b = (int(x) for x in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"--rails {text!r}: give two edge indices as A,B (see 'ruled faces "
                                         f"INPUT --edges')") from None
    return a, b


def _print_files(output: str, others) -> None:
    """The files written: the STEP output, then each (label, path) given."""
    print(f"STEP:   {os.path.abspath(output)}")
    _print_files_only(others)


MAX_MEASURE = 1000      # --measure-samples: n x n OCCT projections each way (1000: about 2 million)


def check_measure_samples(n: int, least: int = 2) -> None:
    """Refuse a measure that cannot be made (too few samples) or would run for hours, with the estimate."""
    if n < least:
        raise RuledError(f"--measure-samples must be at least {least}")
    if n > MAX_MEASURE:
        minutes = 2 * n * n * 60e-6 / 60          # about 60 microseconds per OCCT projection
        raise RuledError(f"--measure-samples {n}: {2 * n * n:,} OCCT projections, about {minutes:,.0f} minutes; "
                         f"use at most {MAX_MEASURE}")


def _argv_with_negative_values(argv: list) -> list:
    """An option followed by a negative number or list (--planes -1.5,1.5) as --planes=-1.5,1.5, which
    argparse would otherwise read as an option."""
    import re
    out, i = [], 0
    while i < len(argv):
        a = argv[i]
        if a.startswith("--") and "=" not in a and i + 1 < len(argv) and re.match(r"^-(\d|\.\d)", argv[i + 1]):
            out.append(f"{a}={argv[i + 1]}")
            i += 2
            continue
        out.append(a)
        i += 1
    return out


def _check_outputs(*paths, inputs=()) -> None:
    """Refuse before any work an output that is an input (however spelled), that another output names too,
    that is a folder or a device, or whose folder does not exist or is not writable."""
    ins = {os.path.realpath(p) for p in inputs if p}
    seen = {}
    for path in paths:
        if not path:
            continue
        real = os.path.realpath(path)
        if real in ins:
            raise RuledError(f"{path} is the input file: writing it would destroy the input; give another file")
        if real in seen:
            raise RuledError(f"{path} is given for two outputs ({seen[real]} and {path}); give each its own file")
        seen[real] = path
        if os.path.isdir(real):
            raise RuledError(f"cannot write {path}: it is a folder; give a file name")
        if os.path.exists(real) and not os.path.isfile(real):
            raise RuledError(f"cannot write {path}: it is not a regular file (a device?); give a file name")
        d = os.path.dirname(real)
        if not os.path.isdir(d):
            raise RuledError(f"cannot write {path}: folder {d} does not exist")
        if not os.access(d, os.W_OK | os.X_OK):
            raise RuledError(f"cannot write {path}: folder {d} is not writable")


def _with_bar(quiet: bool, face_index: int, work):
    """work(progress) under a progress bar (on a terminal); its warnings printed, one line each."""
    from .progress import Bar
    bar = Bar(enabled=not quiet and sys.stderr.isatty())
    try:
        out = work(bar)
    finally:
        bar.done()
    for w in out.warnings:
        print(f"ruled: warning: {_label(face_index)}: {w}", file=sys.stderr)
    return out


def _label(face_index) -> str:
    return f"face {face_index}" if isinstance(face_index, int) else str(face_index)


def cmd_faces(args) -> int:
    from .occ.io import face_info, read_faces
    from .occ.region import edge_lines, face_region, rect_area_ratio
    from .region import four_sides
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
            extra, sides = f"  ({exc})", None
        print(info.line() + extra)
        if args.edges:
            for line in edge_lines(face):
                print(line)
            if sides is not None:
                print("    sides: " + "  ".join(f"{k}: [{','.join(map(str, sides.edges(k))) or 'point'}]"
                                               for k in range(4)) + f"  ({sides.how})")
    return 0


def run_fit(input_path: str, face_index: int, output: str, *, samples=40, objective="sum", max_error=None,
            direction="auto", refine=True, report=None, plot=None, measure_samples=40, quiet=False, method="2d",
            elevations=None, step=None, metric="lsad", memory_cap_mb=None, rails=None, face=None, say=True) -> dict:
    """The whole job: read, fit, build, measure, write. Returns the report dict.  face: the face, read
    already (the batch's workers keep the files they have read); say: print the warnings and notes
    (the batch keeps them in the reports)."""
    from .options import FitOptions
    opts = FitOptions(samples=samples, objective=objective, max_error=max_error, direction=direction,
                      refine=refine, method=method, elevations=elevations, step=step, metric=metric,
                      memory_cap=None if memory_cap_mb is None else memory_cap_mb * 2.0 ** 20).checked()
    _check_outputs(output, report, plot, inputs=(input_path,))
    check_measure_samples(measure_samples)
    # the face before the engine: a wrong --face is answered without loading it
    from .occ.io import face_area, get_face, write_step
    t0 = time.perf_counter()
    face = get_face(input_path, face_index) if face is None else face
    t_read = time.perf_counter() - t0
    from .occ.convert import container_to_face
    from .occ.measure import hausdorff
    from .occ.region import fit_face
    from .progress import Bar
    from .report import plot as make_plot
    from .report import report_dict, write_report
    bar = Bar(enabled=not quiet and sys.stderr.isatty())
    t_fit = time.perf_counter()
    try:
        res, slack = fit_face(face, opts, bar, rails)
    finally:
        bar.done()
    t_fit = time.perf_counter() - t_fit
    warnings = list(res.patch.warnings)
    for w in warnings if say else ():
        print(f"ruled: warning: face {face_index}: {w}", file=sys.stderr)
    t1 = time.perf_counter()
    out_face = container_to_face(res.surface)
    write_step(out_face, output)
    t_write = time.perf_counter() - t1
    t2 = time.perf_counter()
    if not quiet and sys.stderr.isatty():
        print(f"  measuring the Hausdorff distance with OCCT ({measure_samples}x{measure_samples} samples per face)",
              file=sys.stderr)
    h = hausdorff(face, out_face, measure_samples)
    t_meas = time.perf_counter() - t2
    rep = report_dict(res, input_path=input_path, face=face_index, method=method,
                      hausdorff={"max": h.max, "mean": h.mean, "input_to_result": h.max_a_to_b,
                                 "result_to_input": h.max_b_to_a, "samples": h.samples,
                                 "resolution": h.resolution},
                      timings={"read": t_read, "fit": t_fit, "build_and_write": t_write,
                               "measure": t_meas}, version=__version__, conversion_slack=slack)
    rep["area"] = {"face": face_area(face), "result": face_area(out_face)}
    rep["area"]["ratio"] = rep["area"]["result"] / rep["area"]["face"] if rep["area"]["face"] > 0 else None
    rep["warnings"] = warnings
    for note in res.notes if say else ():
        print(f"ruled: {note}", file=sys.stderr)
    if report:
        write_report(rep, report)
    if plot:
        make_plot(res, plot, h.max)
    return rep


def _summary(rep: dict, output: str, report=None, plot=None) -> None:
    h = rep["hausdorff"]
    rg = rep.get("region")
    where = f"along {rep['direction']}"
    if rg is not None and rg["trimmed"]:
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
    print(f"STEP:   {os.path.abspath(output)}")
    if report:
        print(f"report: {os.path.abspath(report)}")
    if plot:
        print(f"plot:   {os.path.abspath(plot)}")


def cmd_fit(args) -> int:
    check_measure_samples(args.measure_samples)
    if args.tol is not None:
        return cmd_partition(args)
    if args.split_faces:
        raise RuledError("--split-faces needs --tol (the partition); for one split use 'ruled split'")
    rep = run_fit(args.input, args.face, args.output, samples=args.samples, objective=args.objective,
                  max_error=args.max_error, direction=args.direction, refine=not args.no_refine,
                  report=args.report, plot=args.plot, measure_samples=args.measure_samples, quiet=args.quiet,
                  method=args.method, elevations=args.elevations, step=args.step, metric=args.metric,
                  memory_cap_mb=args.memory_cap, rails=args.rails)
    _summary(rep, args.output, args.report, args.plot)
    return 0


def _split_options(args, fit_samples: int = 40, objective: str = "sum"):
    from .fit import FitOptions
    from .partition import SplitOptions
    return SplitOptions(samples=getattr(args, "split_samples", None) or 30, interior=getattr(args, "interior", 10),
                        objective=getattr(args, "split_objective", "max"),
                        fit=FitOptions(samples=fit_samples, objective=objective).checked(),
                        max_strips=getattr(args, "max_strips", 16), dims=getattr(args, "dims", 4),
                        levels=getattr(args, "elevations", None) or 2, step=getattr(args, "split_step", None),
                        memory_cap=None if args.memory_cap is None else args.memory_cap * 2.0 ** 20).checked()


def run_split(args) -> dict:
    """Read a face, split it (optimal, best iso, middle), build, fit, measure, write."""
    from .occ.io import get_face, write_step
    from .occ.split import split_of_face
    from .report import write_report
    from .split_report import plot_split, split_report

    check_measure_samples(args.measure_samples, 4)
    args.split_samples, args.split_objective, args.split_step = args.samples, args.objective, args.step
    opts = _split_options(args, args.fit_samples)
    _check_outputs(args.output, args.report, args.plot, args.split_faces, inputs=(args.input,))
    t0 = time.perf_counter()
    face = get_face(args.input, args.face)
    fs = _with_bar(args.quiet, args.face, lambda bar: split_of_face(face, opts, bar, args.measure_samples))
    write_step(fs.fits[fs.chosen], args.output)
    if args.split_faces:
        write_step(fs.faces[fs.chosen].faces, args.split_faces)
    rep = {"version": __version__, "input": os.path.abspath(args.input), "face": args.face, "dims": args.dims,
           "samples": opts.samples, "interior": opts.interior, "objective": opts.objective,
           **split_report(fs.result, fs.measured, fs.chosen, fs.edge_bounds()),
           "checks": {k: _check_json(c) for k, c in fs.checks.items()}}
    rep["timings"] = {**fs.timings, "total": time.perf_counter() - t0}
    if args.plot:
        plot_split(fs.result, args.plot, fs.measured)
    if args.report:
        write_report(rep, args.report)
    return rep


def _check_json(c) -> dict:
    return {"valid": c.valid, "sewn_faces": c.sewn_faces, "free_edges": c.sewn_free_edges, "max_gap": c.max_gap,
            "split_edge_to_surface": c.edge_on_surface, "area_sum": c.area_sum, "area_input": c.area_input,
            "area_rel_diff": c.area_rel}


def cmd_split(args) -> int:
    rep = run_split(args)
    print(f"face {rep['face']}: one ruled strip, error bound {rep['whole']['error_bound']:.6g}; split along "
          f"{'v' if rep['direction'] == 'u' else 'u'} (rulings along {rep['direction']}):")
    for name, c in rep["candidates"].items():
        mark = "  <- chosen" if name == rep["chosen"] else ""
        print(f"  {name:9s} error bound {c['error_bound']:.6g}   measured Hausdorff {c['hausdorff']:.6g}{mark}")
    _print_files(args.output, (("faces", args.split_faces), ("report", args.report), ("plot", args.plot)))
    return 0


def cmd_partition(args) -> int:
    """ruled fit --tol: strips until every ruled fit is within the tolerance."""
    from .occ.io import get_face, write_step
    from .occ.split import edge_bound, partition_of_face
    from .report import write_report
    from .split_report import partition_report

    if args.method != "2d":
        raise RuledError("--tol partitions with 2d fits; drop --method 4d")
    _check_outputs(args.output, args.report, args.split_faces, inputs=(args.input,))
    opts = _split_options(args, args.samples, args.objective)
    t0 = time.perf_counter()
    face = get_face(args.input, args.face)
    fp = _with_bar(args.quiet, args.face, lambda bar: partition_of_face(face, args.tol, opts, bar,
                                                                        args.measure_samples))
    write_step(fp.fits, args.output)
    if args.split_faces:
        write_step(fp.faces.faces, args.split_faces)
    rep = {"version": __version__, "input": os.path.abspath(args.input), "face": args.face,
           **partition_report(fp.partition, fp.measured, edge_bound(fp.faces)), "checks": _check_json(fp.check)}
    rep["tol"], rep["fit_tol"] = args.tol, fp.partition.tol     # the fits aim inside tol by the edges' allowance
    rep["timings"]["total"] = time.perf_counter() - t0
    if args.report:
        write_report(rep, args.report)
    print(f"face {rep['face']}: {rep['strips']} strips within {args.tol:.6g} ({rep['used']}; optimal splitting "
          f"{rep['greedy_strips']}, uniform iso-parametric {rep['uniform_strips'] or '>' + str(opts.max_strips)})")
    print(f"largest error bound {rep['max_error_bound']:.6g}   largest measured Hausdorff {rep['max_hausdorff']:.6g}")
    _print_files(args.output, (("faces", args.split_faces), ("report", args.report)))
    return 0


def _load_domain_curve(uv, uv_curve):
    import json

    from .curve_on_surface import domain_curve_from_json, parse_uv
    if uv is not None:
        return parse_uv(uv), {"kind": "polyline", "text": uv}
    if not os.path.isfile(uv_curve):
        raise RuledError(f"{uv_curve}: no such file; give a JSON curve file")
    try:
        with open(uv_curve) as f:
            d = json.load(f)
    except (OSError, ValueError) as exc:
        raise RuledError(f"{uv_curve}: cannot read it as JSON ({exc})") from None
    return domain_curve_from_json(d), {"kind": "bspline", "file": os.path.abspath(uv_curve)}


def run_curve_on_surface(input_path: str, face_index: int, output: str, *, uv=None, uv_curve=None, tol=1e-3,
                         angle=1.0, bound="local", report=None, measure_samples=2000, quiet=False) -> dict:
    """Read a face, approximate the image of a (u, v) curve by a curve lying on it exactly, build
    the edge (3D curve and pcurve), measure it with OCCT, write STEP. Returns the report dict."""
    from .occ.cos import curve_on_face
    from .occ.io import get_face, write_step
    from .report import write_report

    if measure_samples < 2:
        raise RuledError("--measure-samples must be at least 2")
    _check_outputs(output, report, inputs=(input_path,))
    D, dom = _load_domain_curve(uv, uv_curve)
    t0 = time.perf_counter()
    face = get_face(input_path, face_index)
    fc = _with_bar(quiet, face_index, lambda bar: curve_on_face(face, D, tol, angle, bound=bound, progress=bar,
                                                                 measure_samples=measure_samples))
    t1 = time.perf_counter()
    write_step([fc.edge], output)
    res, m = fc.result, fc.measure
    t_write = time.perf_counter() - t1
    rep = {
        "version": __version__, "input": os.path.abspath(input_path), "face": face_index, "domain_curve": dom,
        "tol": res.tol, "angle_deg": res.angle_deg, "bound_rule": res.bound_rule,
        "segments": res.segments, "segments_after_distance": res.distance_segments, "degree": res.degree,
        "control_points": res.control_points, "closed": res.closed,
        "error_bound": res.error_bound, "hausdorff": m.hausdorff,
        "hausdorff_detail": {"result_to_exact": m.result_to_exact, "exact_to_result": m.exact_to_result,
                             "samples": m.samples, "engine_sampled": fc.engine_hausdorff},
        "max_distance_to_surface": m.on_surface, "max_joint_angle_deg": m.max_joint_angle_deg(res.angle_deg),
        "engine_max_joint_angle_deg": res.max_joint_angle_deg,
        "corners": [{"t": t, "angle_deg": a, "exact_image_angle_deg": e} for t, a, e in m.corners(res.angle_deg)],
        "timings": {"total": time.perf_counter() - t0, **fc.timings, "write": t_write},
        "notes": res.notes, "warnings": fc.warnings,
    }
    for note in res.notes:
        print(f"ruled: {note}", file=sys.stderr)
    if report:
        write_report(rep, report)
    return rep


def cmd_curve_on_surface(args) -> int:
    rep = run_curve_on_surface(args.input, args.face, args.output, uv=args.uv, uv_curve=args.uv_curve, tol=args.tol,
                               angle=args.angle, bound=args.bound, report=args.report,
                               measure_samples=args.measure_samples, quiet=args.quiet)
    print(f"face {rep['face']}: {rep['segments']} segments of degree {rep['degree']} "
          f"({rep['control_points']} control points){' closed' if rep['closed'] else ''}, on the surface to "
          f"{rep['max_distance_to_surface']:.2g}")
    print(f"error bound {rep['error_bound']:.6g} (tolerance {rep['tol']:.6g})   measured Hausdorff to the exact image "
          f"{rep['hausdorff']:.6g}   largest joint angle {rep['max_joint_angle_deg']:.3g} deg")
    print(f"STEP:   {os.path.abspath(args.output)}")
    if args.report:
        print(f"report: {os.path.abspath(args.report)}")
    return 0


def run_cone(input_path: str, face_index: int, output: str, *, tol: float, step: float = 0.1, fit: bool = False,
             direction: str = "auto", paper_search: bool = False, allow_creases: bool = False, report=None,
             plot=None, measure_samples=24, quiet=False) -> dict:
    """Read a face, build its cone spline, sew and write the patches, measure them with OCCT."""
    from .cone_report import cone_report, plot as cone_plot
    from .occ.conespline import check_tolerance, cone_of_face
    from .occ.io import get_face, write_step
    from .report import write_report

    tol = check_tolerance(tol)
    check_measure_samples(measure_samples, 4)
    _check_outputs(output, report, plot, inputs=(input_path,))
    t0 = time.perf_counter()
    face = get_face(input_path, face_index)
    fc = _with_bar(quiet, face_index, lambda bar: cone_of_face(
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
    _print_files(args.output, (("report", args.report), ("plot", args.plot)))
    print(f"to cut it: ruled machine {args.output} --face all --ruled --xyuv -o "
          f"{os.path.splitext(args.output)[0]}.ngc (all its patches as one wire path, the taper of each)")
    return 0


def run_machine(args) -> dict:
    """Read a face, fit it, make the machine path, measure it, write the G-code / APT, CSV, STEP."""
    from .fit import FitOptions
    from .machine import MachineOptions
    from .machine_output import plot_path, write_machine
    from .occ.io import get_face, write_step
    from .occ.machine import cam_shapes, machine_of_face
    from .report import write_report

    planes = None
    if args.planes is not None:
        planes = args.planes.split(",")
    opts = MachineOptions("flank" if args.flank else "xyuv", args.chord_tol, planes, args.axis, args.margin,
                          args.kerf, args.tool_radius, args.taper, args.lead, args.feed, tip=args.tip).checked()
    if args.flank and args.kerf:
        raise RuledError("--kerf is for --xyuv; a flank tool is offset by --tool-radius")
    if args.xyuv and args.tool_radius is not None:
        raise RuledError("--tool-radius is for --flank; a wire is offset by --kerf")
    check_measure_samples(args.measure_samples, 4)
    if args.ruled and args.method != "2d":
        raise RuledError("--ruled machines the face as it is; --method chooses a fit: give one of them")
    if args.ruled and args.rails is not None:
        raise RuledError("--ruled machines the face as it is; --rails chooses a fit's rails: give one of them")
    fit_opts = FitOptions(samples=args.samples, method=args.method).checked()
    csv_path = args.csv or os.path.splitext(args.output)[0] + ".csv"
    _check_outputs(args.output, csv_path, args.step, args.report, args.plot, inputs=(args.input,))
    side = 1.0 if args.side == "outside" else -1.0
    if isinstance(args.face, int):
        face = get_face(args.input, args.face)
        fm = _with_bar(args.quiet, args.face, lambda bar: machine_of_face(
            face, opts, fit_opts, bar, args.measure_samples, side, given=args.ruled, rails=args.rails))
        what, chosen = f"face {args.face}", args.face
    else:
        fm, what, chosen = _machine_patches(args, opts, side)
    title = f"{what} of {os.path.basename(args.input)}"
    write_machine(fm.path, args.output, title, csv_path, args.units)
    if args.step:
        write_step(cam_shapes(fm.face, fm.surface, fm.path.u, args.rulings), args.step)
    rep = {"version": __version__, "input": os.path.abspath(args.input), "face": chosen,
           "output": os.path.abspath(args.output), "csv": os.path.abspath(csv_path), **fm.report}
    if args.plot:
        plot_path(fm.path, args.plot, f"{title}: {opts.mode}")
    if args.report:
        write_report(rep, args.report)
    return rep


def _machine_patches(args, opts, side):
    """'ruled machine --face all|K,L-M --ruled': the patches joined and machined as one."""
    from .occ.io import read_faces
    from .occ.machine import machine_of_patches
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
    fm = _with_bar(args.quiet, what, lambda bar: machine_of_patches(
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
    if "patches" in rep:
        print(f"faces {_face_text(rep['face'])}: {len(rep['patches'])} ruled patches machined as one"
              if len(rep["patches"]) > 1 else f"face {rep['face'][0]}: a ruled result, rulings along {f['direction']}")
        for p in rep["patches"]:
            print(f"  {p['face']}: taper {p['taper_min_deg']:.3g} to {p['taper_max_deg']:.3g} deg, twist along the "
                  f"line {p['twist_deg']:.2g} deg")
    elif args.ruled:
        print(f"face {rep['face']}: a ruled result, rulings along {f['direction']}")
    else:
        rg = f.get("region")
        where = (f"between edges {','.join(map(str, rg['rails'][0])) or 'a point'} and "
                 f"{','.join(map(str, rg['rails'][1])) or 'a point'}" if rg and rg["trimmed"]
                 else f"along {f['direction']}")
        print(f"face {rep['face']}: ruled fit bound {f['error_bound']:.6g}{meas}, rulings {where}")
    if m["mode"] == "xyuv":
        print(f"XYUV: {m['sync_points']} synchronized points, XY path {m['length_xy']:.6g}, UV path "
              f"{m['length_uv']:.6g}, largest taper {m['max_taper_deg']:.3g} deg, planes at "
              f"{m['plane_heights'][0]:.6g} and {m['plane_heights'][1]:.6g} along "
              f"{tuple(round(x, 6) for x in m['axis'])}")
        if "cut" in rep:
            c = rep["cut"]
            print(f"what the wire cuts, against {c['against']}: {c['max']:.6g} (bound {c['bound']:.6g}: the fit's "
                  f"{c['fit_error']:.6g} + {m['cut_bound_beyond_fit']:.6g}, the chord tolerance"
                  f"{'' if m['cut_bound_beyond_fit'] == m['chord_tol'] else ' and the kerf offset deviation'})")
    else:
        print(f"flank: {m['cl_points']} CL points, tool radius {m['tool_radius']:.6g}"
              f"{', taper %.3g deg' % m['taper_deg'] if m['taper_deg'] else ''}, tool-envelope deviation "
              f"{m['envelope_deviation']:.3g}")
        if "tool_envelope" in rep:
            e = rep["tool_envelope"]
            print(f"at the CL points: overcut {e['cl_positions']['overcut']:.6g}, undercut "
                  f"{e['cl_positions']['undercut']:.6g}; with the moves between: overcut "
                  f"{e['with_moves']['overcut']:.6g}, undercut {e['with_moves']['undercut']:.6g}")
    print(f"{'G-code' if m['mode'] == 'xyuv' else 'APT'}: {rep['output']}")
    _print_files_only((("CSV", rep["csv"]), ("STEP", args.step), ("report", args.report), ("plot", args.plot)))
    return 0


def _print_files_only(others) -> None:
    for k, v in others:
        if v:
            print(f"{k}: {' ' * (6 - len(k))}{os.path.abspath(v)}")


def cmd_demo(args) -> int:
    from .examples import elber_ex2
    from .occ.convert import container_to_face
    from .occ.io import write_step

    out = os.path.abspath("ruled-demo")
    os.makedirs(out, exist_ok=True)
    src = os.path.join(out, "input.step")
    write_step(container_to_face(elber_ex2()), src)
    print(f"demo: Elber's B-spline example (ex2) written to {src}; fitting face 0 with 40 samples")
    paths = {k: os.path.join(out, n) for k, n in (("o", "result.step"), ("r", "report.json"), ("p", "plot.png"))}
    rep = run_fit(src, 0, paths["o"], samples=40, report=paths["r"], plot=paths["p"], quiet=args.quiet)
    _summary(rep, paths["o"], paths["r"], paths["p"])
    # the result as machine data: synchronized XYUV contours for a 4-axis wire
    from .machine import MachineOptions
    from .machine_output import plot_path, write_machine
    from .occ.io import get_face
    from .occ.machine import machine_of_face
    fm = _with_bar(args.quiet, 0, lambda bar: machine_of_face(get_face(paths["o"], 0), MachineOptions(),
                                                               progress=bar, measure_samples=20, given=True))
    files = {k: os.path.join(out, n) for k, n in (("g", "wire.ngc"), ("c", "wire.csv"), ("p", "wire.png"))}
    write_machine(fm.path, files["g"], "Ruled demo: the ruled fit of Elber's ex2", files["c"])
    plot_path(fm.path, files["p"], "Ruled demo: XYUV contours of the ruled fit")
    m, c = fm.report["machine"], fm.report["cut"]
    print(f"XYUV: {m['sync_points']} synchronized pairs within {m['chord_tol']:.3g} of the ruled surface "
          f"(measured {c['max']:.3g}), largest taper {m['max_taper_deg']:.3g} deg")
    _print_files_only((("G-code", files["g"]), ("CSV", files["c"]), ("plot", files["p"])))
    return 0


def cmd_batch(args) -> int:
    from .batch import main_batch
    return main_batch(args)


def main(argv=None) -> int:
    """The command line: exit 0 on success (and when the reader of the output closes the pipe early),
    2 on any error a user can cause (one line), 130 on Ctrl-C at any moment, quietly."""
    def on_sigint(*_):
        _SIGINT.append("now")
        raise KeyboardInterrupt

    import threading
    before = signal.getsignal(signal.SIGINT)
    ours = threading.current_thread() is threading.main_thread() and before not in (signal.SIG_IGN, None)
    try:
        if ours:
            signal.signal(signal.SIGINT, on_sigint)
        if _SIGINT:
            raise KeyboardInterrupt
        return _main(argv)
    except KeyboardInterrupt:
        return _interrupted()
    except BrokenPipeError:
        # the reader (e.g. `| head -1`) has what it wanted: no traceback, and no second error when
        # Python flushes stdout at exit
        _quietly(lambda: os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno()))
        return 0
    except Exception:
        if _SIGINT:             # an interrupt inside a C extension's import surfaces as another error
            return _interrupted()
        raise
    finally:
        if ours:
            signal.signal(signal.SIGINT, before if before is not None else signal.default_int_handler)


def _interrupted() -> int:
    _quietly(lambda: print("\nruled: interrupted", file=sys.stderr))
    return 130


def _quietly(action) -> None:
    try:
        action()
    except (OSError, KeyboardInterrupt):
        pass


def _main(argv=None) -> int:
    args = _parser().parse_args(_argv_with_negative_values(sys.argv[1:] if argv is None else list(argv)))
    try:
        if isinstance(getattr(args, "face", None), int) and isinstance(getattr(args, "input", None), str):
            from .facecount import check_known     # a file read before: a wrong --face without OCCT
            check_known(args.input, args.face)
        return {"faces": cmd_faces, "fit": cmd_fit, "split": cmd_split, "curve-on-surface": cmd_curve_on_surface,
                "cone": cmd_cone, "machine": cmd_machine, "batch": cmd_batch, "demo": cmd_demo}[args.cmd](args)
    except RuledError as exc:
        print(f"ruled: error: {exc}", file=sys.stderr)
        return 2
    except MemoryError:
        print("ruled: error: out of memory; use fewer --samples", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
