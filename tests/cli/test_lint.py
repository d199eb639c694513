"""The checks CI runs beside the tests (and the pre-commit hooks run before a commit): ruff (with the NumPy
rules) on the engine, the tests, the benchmarks and the workbench; the layers (import-linter's contracts,
pyproject.toml); mypy on the engine (its public entry
points fully annotated); the documentation built by MkDocs in strict mode (no broken link, no page left out
of the navigation)."""
import inspect
import os
import shutil
import subprocess
import sys

import pytest
from conftest import ROOT


def _tool(name: str) -> str:
    exe = shutil.which(name, path=os.path.dirname(sys.executable)) or shutil.which(name)
    if exe is None:
        pytest.skip(f"{name} is not installed (pip install -e '.[test]')")
    return exe


def test_ruff_clean():
    out = subprocess.run([_tool("ruff"), "check", "ruled", "tests", "benchmarks", "workbench", "InitGui.py",
                          "--output-format", "concise"], cwd=ROOT, capture_output=True, text=True)
    assert out.returncode == 0, out.stdout + out.stderr


def test_the_layers_hold():
    """The house's layers and forbidden imports, pyproject.toml's [tool.importlinter] contracts, by import-linter
    (imports inside functions count)."""
    out = subprocess.run([_tool("lint-imports")], cwd=ROOT, capture_output=True, text=True, timeout=600)
    assert out.returncode == 0 and "0 broken" in out.stdout, out.stdout[-4000:] + out.stderr


def test_an_upward_import_breaks_the_layers(tmp_path):
    """The contracts can fail: the engine's core importing the command line, in a copy of the sources."""
    import shutil as sh
    for top in ("ruled", "workbench"):
        sh.copytree(os.path.join(ROOT, top), tmp_path / top, ignore=sh.ignore_patterns("__pycache__"))
    sh.copy(os.path.join(ROOT, "pyproject.toml"), tmp_path)
    with open(tmp_path / "ruled" / "core" / "nearest.py", "a") as fh:
        fh.write("\n\ndef _up():\n    from ruled.cli.common import cli_text\n    return cli_text\n")
    out = subprocess.run([_tool("lint-imports")], cwd=tmp_path, capture_output=True, text=True, timeout=600,
                         env={**os.environ, "PYTHONPATH": str(tmp_path)})
    assert out.returncode != 0 and "ruled.core is not allowed to import ruled.cli" in out.stdout, out.stdout[-3000:]


def test_mypy_clean():
    """The configuration is pyproject.toml's [tool.mypy]."""
    out = subprocess.run([_tool("mypy")], cwd=ROOT, capture_output=True, text=True, timeout=900)
    assert out.returncode == 0 and "Success" in out.stdout, out.stdout[-4000:] + out.stderr


def test_the_public_api_is_fully_annotated():
    import ruled
    missing = []
    for name in ruled.__all__:
        f = getattr(ruled, name)
        if inspect.isfunction(f):
            sig = inspect.signature(f)
            missing += [f"{name}({p.name})" for p in sig.parameters.values()
                        if p.annotation is inspect.Parameter.empty and p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD)]
            if sig.return_annotation is inspect.Signature.empty:
                missing.append(f"{name} -> ?")
    assert len(ruled.__all__) > 20 and not missing, missing


def test_docs_build(tmp_path):
    out = subprocess.run([_tool("mkdocs"), "build", "--strict", "--site-dir", str(tmp_path / "site")], cwd=ROOT,
                         capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stdout[-4000:] + out.stderr[-4000:]
    assert (tmp_path / "site" / "index.html").exists() and (tmp_path / "site" / "architecture" / "index.html").exists()
