"""A part's wall in one cut (issue 37): one closed XYUV loop over the wall's closed ruled surface, a single
lead-in and lead-out at the start the user names, the kerf round the whole loop with its corners handled.

Measured independently of the path's own measure: the G-code replayed through gcodeparser, the wire's
lines rebuilt from it alone, their distances to the wall's faces by BRepExtrema, and the wall's points'
distances to the lines by brute force over the segments."""

from __future__ import annotations

import os

import numpy as np
import pytest

pytest.importorskip("cadquery")

from tests.machine_helpers import wall_cut_check  # noqa: E402
from tests.wall_parts import tapered_extrusion  # noqa: E402

HEIGHT = 15.0     # the tapered extrusion's bottom and top contours lie at z = 0 and z = 15


@pytest.fixture(scope="module")
def part(tmp_path_factory):
    from ruled.occ.io import write_step
    d = tmp_path_factory.mktemp("wall")
    path = str(d / "tapered.step")
    write_step(tapered_extrusion().wrapped, path)
    return path, d


def _run(part, name, *args):
    import json

    from ruled.cli.main import main
    path, d = part
    out, rep = str(d / f"{name}.ngc"), str(d / f"{name}.json")
    assert main(["machine", path, "--wall", "auto", "--xyuv", *args, "-o", out, "--report", rep, "--quiet",
                 "--measure-samples", "12"]) == 0
    with open(rep) as fh:
        return out, json.load(fh)


def _wall_check(part, ngc: str, rep: dict, kerf: float):
    return wall_cut_check(part[0], ngc, rep, kerf, (0.0, HEIGHT))


def test_the_wall_is_one_closed_xyuv_loop_from_the_longest_straight_stretch(part):
    ngc, rep = _run(part, "plain")
    cut, lo = _wall_check(part, ngc, rep, 0.0)
    # the default start: the middle of the bottom contour's longest straight edge, (0, 0)-(40, 0)
    assert np.allclose(rep["wall"]["start"], [20.0, 0.0, 0.0], atol=0.5)
    assert rep["machine"]["axis"] == [0.0, 0.0, 1.0]
    assert rep["cut"]["max"] <= rep["cut"]["bound"]
    # the taper per ruling: each line's angle from the axis, from the CSV's own points; at least the draft
    from tests.machine_helpers import read_csv
    rows = [r for r in read_csv(os.path.splitext(ngc)[0] + ".csv") if r["kind"] == "cut"]
    for r in rows:
        d = np.array([float(r[f"upper_{c}"]) - float(r[f"lower_{c}"]) for c in "xyz"])
        assert float(r["taper_deg"]) == pytest.approx(np.degrees(np.arccos(abs(d[2]) / np.linalg.norm(d))), abs=1e-3)
    assert min(float(r["taper_deg"]) for r in rows) >= 8.0 - 1e-3


def test_the_kerf_runs_round_the_whole_loop_and_its_corner(part):
    """Outside (a punch), the wire of radius 0.15 pivots round the sharp corner at (0, 0): every line is at
    the kerf from the wall, within the fit and the chord tolerance, both ways."""
    ngc, rep = _run(part, "kerf", "--kerf", "0.15", "--start", "30,0")
    cut, lo = _wall_check(part, ngc, rep, 0.15)
    assert np.allclose(rep["wall"]["start"][:2], [30.0, 0.0], atol=0.5)
    assert rep["cut"]["inside_corner_fillet"] <= 1e-9


def test_a_start_off_the_contour_is_refused_in_one_line(part, tmp_path):
    from tests.conftest import ruled_here
    r = ruled_here("machine", part[0], "--wall", "auto", "--xyuv", "--start", "25,7", "-o", tmp_path / "x.ngc")
    assert r.returncode == 2
    assert r.stderr.strip() == ("ruled: error: --start (25, 7) is 7 off the wall's bottom contour (its nearest point "
                                "is (25.01, 0)); give a point on it")


@pytest.mark.slow     # (6 s: the loop stays under 3 minutes; CI runs it)
def test_cadquery_xyuv_wall_writes_the_same_bytes_as_the_command_line(part, tmp_path):
    """One file from every door (issue 71): the wall's G-code from ruled.cq, named as the command line's, is the
    command line's byte for byte (the same start, direction, post and comments)."""
    import cadquery as cq

    import ruled.cq as rcq
    ngc, _ = _run(part, "cli")
    data = rcq.xyuv_wall(cq.importers.importStep(part[0]).val(), measure=False)     # the same part
    out = str(tmp_path / "cli.ngc")
    data.write(out)
    assert open(out, "rb").read() == open(ngc, "rb").read()
