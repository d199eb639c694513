"""The parametric RuledFit object, headless in freecadcmd (Debian's FreeCAD 0.20): it fits, it
recomputes when its parameters or its source change, it survives save and reopen, bad input leaves it
invalid with a message, and on a face of a STEP read by FreeCAD it gives the command line's bound
and measured Hausdorff distance."""
import json
import os
import re
import subprocess
import sys
import textwrap

import pytest
from conftest import ROOT, WORKBENCH_LOADER, data_file, run_freecadcmd

pytestmark = pytest.mark.freecad

SCRIPT = textwrap.dedent("""
    code = 1
    try:
        import json
        import numpy as np, FreeCAD, Part
        from ruled_workbench.features import make_ruled_fit
        from ruled_workbench.adapter import surface_to_face, face_to_arrays
        from ruled_workbench.units import length
        from ruled.examples import elber_ex2
        from ruled.core.nurbs import Surface
        out = {{}}
        def props(o):
            return {{"valid": o.isValid(), "status": o.Status, "bound": float(o.ErrorBound),
                    "hausdorff": float(o.Hausdorff), "rulings": o.Rulings, "faces": len(o.Shape.Faces),
                    "dev": len(o.Deviation)}}
        doc = FreeCAD.newDocument("T")
        src = doc.addObject("Part::Feature", "Src")
        src.Shape = surface_to_face(elber_ex2())
        fit = make_ruled_fit(doc, src, "Face1", Samples=16, MeasureSamples=10)
        doc.recompute()
        out["first"] = props(fit)
        limit = lambda: [fit.ErrorLimit, fit.getEditorMode("MaxError")]
        out["limits"] = [limit()]
        fit.MaxError = 0.5
        out["limits"].append(limit())
        fit.MaxError = 0.0
        out["limits"].append(limit())
        fit.Samples = 24
        doc.recompute()
        out["samples24"] = props(fit)
        S = elber_ex2()
        P = S.poles.copy(); P[1, 2] += [0.0, 0.0, 0.15]                  # move one pole of the source
        src.Shape = surface_to_face(Surface(P, S.knots_u, S.knots_v, S.degree_u, S.degree_v))
        doc.recompute()
        out["moved"] = props(fit)
        fit4 = make_ruled_fit(doc, src, "Face1", Method="4d", Samples=12, Elevations=2, Metric="sshb",
                              MeasureSamples=0)
        doc.recompute()
        out["fit4"] = props(fit4)
        doc.removeObject(fit4.Name)
        bad_edge = make_ruled_fit(doc, src, "Edge1", Samples=16)
        sphere = doc.addObject("Part::Feature", "Sphere"); sphere.Shape = Part.makeSphere(3)  # poles, no rails
        bad_apex = make_ruled_fit(doc, sphere, "Face1", Samples=16, MeasureSamples=0)
        bad_none = doc.addObject("Part::FeaturePython", "Empty")
        from ruled_workbench.features import RuledFit
        RuledFit(bad_none)
        doc.recompute()
        out["bad"] = [props(o) for o in (bad_edge, bad_apex, bad_none)]
        out["limit_after"] = getattr(sys, "tracebacklimit", "unset")
        path = os.path.join({tmp!r}, "t.FCStd")
        doc.saveAs(path)
        FreeCAD.closeDocument("T")
        d2 = FreeCAD.openDocument(path)
        g = d2.getObject("RuledFit")
        out["reopened"] = dict(props(g), proxy=type(g.Proxy).__module__ + "." + type(g.Proxy).__name__,
                               samples=g.Samples)
        g.Samples = 20
        d2.recompute()
        out["reopened_recomputed"] = props(g)
        # a face of a STEP read by FreeCAD
        shape = Part.read({step!r})
        imp = d2.addObject("Part::Feature", "Impeller"); imp.Shape = shape
        k = make_ruled_fit(d2, imp, "Face7", Samples=16, MeasureSamples=12)
        d2.recompute()
        out["step"] = dict(props(k), area_ratio=k.Shape.Area / imp.Shape.getElement("Face7").Area,
                           rails=list(k.Rails), trimmed=k.Trimmed, patch=float(k.PatchDeviation),
                           ends=k.Ends, ends_used=k.EndsUsed, result_valid=k.Shape.isValid(),
                           rail_edges=[[imp.Shape.getElement(n).isSame(e) for e in imp.Shape.getElement("Face7").Edges]
                                       for r in k.Rails for n in r.split(" + ")],
                           bound_text=length(k.ErrorBound), label=k.Label)
        json.dump(out, open({out!r}, "w"))
        code = 0
    except Exception:
        import traceback; traceback.print_exc()
    sys.stdout.flush(); sys.stderr.flush()
    os._exit(code)
""")


