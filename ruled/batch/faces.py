"""The faces a batch takes (--faces): a word or indices.  Apart from the batch itself, which reaches the
command line's wording of errors, so that the command line's parser can check --faces without it."""

from __future__ import annotations

from ruled.core.errors import BadInputError


def parse_faces(spec: str) -> object:
    """'all', 'bspline', 'ruled-candidates', or indices 'K,L-M' (a sorted list)."""
    if spec in ("all", "bspline", "ruled-candidates"):
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
        raise BadInputError(f"--faces {spec!r}: use all, bspline, ruled-candidates or indices like 0,3-7") from None
    return sorted(out)
