"""The command line's options: one parser per command, with one-line errors (exit code 2)."""

from __future__ import annotations

import argparse

from ruled import __version__
from ruled.core.errors import RuledError


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors (exit code 2)."""

    def error(self, message):
        self.exit(2, f"ruled: error: {message}; see '{self.prog} --help'\n")


def build_parser() -> argparse.ArgumentParser:
    p = _Parser(prog="ruled", description="Optimal ruled-surface fitting for CAD faces "
                                "(wire EDM, flank milling, hot-wire cutting).")
    p.add_argument("--version", action="version", version=f"ruled {__version__}")
    sub = p.add_subparsers(dest="cmd", required=True, parser_class=_Parser,
                           metavar="{faces,fit,split,curve-on-surface,cone,machine,replay,posts,batch,demo}")
    f = sub.add_parser("faces", help="list the faces of a STEP/BREP file (trimmed or not, edges, sides, holes)")
    f.add_argument("input")
    f.add_argument("--edges", action="store_true",
                   help="also list each face's outer-wire edges (the indices --rails takes) and its four sides")
    f.add_argument("--walls", action="store_true",
                   help="also list the part's walls: rings of faces between two closed contours (the faces "
                        "--wall takes)")
    g = sub.add_parser("fit", help="fit the best ruled surface to one face, or one closed ruled surface to a wall")
    g.add_argument("input", help="STEP (.step/.stp) or BREP (.brep) file")
    what = g.add_mutually_exclusive_group(required=True)
    what.add_argument("--face", type=int, help="face index (0-based, as 'ruled faces' lists)")
    what.add_argument("--wall", metavar="auto|K,L-M",
                      help="a wall: the ring of faces between two closed contours, found (auto) or given by face "
                           "indices ('ruled faces INPUT --walls'), fitted as one closed ruled surface")
    g.add_argument("--per-face", action="store_true",
                   help="--wall: OUTPUT holds the closed ruled surface in one piece per face of the wall (cut along "
                        "the faces' joints), sewn into one shell")
    g.add_argument("--method", choices=["2d", "4d"], default="2d",
                   help="2d: rulings between boundary samples (Elber); 4d: their ends also lifted along the "
                        "surface normal (Wang & Elber), never worse than 2d")
    g.add_argument("--elevations", type=int, default=None,
                   help="4d: elevation levels on each side of the surface (default 10, i.e. 21 levels)")
    g.add_argument("--lift-step", dest="step", type=float, default=None, metavar="TAU",
                   help="4d: elevation step in model units (default: the 2d result's distance / elevations; "
                        "formerly --step)")
    _renamed(g, "--step", "--lift-step", "ruled fit", type=float)
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
    g.add_argument("--ends", choices=["auto", "pinned", "trimmed"], default="auto",
                   help="pinned: the end rulings at the face's corners; trimmed: the rails run past the face and the "
                        "result is trimmed by its edges, so rulings may cross its end edges; auto (default): the "
                        "one with the smaller certified bound")
    g.add_argument("--no-refine", action="store_true", help="keep the DP pairing (no continuous refinement)")
    g.add_argument("-o", "--output", required=True, help="STEP file for the ruled face")
    g.add_argument("--replace", action="store_true",
                   help="OUTPUT holds the whole part, its face --face replaced by the ruled result and sewn to its "
                        "neighbours (refused if the sewn part is no longer closed)")
    g.add_argument("--report", help="JSON report")
    g.add_argument("--plot", help="PNG plot of the pairing and the error per ruling")
    g.add_argument("--measure-samples", type=int, default=40, help="n x n samples per face for the measure")
    g.add_argument("--quiet", action="store_true", help="no progress bars")
    g.add_argument("--face-timeout", type=float, default=600.0,
                   help="seconds the fit and its measure may take before the face is refused (default 600)")
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
    s.add_argument("--lift-step", dest="step", type=float, default=None, metavar="TAU",
                   help="5d/7d: lift per level in model units (default: the one-strip fit's bound / "
                        "(2 elevations + 1); formerly --step)")
    _renamed(s, "--step", "--lift-step", "ruled split", type=float)
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
    k.add_argument("--arc-step", dest="step", type=float, default=0.1, metavar="D",
                   help="first forward step along the boundaries, a fraction of their parameter (default 0.1; "
                        "formerly --step)")
    _renamed(k, "--step", "--arc-step", "ruled cone", type=float)
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
    _replay_parser(sub)
    q = sub.add_parser("posts", help="the posts 'ruled machine --post' takes (the controllers it writes for)")
    q.add_argument("name", nargs="?", help="print this post's file (a TOML to copy and change for your controller)")
    _batch_parser(sub)
    d = sub.add_parser("demo", help="fit a bundled example; files go to ./ruled-demo/")
    d.add_argument("--quiet", action="store_true")
    return p


def _batch_parser(sub) -> None:
    b = sub.add_parser("batch", help="fit every selected face of many files (a process pool or a Dask cluster), "
                       "with a summary (CSV, JSON, HTML)")
    b.add_argument("inputs", nargs="+", metavar="INPUT", help="STEP (.step/.stp) or BREP (.brep) files")
    b.add_argument("--walls", action="store_true",
                   help="fit every wall of each part instead (the rings of faces between two planar caps, each as "
                        "one closed ruled surface, as 'ruled fit --wall'); --samples is then per face of a wall")
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
    b.add_argument("--post", default=None, metavar="NAME|FILE.toml",
                   help="also write each fitted face's (or wall's) XYUV wire file for this post beside its STEP "
                        "(linuxcnc, grbl, iso-wedm, apt-sync or your own .toml; 'ruled posts' lists them)")
    b.add_argument("-o", "--output", required=True, help="output folder: one folder per input file, summary.*")
    b.add_argument("--quiet", action="store_true", help="no progress bar")


def _machine_parser(sub) -> None:
    m = sub.add_parser("machine", help="machine data for the ruled fit of a face: synchronized XYUV contours "
                       "(4-axis wire EDM, hot wire) or flank-milling tool axes")
    m.add_argument("input", help="STEP (.step/.stp) or BREP (.brep) file")
    which = m.add_mutually_exclusive_group(required=True)
    which.add_argument("--face", type=_face_or_patches,
                       help="face index (0-based, as 'ruled faces' lists); with --ruled also all or K,L-M: ruled "
                            "patches that follow one another (the patches 'ruled cone' writes), machined as one")
    which.add_argument("--wall", metavar="auto|K,L-M",
                       help="a part's wall (the ring of faces between two contours, 'ruled faces INPUT --walls'): "
                            "one closed ruled surface, one closed path with a single lead-in and lead-out")
    m.add_argument("--start", type=_point2, default=None, metavar="X,Y",
                   help="--wall: where the loop starts and ends, a point of the bottom contour (default: the middle "
                        "of its longest straight stretch)")
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
    m.add_argument("--positions", choices=["envelope", "offset"], default="envelope",
                   help="flank: the tool's positions fitted so the swept tool's envelope fits the face, its overcut "
                        "held to --gouge-tol (envelope, the default), or each ruling offset by the radius (offset)")
    m.add_argument("--gouge-tol", type=float, default=None,
                   help="flank, envelope: the overcut allowed, the moves between CL points included (default: the "
                        "fit's bound, not below --chord-tol where given, nor 1e-5 of the diagonal)")
    m.add_argument("--side", choices=["outside", "inside"], default=None,
                   help="the side the wire's kerf or the tool is on: of a face, outside is its normal's side "
                        "(the default); of a wall, outside or inside its contour (default: off the material, "
                        "outside a punch, inside a hole)")
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
    m.add_argument("--ends", choices=["auto", "pinned", "trimmed"], default="auto",
                   help="the fit's ends, as 'ruled fit --ends' (default auto: the fit 'ruled fit' returns, the "
                        "smaller certified bound); trimmed: the wire or tool sweeps the rulings that cross the face, "
                        "plane to plane, of the result trimmed by its edges; pinned: the end rulings at the face's "
                        "corners")
    m.add_argument("--rails", type=_rails, default=None, metavar="A,B",
                   help="the two opposite edges the fit's rulings join ('ruled faces INPUT --edges')")
    m.add_argument("-o", "--output", required=True,
                   help="G-code (.ngc) for --xyuv, APT CL data (.apt) for --flank")
    m.add_argument("--csv", help="CSV of the synchronized pairs or CL points (default: OUTPUT with .csv)")
    m.add_argument("--cam-step", dest="step", metavar="CAM.step",
                   help="STEP file for CAM: the ruled result face (formerly --step)")
    _renamed(m, "--step", "--cam-step", "ruled machine")
    m.add_argument("--rulings", action="store_true", help="with --cam-step: the rulings at the sync points as edges")
    m.add_argument("--report", help="JSON report")
    m.add_argument("--plot", help="PNG: the two contours with their synchronisation links")
    m.add_argument("--measure-samples", type=int, default=30, help="n x n samples per face for the measure")
    m.add_argument("--quiet", action="store_true", help="no progress bars")
    post_options(m)


def post_options(m) -> None:
    """How the machine file is written: the post and its settings ('ruled machine', 'ruled batch')."""
    m.add_argument("--post", default=None, metavar="NAME|FILE.toml",
                   help="the controller the file is written for: linuxcnc (the default for --xyuv), grbl, iso-wedm, "
                        "apt-sync, apt (flank), or your own post's .toml ('ruled posts' lists them)")
    m.add_argument("--feed-mode", choices=["g93", "g94"], default=None,
                   help="G-code feeds: g93, inverse time (each move's time from its longer guide at --feed: the "
                        "faster guide runs at the feed asked), or g94, units per minute (default: the post's first)")
    m.add_argument("--wire-power", dest="power", type=float, default=None, metavar="S",
                   help="a hot wire's power: M3 S<power> before the cut, M5 after (default: the post's; none for "
                        "linuxcnc)")
    m.add_argument("--dwell", type=float, default=None,
                   help="seconds the wire heats (G4 P) before the first move (default: the post's)")
    m.add_argument("--letters", default=None, metavar="XYZA",
                   help="the axis letters of lower X, lower Y, upper X, upper Y (default: the post's; grbl: XYZA)")
    m.add_argument("--home", action="store_true", help="home the machine first (the post's homing: $H, G28)")
    m.add_argument("--origin", action="store_true", default=None,
                   help="G92: the wire stands at the path's first point (no move to it; iso-wedm always)")
    m.add_argument("--compensation", type=int, default=None, metavar="D",
                   help="wire EDM: the controller offsets the wire by its D register (G41/G42 D, with the "
                        "uncompensated path; instead of --kerf)")
    m.add_argument("--corner-radius", type=float, default=0.0,
                   help="flank: the tool's corner radius in APT's CUTTER (default 0, a flat end)")


def _replay_parser(sub) -> None:
    r = sub.add_parser("replay", help="read a machine file back (LinuxCNC's interpreter where installed) and measure "
                                      "what it cuts against the part, both ways")
    r.add_argument("file", help="the G-code or APT file ('ruled machine' writes them; a hand-edited one too)")
    r.add_argument("--against", required=True, metavar="PART", help="the part: STEP (.step/.stp) or BREP (.brep)")
    which = r.add_mutually_exclusive_group(required=True)
    which.add_argument("--face", type=int, help="the face the file cuts (0-based, as 'ruled faces' lists)")
    which.add_argument("--wall", metavar="auto|K,L-M", help="the wall the file cuts ('ruled faces PART --walls')")
    r.add_argument("--post", default=None, metavar="NAME|FILE.toml",
                   help="the post the file was written for (default: the one its Ruled comments name, else guessed)")
    r.add_argument("--reader", choices=["auto", "linuxcnc", "ruled"], default="auto",
                   help="auto: LinuxCNC's own interpreter for a LinuxCNC file where it is installed, else Ruled's "
                        "reader for the post")
    r.add_argument("--axis", default=None, help="the machine axis (x, y, z or ax,ay,az) when the file does not say it")
    r.add_argument("--planes", default=None, help="the guide planes' heights a,b when the file does not say them")
    r.add_argument("--kerf", type=float, default=None, help="the wire's kerf (default: the file's)")
    r.add_argument("--side", choices=["outside", "inside"], default=None,
                   help="the side the wire runs on (default: the file's)")
    r.add_argument("--report", help="JSON report (its 'cut' has the keys of 'ruled machine''s)")
    r.add_argument("--plot", help="PNG: the guides' paths and the deviation along the path")
    r.add_argument("--measure-samples", type=int, default=30, help="n x n samples per face for the measure")
    r.add_argument("--quiet", action="store_true", help="no progress bars")


class _Renamed(argparse.Action):
    """An old spelling of an option: it still works for one release, with a deprecation message."""

    def __init__(self, option_strings, dest, new: str = "", command: str = "", **kw):
        self.new, self.command = new, command
        super().__init__(option_strings, dest, **kw)

    def __call__(self, parser, namespace, values, option_string=None):
        import sys
        print(f"ruled: warning: {option_string} of '{self.command}' is now {self.new} (it meant different things "
              f"in different commands); the old spelling goes in the next release", file=sys.stderr)
        setattr(namespace, self.dest, values)


def _renamed(parser, old: str, new: str, command: str, **kw) -> None:
    """old (hidden from --help) as a deprecated spelling of new."""
    parser.add_argument(old, dest="step", action=_Renamed, new=new, command=command, help=argparse.SUPPRESS, **kw)


def _point2(text: str) -> tuple:
    """--start X,Y."""
    try:
        x, y = (float(t) for t in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"--start {text!r}: give a point X,Y of the bottom contour") from None
    return x, y


def _face_or_patches(text: str):
    """--face of 'ruled machine': an index, or (for --ruled) 'all' or indices 'K,L-M' in their order."""
    try:
        return int(text)
    except ValueError:
        pass
    if text == "all":
        return text
    from ruled.core.errors import parse_faces
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


def argv_with_negative_values(argv: list) -> list:
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
