"""What every command shares: refusing bad outputs before any work, the progress bar, the files written."""

from __future__ import annotations

import os
import sys

from ruled.core.errors import in_terms, names_from
from ruled.core.outputs import MAX_MEASURE, check_measure_samples, check_outputs  # noqa: F401 (the commands' checks)

# the engine's options in the command line's terms (see ruled.core.errors): --key-with-dashes, but for these
CLI_NAMES = names_from({"lift_step": "--lift-step", "arc_step": "--arc-step",
                        "fit_first": "run 'ruled fit' first, or 'ruled cone --fit'",
                        "keep_creases": "pass --allow-creases to keep the creases",
                        "split_elevations": "--elevations",
                        "edges_listing": "'ruled faces INPUT --edges'", "fit_help": "'ruled fit --help'",
                        "partition": "ruled fit --tol T",
                        "walls_listing": "pick the ring of faces between the bottom and the top contour (see 'ruled "
                                         "faces INPUT --walls')",
                        "one_face": "--face", "power": "--wire-power"},
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


def rails_text(rg: dict) -> str:
    """Where a face's rulings run, in words, from its region report: between which of its edges (the rails),
    or, for a closed face folded onto one ruled surface (ruled.fit.face.fold), between its fold lines."""
    if rg.get("fold"):
        f = rg["fold"]
        return (f"across the closed face, between its fold lines {f['axis']} = {f['lines'][0]:.4g} and "
                f"{f['lines'][1]:.4g} (both its sides folded onto one ruled surface)")
    return (f"between edges {','.join(map(str, rg['rails'][0])) or 'a point'} and "
            f"{','.join(map(str, rg['rails'][1])) or 'a point'}")

