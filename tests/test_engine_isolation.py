"""House rule: the engine imports no CAD host."""
import os
import subprocess
import sys

from conftest import ROOT

BLOCK = r"""
import sys
class Block:
    def find_spec(self, name, path=None, target=None):
        if name.split('.')[0] in ('OCP', 'cadquery', 'FreeCAD', 'FreeCADGui', 'Part'):
            raise ImportError('blocked: ' + name)
        return None
sys.meta_path.insert(0, Block())
import ruled
from ruled import fit_surface, FitOptions
from ruled.examples import elber_ex1
r = fit_surface(elber_ex1(), FitOptions(samples=12))
assert r.error_bound > 0
r = fit_surface(elber_ex1(), FitOptions(samples=12, method="4d", elevations=3, metric="sshb"))
assert r.error_bound > 0
mods = [m for m in sys.modules if m.split('.')[0] in ('OCP', 'cadquery', 'FreeCAD', 'Part')]
assert not mods, mods
print('ok')
"""


def test_engine_runs_with_cad_hosts_blocked():
    out = subprocess.run([sys.executable, "-c", BLOCK], cwd=ROOT, capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr
    assert "ok" in out.stdout


def test_no_host_imports_in_engine_sources():
    bad = []
    for dirpath, _, files in os.walk(os.path.join(ROOT, "ruled")):
        if os.path.basename(dirpath) == "occ":
            continue
        for f in files:
            if not f.endswith(".py") or f in ("cli.py", "cq.py"):
                continue
            text = open(os.path.join(dirpath, f)).read()
            for mod in ("OCP", "cadquery", "FreeCAD"):
                if f"import {mod}" in text or f"from {mod}" in text:
                    bad.append((f, mod))
    assert not bad


def test_no_occ_or_cadquery_in_the_workbench():
    """FreeCAD's Python has neither: the workbench reaches geometry through FreeCAD's Part only."""
    paths = [os.path.join(ROOT, "InitGui.py")]
    for dirpath, _, files in os.walk(os.path.join(ROOT, "workbench")):
        paths += [os.path.join(dirpath, f) for f in files if f.endswith(".py")]
    bad = []
    for p in paths:
        text = open(p).read()
        for mod in ("OCP", "cadquery", "ruled.occ", "ruled.cq"):
            if f"import {mod}" in text or f"from {mod}" in text:
                bad.append((os.path.relpath(p, ROOT), mod))
    assert len(paths) > 2 and not bad
