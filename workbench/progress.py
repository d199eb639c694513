"""Progress and cancel of the workbench's computations (no GUI imports: they run in freecadcmd too): the
engine's progress(stage, fraction) on FreeCAD's console indicator headless, on the status bar in the GUI
(workbench.busy), with the engine in a worker thread there so that the window stays usable; a task panel's
Cancel and Esc stop it (workbench.state.request_cancel)."""

from __future__ import annotations

import threading
import time

import FreeCAD

from . import state
from .state import request_cancel  # noqa: F401  (the name the workbench's callers use)


class _Progress:
    """The engine's progress(stage, fraction), one run over the whole computation (each stage a share of it),
    shown on FreeCAD's status bar in the GUI (workbench.busy) or its console progress indicator headless,
    and on the listeners (a task panel's own bar and stage label).  In the GUI the engine runs in a worker
    thread (run) while the main thread keeps processing events, so that the window stays usable: the task
    panel's Cancel (request_cancel) and Esc stop the computation at once (the worker at its next report)."""

    PUMP = 0.03
    STAGES = 8           # about as many stages as a fit reports (the overall bar never goes back)

    def __init__(self, text: str, steps: int = 1000, capability: str = ""):
        state.CANCEL[0] = False
        self.text, self.stage, self.frac, self.steps = text, None, 0.0, steps
        self.stages = -1
        self.shown = 0                      # the percentage shown last (it never goes back)
        self.started = time.perf_counter()  # when the current stage started ...
        self.expected = None                # ... and how long it takes, where known (the first-use stage)
        self.cancelled = False
        self.main = threading.get_ident()
        self.pumped = 0.0
        self.capability = capability        # (ruled.warm.NEEDS: the kernels its first use compiles)
        self.bar = self.display = None
        if FreeCAD.GuiUp:
            from .busy import StatusDisplay
            self.display = StatusDisplay(text)
        else:
            self.done = 0
            self.bar = FreeCAD.Base.ProgressIndicator()
            self.bar.start(text, steps)

    def __call__(self, stage: str, frac: float) -> None:
        from ruled.core.errors import CancelledError
        frac = min(max(float(frac), 0.0), 1.0)
        if stage != self.stage:
            self.stage = stage
            self.stages += 1
            self.started, self.expected = time.perf_counter(), None
        self.frac = frac
        if state.CANCEL[0] or self.cancelled:
            self.cancelled = True
            raise CancelledError("cancelled by the user")
        if threading.get_ident() == self.main:      # (a worker only records it: the main thread shows it)
            self.show()

    def expect(self, seconds: float) -> None:
        """The current stage takes about this long (the kernels' first compile: ruled.warm): its fraction moves
        with the time while its one long step runs."""
        self.started, self.expected = time.perf_counter(), float(seconds)

    def percent(self) -> int:
        """The whole computation's percentage, one figure for every display (the panel's bar, the status bar's
        text and its bar): each stage a share, the current one's fraction (or its time against what it is
        expected to take), never going back, 99 at most until it ends."""
        frac = self.frac
        if self.expected:
            frac = max(frac, min(0.99, (time.perf_counter() - self.started) / self.expected))
        overall = (max(self.stages, 0) + frac) / max(self.STAGES, self.stages + 1)
        self.shown = max(self.shown, min(99, int(100 * overall)))
        return self.shown

    def show(self) -> None:
        """The progress on the bars; in the GUI, pending events processed (at most every PUMP seconds)."""
        from ruled.core.errors import CancelledError
        pct = self.percent()
        overall = pct / 100.0
        if self.bar is not None:
            want = int(overall * self.steps * 0.999)
            while self.done < want:
                self.done += 1
                try:
                    self.bar.next(True)
                except Exception:  # FreeCAD raises when the user aborts
                    raise CancelledError("cancelled by the user") from None
            return
        if time.perf_counter() - self.pumped > self.PUMP:
            self.pumped = time.perf_counter()
            if self.stage is not None:
                self.display.show(self.stage, pct)
                for listener in state.LISTENERS:
                    listener(self.stage, overall)
                state.SHOWN[:] = [self.stage, pct]
            from PySide import QtGui
            QtGui.QApplication.processEvents()
        if state.CANCEL[0]:
            self.cancelled = True
            raise CancelledError("cancelled by the user")

    def run(self, fn, *args, **kwargs):
        """fn(*args, **kwargs), the engine's work on plain arrays (no FreeCAD in it): in the GUI in a worker
        thread, the main thread showing its progress and processing events until it ends; Cancel or Esc end
        the wait at once (the worker stops at its next progress report, its result dropped)."""
        if self.capability:
            self.first_use()
        if self.display is None:
            return fn(*args, **kwargs)
        out: dict = {}

        def work():
            try:
                out["value"] = fn(*args, **kwargs)
            except BaseException as exc:   # handed to the main thread
                out["error"] = exc
        worker = threading.Thread(target=work, name="ruled-engine", daemon=True)
        worker.start()
        while worker.is_alive():
            worker.join(self.PUMP)
            self.show()
        if "error" in out:
            raise out["error"]
        return out["value"]

    def first_use(self) -> None:
        """When numba's cache holds none of the kernels this capability runs (its first use in this
        installation), compile them first, saying so and how long it takes, on the bar and in the report view."""
        from ruled import warm
        todo, self.capability = warm.cold(self.capability), ""
        if todo:
            FreeCAD.Console.PrintMessage(f"Ruled: first use: preparing the fast kernels, once (about "
                                         f"{warm.seconds(todo)} s; later runs load them)\n")
            self.expected = None
            self.run(warm.warm, todo, self)

    def stop(self) -> None:
        if self.bar is not None:
            self.bar.stop()
        if self.display is not None:
            self.display.close()
            self.display = None