@pytest.mark.slow     # (29 s: the loop stays under 3 minutes; CI runs it)
def test_ruled_fit_object_in_freecadcmd(tmp_path):
    step = data_file("kj66_impeller.step")
    out = tmp_path / "out.json"
    run = run_freecadcmd(WORKBENCH_LOADER + SCRIPT.format(tmp=str(tmp_path), step=step, out=str(out)), tmp_path,
                         1200)
    # refusals are messages in the report view, not Python tracebacks; the limit is restored afterwards
    assert "Traceback" not in run.stdout + run.stderr
    assert "the source must be exactly one face" in run.stdout + run.stderr
    r = json.loads(out.read_text())
    first = r["first"]
    assert first["valid"] and first["status"] == "ok" and first["faces"] == 1 and first["dev"] == 100
    # no limit says so, Max Error hidden; a Max Error set sets the limit and shows it (issue 59)
    assert r["limits"] == [["no limit", ["Hidden"]], ["at most Max Error", []], ["no limit", ["Hidden"]]], r["limits"]
    assert first["bound"] >= first["hausdorff"] > 0
    # the same fit as the engine's in this venv (numba here, NumPy in FreeCAD)
    from ruled import FitOptions, fit_surface
    from ruled.examples import elber_ex2
    ref = fit_surface(elber_ex2(), FitOptions(samples=16))
    # plus how far the face's edges lie off its surface (OCCT's 3D curves at their pcurves' parameters: to
    # round-off since issue 36), the two computations the same to round-off
    assert ref.error_bound * (1 - 1e-9) <= first["bound"] <= ref.error_bound + 1e-6, (first["bound"], ref.error_bound)
    assert first["rulings"] == len(ref.best.rulings)
    assert r["samples24"]["valid"] and r["samples24"]["rulings"] != first["rulings"]
    assert r["moved"]["valid"] and abs(r["moved"]["bound"] - r["samples24"]["bound"]) > 1e-4
    assert r["fit4"]["valid"] and r["fit4"]["status"] == "ok" and r["fit4"]["bound"] > 0
    edge, apex, none = r["bad"]
    assert not edge["valid"] and "exactly one face" in edge["status"] and "Edge1" in edge["status"]
    assert not apex["valid"] and apex["status"] and "\n" not in apex["status"]
    assert not none["valid"] and "no source face" in none["status"]
    assert r["limit_after"] == "unset"
    ro = r["reopened"]
    assert ro["proxy"] == "ruled_workbench.features.RuledFit" and ro["samples"] == 24
    assert ro["bound"] == pytest.approx(r["moved"]["bound"], rel=1e-12) and ro["faces"] == 1   # saved with 16 digits
    assert r["reopened_recomputed"]["valid"] and r["reopened_recomputed"]["bound"] != ro["bound"]
    # the command line on the same face (index 6 = Face7): the same bound and measured distance
    rep = tmp_path / "cli.json"
    # (both at their default ends, auto: here the result trimmed by the face's edges)
    cli = subprocess.run([sys.executable, "-m", "ruled.cli", "fit", step, "--face", "6", "--samples", "16",
                          "--measure-samples", "12", "-o", str(tmp_path / "f.step"),
                          "--report", str(rep), "--quiet"],
                         capture_output=True, text=True, cwd=ROOT, timeout=600)
    assert cli.returncode == 0, cli.stderr
    c = json.loads(rep.read_text())
    st = r["step"]
    assert st["valid"], st["status"]
    assert st["bound"] == pytest.approx(c["error_bound"], rel=1e-6)
    assert st["hausdorff"] == pytest.approx(c["hausdorff"]["max"], rel=1e-6, abs=1e-9)
    # the face as bounded by its edges: the result trimmed by them (issue 35) has the face's area, the rails are
    # two of its edges
    assert c["trim"]["ends"] == "trimmed" and st["ends"] == "auto" and "run past the face" in st["ends_used"], st
    assert st["trimmed"] and st["result_valid"] and abs(st["area_ratio"] - 1.0) <= 5e-3, st
    assert len(st["rails"]) == 2 and all(r.startswith("Edge") for r in st["rails"])
    assert all(any(hits) for hits in st["rail_edges"])          # each rail is an edge of the source face
    assert st["bound"] >= st["hausdorff"] and 0 < st["patch"] < st["bound"]
    # the report view's notes give the object's bound, in the user's unit, as the panel prints it (issue 59)
    notes = [line for line in (run.stdout + run.stderr).splitlines() if line.startswith(st["label"] + ": ")]
    assert any(f"bound {st['bound_text']}" in line for line in notes), (st["bound_text"], notes)
    assert not any(re.search(r"(bound|trimmed|pinned) \d[\d.e-]*(?! ?[µnm]m)[ ,)]", line) for line in notes), notes


