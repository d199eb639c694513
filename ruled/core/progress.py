"""A small text progress bar for the command line (stderr), throttled; a time limit on long work."""

from __future__ import annotations

import sys
import time
from typing import Any, Callable, Optional, TextIO

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


class TimeLimit:
    """A time limit on long work, as a progress callback wrapping another (or None): the work is stopped with
    a TimeLimitError naming the limit and the stage it was in, at its next progress call past the limit, or,
    in the main thread where the platform has SIGALRM, at the limit itself (a stage that reports no progress:
    the signal interrupts it between two Python operations).  Use as a context manager around the work."""

    def __init__(self, seconds: Optional[float], progress: Progress = None, what: str = "the face",
                 advice: str = ""):
        self.seconds, self.progress, self.what, self.advice = seconds, progress, what, advice
        self.stage = "starting"
        self.t0 = time.perf_counter()
        self._old: Any = None

    def __call__(self, stage: str, frac: float) -> None:
        self.stage = stage
        if self.seconds is not None and time.perf_counter() - self.t0 > self.seconds:
            self._stop()
        if self.progress is not None:
            self.progress(stage, frac)

    def _stop(self, *_: Any) -> None:
        from ruled.core.errors import TimeLimitError
        raise TimeLimitError(f"{self.what} ran past its time limit of {self.seconds:g} s (in {self.stage}) and was "
                             f"stopped{self.advice}")

    def __enter__(self) -> "TimeLimit":
        import signal
        import threading
        self.t0 = time.perf_counter()
        if (self.seconds is not None and hasattr(signal, "setitimer")
                and threading.current_thread() is threading.main_thread()):
            self._old = signal.signal(signal.SIGALRM, self._stop)
            signal.setitimer(signal.ITIMER_REAL, self.seconds)
        return self

    def __exit__(self, *exc: Any) -> None:
        if self._old is not None:
            import signal
            signal.setitimer(signal.ITIMER_REAL, 0)
            signal.signal(signal.SIGALRM, self._old)
            self._old = None
