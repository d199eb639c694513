import os
import sys

# Under pytest-xdist every worker (and the batches, CLI runs and FreeCAD sessions it starts) computes on
# one thread: the workers already fill the cores, and OpenBLAS's, numba's and the kernels' own threads
# would only contend with the other worker (OpenBLAS's spin on the other core: about 10 % of the suite).
# Set before numpy loads OpenBLAS; a variable the caller set wins.
if int(os.environ.get("PYTEST_XDIST_WORKER_COUNT") or 1) > 1:
    for _var in ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "OMP_NUM_THREADS", "NUMBA_NUM_THREADS", "RULED_THREADS"):
        os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402
import pytest  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
SHARED_DATA = os.path.normpath(os.path.join(ROOT, "..", "shared", "data"))
LOCAL_DATA = os.path.join(HERE, "data")
sys.path.insert(0, HERE)
# the face-count cache (ruled.core.facecount) of the tests' own, not the user's (subprocesses inherit it)
if "RULED_TEST_CACHE" not in os.environ:
    import tempfile
    os.environ["RULED_TEST_CACHE"] = os.environ["XDG_CACHE_HOME"] = tempfile.mkdtemp(prefix="ruled-test-cache-")
# Bytecode into the tests' cache: with PYTHONDONTWRITEBYTECODE set (as on this machine) every CLI run, batch
# worker and FreeCAD session compiled every module it imports again (0.7-1 s each, some hundred of them).
# The prefix keeps the compiled files out of the sources and the system's folders.
os.environ.pop("PYTHONDONTWRITEBYTECODE", None)
os.environ.setdefault("PYTHONPYCACHEPREFIX", os.path.join(os.environ["RULED_TEST_CACHE"], "pycache"))
sys.pycache_prefix, sys.dont_write_bytecode = os.environ["PYTHONPYCACHEPREFIX"], False


def data_file(name: str) -> str:
    """A CAD file from tests/data (licensed copies) or ../shared/data; skip when absent."""
    for d in (LOCAL_DATA, SHARED_DATA):
        p = os.path.join(d, name)
        if os.path.exists(p):
            return p
    pytest.skip(f"{name} is not available (needs ../shared/data beside the repository)")


def ruled_process(*args, cwd=None, timeout=900, env=None):
    """``ruled ARGS`` in a process of its own (what a user runs: start-up, signals, exit code)."""
    import subprocess
    path = os.pathsep.join(filter(None, [ROOT, os.environ.get("PYTHONPATH")]))
    return subprocess.run([sys.executable, "-m", "ruled.cli", *map(str, args)], cwd=cwd or ROOT,
                          capture_output=True, text=True, timeout=timeout,
                          env={**os.environ, "PYTHONPATH": path, **(env or {})})


def ruled_here(*args, cwd=None):
    """``ruled ARGS`` through the command line's own ``main(argv)`` in this process, its output and exit
    code returned as ruled_process returns them: for refusals, which the command decides before any long
    work, without a second of interpreter and OCCT start-up per case."""
    import contextlib
    import io
    import subprocess

    from ruled.cli.main import main
    out, err = io.StringIO(), io.StringIO()
    with contextlib.ExitStack() as stack:
        if cwd is not None:
            stack.enter_context(contextlib.chdir(cwd))
        stack.enter_context(contextlib.redirect_stdout(out))
        stack.enter_context(contextlib.redirect_stderr(err))
        try:
            code = main([str(a) for a in args])
        except SystemExit as exc:         # argparse's own refusals
            code = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 2)
    return subprocess.CompletedProcess(list(args), code, out.getvalue(), err.getvalue())


@pytest.fixture
def rng():
    return np.random.default_rng(12345)


# the workbench package as FreeCAD loads an installed addon (its Init.py), the repository on sys.path
WORKBENCH_LOADER = f"""
import os, sys
sys.path.insert(0, {ROOT!r})
exec(compile(open({os.path.join(ROOT, "Init.py")!r}).read(), "Init.py", "exec"), {{}})
"""


# FreeCAD in a chroot (issue 73: Debian 13's FreeCAD 1.0, built by .ci/freecad1.sh): RULED_FREECAD_ROOT names its
# folder, where the repository, ../shared and /tmp are bound at their own paths; the FreeCAD tests' commands run in it
FREECAD_ROOT = os.environ.get("RULED_FREECAD_ROOT") or None


def freecad_command(*names: str):
    """The command line prefix that runs the programs `names` of FreeCAD's machine (freecadcmd; xvfb-run and
    freecad): in the chroot RULED_FREECAD_ROOT names, else on this machine; None where one is absent."""
    import shutil
    if FREECAD_ROOT:
        have = all(os.path.lexists(os.path.join(FREECAD_ROOT, "usr", "bin", n)) for n in names)
        return ["chroot", FREECAD_ROOT, names[0]] if have else None
    exe = [shutil.which(n) for n in names]
    return [exe[0]] if all(exe) else None


