"""A small text progress bar for the command line (stderr), throttled."""

from __future__ import annotations

import sys
import time
from typing import Callable, Optional, TextIO

# what the engine's long functions take: progress(stage, fraction in [0, 1]), or None
Progress = Optional[Callable[[str, float], None]]


class Bar:
    def __init__(self, stream: Optional[TextIO] = None, enabled: bool = True, width: int = 28) -> None:
        self.stream = stream or sys.stderr
        self.enabled = enabled
        self.width = width
        self.stage: Optional[str] = None
        self.last = 0.0
        self.t0 = time.perf_counter()

    def __call__(self, stage: str, frac: float) -> None:
        if not self.enabled:
            return
        now = time.perf_counter()
        if stage == self.stage and frac < 1.0 and now - self.last < 0.1:
            return
        if stage != self.stage and self.stage is not None:
            self.stream.write("\n")
        self.stage = stage
        self.last = now
        k = int(round(self.width * min(max(frac, 0.0), 1.0)))
        self.stream.write(f"\r  {stage:<30s} [{'#' * k}{'.' * (self.width - k)}] {100 * frac:5.1f}%")
        self.stream.flush()

    def done(self) -> None:
        if self.enabled and self.stage is not None:
            self.stream.write("\n")
            self.stream.flush()
        self.stage = None
