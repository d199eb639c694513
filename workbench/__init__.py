"""FreeCAD workbench of Ruled: adapter, parametric objects, view providers, task panels, commands.

No algorithm lives here; the engine is the ``ruled`` package.  InitGui.py loads this package under
the unique module name ``ruled_workbench`` (saved documents refer to ``ruled_workbench.features``);
use relative imports only.  This file stays tiny: FreeCAD loads it at start-up.
"""

import os

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ICONS = os.path.join(ROOT, "icons")


def icon(name: str) -> str:
    return os.path.join(ICONS, name)
