"""``ruled batch``: every B-spline face of kj66 on a local pool of 2 workers, the same faces on a Dask
LocalCluster, the figures of single ``ruled fit`` runs, the HTML summary, a batch killed (SIGKILL) at
random moments and resumed, never a truncated output, and bad arguments refused in one line."""
import csv
import json
import os
import random
import signal
import subprocess
import sys
import time

import pytest
from conftest import ROOT, data_file, ruled_here, ruled_process

FAST = ["--samples", "12", "--measure-samples", "6"]      # quick fits: the batch, not the fit, is under test
TIMED = ("seconds",)                                      # what differs between two runs of the same face


def _rows(folder):
    with open(os.path.join(folder, "summary.json")) as fh:
        rows = json.load(fh)["rows"]
    return [{k: v for k, v in r.items() if k not in TIMED} for r in rows]


@pytest.fixture(scope="module")
def pool_batch(tmp_path_factory):
    step = data_file("kj66_impeller.step")
    out = str(tmp_path_factory.mktemp("batch") / "out")
    t0 = time.perf_counter()
    r = ruled_process("batch", step, "--faces", "bspline", "--jobs", "2", *FAST, "-o", out, "--quiet")
    assert r.returncode == 0, r.stderr[-3000:]
    return step, out, time.perf_counter() - t0, r