SPLIT_SCRIPT = textwrap.dedent("""
    code = 1
    try:
        import json
        import FreeCAD, Part
        from ruled_workbench.features import make_ruled_split
        from ruled_workbench.adapter import surface_to_face
        from ruled.examples import elber_ex2
        doc = FreeCAD.newDocument("S")
        src = doc.addObject("Part::Feature", "Src")
        src.Shape = surface_to_face(elber_ex2())
        sp = make_ruled_split(doc, src, "Face1", Samples=10, Interior=4, FitSamples=12)
        bad = make_ruled_split(doc, src, "Edge1")
        small = make_ruled_split(doc, src, "Face1", Samples=2)
        doc.recompute()
        on_face = max(src.Shape.Faces[0].distToShape(Part.Vertex(p))[0] for p in sp.SplitCurve)
        out = {{"valid": sp.isValid(), "status": sp.Status, "chosen": sp.Chosen, "bound": float(sp.ErrorBound),
               "whole": float(sp.WholeBound), "candidates": list(sp.Candidates), "faces": len(sp.Shape.Faces),
               "edges": len(sp.Shape.Edges), "curve": len(sp.SplitCurve), "on_face": on_face,
               "bad": [bad.isValid(), bad.Status],
               "small": [small.isValid(), small.Status, small.PropertiesList]}}
        path = os.path.join({tmp!r}, "s.FCStd")
        doc.saveAs(path)
        FreeCAD.closeDocument("S")
        d2 = FreeCAD.openDocument(path)
        g = d2.getObject("RuledSplit")
        out["reopened"] = type(g.Proxy).__module__ + "." + type(g.Proxy).__name__
        json.dump(out, open({out!r}, "w"))
        code = 0
    except Exception:
        import traceback; traceback.print_exc()
    sys.stdout.flush(); sys.stderr.flush()
    os._exit(code)
""")


