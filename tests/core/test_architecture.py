"""The house's rules, read from the sources, besides the layers that import-linter checks (pyproject.toml,
tests/cli/test_lint.py): no import cycle between Ruled's modules nor the workbench's (imports inside
functions count), no module past 500 lines, and the engine runs with every CAD host blocked."""
import ast
import os
import re
import subprocess
import sys

import pytest
from conftest import ROOT

HOSTS = ("OCP", "cadquery", "FreeCAD", "FreeCADGui", "Part")
# the front doors and the OCCT layer, which may import the hosts (or the layers that do)
FRONT = ("ruled.occ", "ruled.jobs", "ruled.cli", "ruled.cq", "ruled.batch")


def _modules(top: str) -> dict:
    """module name -> its source path, for every .py under ROOT/top."""
    out = {}
    for dirpath, _, files in os.walk(os.path.join(ROOT, top)):
        for f in files:
            if f.endswith(".py"):
                path = os.path.join(dirpath, f)
                name = os.path.relpath(path, ROOT)[:-3].replace(os.sep, ".")
                out[name[:-9] if name.endswith(".__init__") else name] = path
    return out


def _imports(path: str, name: str) -> set:
    """Every module path imports, at any depth (function-level imports count)."""
    tree = ast.parse(open(path).read())
    pkg = name if path.endswith("__init__.py") else name.rpartition(".")[0]
    out = set()
    for n in ast.walk(tree):
        if isinstance(n, ast.Import):
            out |= {a.name for a in n.names}
        elif isinstance(n, ast.ImportFrom):
            base = n.module or ""
            if n.level:
                parts = pkg.split(".")
                base = ".".join(parts[:len(parts) - n.level + 1] + ([base] if base else []))
            out.add(base)
            out |= {f"{base}.{a.name}" for a in n.names}        # `from ruled.fit import dp` imports ruled.fit.dp
    return out


RULED = _modules("ruled")
GRAPH = {m: {i for i in _imports(p, m) if i in RULED and i != m} for m, p in RULED.items()}


def _is(mod: str, prefixes) -> bool:
    return any(mod == p or mod.startswith(p + ".") for p in prefixes)


def _cycles(graph: dict) -> list:
    """The strongly connected components of more than one module (Tarjan)."""
    index, low, stack, on, out = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


@pytest.mark.parametrize("top", ["ruled", "workbench"])
def test_no_import_cycle(top):
    # a package imports its own modules (its __init__ re-exports); a module importing its package is not a cycle
    mods = _modules(top)
    deps = {m: {i for i in _imports(p, m) if i in mods and i != m} for m, p in mods.items()}
    graph = {m: {i for i in d if not m.startswith(i + ".")} for m, d in deps.items()}
    assert len(graph) > 10 and not _cycles(graph), _cycles(graph)


def test_the_cycle_finder_finds_a_cycle():
    assert _cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]


@pytest.mark.parametrize("top", ["ruled", "workbench", "tests", "benchmarks"])
def test_no_module_past_500_lines(top):
    long = {os.path.relpath(p, ROOT): n for p in _modules(top).values()
            if (n := sum(1 for _ in open(p))) > 500}
    assert not long, long


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


def test_the_architecture_page_names_every_package_and_module():
    """docs/architecture.md stays true: every package and module of the engine and the workbench is in its
    table, and every module it names exists."""
    text = open(os.path.join(ROOT, "docs", "architecture.md")).read()
    table = text[text.index("## The packages"):text.index("## The rules")]
    rows = {}
    for line in table.splitlines():
        cells = [c.strip() for c in line.split("|")[1:-1]]
        if len(cells) == 3 and cells[0].startswith("`"):
            rows[cells[0].strip("`")] = set(re.findall(r"`(\w+)`", cells[2]))
    have = {}
    for m in list(RULED) + list(_modules("workbench")):
        pkg, _, name = m.rpartition(".")
        if m in ("ruled", "workbench") or (m.count(".") == 1 and m.split(".")[1] in rows.get("ruled", set())):
            pkg, name = m.split(".")[0], (name if m.count(".") else "__init__")
        elif m.count(".") == 1 and os.path.isdir(os.path.join(ROOT, *m.split("."))):
            continue                                      # a package's __init__
        have.setdefault(pkg, set()).add(name)
    assert set(rows) == set(have), (sorted(rows), sorted(have))
    for pkg, names in have.items():
        assert rows[pkg] == names, (pkg, sorted(rows[pkg] ^ names))
