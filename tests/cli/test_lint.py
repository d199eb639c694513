"""ruff (with the NumPy rules) on the engine, the tests, the benchmarks and the FreeCAD workbench."""
import shutil
import subprocess
import sys

import pytest

from conftest import ROOT


def test_ruff_clean():
    exe = shutil.which("ruff") or shutil.which("ruff", path=sys.prefix + "/bin")
    if exe is None:
        pytest.skip("ruff is not installed (pip install -e '.[test]')")
    out = subprocess.run([exe, "check", "ruled", "tests", "benchmarks", "workbench", "InitGui.py", "--output-format",
                          "concise"],
                         cwd=ROOT, capture_output=True, text=True)
    assert out.returncode == 0, out.stdout + out.stderr