@pytest.mark.slow
def test_ruled_split_object_in_freecadcmd(tmp_path):
    """'Split for ruling' headless: the same split as the engine in the venv, the split curve on the face,
    the two fitted sides, an invalid object for an edge, and the proxy's name after reopening."""
    out = tmp_path / "split.json"
    run_freecadcmd(WORKBENCH_LOADER + SPLIT_SCRIPT.format(tmp=str(tmp_path), out=str(out)), tmp_path)
    r = json.loads(out.read_text())
    assert r["valid"] and r["status"] == "ok", r
    assert r["faces"] == 2 and r["edges"] >= 9 and r["curve"] == 101
    assert r["on_face"] <= 1e-6
    from ruled import FitOptions
    from ruled.examples import elber_ex2
    from ruled.split.partition import SplitOptions, split_face
    res = split_face(elber_ex2(), SplitOptions(samples=10, interior=4, fit=FitOptions(samples=12)))
    best = res.best()
    assert r["chosen"] == best.name
    # plus how far the face's edges lie off its surface (OCCT's 3D curves at their pcurves' parameters: to
    # round-off since issue 36), the two computations the same to round-off
    assert best.bound * (1 - 1e-9) <= r["bound"] <= best.bound + 1e-6 and r["bound"] < r["whole"], \
        (r["bound"], best.bound)
    assert len(r["candidates"]) == len(res.candidates)
    assert r["bad"][0] is False and "exactly one face" in r["bad"][1]
    # an engine refusal names the remedy in FreeCAD's terms: the object's own properties, no flags
    valid, status, props = r["small"]
    assert valid is False and status.startswith("Samples = 2 is too small for a split; use at least 4"), status
    assert "--" not in status and "samples=" not in status
    named = set(re.findall(r"\b([A-Z][A-Za-z]+) = ", status))
    assert named == {"Samples"} and named <= set(props)
    assert r["reopened"] == "ruled_workbench.features.RuledSplit"


REOPEN_MAKE = textwrap.dedent("""
    import os, sys, json
    code = 1
    try:
        import FreeCAD, Part
        from ruled_workbench.features import make_ruled_fit, make_ruled_split    # loaded by the addon's Init.py
        from ruled_workbench.adapter import surface_to_face
        from ruled.examples import elber_ex2
        doc = FreeCAD.newDocument("R")
        src = doc.addObject("Part::Feature", "Src")
        src.Shape = surface_to_face(elber_ex2())
        fit = make_ruled_fit(doc, src, "Face1", Samples=16, MeasureSamples=10)
        sp = make_ruled_split(doc, src, "Face1", Samples=10, Interior=4, FitSamples=12)
        doc.recompute()
        json.dump({{"fit": float(fit.ErrorBound), "split": float(sp.ErrorBound)}}, open({out!r}, "w"))
        doc.saveAs({path!r})
        code = 0
    except Exception:
        import traceback; traceback.print_exc()
    sys.stdout.flush(); sys.stderr.flush()
    os._exit(code)
""")

REOPEN_OPEN = textwrap.dedent("""
    import os, sys, json
    code = 1
    try:
        import FreeCAD
        doc = FreeCAD.openDocument({path!r})
        fit, sp = doc.getObject("RuledFit"), doc.getObject("RuledSplit")
        proxies = [type(o.Proxy).__module__ + "." + type(o.Proxy).__name__ for o in (fit, sp)]
        fit.touch(); sp.touch()
        doc.recompute()
        json.dump({{"proxies": proxies, "valid": [fit.isValid(), sp.isValid()], "fit": float(fit.ErrorBound),
                   "split": float(sp.ErrorBound), "status": [fit.Status, sp.Status]}}, open({out!r}, "w"))
        code = 0
    except Exception:
        import traceback; traceback.print_exc()
    sys.stdout.flush(); sys.stderr.flush()
    os._exit(code)
""")


