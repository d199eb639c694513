"""The faces a batch takes (--faces): a word or indices.  Apart from the batch itself, which reaches the
command line's wording of errors, so that the command line's parser can check --faces without it."""

from __future__ import annotations

from ruled.core.errors import BadInputError


def parse_faces(spec: str, option: str = "--faces", words: tuple = ("all", "bspline", "ruled-candidates")) -> object:
    """One of words (default 'all', 'bspline', 'ruled-candidates'), or indices 'K,L-M' (a sorted list)."""
    if spec in words:
        return spec
    out: set = set()
    try:
        for part in spec.split(","):
            a, _, b = part.strip().partition("-")
            lo, hi = int(a), int(b) if b else int(a)
            if lo < 0 or hi < lo:
                raise ValueError
            out.update(range(lo, hi + 1))
    except ValueError:
        raise BadInputError(f"{option} {spec!r}: use {', '.join(words)} or indices like 0,3-7") from None
    return sorted(out)
