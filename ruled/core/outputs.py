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
