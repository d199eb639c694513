import os
import sys

import numpy as np
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
SHARED_DATA = os.path.normpath(os.path.join(ROOT, "..", "shared", "data"))
LOCAL_DATA = os.path.join(HERE, "data")
sys.path.insert(0, HERE)
# the face-count cache (ruled.core.facecount) of the tests' own, not the user's (subprocesses inherit it)
if "RULED_TEST_CACHE" not in os.environ:
    import tempfile
    os.environ["RULED_TEST_CACHE"] = os.environ["XDG_CACHE_HOME"] = tempfile.mkdtemp(prefix="ruled-test-cache-")


def data_file(name: str) -> str:
    """A CAD file from tests/data (licensed copies) or ../shared/data; skip when absent."""
    for d in (LOCAL_DATA, SHARED_DATA):
        p = os.path.join(d, name)
        if os.path.exists(p):
            return p
    pytest.skip(f"{name} is not available (needs ../shared/data beside the repository)")


@pytest.fixture
def rng():
    return np.random.default_rng(12345)


# the workbench package as FreeCAD loads an installed addon (its Init.py), the repository on sys.path
WORKBENCH_LOADER = f"""
import os, sys
sys.path.insert(0, {ROOT!r})
exec(compile(open({os.path.join(ROOT, "Init.py")!r}).read(), "Init.py", "exec"), {{}})
"""


def run_freecadcmd(script: str, tmp_path, timeout: int = 600, env: dict = None):
    """Run a script in Debian's freecadcmd (skip when it is absent); the script must end with
    os._exit(code) (freecadcmd exits 0 even when a script raises).  Asserts it exited 0.  env: more
    environment variables."""
    import shutil
    import subprocess
    exe = shutil.which("freecadcmd")
    if exe is None:
        pytest.skip("freecadcmd is not installed (apt-get install -y freecad)")
    path = tmp_path / "fc_script.py"
    path.write_text(script)
    run = subprocess.run([exe, str(path)], capture_output=True, text=True, timeout=timeout,   # the script first
                         env={**os.environ, "HOME": str(tmp_path), **(env or {})})
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    return run


def freecad_json(body: str, tmp_path, timeout: int = 600, env: dict = None):
    """Run body (statements, at no indent, that fill a dict `out`) in freecadcmd with the workbench loaded;
    the wrapper writes `out` as JSON and exits with the script's outcome (freecadcmd itself exits 0 even
    when a script raises).  Returns `out`."""
    import json
    import textwrap
    path = tmp_path / "freecad_out.json"
    script = (WORKBENCH_LOADER + "code = 1\ntry:\n    import json\n    out = {}\n"
              + textwrap.indent(body.strip(), "    ")
              + f"\n    json.dump(out, open({str(path)!r}, 'w'))\n    code = 0\nexcept Exception:\n"
              "    import traceback; traceback.print_exc()\nsys.stdout.flush(); sys.stderr.flush()\nos._exit(code)\n")
    run_freecadcmd(script, tmp_path, timeout, env)
    return json.loads(path.read_text())


# The fuzz batches (tests/batch/test_fuzz.py) start as soon as the tests are collected, in a process of their own
# on one worker: the suite runs on one core and their minutes pass on the other.
FUZZ = {}


def pytest_collection_modifyitems(session, config, items):
    """The fuzz batches run in the background on the core the suite leaves idle (the suite runs on one):
    their checks come last, so that the batches have the whole suite's time."""
    FUZZ["wanted"] = any("test_fuzz.py" in item.nodeid for item in items)
    items.sort(key=lambda item: "test_fuzz.py" in item.nodeid)        # stable: the rest keep their order


def pytest_runtest_setup(item):
    """Start the fuzz batches at the first test past the batch tests (which use both cores)."""
    if FUZZ.get("wanted") and "proc" not in FUZZ and "test_batch.py" not in item.nodeid:
        import subprocess
        import tempfile
        FUZZ["dir"] = tempfile.mkdtemp(prefix="ruled-fuzz-")
        FUZZ["proc"] = subprocess.Popen([sys.executable, os.path.join(HERE, "fuzz_faces.py"), FUZZ["dir"], "1"],
                                        cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def pytest_sessionfinish(session):
    proc = FUZZ.get("proc")
    if proc is not None and proc.poll() is None:
        proc.kill()
