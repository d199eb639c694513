"""FreeCAD GUI entry of Ruled: registers the "Ruled" workbench.  Nothing heavy is imported here; the
commands load when the workbench is first activated.

FreeCAD puts every Mod folder on sys.path, so the workbench/ package is loaded under the unique name
``ruled_workbench`` (saved documents refer to ``ruled_workbench.features.RuledFit``).  FreeCAD 0.20 runs
this file without __file__ and with separate global and local namespaces: each function here is
self-contained.
"""

import FreeCADGui


def _load_ruled_workbench():
    """Import workbench/ as ruled_workbench (once); the addon folder is the sys.path entry holding it."""
    import importlib.util
    import os
    import sys
    if "ruled_workbench" in sys.modules:
        return sys.modules["ruled_workbench"]
    here = globals().get("__file__")
    roots = [os.path.dirname(os.path.abspath(here))] if here else []
    roots += [p for p in sys.path if os.path.isfile(os.path.join(p, "workbench", "features.py"))
              and os.path.isdir(os.path.join(p, "ruled"))]
    if not roots:
        return None
    root = roots[0]
    if root not in sys.path:
        sys.path.append(root)
    spec = importlib.util.spec_from_file_location("ruled_workbench", os.path.join(root, "workbench", "__init__.py"),
                                                  submodule_search_locations=[os.path.join(root, "workbench")])
    mod = importlib.util.module_from_spec(spec)
    sys.modules["ruled_workbench"] = mod
    spec.loader.exec_module(mod)
    return mod


class RuledWorkbench(FreeCADGui.Workbench):
    MenuText = "Ruled"
    ToolTip = "Ruled surfaces for wire EDM, flank milling and hot-wire cutting, with a certified error"

    def Initialize(self):
        from ruled_workbench import commands
        commands.register()
        self.appendToolbar("Ruled", commands.NAMES)
        self.appendMenu("Ruled", commands.NAMES)

    def GetClassName(self):
        return "Gui::PythonWorkbench"


_wb_package = _load_ruled_workbench()
if _wb_package is not None:
    RuledWorkbench.Icon = _wb_package.icon("ruled.svg")
FreeCADGui.addWorkbench(RuledWorkbench())
