"""``ruled batch``: every selected face of many files, each fitted as ``ruled fit`` fits it, on a local
process pool or an existing Dask cluster, with a summary (CSV, JSON and a self-contained HTML page).  The face
task (run_face) is written once; the executors (ruled.batch.pools) only submit it.  A face's outputs go to
OUTDIR/<file stem>/face_<k>.step, .json (its report, with the batch key) and .png (its plot, the summary's
thumbnail), each written whole or not at all.  --resume skips the faces whose report holds the same key (the
file's content, the face, the options): a batch killed half-way and resumed ends as an uninterrupted one.  A
face the engine refuses is recorded with its reason; one that crashes its worker or runs past --face-timeout
is recorded as failed, and the batch goes on."""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import time
from typing import Optional

from ruled.core.errors import BadInputError, RuledError, parse_faces, positive

COLUMNS = ["file", "face", "type", "trimmed_pct", "method", "status", "error_bound", "hausdorff", "seconds",
           "warnings", "reason"]


# ------------------------------------------------------------------------------------------ selection
def naive_ruled_error(S) -> float:
    """The smaller, over the two directions, of the largest parametric distance between the face's surface
    and the iso-parametric ruled surface between its two opposite boundaries (at the same parameters): a
    cheap over-estimate of what a ruled surface can reach, for picking candidates."""
    import numpy as np
    u0, u1, v0, v1 = S.domain
    s = np.linspace(0.0, 1.0, 17)
    uu, vv = np.meshgrid(u0 + s * (u1 - u0), v0 + s * (v1 - v0), indexing="ij")
    P = S(uu.ravel(), vv.ravel()).reshape(17, 17, 3)
    t = s[None, :, None]
    along_v = np.linalg.norm(P - ((1 - t) * P[:, :1] + t * P[:, -1:]), axis=2).max()
    t = s[:, None, None]
    along_u = np.linalg.norm(P - ((1 - t) * P[:1] + t * P[-1:]), axis=2).max()
    return float(min(along_u, along_v))


def select(path: str, spec, fraction: float) -> list:
    """[(face index, surface type, trimmed %)] of the file's faces chosen by spec."""
    from ruled.fit.face.fit import face_patch
    from ruled.occ.convert import face_surface_type
    from ruled.occ.io import face_area, read_faces
    from ruled.occ.region import face_region, rect_area_ratio
    faces = read_faces(path)
    chosen = range(len(faces)) if not isinstance(spec, list) else spec
    out = []
    for k in chosen:
        if k >= len(faces):
            raise BadInputError(f"{path} has {len(faces)} faces (0..{len(faces) - 1}); --faces names {k}")
        face = faces[k]
        kind = face_surface_type(face)
        if spec == "bspline" and kind != "bspline":
            continue
        trimmed = None
        try:
            region = face_region(face)
            trimmed = 0.0 if region.is_rectangle() else 100.0 * (1.0 - rect_area_ratio(face, region.surface,
                                                                                      face_area(face)))
            if spec == "ruled-candidates":
                patch = face_patch(region)
                if naive_ruled_error(patch.surface) > fraction * max(patch.face_size, 1e-300):
                    continue
        except RuledError:
            if spec == "ruled-candidates":
                continue
        out.append((k, kind, trimmed))
    return out


# ------------------------------------------------------------------------------------------ the task
def file_digest(path: str) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def job_key(digest: str, face, options: dict) -> str:
    return hashlib.sha256(json.dumps([digest, face, options], sort_keys=True).encode()).hexdigest()[:24]


NO_WALL = "no wall"     # the row of a file 'ruled batch --walls' finds no wall in


def face_paths(folder: str, face) -> dict:
    """A face's outputs (face_<k>.*), or a wall's (face "wall <k>": wall_<k>.*)."""
    base = os.path.join(folder, f"face_{face}" if isinstance(face, int) else str(face).replace(" ", "_"))
    return {"step": base + ".step", "json": base + ".json", "png": base + ".png", "base": base}


