"""The fuzz test's rotating seed (tests/batch/test_fuzz.py), without OCCT: the pytest session prints it in
its header."""

from __future__ import annotations

import os

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def commit_seed() -> int:
    """RULED_FUZZ_SEED when set, else the checked-out commit's first eight hex digits as a number."""
    if os.environ.get("RULED_FUZZ_SEED"):
        return int(os.environ["RULED_FUZZ_SEED"])
    import subprocess
    try:
        head = subprocess.run(["git", "rev-parse", "HEAD"], cwd=ROOT, capture_output=True, text=True).stdout.strip()
    except OSError:          # no git: a fixed seed
        head = ""
    return int(head[:8], 16) if head else 0
