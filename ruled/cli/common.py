"""What every command shares: refusing bad outputs before any work, the progress bar, the files written."""

from __future__ import annotations

import os
import sys

from ruled.core.errors import RuledError, in_terms, names_from

# the engine's options in the command line's terms (see ruled.core.errors): --key-with-dashes, but for these
CLI_NAMES = names_from({"lift_step": "--lift-step", "arc_step": "--arc-step",
                        "fit_first": "run 'ruled fit' first, or 'ruled cone --fit'",
                        "keep_creases": "pass --allow-creases to keep the creases",
                        "split_elevations": "--elevations",
                        "edges_listing": "'ruled faces INPUT --edges'", "fit_help": "'ruled fit --help'",
                        "partition": "ruled fit --tol T"},
                       lambda key: "--" + key.replace("_", "-"), " ", ("True",))


def cli_text(message) -> str:
    """An engine error, warning or note as the command line says it."""
    return in_terms(message, CLI_NAMES)


_FLAGS: dict = {}     # command -> {flag: its metavar}


def _flags(command: str) -> dict:
    """The options of a command of the command line, each with the metavar its help shows."""
    if command not in _FLAGS:
        import argparse

        from ruled.cli.parser import build_parser
        sub = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
        _FLAGS[command] = {s: (a.metavar or a.dest.upper()) for a in sub.choices[command]._actions
                           for s in a.option_strings if a.nargs != 0}
    return _FLAGS[command]


def batch_text(message, face) -> str:
    """An engine message in a batch's summary: the options 'ruled batch' takes by their flags; one it does
    not take (--rails, say) as the 'ruled fit' command of that face, which does."""
    own, fit = _flags("batch"), _flags("fit")

    def name(key, value):
        n = CLI_NAMES(key, value)
        flag = n.split()[0]
        if not flag.startswith("--") or flag in own or flag not in fit:
            return n
        return f"'ruled fit INPUT --face {face} {n if value is not None else f'{flag} {fit[flag]}'}'"
    return in_terms(message, name)


def print_files(output: str, others) -> None:
    """The files written: the STEP output, then each (label, path) given."""
    print(f"STEP:   {os.path.abspath(output)}")
    print_files_only(others)


MAX_MEASURE = 1000      # --measure-samples: n x n OCCT projections each way (1000: about 2 million)


def check_measure_samples(n: int, least: int = 2) -> None:
    """Refuse a measure that cannot be made (too few samples) or would run for hours, with the estimate."""
    if n < least:
        raise RuledError(f"--measure-samples must be at least {least}")
    if n > MAX_MEASURE:
        minutes = 2 * n * n * 60e-6 / 60          # about 60 microseconds per OCCT projection
        raise RuledError(f"--measure-samples {n}: {2 * n * n:,} OCCT projections, about {minutes:,.0f} minutes; "
                         f"use at most {MAX_MEASURE}")


def check_outputs(*paths, inputs=()) -> None:
    """Refuse before any work an output that is an input (however spelled), that another output names too,
    that is a folder or a device, or whose folder does not exist or is not writable."""
    ins = {os.path.realpath(p) for p in inputs if p}
    seen: dict = {}
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


def with_bar(quiet: bool, face_index, work):
    """work(progress) under a progress bar (on a terminal); its warnings printed, one line each."""
    from ruled.core.progress import Bar
    bar = Bar(enabled=not quiet and sys.stderr.isatty())
    try:
        out = work(bar)
    finally:
        bar.done()
    for w in map(cli_text, out.warnings):
        print(f"ruled: warning: {label(face_index)}: {w}", file=sys.stderr)
    return out


def label(face_index) -> str:
    return f"face {face_index}" if isinstance(face_index, int) else str(face_index)


def check_json(c) -> dict:
    return {"valid": c.valid, "sewn_faces": c.sewn_faces, "free_edges": c.sewn_free_edges, "max_gap": c.max_gap,
            "split_edge_to_surface": c.edge_on_surface, "area_sum": c.area_sum, "area_input": c.area_input,
            "area_rel_diff": c.area_rel}


def print_files_only(others) -> None:
    for k, v in others:
        if v:
            print(f"{k}: {' ' * (6 - len(k))}{os.path.abspath(v)}")
