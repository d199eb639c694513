"""FreeCAD entry point of the Ruled workbench (placeholder).

The workbench (commands, task panels, parametric objects) comes with its own issue.  This file
stays tiny: FreeCAD runs it at start-up, so it imports nothing heavy.
"""