_FACES: dict = {}    # a worker's faces of the files it has read: (path, digest) -> faces


def run_face(job: dict) -> dict:
    """The face task: fit one face as ``ruled fit`` does (or one wall as ``ruled fit --wall``: a job with
    "wall"), write its STEP, report and plot; return its summary row.  A refusal (RuledError) is a row
    with its reason, not an exception."""
    from ruled.fit.report import write_report
    t0 = time.perf_counter()
    row = _row(job, "ok")
    paths = face_paths(job["folder"], job["face"])
    try:
        if not job["options"].get("plots", True):    # no thumbnail of an earlier run beside this run's figures
            with contextlib.suppress(OSError):
                os.unlink(paths["png"])
        if job.get("refusal"):
            raise BadInputError(job["refusal"])
        rep = (_wall_job if job.get("wall") is not None else _face_job)(job, paths)
        row.update(error_bound=rep["error_bound"], hausdorff=rep["hausdorff"]["max"],
                   warnings="; ".join(rep.get("warnings", [])))
    except RuledError as exc:
        rep = {}
        row.update(status="refused", reason=_text(job)(exc, job["face"]))
    row["seconds"] = time.perf_counter() - t0
    write_report({**rep, "batch": {"key": job["key"], "row": row}}, paths["json"])
    return row


def warm_worker() -> None:
    """What a new worker's first face would load, loaded while the batch plans its faces: the face job's modules
    and numba's compiler (its first call of a kernel, not the kernels)."""
    import numpy as np

    import ruled.jobs.face  # noqa: F401
    import ruled.occ.io  # noqa: F401
    from ruled.core.nurbs import Curve
    Curve(np.zeros((2, 3)), np.array([0.0, 0.0, 1.0, 1.0]), 1)(np.array([0.5]))


def _face_job(job: dict, paths: dict) -> dict:
    from ruled.jobs.face import run_fit
    from ruled.occ.io import read_faces
    faces = _FACES.get((job["input"], job["digest"]))
    if faces is None:
        faces = _FACES[(job["input"], job["digest"])] = read_faces(job["input"])
    o = job["options"]
    face = faces[job["face"]]

    def machine(ff):            # (--post: the face's wire path from its fit)
        from ruled.jobs.machine import machine_job
        from ruled.machine.paths import MachineOptions
        fm = machine_job(face, MachineOptions(), fit=ff, measure_samples=o["measure_samples"])
        return _machine_file(fm, o, paths)
    return run_fit(job["input"], job["face"], paths["step"], samples=o["samples"], objective=o["objective"],
                   max_error=o["max_error"], direction=o["direction"], method=o["method"],
                   measure_samples=o["measure_samples"], memory_cap_mb=job["memory_cap_mb"],
                   report=None, plot=paths["png"] if o.get("plots", True) else None, quiet=True,
                   face=face, say=False, text=lambda m: _text(job)(m, job["face"]),
                   after=machine if o.get("post") else None)


def _machine_file(fm, o: dict, paths: dict) -> dict:
    """A face's or a wall's XYUV file for the batch's --post, beside its STEP."""
    from ruled.jobs.machine import machine_file, post_extension
    from ruled.machine.program import PostSettings
    settings = PostSettings(post=o["post"])
    return machine_file(fm, paths["base"] + post_extension(settings), settings)


def _wall_job(job: dict, paths: dict) -> dict:
    from ruled.jobs.wall import run_wall
    o = job["options"]
    def machine(wf):            # (--post: the wall's one closed wire loop from its fit)
        from ruled.machine.paths import MachineOptions
        from ruled.occ.wallmachine import machine_of_wall
        return _machine_file(machine_of_wall(wf, MachineOptions(), measure_samples=o["measure_samples"]), o, paths)
    return run_wall(job["input"], job["wall"], paths["step"], samples=o["samples"], objective=o["objective"],
                    max_error=o["max_error"], method=o["method"], measure_samples=o["measure_samples"],
                    memory_cap_mb=job["memory_cap_mb"], quiet=True, say=False,
                    text=lambda m: _text(job)(m, job["face"]), after=machine if o.get("post") else None)


