"""Never worse than Part Ruled (issue 72): faces CadQuery users make (tests/cq_faces.py: lofts through 3-4
sections, sweeps along 3D splines with a closed elliptic tube among them, variable-radius fillets), each fitted
by the whole ``ruled fit`` job and measured by OCCT alone (ruled.occ.measure, both ways, as bounded by the
edges) against FreeCAD's Part "Ruled Surface" (BRepFill) between each pair of the face's opposite edges, in
both orientations: the result is within 2 % of the best of them (or at round-off, 1e-9 of the face's size),
and its certified bound is not below its measure."""

from __future__ import annotations

import pytest

pytest.importorskip("cadquery")

import os  # noqa: E402

from cq_faces import cq_faces  # noqa: E402
from trimmed_faces import measure, outer_edges, part_ruled  # noqa: E402

from ruled.jobs.face import run_fit  # noqa: E402
from ruled.occ.io import read_faces, write_step  # noqa: E402

N = 30
FACES = cq_faces()


def _size(face) -> float:
    from OCP.Bnd import Bnd_Box
    from OCP.BRepBndLib import BRepBndLib
    b = Bnd_Box()
    BRepBndLib.Add_s(face, b)
    x0, y0, z0, x1, y1, z1 = b.Get()
    return ((x1 - x0) ** 2 + (y1 - y0) ** 2 + (z1 - z0) ** 2) ** 0.5


def test_there_are_at_least_twenty_faces_of_each_kind_together():
    kinds = {name.split()[0] for name, _ in FACES}
    assert len(FACES) >= 20 and kinds == {"loft", "sweep", "fillet"}


@pytest.mark.slow
@pytest.mark.parametrize("k", range(len(FACES)), ids=[f"{n} #{k}" for k, (n, _) in enumerate(FACES)])
def test_the_fit_is_never_worse_than_part_ruled_between_the_same_edges(k, tmp_path):
    name, face = FACES[k]
    src, out = os.path.join(tmp_path, "face.step"), os.path.join(tmp_path, "result.step")
    write_step(face, src)
    rep = run_fit(src, 0, out, quiet=True, say=False)
    ours = measure(face, read_faces(out)[0], N)
    assert len(outer_edges(face)) == 4
    theirs = min(measure(face, s, N) for a, b in (([0], [2]), ([1], [3])) for s in part_ruled(face, a, b))
    floor = 1e-9 * _size(face)
    assert ours <= 1.02 * theirs + floor, f"{name}: ours {ours:.6g}, Part Ruled {theirs:.6g}"
    assert rep["error_bound"] >= ours - floor, f"{name}: bound {rep['error_bound']:.6g} below the measure {ours:.6g}"
