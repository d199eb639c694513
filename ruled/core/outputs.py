"""Outputs written whole or not at all: every file (STEP, JSON, CSV, PNG, G-code, APT, summaries) is
written under a temporary name in its own folder and renamed onto its name when complete, so a killed
process never leaves a truncated file, an existing output is replaced only as a whole, and two
processes writing the same output never interleave (each writes its own temporary file)."""

from __future__ import annotations

import contextlib
import errno
import os
import threading

from ruled.core.errors import RuledError

_WHY = {errno.ENOSPC: "the disk is full; free some space or write elsewhere",
        errno.EDQUOT: "the disk quota is used up; free some space or write elsewhere",
        errno.EFBIG: "the file would be larger than this file system allows; write elsewhere",
        errno.EROFS: "the file system is read-only; write elsewhere",
        errno.EACCES: "permission denied; write to a folder you own",
        errno.EPERM: "permission denied; write to a folder you own",
        errno.EIO: "the disk reported an input/output error; check it, or write elsewhere"}


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
    except BaseException as exc:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        if isinstance(exc, OSError) and exc.errno in _WHY:
            raise RuledError(f"cannot write {path}: {_WHY[exc.errno]}") from None
        raise


def write_text(path: str, text: str) -> None:
    with atomic(path) as tmp, open(tmp, "w") as fh:
        fh.write(text)


MAX_MEASURE = 1000      # --measure-samples: n x n OCCT projections each way (1000: about 2 million)


def check_measure_samples(n: int, least: int = 2) -> None:
    """Refuse a measure that cannot be made (too few samples) or would run for hours, with the estimate."""
    if n < least:
        raise RuledError(f"«measure_samples» must be at least {least}")
    if n > MAX_MEASURE:
        minutes = 2 * n * n * 60e-6 / 60          # about 60 microseconds per OCCT projection
        raise RuledError(f"«measure_samples={n}»: {2 * n * n:,} OCCT projections, about {minutes:,.0f} minutes; "
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