# ... and each FreeCAD test module (tests/workbench) runs on each FreeCAD at hand: this machine's (Debian 12's 0.20.2
# in CI) and, where .ci/freecad1.sh has built it, Debian 13's FreeCAD 1.0.0 in its chroot, the same assertions (ids
# [host] and [freecad1]; the chroot's tests their own group on the cores, below).  The chroot has a file
# .ruled-ready once complete, and sees the repository, ../shared and /tmp at their own paths while CI runs.
FREECAD1 = os.environ.get("RULED_FREECAD1_DIR", "/var/cache/ruled/freecad1")


def freecad_hosts() -> list:
    return ["host", "freecad1"] if os.path.exists(os.path.join(FREECAD1, ".ruled-ready")) else ["host"]


def pytest_generate_tests(metafunc):
    if "freecad_host" in metafunc.fixturenames and "tests/workbench/" in str(metafunc.definition.path).replace(
            os.sep, "/"):
        metafunc.parametrize("freecad_host", freecad_hosts(), indirect=True, scope="module")


@pytest.fixture(scope="module", autouse=True)
def freecad_host(request):
    """Which FreeCAD a FreeCAD test module's commands run in (FREECAD_ROOT), and its GUI outputs' folder (the
    module's OUT: artifacts/gui, or artifacts/gui-freecad1)."""
    global FREECAD_ROOT
    host = getattr(request, "param", "host")
    if host != "freecad1":
        yield host
        return
    if not os.path.exists(FREECAD1 + os.path.join(ROOT, "Init.py")):
        pytest.skip(f"the FreeCAD 1.0 chroot {FREECAD1} does not see the repository: bind it (bash .ci/freecad1.sh "
                    f"mount)")
    saved, out = FREECAD_ROOT, getattr(request.module, "OUT", None)
    FREECAD_ROOT = FREECAD1
    if out is not None:
        request.module.OUT = out.rstrip(os.sep) + "-freecad1"
    try:
        yield host
    finally:
        FREECAD_ROOT = saved
        if out is not None:
            request.module.OUT = out


def freecad_has(pattern: str) -> bool:
    """Whether FreeCAD's machine has files matching the glob pattern (an absolute path: in the chroot when one
    is named)."""
    import glob
    return bool(glob.glob((FREECAD_ROOT or "") + pattern))


# os._exit that first flushes C's stdio too: FreeCAD 1.0's console writes its messages (PrintMessage) to a buffered
# stdout, which os._exit would drop (0.20's reached the pipe at once)
FLUSHED_EXIT = """import os as _os, sys as _sys, ctypes as _ctypes
def _flushed_exit(code, _exit=_os._exit):
    try:
        _sys.stdout.flush(); _sys.stderr.flush(); _ctypes.CDLL(None).fflush(None)
    finally:
        _exit(code)
_os._exit = _flushed_exit
"""


def run_freecadcmd(script: str, tmp_path, timeout: int = 600, env: dict = None):
    """Run a script in Debian's freecadcmd (skip when it is absent); the script must end with
    os._exit(code) (freecadcmd exits 0 even when a script raises).  Asserts it exited 0.  env: more
    environment variables."""
    import subprocess
    cmd = freecad_command("freecadcmd")
    if cmd is None:
        pytest.skip("freecadcmd is not installed (apt-get install -y freecad)")
    path = tmp_path / "fc_script.py"
    path.write_text(FLUSHED_EXIT + script)
    run = subprocess.run([*cmd, str(path)], capture_output=True, text=True, timeout=timeout,   # the script first
                         env={**os.environ, "HOME": str(tmp_path), **(env or {})})
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    return run


def freecad_json(body: str, tmp_path, timeout: int = 600, env: dict = None, with_run: bool = False):
    """Run body (statements, at no indent, that fill a dict `out`) in freecadcmd with the workbench loaded;
    the wrapper writes `out` as JSON and exits with the script's outcome (freecadcmd itself exits 0 even
    when a script raises).  Returns `out` (with_run: and the finished process, its output)."""
    import json
    import textwrap
    path = tmp_path / "freecad_out.json"
    script = (WORKBENCH_LOADER + "code = 1\ntry:\n    import json\n    out = {}\n"
              + textwrap.indent(body.strip(), "    ")
              + f"\n    json.dump(out, open({str(path)!r}, 'w'))\n    code = 0\nexcept Exception:\n"
              "    import traceback; traceback.print_exc()\nsys.stdout.flush(); sys.stderr.flush()\nos._exit(code)\n")
    run = run_freecadcmd(script, tmp_path, timeout, env)
    out = json.loads(path.read_text())
    return (out, run) if with_run else out


