"""The ``ruled`` command line: one module per command (fit, split, curves, cone, machine; batch in
ruled.batch), the options in parser, what they share in common, and the entry point in main."""

from ruled.cli.main import main

__all__ = ["main"]
