"""How many faces a CAD file holds, remembered between runs (no CAD host needed to ask).

Reading a STEP file takes OCCT (about a second to load, and the read itself); a wrong ``--face`` on a
file read before is answered from this small cache instead: the count, keyed by the file's real
path, size and modification time (a changed file is read again).  The cache lives in
$XDG_CACHE_HOME/ruled (default ~/.cache/ruled); RULED_NO_CACHE=1 turns it off; any failure to read or
write it is ignored (the file is then simply read).
"""

from __future__ import annotations

import json
import os
from typing import Optional

from ruled.core.errors import BadInputError

_KEEP = 256


def _cache_file() -> Optional[str]:
    if os.environ.get("RULED_NO_CACHE", "") in ("1", "true", "yes"):
        return None
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return os.path.join(base, "ruled", "face-counts.json")


def _key(path: str) -> Optional[str]:
    try:
        st = os.stat(path)
    except OSError:
        return None
    return f"{os.path.realpath(path)}|{st.st_size}|{st.st_mtime_ns}"


def _load(fn: str) -> dict:
    try:
        with open(fn) as fh:
            data = json.load(fh)
        return data if isinstance(data, dict) else {}
    except (OSError, ValueError):
        return {}


def known_count(path: str) -> Optional[int]:
    """The number of faces of the file as last read, or None (not read, changed since, no cache)."""
    fn, key = _cache_file(), _key(path)
    if fn is None or key is None:
        return None
    n = _load(fn).get(key)
    return n if isinstance(n, int) and n >= 0 else None


def remember(path: str, count: int) -> None:
    """Record the file's face count (best effort)."""
    fn, key = _cache_file(), _key(path)
    if fn is None or key is None:
        return
    data = _load(fn)
    real = key.split("|")[0]
    data = {k: v for k, v in data.items() if k.split("|")[0] != real}     # older versions of the file
    data[key] = int(count)
    if len(data) > _KEEP:
        data = dict(list(data.items())[-_KEEP:])
    try:
        os.makedirs(os.path.dirname(fn), exist_ok=True)
        tmp = f"{fn}.{os.getpid()}.tmp"
        with open(tmp, "w") as fh:
            json.dump(data, fh)
        os.replace(tmp, fn)
    except OSError:
        pass


def out_of_range(path: str, index: int, count: int) -> Optional[BadInputError]:
    """The error for a face index the file does not have (None when it has it)."""
    if count == 0:
        return BadInputError(f"{path}: the file holds no faces")
    if index < 0 or index >= count:
        return BadInputError(f"«face={index}» is out of range: {path} has {count} faces (0..{count - 1}); "
                             f"run 'ruled faces {path}' to list them")
    return None


def check_known(path: str, index: int) -> None:
    """Raise the out-of-range error at once when the cache already knows the file has no such face."""
    n = known_count(path)
    if n is not None:
        err = out_of_range(path, index, n)
        if err is not None:
            raise err
