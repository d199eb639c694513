"""The checks CI runs beside the tests (and the pre-commit hooks run before a commit): ruff (with the NumPy
rules) on the engine, the tests, the benchmarks and the workbench; mypy on the engine (its public entry
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