def _row(job: dict, status: str, reason: str = "", seconds=None) -> dict:
    """A summary row of the job's face (its figures None until the task fills them)."""
    return {"file": job["file"], "face": job["face"], "type": job["type"], "trimmed_pct": job["trimmed_pct"],
            "method": job["options"]["method"], "status": status, "error_bound": None, "hausdorff": None,
            "seconds": seconds, "warnings": "", "reason": reason}


def failed_row(job: dict, reason: str, seconds: float) -> dict:
    return _row(job, "failed", reason, seconds)


def _text(job: dict):       # how the job words an engine message (run_batch's text; default Python's terms)
    return job.get("text") or (lambda message, face: str(message))


def done_row(job: dict) -> Optional[dict]:
    """The row of a face finished by an earlier run with the same key (resume), or None."""
    paths = face_paths(job["folder"], job["face"])
    try:
        with open(paths["json"]) as fh:
            b = json.load(fh).get("batch", {})
    except (OSError, ValueError):
        return None
    if b.get("key") != job["key"] or b.get("row", {}).get("status") not in ("ok", "refused"):
        return None
    if b["row"]["status"] == "ok" and not os.path.exists(paths["step"]):
        return None
    return b["row"]


# ------------------------------------------------------------------------------------------ summary
def write_summary(rows: list, outdir: str) -> dict:
    """summary.csv, summary.json and summary.html (the worst faces first); returns the paths."""
    import csv
    import io

    from ruled.core.outputs import write_text
    rows = sort_rows(rows)
    paths = {k: os.path.join(outdir, f"summary.{k}") for k in ("csv", "json", "html")}
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=COLUMNS)
    w.writeheader()
    for r in rows:
        w.writerow({k: ("" if r.get(k) is None else r[k]) for k in COLUMNS})
    write_text(paths["csv"], buf.getvalue())
    counts = {s: sum(r["status"] == s for r in rows) for s in ("ok", "refused", "failed")}
    write_text(paths["json"], json.dumps({"faces": len(rows), **counts, "rows": rows}, indent=1))
    write_text(paths["html"], html_page(rows, outdir, counts))
    return paths


def sort_rows(rows: list) -> list:
    """The fitted faces from the largest error bound down, then the refused, then the failed."""
    order = {"ok": 0, "refused": 1, "failed": 2}
    return sorted(rows, key=lambda r: (order[r["status"]], -(r["error_bound"] or 0.0), r["file"], str(r["face"])))


