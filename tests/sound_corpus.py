"""The soundness corpus (issue 72): faces of every source the project has, each through the whole ``ruled fit`` job
and its result measured again densely by OCCT (ruled.occ.measure.hausdorff at DENSE x DENSE of each face as
bounded by its edges, both ways, its edges and the rows beside edges that lie off their surface), against the
certified bound.  A row per face; benchmarks/soundness.py runs the whole corpus, tests/fit/test_soundness.py a
slice that rotates with the commit (fuzz_seed.commit_seed), as the fuzz run does.

Sources: "data" (every B-spline face of tests/data and ../shared/data: benchmarks/data.data_files), "wavy" and
"ruled" (tests/wavy_faces.py: trimmed faces with wavy boundaries; exactly ruled faces across their iso lines),
"fuzz" (tests/fuzz_faces.py's random faces and issue 34's kinds, by name)."""

from __future__ import annotations

import glob
import os
import time

from fuzz_seed import ROOT

DENSE = 80          # the independent measure's samples per direction of each face
SAMPLES = 12        # the job's own measure (as the census takes it): the dense one is the check


def data_files() -> list:
    """The CAD files of tests/data, and those of ../shared/data not copied there."""
    own = sorted(glob.glob(os.path.join(ROOT, "tests", "data", "*.st*p")) +
                 glob.glob(os.path.join(ROOT, "tests", "data", "*.brep")))
    names = {os.path.basename(p) for p in own}
    shared = os.path.join(os.path.dirname(ROOT), "shared", "data")
    more = sorted(p for p in glob.glob(os.path.join(shared, "*")) if p.lower().endswith((".step", ".stp", ".brep"))
                  and os.path.basename(p) not in names)
    return own + more


def data_faces(files=None) -> list:
    """("data", (path, k)) for every B-spline face of the files (default: data_files())."""
    from ruled.occ.convert import face_surface_type
    from ruled.occ.io import read_faces
    return [("data", (p, k)) for p in (files or data_files()) for k, f in enumerate(read_faces(p))
            if face_surface_type(f) == "bspline"]


def _face(source: str, key, folder: str) -> tuple:
    """(the STEP or BRep file, the face's index in it, a name) of a corpus face."""
    if source == "data":
        path, k = key
        return path, k, f"{os.path.basename(path)} face {k}"
    from ruled.occ.io import write_step
    if source in ("wavy", "ruled"):
        from wavy_faces import ruled_face, wavy_face
        face, name = (wavy_face if source == "wavy" else ruled_face)(key)
    else:
        from fuzz_faces import face_named
        ff = face_named(key)
        face, name = ff.face, f"fuzz {key} ({ff.desc})"
    path = os.path.join(folder, f"{source}_{str(key).replace(':', '_')}.step")
    write_step(face, path)
    return path, 0, name


def sound_row(job: tuple) -> dict:
    """One corpus face: job = (source, key, folder, dense).  The row: status (fitted, refused, failed, invalid
    input: a generated face OCCT's checker refuses), the bound, the job's own measure, the dense measure (both
    ways) and the face's size, the CPU seconds; a refusal's reason (one for "measured above the bound" is a
    certificate's bug)."""
    from OCP.BRepCheck import BRepCheck_Analyzer

    from ruled.core.errors import RuledError
    from ruled.jobs.face import run_fit
    from ruled.occ.io import read_faces
    from ruled.occ.measure import hausdorff
    source, key, folder, dense = job
    path, k, name = _face(source, key, folder)
    row = {"source": source, "key": key, "name": name}
    face = read_faces(path)[k]
    if source != "data" and not BRepCheck_Analyzer(face).IsValid():     # (a file's face is fitted as it is)
        return {**row, "status": "invalid input"}
    out = os.path.join(folder, f"{source}_{abs(hash(str(key)))}_result.step")
    t0 = time.process_time()
    try:
        rep = run_fit(path, k, out, quiet=True, say=False, measure_samples=SAMPLES, face_timeout=300.0)
    except RuledError as exc:
        return {**row, "status": "refused", "reason": str(exc), "cpu": time.process_time() - t0}
    except Exception as exc:  # a crash is a row too: the count says so
        return {**row, "status": "failed", "reason": f"{type(exc).__name__}: {exc}", "cpu": time.process_time() - t0}
    t1 = time.process_time()
    h = hausdorff(face, read_faces(out)[0], dense)
    return {**row, "status": "fitted", "bound": rep["error_bound"], "measured": rep["hausdorff"]["max"],
            "dense": h.max, "face_to_result": h.max_a_to_b, "result_to_face": h.max_b_to_a,
            "size": (rep.get("region") or {}).get("face_size") or 0.0, "cpu": t1 - t0,
            "measure_cpu": time.process_time() - t1}


def above(row: dict) -> bool:
    """A fitted face whose dense measure exceeds its bound (beyond round-off)."""
    return row["status"] == "fitted" and row["dense"] > row["bound"] * (1.0 + 1e-9) + 1e-12 * max(row["size"], 1.0)


def refused_above(row: dict) -> bool:
    """A face refused because the job measured its result above the bound: the gate caught a certificate's bug."""
    return row["status"] == "refused" and "above its certified bound" in row["reason"]


__all__ = ["DENSE", "SAMPLES", "data_files", "data_faces", "sound_row", "above", "refused_above"]
