"""FreeCAD GUI entry of Ruled: registers the "Ruled" workbench.  Nothing heavy is imported here; the
commands load when the workbench is first activated.

Init.py (FreeCAD runs it first, in freecadcmd too) loads the workbench/ package under the unique name
``ruled_workbench`` (saved documents refer to ``ruled_workbench.features.RuledFit``).  FreeCAD 0.20 runs
this file without __file__ and with separate global and local namespaces: each function here is
self-contained.
"""

import FreeCADGui


def _ruled_workbench():
    """The workbench/ package, which Init.py (run first, in freecadcmd too) loaded as ruled_workbench."""
    import sys
    return sys.modules.get("ruled_workbench")


class RuledWorkbench(FreeCADGui.Workbench):
    MenuText = "Ruled"
    ToolTip = "Ruled surfaces for wire EDM, flank milling and hot-wire cutting, with a certified error"

    def Initialize(self):
        import ruled_workbench
        from ruled_workbench import commands
        from ruled_workbench.exportpanel import PreferencesPage
        commands.register()
        # the preferences page's icon: FreeCAD looks for "preferences-ruled" on its icon paths
        FreeCADGui.addIconPath(ruled_workbench.ICONS)
        FreeCADGui.addPreferencePage(PreferencesPage, "Ruled")     # Edit > Preferences > Ruled
        self.appendToolbar("Ruled", commands.NAMES)
        self.appendMenu("Ruled", commands.NAMES)

    def Activated(self):
        from ruled_workbench import greyed
        greyed.install()       # a click on a greyed Ruled command says why in the status bar

    def GetClassName(self):
        return "Gui::PythonWorkbench"


_wb_package = _ruled_workbench()
if _wb_package is not None:
    RuledWorkbench.Icon = _wb_package.icon("ruled.svg")
FreeCADGui.addWorkbench(RuledWorkbench())