# How the suite shares the two cores (``-n auto``, pyproject.toml; the scheduler below):
# - each module is a group that runs whole on one worker, so that its module fixtures are computed once;
#   the FreeCAD tests (freecadcmd and the GUI under Xvfb, marked freecad) are one group: they share
#   FreeCAD's own numba cache (Debian's numba 0.56), which the first of them compiles in a clean clone;
# - a worker takes the next group when it is almost done with one; the longest go first (the FreeCAD
#   group's subprocesses overlapping the in-process tests on the other core), so that the last to
#   finish is a short one;
# - the venv's numba kernels are compiled once, by tests/warm_kernels.py, started with the session; the
#   tests that run the engine wait for it (in a clean clone every process compiled them anew).
# Seconds per group (the sum of its tests' durations) measured on this 2-core machine with -n 2 and cold
# caches; a module not listed counts as 5 s.
GROUP_SECONDS = {
    "batch/test_fuzz.py": 330, "freecad": 450, "freecad1": 450, "split/test_split_faces.py": 245,
    "batch/test_batch.py": 210,
    "cone/test_cone_faces.py": 130, "machine/test_machine.py": 110, "machine/test_posts.py": 100,
    "fit/test_trimmed.py": 85, "fit/test_part_ruled.py": 90, "fit/test_ring_bound.py": 30,
    "fit/test_fit4d.py": 70, "fit/test_fit.py": 70, "cli/test_cli.py": 65, "cone/test_cone_acceptance.py": 55,
    "fit/test_figures.py": 50, "curves/test_cos_acceptance.py": 45, "split/test_split.py": 30,
    "machine/test_flank.py": 25, "cli/test_lint.py": 20, "fit/test_dp4d.py": 12, "core/test_distance.py": 10,
}


def _group(nodeid: str) -> str:
    """A test's group: its module, or "freecad" for the FreeCAD tests (all of tests/workbench), "freecad1" for
    them in FreeCAD 1.0's chroot (tests/workbench/conftest.py)."""
    path = nodeid.split("::")[0]
    path = path[len("tests/"):] if path.startswith("tests/") else path
    if path.startswith("workbench/"):
        return "freecad1" if "freecad1]" in nodeid or "freecad1-" in nodeid else "freecad"
    return path


def pytest_collection_modifyitems(session, config, items):
    """The longest groups first (stable: inside a group the tests keep their order), and in the FreeCAD
    group the GUI's first: they use no kernels of the venv, which are still compiling."""
    items.sort(key=lambda item: (-GROUP_SECONDS.get(_group(item.nodeid), 5.0), "gui" not in item.nodeid))


def pytest_xdist_make_scheduler(config, log):
    """pytest-xdist's loadscope with our groups as its scopes (its own loadgroup does not group under
    pytest 9, which ignores the group it writes into a test's id)."""
    from xdist.scheduler import LoadScopeScheduling

    class GroupScheduling(LoadScopeScheduling):
        def _split_scope(self, nodeid: str) -> str:
            return _group(nodeid)
    return GroupScheduling(config, log)


def pytest_report_header(config):
    from fuzz_seed import commit_seed
    s = commit_seed()
    return [f"fuzz seed {s} (tests/batch/test_fuzz.py; repeat with RULED_FUZZ_SEED={s}, or python "
            f"tests/fuzz_faces.py --seed {s})"]


@pytest.hookimpl(tryfirst=True)
def pytest_xdist_auto_num_workers(config):
    """``-n auto``: one worker per core, at most 4 (each FreeCAD subprocess and batch takes a core too)."""
    return max(1, min(4, len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1))


WARM = os.path.join(os.environ["RULED_TEST_CACHE"], "kernels-compiled")


@pytest.hookimpl(tryfirst=True)
def pytest_sessionstart(session):
    """The controller (or the only process) compiles the kernels in the background."""
    if hasattr(session.config, "workerinput") or os.path.exists(WARM + ".log") or os.environ.get("RULED_NO_NUMBA"):
        return
    import subprocess
    with open(WARM + ".log", "w") as log:
        subprocess.Popen([sys.executable, os.path.join(HERE, "warm_kernels.py"), WARM], cwd=ROOT, stdout=log,
                         stderr=subprocess.STDOUT)


_WAITED = []


def pytest_runtest_setup(item):
    """Tests that run the venv's engine start once its kernels are compiled (at most 10 minutes' wait)."""
    if _WAITED or item.get_closest_marker("freecad"):
        return
    import time
    end = time.monotonic() + 600
    while not os.path.exists(WARM) and time.monotonic() < end and os.path.exists(WARM + ".log"):
        time.sleep(0.5)
    _WAITED.append(True)
