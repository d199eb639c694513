"""The ``ruled`` command line.

    ruled faces INPUT
    ruled fit INPUT --face K [--method 2d|4d] [--samples N] [--objective sum|max]
              [--max-error E] [--direction auto|u|v] [--elevations M] [--lift-step TAU]
              [--metric lsad|sshb] [--memory-cap MB] -o OUTPUT.step [--report R.json] [--plot P.png]
    ruled curve-on-surface INPUT --face K (--uv "u0,v0;u1,v1;..." | --uv-curve CURVE.json)
              [--tol EPS] [--angle DEG] -o OUTPUT.step [--report R.json]
    ruled cone INPUT --face K --tol T [--arc-step D] [--fit] [--direction auto|u|v] [--allow-creases] -o OUTPUT.step
              [--report R.json] [--plot P.png]
    ruled split INPUT --face K [--dims 4|5|7] [--elevations M] [--lift-step TAU] [--samples N] [--interior D]
              [--objective max|sum] -o OUTPUT.step
              [--split-faces FACES.step] [--report R.json] [--plot P.png]
    ruled fit INPUT --face K --tol T [--max-strips N] -o OUTPUT.step [--split-faces FACES.step] [--report R.json]
    ruled machine INPUT --face K (--xyuv [--planes a,b] [--kerf k] |
              --flank --tool-radius r [--taper deg] [--tip T] [--positions P] [--gouge-tol g])
              [--chord-tol t] [--units mm|inch] [--method 2d|4d | --ruled] -o OUTPUT.ngc|.apt [--csv C.csv]
              [--cam-step CAM.step [--rulings]]
              [--report R.json] [--plot P.png]
              [--post NAME|FILE.toml] [--feed-mode g93|g94] [--wire-power S] [--dwell s] [--letters XYZA]
              [--home] [--origin] [--compensation D] [--corner-radius r]
    ruled replay FILE --against PART (--face K | --wall auto|K,L-M) [--post P] [--reader auto|linuxcnc|ruled]
              [--axis A] [--planes a,b] [--kerf k] [--side S] [--report R.json] [--plot P.png]
    ruled posts [NAME]
    ruled batch INPUT... [--faces all|bspline|ruled-candidates|K,L-M] [fit options] [--jobs N]
              [--scheduler tcp://HOST:PORT] [--resume] [--face-timeout S] -o OUTDIR
    ruled demo

Every error a user can cause ends in one line on stderr and exit code 2.
"""

from __future__ import annotations

import signal
import sys

# Ctrl-C while the command line starts: noted, acted on (exit 130, quietly) once main() runs
_SIGINT: list = []
# (the `ruled` script, or `python -m ruled.cli`, whose package imports run while argv[0] is still "-m")
if (sys.argv and sys.argv[0].replace("\\", "/").split("/")[-1] in ("ruled", "ruled.exe")
        or "ruled.cli" in getattr(sys, "orig_argv", ())[1:3]) \
        and signal.getsignal(signal.SIGINT) is signal.default_int_handler:
    signal.signal(signal.SIGINT, lambda *_: _SIGINT.append("early"))

import os  # noqa: E402

from ruled.cli.common import cli_text  # noqa: E402
from ruled.cli.cone import cmd_cone  # noqa: E402
from ruled.cli.curves import cmd_curve_on_surface  # noqa: E402
from ruled.cli.fit import cmd_demo, cmd_faces, cmd_fit  # noqa: E402
from ruled.cli.machine import cmd_machine  # noqa: E402
from ruled.cli.parser import argv_with_negative_values, build_parser  # noqa: E402
from ruled.cli.replay import cmd_posts, cmd_replay  # noqa: E402
from ruled.cli.split import cmd_split  # noqa: E402
from ruled.core.errors import RuledError  # noqa: E402

# the engine's matrices are small: a multi-threaded BLAS only spins (measured: twice the CPU time of
# a fit, and slower); set before numpy loads (the imports above do not load it), in the command
# line's own process only
for _var in ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")


def cmd_batch(args) -> int:
    from ruled.cli.batch import main_batch
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
        return _interrupted(argv is None)
    except BrokenPipeError:
        # the reader (e.g. `| head -1`) has what it wanted: no traceback, and no second error when
        # Python flushes stdout at exit
        _quietly(lambda: os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno()))
        return 0
    except Exception:
        if _SIGINT:             # an interrupt inside a C extension's import surfaces as another error
            return _interrupted(argv is None)
        raise
    finally:
        if ours:
            signal.signal(signal.SIGINT, before if before is not None else signal.default_int_handler)


def _interrupted(exiting: bool = False) -> int:
    """Exit code 130 after one line.  exiting: the process's own command line ends here, so nothing left
    half-built by the interrupt (numba's compiler, say, mid-initialisation) may print "Exception ignored"
    tracebacks from its finalizers as Python shuts down."""
    _quietly(lambda: print("\nruled: interrupted", file=sys.stderr))
    if exiting:
        sys.unraisablehook = lambda *_: None
    return 130


def _quietly(action) -> None:
    try:
        action()
    except (OSError, KeyboardInterrupt):
        pass


def _main(argv=None) -> int:
    args = build_parser().parse_args(argv_with_negative_values(sys.argv[1:] if argv is None else list(argv)))
    try:
        if isinstance(getattr(args, "face", None), int) and isinstance(getattr(args, "input", None), str):
            from ruled.core.facecount import check_known  # a file read before: a wrong --face without OCCT
            check_known(args.input, args.face)
        return {"faces": cmd_faces, "fit": cmd_fit, "split": cmd_split, "curve-on-surface": cmd_curve_on_surface,
                "cone": cmd_cone, "machine": cmd_machine, "replay": cmd_replay, "posts": cmd_posts, "batch": cmd_batch,
                "demo": cmd_demo}[args.cmd](args)
    except RuledError as exc:
        print(f"ruled: error: {cli_text(exc)}", file=sys.stderr)
        return 2
    except MemoryError:
        print("ruled: error: out of memory; use fewer --samples", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