def html_page(rows: list, outdir: str, counts: dict) -> str:
    """One self-contained page: the table (sortable by clicking a column), each face's plot inline."""
    import base64
    import html

    def num(x, fmt="{:.6g}"):
        return "" if x is None else fmt.format(x)
    cells = []
    for r in rows:
        png = face_paths(os.path.join(outdir, os.path.splitext(r["file"])[0]), r["face"])["png"]
        img = ""
        if os.path.exists(png):
            with open(png, "rb") as fh:
                img = f'<img src="data:image/png;base64,{base64.b64encode(fh.read()).decode()}" alt="plot">'
        cells.append(
            f'<tr class="{r["status"]}"><td>{html.escape(r["file"])}</td><td>{r["face"]}</td>'
            f'<td>{html.escape(str(r["type"]))}</td><td>{num(r["trimmed_pct"], "{:.0f}")}</td>'
            f'<td>{r["method"]}</td><td>{r["status"]}</td><td data-v="{r["error_bound"] or -1}">'
            f'{num(r["error_bound"])}</td><td data-v="{r["hausdorff"] or -1}">{num(r["hausdorff"])}</td>'
            f'<td>{num(r["seconds"], "{:.2f}")}</td><td class="note">{html.escape(r["reason"] or r["warnings"])}</td>'
            f'<td>{img}</td></tr>')
    head = "".join(f"<th onclick=\"sortBy({i})\">{h}</th>" for i, h in enumerate(
        ["file", "face", "type", "trimmed %", "method", "status", "error bound", "Hausdorff", "seconds", "note",
         "plot"]))
    return f"""<!DOCTYPE html>
<html><head><meta charset="utf-8"><title>ruled batch summary</title>
<style>
body {{ font-family: sans-serif; margin: 1.5em; }}
table {{ border-collapse: collapse; }}
th, td {{ border: 1px solid #ccc; padding: 3px 7px; text-align: right; vertical-align: middle; }}
th {{ background: #1f4e79; color: white; cursor: pointer; }}
td.note {{ text-align: left; max-width: 28em; font-size: 85%; }}
tr.refused td {{ background: #fff4d6; }} tr.failed td {{ background: #fbdcdc; }}
img {{ height: 90px; }}
</style></head><body>
<h1>ruled batch: {len(rows)} faces</h1>
<p>{counts['ok']} fitted, {counts['refused']} refused, {counts['failed']} failed; the worst first. Click a
column to sort by it. Lengths in model units; the error bound is certified, the Hausdorff distance measured
with OCCT against the face as bounded by its edges.</p>
<table id="t"><thead><tr>{head}</tr></thead><tbody>
{chr(10).join(cells)}
</tbody></table>
<script>
function sortBy(c) {{
  var t = document.getElementById("t").tBodies[0], rows = Array.from(t.rows);
  var dir = t.getAttribute("data-c") == c ? -1 : 1;
  t.setAttribute("data-c", dir == 1 ? c : "");
  rows.sort(function (a, b) {{
    var x = a.cells[c].getAttribute("data-v") || a.cells[c].textContent;
    var y = b.cells[c].getAttribute("data-v") || b.cells[c].textContent;
    var fx = parseFloat(x), fy = parseFloat(y);
    if (!isNaN(fx) && !isNaN(fy)) return dir * (fy - fx);
    return dir * x.localeCompare(y);
  }});
  rows.forEach(function (r) {{ t.appendChild(r); }});
}}
</script></body></html>
"""


def plan(inputs: list, outdir: str, spec, fraction: float, options: dict, memory_cap_mb: Optional[float],
         jobs: int) -> list:
    """The jobs of every selected face of every input."""
    from ruled.fit.fit2d import available_memory
    ins = [os.path.realpath(p) for p in inputs]
    out = os.path.realpath(outdir)
    for p, real in zip(inputs, ins):
        if not os.path.isfile(real):
            raise BadInputError(f"{p}: no such file; check the path")
    stems = [os.path.splitext(os.path.basename(p))[0] for p in ins]
    if len(set(stems)) != len(stems):
        raise BadInputError("two inputs have the same file name; their result folders would collide: rename one")
    cap = memory_cap_mb if memory_cap_mb is not None else 0.8 * available_memory() / 2.0 ** 20
    out_jobs = []
    for path, stem in zip(ins, stems):
        digest = file_digest(path)
        if options.get("walls"):
            from ruled.occ.io import read_shape
            from ruled.occ.ring import find_walls
            rings: list = [(f"wall {k}", list(r.faces), f"wall of {len(r.faces)} faces", None)
                     for k, r in enumerate(find_walls(read_shape(path)))]
            # a file with no wall is a row of the summary all the same: it says why nothing was cut
            for name, faces, kind, refusal in rings or [(NO_WALL, None, NO_WALL, "the part has no wall (no ring of "
                                                         "faces between two planar caps); give a wall's faces with "
                                                         "'ruled fit INPUT --wall K,L-M'")]:
                out_jobs.append({"input": path, "file": os.path.basename(path), "face": name, "wall": faces,
                                 "type": kind, "trimmed_pct": None, "refusal": refusal,
                                 "folder": os.path.join(out, stem), "digest": digest, "options": options,
                                 "key": job_key(digest, name, options), "memory_cap_mb": cap / max(1, jobs)})
            continue
        for k, kind, trimmed in select(path, spec, fraction):
            out_jobs.append({"input": path, "file": os.path.basename(path), "face": k, "type": kind,
                             "trimmed_pct": trimmed, "folder": os.path.join(out, stem), "digest": digest,
                             "options": options, "key": job_key(digest, k, options),
                             "memory_cap_mb": cap / max(1, jobs)})
    written = {os.path.join(j["folder"], f) for j in out_jobs for f in map(os.path.basename,
                                                                           face_paths(j["folder"], j["face"]).values())}
    written |= {os.path.join(out, f"summary.{k}") for k in ("csv", "json", "html")}
    clash = sorted(set(ins) & written)
    if clash:
        raise BadInputError(f"the input {clash[0]} would be overwritten by the batch's outputs; give another -o folder")
    return out_jobs


