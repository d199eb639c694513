"""Walls in the workbench, headless in Debian's freecadcmd: FreeCAD's adapter reads a wall's faces into the
same joined surface as the command line's OCCT reading (the engine's ring, patches and joining on both), a
RuledWall recomputes within its bound against the wall's faces, measured here with OCCT both ways, and bad
rings leave an invalid object with the engine's one-line reason."""
import json
import os

import numpy as np
import pytest
from conftest import freecad_json

pytestmark = pytest.mark.freecad

BODY = """
import FreeCAD, Part
from ruled_workbench.adapter import Wall
from ruled_workbench.walls import make_ruled_wall
doc = FreeCAD.newDocument("W")
for name, ids in PARTS.items():
    part = doc.addObject("Part::Feature", name)
    part.Shape = Part.read(STEPS[name])
    w = Wall([part.Shape.Faces[i] for i in ids], [f"Face{i + 1}" for i in ids])
    S = w.surface
    out[name] = {"poles": S.poles.tolist(), "knots": S.knots_u.tolist(), "breaks": w.breaks.tolist(),
                 "corners": w.corners, "names": w.names,
                 "weights": None if S.weights is None else S.weights.tolist()}
part = doc.getObject("square_to_circle")
obj = make_ruled_wall(doc, part, [f"Face{i + 1}" for i in PARTS["square_to_circle"]], MeasureSamples=12)
bad = {"not_a_band": make_ruled_wall(doc, part, ["Face1", "Face2"]),
       "an_edge": make_ruled_wall(doc, part, ["Face1", "Edge2"])}
doc.recompute()
out["fit"] = {"valid": obj.isValid(), "status": obj.Status, "bound": obj.ErrorBound.Value,
              "hausdorff": obj.Hausdorff.Value, "pieces": obj.Pieces}
obj.Shape.exportStep(STEPS["out"])
out["bad"] = {k: [o.isValid(), o.Status] for k, o in bad.items()}
"""


@pytest.mark.slow     # (11 s: the loop stays under 3 minutes; CI runs it)
def test_a_wall_read_by_freecad_is_the_command_lines(tmp_path):
    from wall_parts import airfoil_loft, square_to_circle, tapered_extrusion

    from ruled.core.nurbs import Surface
    from ruled.occ.io import faces_of, read_shape, write_step
    from ruled.occ.wall import measure_wall, wall_of
    walls, steps = {}, {"out": str(tmp_path / "out.step")}
    for build in (tapered_extrusion, square_to_circle, airfoil_loft):
        steps[build.__name__] = str(tmp_path / f"{build.__name__}.step")
        write_step(build().wrapped, steps[build.__name__])
        walls[build.__name__] = wall_of(read_shape(steps[build.__name__]))
    parts = {k: list(w.ring.faces) for k, w in walls.items()}
    out = freecad_json(f"PARTS = {parts!r}\nSTEPS = {steps!r}\n" + BODY, tmp_path)
    for name, w in walls.items():
        r = out[name]
        assert r["names"] == [f"Face{i + 1}" for i in w.ring.faces] and r["corners"] == w.corners
        got = Surface(np.array(r["poles"]), np.array(r["knots"]), w.surface.knots_v, w.surface.degree_u,
                      w.surface.degree_v, None if r["weights"] is None else np.array(r["weights"]))
        assert np.allclose(r["breaks"], w.breaks, atol=1e-12)
        u = np.linspace(0, 1, 401)
        for v in (0.0, 0.37, 1.0):
            assert np.abs(got(u, np.full(u.size, v)) - w.surface(u, np.full(u.size, v))).max() <= 1e-9 * w.size
    f = out["fit"]
    assert f["valid"] and f["status"] == "ok" and f["pieces"] == 1, f
    # the RuledWall's face against the wall's faces, measured here with OCCT, both ways
    h = measure_wall(walls["square_to_circle"].faces, faces_of(read_shape(steps["out"]))[0], 20)
    assert h.max <= f["bound"] <= 1e-6 * walls["square_to_circle"].size, (h.max, f)
    assert f["hausdorff"] <= f["bound"]
    for key, words in (("not_a_band", "are not a wall: their free edges make one free contour"),
                       ("an_edge", "a wall is made of faces, not Edge2")):
        valid, status = out["bad"][key]
        assert not valid and words in status and "\n" not in status, (key, status)
    json.dumps(out)


DIE = """
import FreeCAD, Part
from ruled_workbench.walls import make_ruled_wall
from ruled_workbench.export import wall_export
doc = FreeCAD.newDocument("D")
part = doc.addObject("Part::Feature", "Die")
part.Shape = Part.read(STEPS["die"])
hole = make_ruled_wall(doc, part, [f"Face{i + 1}" for i in FACES], MeasureSamples=0)
pieces = make_ruled_wall(doc, part, [f"Face{i + 1}" for i in FACES], MeasureSamples=0, PerFace=True)
doc.recompute()
out["hole"] = {"status": hole.Status, "bound": hole.ErrorBound.Value}
out["pieces"] = {"status": pieces.Status, "faces": len(pieces.Shape.Faces), "valid": pieces.Shape.isValid(),
                 "area": pieces.Shape.Area, "type": pieces.Shape.ShapeType,
                 "design": sum(part.Shape.Faces[i].Area for i in FACES)}
rep = wall_export(hole, STEPS["ngc"], "xyuv", kerf=0.15, measure_samples=0)
out["side"] = rep["side"]
"""


@pytest.mark.slow
def test_a_die_holes_wall_in_freecad_cuts_as_the_command_line_and_per_face(tmp_path):
    """The die block's hole: FreeCAD's RuledWall exported with the kerf on its default side (in the hole, off
    the material) is 'ruled machine --wall hole''s file byte for byte; with PerFace, one valid sewn shell
    of one piece per face covering the wall."""
    from wall_parts import die_block

    from ruled.cli.main import main
    from ruled.occ.io import read_shape, write_step
    from ruled.occ.wall import wall_of
    step = str(tmp_path / "die.step")
    write_step(die_block().wrapped, step)
    faces = sorted(wall_of(read_shape(step), "hole").ring.faces)
    os.makedirs(tmp_path / "fc")
    steps = {"die": step, "ngc": str(tmp_path / "fc" / "hole.ngc")}
    out = freecad_json(f"STEPS = {steps!r}\nFACES = {faces!r}\n" + DIE, tmp_path)
    assert out["hole"]["status"] == "ok" and out["side"] == "inside the hole (off the material)", out
    p = out["pieces"]
    assert p["status"] == "ok" and p["valid"] and p["faces"] == len(faces) and p["type"] == "Shell", p
    assert abs(p["area"] - p["design"]) <= 1e-4 * p["design"], p       # (the fit is 1e-3 off near two corners)
    cli = str(tmp_path / "hole.ngc")
    assert main(["machine", step, "--wall", "hole", "--xyuv", "--kerf", "0.15", "-o", cli, "--quiet",
                 "--measure-samples", "4"]) == 0
    assert open(steps["ngc"], "rb").read() == open(cli, "rb").read()      # one file from every door (issue 71)
