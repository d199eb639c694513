"""FreeCAD workbench of Ruled (to come): adapter, parametric objects, task panels, commands.

No algorithm lives here; the engine is the ``ruled`` package.  Loaded by InitGui.py under a
unique module name (see ../shared/DESIGN.md), so use relative imports only.
"""