def run_batch(inputs: list, outdir: str, *, faces: str = "all", fraction: float = 0.01, options: dict,
              jobs: Optional[int] = None, scheduler: Optional[str] = None, resume: bool = False,
              face_timeout: float = 600.0, memory_cap_mb: Optional[float] = None, progress=None,
              text=None) -> dict:
    """The whole batch; returns {"rows": [...], "paths": {...}, "interrupted": bool}.  text(message, face): how
    a row words the engine's messages (a module-level function, which the workers get by name)."""
    if jobs is None:
        jobs = os.cpu_count() or 1
    if jobs < 1:
        raise BadInputError(f"--jobs {jobs} must be at least 1")
    positive("face_timeout", face_timeout, "seconds")
    spec = parse_faces(faces)
    # the cluster reachable first
    from ruled.batch.pools import DaskPool, LocalPool
    pool = DaskPool(scheduler, face_timeout, run_face, failed_row) if scheduler else \
        LocalPool(jobs, face_timeout, run_face, failed_row, warm_worker)
    try:
        pool.start(jobs)
        return _run(pool, inputs, outdir, spec, fraction, options, jobs, scheduler, resume, memory_cap_mb, progress,
                    text)
    finally:
        pool.close()


def _run(pool, inputs, outdir, spec, fraction, options, jobs, scheduler, resume, memory_cap_mb, progress,
         text=None) -> dict:
    os.makedirs(outdir, exist_ok=True)
    todo = plan(inputs, outdir, spec, fraction, options, memory_cap_mb, jobs)
    for j in todo:
        j["text"] = text
    for folder in {j["folder"] for j in todo}:
        os.makedirs(folder, exist_ok=True)
        for name in os.listdir(folder):          # what a killed batch was writing (never a named output)
            if name.startswith(".face_") and ".part" in name:
                with contextlib.suppress(OSError):
                    os.unlink(os.path.join(folder, name))
    finished = [done_row(job) if resume else None for job in todo]
    rows, run = [r for r in finished if r is not None], [j for j, r in zip(todo, finished) if r is None]
    run.sort(key=lambda j: -(j["trimmed_pct"] or 0.0))    # the longest (most trimmed) first: a short tail
    total, t0 = len(todo), time.perf_counter()

    def on_row(row):
        rows.append(row)
        if progress is not None:
            done = len(rows)
            per = (time.perf_counter() - t0) / max(1, done - (total - len(run)))
            left = per * (total - done) / (1 if scheduler else min(jobs, max(1, total - done)))
            progress(f"batch: {done}/{total} faces, ~{left:.0f} s left", done / max(1, total))

    interrupted = False
    try:
        pool.run(run, on_row)
    except KeyboardInterrupt:   # the summary of what finished; run_batch then stops the running faces
        interrupted = True
    paths = write_summary(rows, outdir)
    return {"rows": sort_rows(rows), "paths": paths, "interrupted": interrupted, "total": total}
