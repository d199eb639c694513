"""Outputs written whole or not at all: every file (STEP, JSON, CSV, PNG, G-code, APT, summaries) is
written under a temporary name in its own folder and renamed onto its name when complete, so a killed
process never leaves a truncated file, an existing output is replaced only as a whole, and two
processes writing the same output never interleave (each writes its own temporary file)."""

from __future__ import annotations

import contextlib
import os
import threading


@contextlib.contextmanager
def atomic(path: str):
    """Yield a temporary name beside path (same extension); rename it onto path when the block ends
    without an exception, else remove it."""
    folder, base = os.path.split(os.path.abspath(path))
    stem, ext = os.path.splitext(base)
    tmp = os.path.join(folder, f".{stem}.{os.getpid()}-{threading.get_ident()}.part{ext}")
    try:
        yield tmp
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def write_text(path: str, text: str) -> None:
    with atomic(path) as tmp, open(tmp, "w") as fh:
        fh.write(text)
