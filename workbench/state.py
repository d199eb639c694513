"""What the workbench's modules share while Ruled computes and while a task panel is open, importing none of
them: the objects being computed and the cancel request (a panel's Cancel, Esc), the progress listeners (a
panel's bar), the open task panel, and which panel edits each kind of object (filled by the panel modules
when they load, with the workbench's commands).  The panels, features, view providers and the GUI's busy
state import this; none of them imports a panel."""

from __future__ import annotations

LISTENERS: list = []     # callables (stage, fraction of the whole computation): a task panel's progress display
SHOWN: list = []         # the stage and percentage shown last (every display shows the same: scripts and tests)
RUNNING: list = []       # the objects being computed now (a panel's Cancel asks them to stop)
CANCEL = [False]         # the cancel request (a list: set and read through this module's one object)
ACTIVE = None            # the open Ruled task panel (for Esc, scripts and tests)
PANELS: dict = {}        # proxy class name -> the task panel that edits such an object: panel(obj)


def request_cancel() -> bool:
    """Ask the running computation to stop at its next progress report; False when none runs."""
    if not RUNNING:
        return False
    CANCEL[0] = True
    return True


def set_active(panel) -> None:
    global ACTIVE
    ACTIVE = panel


__all__ = ["LISTENERS", "SHOWN", "RUNNING", "CANCEL", "ACTIVE", "PANELS", "request_cancel", "set_active"]
