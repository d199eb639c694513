"""A refusal said in one line (no GUI imports): while FreeCAD reports an object's refusal of bad input, its
traceback and the console's and report view's error output are off (workbench.features arms it)."""

from __future__ import annotations

import FreeCAD


class _TracebackRestorer:
    """FreeCAD reports an exception raised by execute() with its Python traceback and a line
    "<class 'RuntimeError'>: ..." of its own.  A refusal of bad input is one line, the object's, not a crash:
    while FreeCAD reports it, sys.tracebacklimit is 0 and the console's and report view's error output are
    off; both come back when the object's (or the document's) recompute ends."""

    saved = None
    armed = False
    registered = False
    OUTPUTS = ("Console", "ReportOutput")     # FreeCAD's console observers: the terminal, the report view
    errors: dict = {}

    def arm(self) -> None:
        import sys
        if not self.registered:
            FreeCAD.addDocumentObserver(self)
            self.registered = True
        if not self.armed:
            self.saved = getattr(sys, "tracebacklimit", None)
            self.errors = {}
            for name in self.OUTPUTS:
                try:
                    self.errors[name] = FreeCAD.Console.GetStatus(name, "Err")
                    FreeCAD.Console.SetStatus(name, "Err", False)
                except Exception:     # (no such observer here: freecadcmd has no report view)
                    continue
            self.armed = True
        sys.tracebacklimit = 0

    def restore(self) -> None:
        import sys
        if not self.armed:
            return
        if self.saved is None:
            if hasattr(sys, "tracebacklimit"):
                del sys.tracebacklimit
        else:
            sys.tracebacklimit = self.saved
        for name, on in self.errors.items():
            if on is not None:
                FreeCAD.Console.SetStatus(name, "Err", bool(on))
        self.armed = False

    def slotRecomputedObject(self, obj) -> None:
        self.restore()

    def slotRecomputedDocument(self, doc) -> None:
        self.restore()


RESTORER = _TracebackRestorer()


__all__ = ["RESTORER"]
