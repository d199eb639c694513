"""FreeCAD's non-GUI entry of Ruled (run in freecad and freecadcmd alike, before InitGui.py): makes the
workbench/ package importable under its unique name ``ruled_workbench``, so that documents whose objects
refer to ``ruled_workbench.features`` restore with their code (FreeCAD permits modules found in its Mod
folders only, and finds this one through the addon's own folder).

FreeCAD puts every Mod folder on sys.path and runs this file without __file__ and with separate global
and local namespaces: the loader is self-contained.  Nothing heavy is imported here.
"""


def _load_ruled_workbench():
    """Import workbench/ as ruled_workbench (once); the addon folder is the sys.path entry holding it."""
    import importlib.util
    import os
    import sys
    if "ruled_workbench" in sys.modules:
        return sys.modules["ruled_workbench"]
    roots = [p for p in sys.path if os.path.isfile(os.path.join(p, "workbench", "features.py"))
             and os.path.isdir(os.path.join(p, "ruled")) and os.path.isfile(os.path.join(p, "Init.py"))]
    if not roots:
        return None
    root = roots[0]
    # the engine imported through the real path of a linked addon (the README's install): numba keys its
    # kernel cache by the source's path, and a link's path would make every link a cache of its own
    real = os.path.realpath(root)
    if real != root and real not in sys.path:
        sys.path.insert(0, real)
    spec = importlib.util.spec_from_file_location("ruled_workbench", os.path.join(root, "workbench", "__init__.py"),
                                                  submodule_search_locations=[os.path.join(root, "workbench")])
    mod = importlib.util.module_from_spec(spec)
    sys.modules["ruled_workbench"] = mod
    spec.loader.exec_module(mod)
    return mod


_load_ruled_workbench()
