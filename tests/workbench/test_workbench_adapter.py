"""The FreeCAD adapter (workbench/adapter.py) in FreeCAD 0.20's own Python: Part.BSplineSurface <->
the engine's arrays, exactly, for rational and periodic surfaces; FreeCAD evaluates the rebuilt
surfaces where the engine evaluates the containers."""
import json
import textwrap

import numpy as np
import pytest
from cases import random_surface
from conftest import WORKBENCH_LOADER, run_freecadcmd

from ruled.core.nurbs import Surface

pytestmark = pytest.mark.freecad

SCRIPT = textwrap.dedent("""
    import json
    code = 1
    try:
        import numpy as np, Part, FreeCAD
        from ruled_workbench.adapter import arrays_to_surface, surface_to_arrays, face_to_arrays, surface_to_face
        from ruled.core.nurbs import Surface
        cases = json.load(open({inp!r}))
        out = {{"containers": [], "native": []}}
        for c in cases["containers"]:
            S = Surface(np.array(c["poles"]), c["knots_u"], c["knots_v"], c["pu"], c["pv"],
                        None if c["weights"] is None else np.array(c["weights"]), c["per_u"], c["per_v"])
            bs = arrays_to_surface(S)
            back = surface_to_arrays(bs)
            vals = [tuple(bs.value(u, v)) for u, v in c["uv"]]
            out["containers"].append({{"values": vals, "periodic": [bs.isUPeriodic(), bs.isVPeriodic()],
                                      "face_ok": surface_to_face(S).isValid()}})
        natives = [Part.makeCylinder(5, 10).Faces[0], Part.makeCone(4, 2, 6).Faces[0],
                   Part.makeSphere(3).Faces[0], Part.makeTorus(6, 2).Faces[0]]
        for f in natives:
            s = f.toNurbs().Faces[0].Surface
            S = face_to_arrays(f)
            b = arrays_to_surface(S)
            same = (b.getPoles() == s.getPoles() and b.getWeights() == s.getWeights() and
                    b.getUKnots() == s.getUKnots() and b.getVKnots() == s.getVKnots() and
                    b.getUMultiplicities() == s.getUMultiplicities() and
                    b.getVMultiplicities() == s.getVMultiplicities() and
                    (b.isUPeriodic(), b.isVPeriodic()) == (s.isUPeriodic(), s.isVPeriodic()))
            u0, u1, v0, v1 = s.bounds()
            uv = [(u0 + (u1 - u0) * a, v0 + (v1 - v0) * b_) for a in (0.1, 0.37, 0.9) for b_ in (0.2, 0.55, 0.8)]
            out["native"].append({{"same": same, "periodic": [s.isUPeriodic(), s.isVPeriodic()],
                                  "uv": uv, "values": [tuple(s.value(u, v)) for u, v in uv],
                                  "S": {{"poles": S.poles.tolist(),
                                        "weights": None if S.weights is None else S.weights.tolist(),
                                        "knots_u": S.knots_u.tolist(), "knots_v": S.knots_v.tolist(),
                                        "pu": S.degree_u, "pv": S.degree_v, "per_u": S.periodic_u,
                                        "per_v": S.periodic_v}}}})
        try:
            face_to_arrays(Part.makeBox(1, 1, 1).Edges[0])
        except Exception as exc:
            out["edge_error"] = type(exc).__name__ + ": " + str(exc)
        json.dump(out, open({out!r}, "w"))
        code = 0
    except Exception:
        import traceback; traceback.print_exc()
    sys.stdout.flush(); sys.stderr.flush()
    os._exit(code)
""")


def _as_dict(S: Surface, uv):
    return {"poles": S.poles.tolist(), "weights": None if S.weights is None else S.weights.tolist(),
            "knots_u": S.knots_u.tolist(), "knots_v": S.knots_v.tolist(), "pu": S.degree_u, "pv": S.degree_v,
            "per_u": S.periodic_u, "per_v": S.periodic_v, "uv": uv}


def test_adapter_round_trips_exactly_in_freecad(tmp_path, rng):
    surfaces = [random_surface(rng, rational=True), random_surface(rng, rational=False),
                random_surface(rng, rational=True, periodic_u=True)]
    uv = []
    for S in surfaces:
        u0, u1, v0, v1 = S.domain
        uv.append([(u0 + (u1 - u0) * a, v0 + (v1 - v0) * b) for a in (0.05, 0.5, 0.93) for b in (0.1, 0.6, 0.99)])
    inp, out = tmp_path / "in.json", tmp_path / "out.json"
    inp.write_text(json.dumps({"containers": [_as_dict(S, p) for S, p in zip(surfaces, uv)]}))
    run_freecadcmd(WORKBENCH_LOADER + SCRIPT.format(inp=str(inp), out=str(out)), tmp_path)
    res = json.loads(out.read_text())
    # engine containers -> Part.BSplineSurface: FreeCAD evaluates them where the engine does
    for S, p, r in zip(surfaces, uv, res["containers"]):
        u, v = np.array(p).T
        assert np.abs(np.array(r["values"]) - S(u, v)).max() <= 1e-12 * S.diagonal()
        assert r["face_ok"]
    assert res["containers"][2]["periodic"] == [True, False]
    # FreeCAD's own surfaces (periodic, rational) -> arrays -> Part: identical poles, weights, knots,
    # multiplicities and periodic flags; the containers evaluate like FreeCAD
    assert all(n["same"] for n in res["native"])
    assert any(n["periodic"][0] or n["periodic"][1] for n in res["native"])
    for n in res["native"]:
        d = n["S"]
        S = Surface(np.array(d["poles"]), d["knots_u"], d["knots_v"], d["pu"], d["pv"],
                    None if d["weights"] is None else np.array(d["weights"]), d["per_u"], d["per_v"])
        u, v = np.array(n["uv"]).T
        assert np.abs(np.array(n["values"]) - S(u, v)).max() <= 1e-12 * max(S.diagonal(), 1.0)
    assert "BadInputError" in res["edge_error"] and "select one face" in res["edge_error"]