@pytest.mark.slow
def test_pool_batch_summary_matches_single_fits(pool_batch, tmp_path):
    step, out, seconds, run = pool_batch
    with open(os.path.join(out, "summary.json")) as fh:
        s = json.load(fh)
    rows = s["rows"]
    assert s["faces"] == len(rows) == 48 and all(r["type"] == "bspline" for r in rows)
    assert "48 of 48 faces" in run.stdout and run.stderr == ""
    # the worst faces first: fitted by decreasing bound, then refused, then failed
    ok = [r for r in rows if r["status"] == "ok"]
    assert [r["error_bound"] for r in ok] == sorted((r["error_bound"] for r in ok), reverse=True)
    assert len(ok) >= 40 and all(r["reason"] for r in rows if r["status"] != "ok")
    with open(os.path.join(out, "summary.csv")) as fh:
        table = list(csv.DictReader(fh))
    assert [int(r["face"]) for r in table] == [r["face"] for r in rows]
    # a face (a middle one) against a single 'ruled fit' run with the same options
    for r in (ok[len(ok) // 2],):
        rep = tmp_path / f"f{r['face']}.json"
        single = ruled_process("fit", step, "--face", str(r["face"]), *FAST, "-o", str(tmp_path / "f.step"), "--report",
                      str(rep), "--quiet")
        assert single.returncode == 0, single.stderr
        d = json.loads(rep.read_text())
        assert r["error_bound"] == pytest.approx(d["error_bound"], rel=1e-12)
        assert r["hausdorff"] == pytest.approx(d["hausdorff"]["max"], rel=1e-12)
        face_json = os.path.join(out, "kj66_impeller", f"face_{r['face']}.json")
        assert json.load(open(face_json))["error_bound"] == pytest.approx(d["error_bound"], rel=1e-12)
    # every face's STEP, report and plot; the page holds the table and a thumbnail per fitted face
    files = os.listdir(os.path.join(out, "kj66_impeller"))
    assert sum(f.endswith(".step") for f in files) == len(ok) and not [f for f in files if ".part" in f]
    page = open(os.path.join(out, "summary.html")).read()
    assert page.count("<tr class=") == 48 and page.count("data:image/png;base64,") == len(ok)
    assert "sortBy(" in page and "http" not in page.split("<body>")[1]          # self-contained


@pytest.mark.slow
def test_dask_local_cluster_gives_the_same_summary(pool_batch, tmp_path):
    """Four of the faces (the two worst, the best, one between) through a Dask LocalCluster of 2 workers: the
    pool's rows, figure for figure."""
    distributed = pytest.importorskip("distributed")
    step, out, _, _ = pool_batch
    rows = _rows(out)
    chosen = sorted({r["face"] for r in rows[:2] + rows[-1:] + rows[20:21]})
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as c:
        r = ruled_process("batch", step, "--faces", ",".join(map(str, chosen)), *FAST, "--scheduler",
                          c.scheduler_address, "-o", str(tmp_path / "dask"), "--quiet")
        # a limit no fit meets: recorded as failed, and the batch ends (Dask cannot stop the tasks)
        t = ruled_process("batch", step, "--faces", ",".join(map(str, chosen[:3])), *FAST, "--scheduler",
                 c.scheduler_address, "--face-timeout", "0.05", "-o", str(tmp_path / "late"), "--quiet")
    assert r.returncode == 0, r.stderr[-3000:]
    assert _rows(str(tmp_path / "dask")) == [x for x in rows if x["face"] in chosen]
    assert t.returncode == 0, t.stderr[-3000:]
    late = json.load(open(tmp_path / "late" / "summary.json"))["rows"]
    assert len(late) == 3 and all(x["status"] == "failed" and "ran past --face-timeout 0.05 s" in x["reason"]
                                  for x in late), late


def _intact(folder) -> None:
    """Every named output is whole: the JSON reports parse, the STEP files end with their trailer."""
    for name in os.listdir(folder):
        path = os.path.join(folder, name)
        if name.startswith("."):
            continue              # a temporary file being written: never a named output
        if name.endswith(".json"):
            json.load(open(path))
        elif name.endswith(".step"):
            assert open(path).read().rstrip().endswith("END-ISO-10303-21;"), path
        elif name.endswith(".png"):
            assert open(path, "rb").read()[-8:] == b"IEND\xaeB`\x82", path


@pytest.mark.slow
def test_killed_and_resumed_gives_the_uninterrupted_summary(pool_batch, tmp_path):
    step, out, _, _ = pool_batch
    chosen = sorted(r["face"] for r in _rows(out))[:8]             # eight of the B-spline faces
    faces = ",".join(map(str, chosen))
    ref = [r for r in _rows(out) if r["face"] in chosen]
    dest = str(tmp_path / "resumed")
    rnd = random.Random(7)
    args = [sys.executable, "-m", "ruled.cli", "batch", step, "--faces", faces, "--jobs", "2", *FAST, "-o", dest,
            "--quiet", "--resume"]
    # Ctrl-C (every B-spline face, at the fits' defaults: far from done when it comes): the batch stops at
    # once with the summary of what finished
    stopped = str(tmp_path / "stopped")
    # (Ctrl-C as a terminal delivers it: a test run started in the background, as by nohup, would pass
    # SIGINT ignored to the batch)
    p = subprocess.Popen(args[:args.index("--faces")] + ["--faces", "bspline", "--jobs", "2", "-o", stopped],
                         cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    time.sleep(6.0)
    p.send_signal(signal.SIGINT)
    t0 = time.perf_counter()
    _, err = p.communicate(timeout=60)
    assert p.returncode == 130 and time.perf_counter() - t0 < 10 and "interrupted" in err, err
    with open(os.path.join(stopped, "summary.json")) as fh:
        assert json.load(fh)["faces"] < len(_rows(out))
    for _ in range(2):                   # killed at random moments, resumed each time
        p = subprocess.Popen(args, cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                             start_new_session=True)
        time.sleep(rnd.uniform(3.0, 6.0))
        try:
            os.killpg(p.pid, signal.SIGKILL)
        except ProcessLookupError:       # it finished first
            pass
        p.wait()
        if os.path.isdir(os.path.join(dest, "kj66_impeller")):
            _intact(os.path.join(dest, "kj66_impeller"))
        if os.path.isdir(dest):
            _intact(dest)
    r = subprocess.run(args, cwd=ROOT, capture_output=True, text=True, timeout=900)
    assert r.returncode == 0, r.stderr
    got = _rows(dest)
    assert sorted(got, key=lambda x: x["face"]) == sorted(ref, key=lambda x: x["face"])
    _intact(os.path.join(dest, "kj66_impeller"))
    # a resumed run with every face done fits nothing again
    t0 = time.perf_counter()
    again = subprocess.run(args, cwd=ROOT, capture_output=True, text=True, timeout=900)
    assert again.returncode == 0 and _rows(dest) == _rows(dest)
    assert time.perf_counter() - t0 < 60


@pytest.mark.parametrize("args, needle", [
    (["--faces", "3-x"], "--faces '3-x'"),
    (["--faces", "999"], "--faces names 999"),
    (["--jobs", "0"], "--jobs 0 must be at least 1"),
    (["--face-timeout", "0"], "--face-timeout must be a positive finite number (seconds), not 0"),
    (["--samples", "1"], "samples"),
    pytest.param(["--scheduler", "tcp://127.0.0.1:9"], "cannot reach the Dask scheduler", marks=pytest.mark.slow),
])
def test_bad_arguments_are_refused_in_one_line(tmp_path, args, needle):
    r = ruled_here("batch", data_file("kj66_impeller.step"), *args, "-o", str(tmp_path / "o"))
    assert r.returncode == 2 and needle in r.stderr and len(r.stderr.strip().splitlines()) == 1, r.stderr


@pytest.mark.slow
def test_a_refusal_names_only_what_the_batch_takes(tmp_path):
    """Issue 34: a batch's refusal advised --rails, which 'ruled batch' does not take.  A five-edge face whose
    Coons map folds, fitted by the 4D fit (its rulings pinned to the face's corners: the 2D fit's last resort,
    the surface's whole rectangle, is not its): its row says the 'ruled fit' command of that face that takes the
    rails; an option the batch does take is still named by its flag."""
    pytest.importorskip("OCP")
    from trimmed_faces import folding_face

    from ruled.cli.common import batch_text
    from ruled.core.errors import BadInputError
    from ruled.occ.io import write_step
    src = str(tmp_path / "fold.step")
    write_step([folding_face(4), folding_face(5)], src)
    r = ruled_process("batch", src, "--jobs", "1", "--method", "4d", "--no-plots", "--quiet", "-o",
                      str(tmp_path / "o"), timeout=300)
    assert r.returncode == 0, r.stderr
    rows = {x["face"]: x for x in json.load(open(tmp_path / "o" / "summary.json"))["rows"]}
    assert rows[0]["status"] == rows[1]["status"] == "refused", rows
    assert "fold" in rows[1]["reason"] and "'ruled fit INPUT --face 1 --rails A,B'" in rows[1]["reason"], rows[1]
    assert "--rails" not in rows[0]["reason"] and "--rails" not in rows[1]["reason"].replace("--face 1 --rails", "")
    line = batch_text(BadInputError("too big; use fewer «samples=40» or pick «rails»"), 3)
    assert line == "too big; use fewer --samples 40 or pick 'ruled fit INPUT --face 3 --rails A,B'", line


def test_missing_input_refused(tmp_path):
    r = ruled_here("batch", str(tmp_path / "nope.step"), "-o", str(tmp_path / "o"))
    assert r.returncode == 2 and "no such file" in r.stderr


def test_face_timeout_records_failed_and_goes_on(tmp_path):
    """Two faces with a limit no fit meets: both recorded as failed with the reason, the batch ends
    normally (their workers replaced)."""
    r = ruled_process("batch", data_file("kj66_impeller.step"), "--faces", "6,8", "--jobs", "1", "--face-timeout",
                      "0.2", "-o", str(tmp_path / "t"), "--quiet", timeout=300)
    assert r.returncode == 0, r.stderr
    rows = json.load(open(tmp_path / "t" / "summary.json"))["rows"]
    assert [x["status"] for x in rows] == ["failed", "failed"]
    assert all("ran past --face-timeout 0.2 s" in x["reason"] for x in rows)


def test_ruled_candidates_are_the_nearly_ruled_faces(tmp_path):
    """--faces ruled-candidates keeps the faces whose iso-parametric ruled surface is within 1 % of their
    size: of a cone's side, a plane and Elber's ex2 (0.27 from its boundaries' ruled surface, 14 % of its
    size), the first two."""
    pytest.importorskip("OCP")
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeCone
    from OCP.gp import gp_Pln

    from ruled.batch.batch import select
    from ruled.examples import elber_ex2
    from ruled.occ.convert import container_to_face
    from ruled.occ.io import faces_of, write_step
    cone = faces_of(BRepPrimAPI_MakeCone(10.0, 6.0, 8.0).Shape())[0]
    plane = BRepBuilderAPI_MakeFace(gp_Pln(), 0.0, 5.0, 0.0, 3.0).Face()
    path = str(tmp_path / "three.step")
    write_step([cone, plane, container_to_face(elber_ex2())], path)
    kinds = [k for _, k, _ in select(path, "all", 0.01)]
    kept = [k for k, _, _ in select(path, "ruled-candidates", 0.01)]
    assert len(kinds) == 3 and kept == [0, 1], (kinds, kept)


@pytest.mark.slow
def test_summary_page_in_a_real_browser(pool_batch):
    """The summary page opened by headless Chromium: a screenshot (artifacts/batch/summary.png, look at
    it) with the table's header and the thumbnails drawn (many distinct colours, not a blank page)."""
    import shutil
    exe = shutil.which("chromium") or shutil.which("chromium-browser")
    if exe is None:
        pytest.skip("Chromium is not installed (apt-get install -y chromium)")
    _, out, _, _ = pool_batch
    dest = os.path.join(ROOT, "artifacts", "batch")
    os.makedirs(dest, exist_ok=True)
    png = os.path.join(dest, "summary.png")
    if os.path.exists(png):
        os.unlink(png)
    r = subprocess.run([exe, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
                        "--window-size=1400,1800", f"--screenshot={png}",
                        "file://" + os.path.join(out, "summary.html")], capture_output=True, text=True, timeout=120)
    assert os.path.exists(png), r.stderr[-2000:]
    from PIL import Image
    img = Image.open(png).convert("RGB")
    assert img.size == (1400, 1800)
    colours = img.resize((350, 450)).getcolors(1 << 20)
    assert colours is not None and len(colours) > 200                 # text, the header, the plots
    # the header's dark blue band is there (the table is drawn)
    px = img.load()
    assert any(px[x, y] == (0x1f, 0x4e, 0x79) for x in range(0, 1400, 7) for y in range(0, 400, 3))