@pytest.mark.slow
def test_reopen_in_a_fresh_freecadcmd_with_the_addon_installed(tmp_path):
    """The README's install (a link in the user Mod folder): a document saved with a RuledFit and a
    RuledSplit reopens in another freecadcmd with their code (Init.py makes ruled_workbench importable
    from the Mod folder, which FreeCAD's restore check permits), no traceback or blocked import in the
    log, and recomputes to the same results."""
    import os
    mod = tmp_path / ".local" / "share" / "FreeCAD" / "Mod"
    mod.mkdir(parents=True)
    os.symlink(ROOT, mod / "Ruled")
    path, made, opened = str(tmp_path / "r.FCStd"), tmp_path / "made.json", tmp_path / "opened.json"
    run_freecadcmd(REOPEN_MAKE.format(path=path, out=str(made)), tmp_path)
    run = run_freecadcmd(REOPEN_OPEN.format(path=path, out=str(opened)), tmp_path)
    log = run.stdout + run.stderr
    assert "Traceback" not in log and "blocked import" not in log and "not permitted" not in log, log[-2000:]
    a, b = json.loads(made.read_text()), json.loads(opened.read_text())
    assert b["proxies"] == ["ruled_workbench.features.RuledFit", "ruled_workbench.features.RuledSplit"]
    assert b["valid"] == [True, True] and b["status"] == ["ok", "ok"]
    assert b["fit"] == pytest.approx(a["fit"], rel=1e-12) and b["split"] == pytest.approx(a["split"], rel=1e-12)


@pytest.mark.slow     # (6 s: the loop stays under 3 minutes; CI runs it)
def test_a_result_that_contradicts_its_own_figures_is_an_invalid_object(tmp_path):
    """Issue 34 in FreeCAD: the bound of a face whose measure is within 0.02 % of it (the fuzz's face
    2202:7) broken to 0.9x itself inside freecadcmd: the RuledFit is invalid, its Status names both
    figures; with the true bound the same object is valid.  A face ruled exactly whose result is folded back
    over itself (tests/provoke.py: twice the face's area, as close as before), along v (across, the fit is far
    enough that its area may differ): invalid, its Status saying it covers another region."""
    pytest.importorskip("OCP")
    import fuzz_faces as fz
    from conftest import freecad_json
    from trimmed_faces import ruled_sheet_face

    from ruled.occ.io import write_step
    step, sheet = str(tmp_path / "tight.step"), str(tmp_path / "sheet.step")
    write_step(fz.face_named("2d:2202:7").face, step)
    write_step(ruled_sheet_face(), sheet)
    out = freecad_json(f"""
import FreeCAD, Part
import ruled.fit.fit2d as f
from ruled_workbench.features import make_ruled_fit
doc = FreeCAD.newDocument("T")
src = doc.addObject("Part::Feature", "Src")
src.Shape = Part.read({step!r})
fit = make_ruled_fit(doc, src, "Face1", Samples={fz.SAMPLES}, MeasureSamples={fz.SAMPLES})
true_bound = f.DirectionFit.error_bound
f.DirectionFit.error_bound = property(lambda self: 0.9 * self.certificate.bound)
doc.recompute()
out["broken"] = [fit.isValid(), fit.Status]
f.DirectionFit.error_bound = true_bound
fit.touch()
doc.recompute()
out["true"] = [fit.isValid(), fit.Status, float(fit.ErrorBound), float(fit.Hausdorff)]
sys.path.insert(0, {os.path.dirname(os.path.dirname(__file__))!r})
import provoke, ruled.fit.face.fit
provoke.fold_results(ruled.fit.face.fit)
src2 = doc.addObject("Part::Feature", "Sheet")
src2.Shape = Part.read({sheet!r})
folded = make_ruled_fit(doc, src2, "Face1", Samples=16, MeasureSamples=16, Direction="v")
doc.recompute()
out["folded"] = [folded.isValid(), folded.Status]
""", tmp_path)
    valid, status = out["broken"]
    assert not valid and "is above its certified bound" in status and "\n" not in status, out
    valid, status, bound, measured = out["true"]
    assert valid and status == "ok" and 0.9 * bound < measured <= bound, out
    valid, status = out["folded"]
    assert not valid and "covers another region" in status and "\n" not in status, out
