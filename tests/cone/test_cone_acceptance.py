"""Cone splines (Yang & Yang 2006): the issue's acceptance, measured independently.

The original surfaces are defined here (callables); the patches are built as OCCT faces and read
back through OCCT: distances from the original to the patches by OCCT projection, from the patches
to the original by exact distances to its ruling segments (brute force over dense rulings),
Theorem 1 from the OCCT poles, G1 from OCCT's derivatives along the common rulings."""

import numpy as np
import pytest
from test_cone import _spiral, paper_examples

from ruled.cone.conespline import cone_spline

OCP = pytest.importorskip("OCP")
from OCP.BRep import BRep_Tool  # noqa: E402
from OCP.gp import gp_Pnt, gp_Vec  # noqa: E402

from ruled.occ.conespline import cone_faces, sew  # noqa: E402
from ruled.occ.faceset import FaceSet, sample_faces, to_lines  # noqa: E402

PAPER = {"1": 7, "2": 16, "3a": 7, "3b": 15}


def _lift(b, db, z):
    return (lambda v: np.column_stack([b(v), np.full(len(np.atleast_1d(v)), z)]),
            lambda v: np.column_stack([db(v), np.zeros(len(np.atleast_1d(v)))]))


def _original(b0, db0, b1, db1, h):
    """The paper's original surface inside its extended form: between 0.8 b0 + 0.2 b1 at 0.2 h and
    0.2 b0 + 0.8 b1 at 0.8 h."""
    c0, dc0 = _lift(lambda v: 0.8 * b0(v) + 0.2 * b1(v), lambda v: 0.8 * db0(v) + 0.2 * db1(v), 0.2 * h)
    c1, dc1 = _lift(lambda v: 0.2 * b0(v) + 0.8 * b1(v), lambda v: 0.2 * db0(v) + 0.8 * db1(v), 0.8 * h)
    return c0, dc0, c1, dc1


def _occ_poles(face):
    s = BRep_Tool.Surface_s(face)
    return np.array([[s.Pole(i, j).Coord() for j in range(1, s.NbVPoles() + 1)] for i in range(1, s.NbUPoles() + 1)])


def _concurrent(P, Q, rel=1e-9):
    """The three lines P_j Q_j meet at one point or are parallel (relative to the patch size)."""
    D = (Q - P) / np.linalg.norm(Q - P, axis=1)[:, None]
    size = np.ptp(np.vstack([P, Q]), axis=0).max()
    if np.abs(np.cross(D[0], D[1])).max() <= rel and np.abs(np.cross(D[0], D[2])).max() <= rel:
        return True
    M = sum(np.eye(3) - np.outer(d, d) for d in D)
    X = np.linalg.solve(M, sum((np.eye(3) - np.outer(d, d)) @ p for p, d in zip(P, D)))
    dist = max(np.linalg.norm((np.eye(3) - np.outer(d, d)) @ (X - p)) for p, d in zip(P, D))
    return dist <= rel * max(size, np.linalg.norm(X - P[0]))


def _normal(face, u, v):
    s = BRep_Tool.Surface_s(face)
    p, du, dv = gp_Pnt(), gp_Vec(), gp_Vec()
    s.D1(float(u), float(v), p, du, dv)
    n = np.cross(du.Coord(), dv.Coord())
    ln = np.linalg.norm(n)
    return None if ln <= 1e-12 * (np.linalg.norm(du.Coord()) + np.linalg.norm(dv.Coord())) ** 2 else n / ln


def _check_patches(faces, pieces_of):
    """Theorem 1 on every patch and G1 (rad) between neighbours of one piece, through OCCT."""
    worst = 0.0
    for f in faces:
        P = _occ_poles(f)
        assert P.shape[:2] == (2, 3)
        assert _concurrent(P[0], P[1])
    for i in range(len(faces) - 1):
        if pieces_of[i] != pieces_of[i + 1]:
            continue
        for u in np.linspace(0, 1, 7):
            na, nb = _normal(faces[i], u, 1.0), _normal(faces[i + 1], u, 0.0)
            if na is None or nb is None:                  # a cone's apex: no tangent plane there
                continue
            worst = max(worst, float(np.arctan2(np.linalg.norm(np.cross(na, nb)), na @ nb)))
    return worst


def _measured(faces, ends, n=24):
    """Two-sided distance between the patches and the ruled surface swept by ends(v) = (A(v), B(v))."""
    s = np.linspace(0, 1, n)
    A, B = ends(np.linspace(0, 1, 3 * n))
    design = (A[:, None, :] + s[None, :, None] * (B - A)[:, None, :]).reshape(-1, 3)
    d1 = float(FaceSet(faces).distances(design).max())       # the exact search's maximum (measure.screened)
    d2 = float(to_lines(sample_faces(faces, n // 2), ends).max())
    return d1, d2


def _paper_cases():
    b0, db0, b1, db1 = _spiral()
    return [("1", b0, db0, b1, db1, 1e-3, 0.5, 1.0)] + [c[:-1] for c in paper_examples()]


@pytest.mark.parametrize("case", _paper_cases(), ids=lambda c: "example " + c[0])
def test_paper_examples_in_space(case):
    name, b0, db0, b1, db1, tol, step, h = case
    c0, dc0, c1, dc1 = _original(b0, db0, b1, db1, h)
    res = cone_spline(c0, dc0, c1, dc1, tol, step)
    assert len(res.pieces) == 1 and res.pieces[0].planar_boundaries
    (h0, h1), (H0, H1) = res.pieces[0].heights, res.pieces[0].fit_heights
    assert (H1 - H0, h0 - H0, H1 - h1) == pytest.approx((h, 0.2 * h, 0.2 * h), abs=1e-9)   # the paper's extended form
    assert len(res.patches) <= PAPER[name]
    assert res.bound <= tol
    faces = cone_faces(res)
    g1 = _check_patches(faces, [p.piece for p in res.patches])
    assert g1 <= 1e-6

    def ends(v):
        return c0(v), c1(v)
    d1, d2 = _measured(faces, ends)
    assert max(d1, d2) <= tol
    print(f"example {name}: {len(res.patches)} patches (paper {PAPER[name]}), bound {res.bound:.4g}, measured "
          f"{max(d1, d2):.4g} for tolerance {tol}, G1 {g1:.2g} rad")


def _cq_face(kind):
    cq = pytest.importorskip("cadquery")
    if kind == "cone":
        solid = cq.Solid.makeCone(10, 6, 8)
        return [f for f in solid.Faces() if f.geomType() == "CONE"][0].wrapped
    if kind == "cylinder":
        solid = cq.Solid.makeCylinder(5, 12)
        return [f for f in solid.Faces() if f.geomType() == "CYLINDER"][0].wrapped
    # exact rational B-spline faces: a full circle (9 poles, quadratic) mapped affinely
    from ruled.core.nurbs import Surface
    from ruled.occ.convert import container_to_face
    c = np.array([(1, 0), (1, 1), (0, 1), (-1, 1), (-1, 0), (-1, -1), (0, -1), (1, -1), (1, 0)], float)
    w = np.array([1, np.sqrt(0.5)] * 4 + [1.0])
    if kind == "elliptic cone":
        lo = np.column_stack([12 * c[:, 0], 5 * c[:, 1], np.zeros(9)])
        hi = np.column_stack([6 * c[:, 0], 2.5 * c[:, 1], np.full(9, 7.0)])
    else:                                                 # an oblique circular cone
        lo = np.column_stack([10 * c, np.zeros(9)])
        hi = np.column_stack([5 * c + [3, 0], np.full(9, 8.0)])
    S = Surface(np.array([lo, hi]), [0, 0, 1, 1], [0, 0, 0, .25, .25, .5, .5, .75, .75, 1, 1, 1], 1, 2,
                np.array([w, w]))
    return container_to_face(S)


@pytest.mark.parametrize("kind", ["cone", "cylinder", "elliptic cone", "oblique cone"])
def test_exact_cones_and_cylinders_full_turn(kind):
    from ruled.occ.conespline import cone_of_face
    face = _cq_face(kind)
    fc = cone_of_face(face, 1e-6, 0.1, measure_samples=None)
    res = fc.result
    assert len(res.patches) <= 3                          # a full turn
    faces = fc.faces
    g1 = _check_patches(faces, [p.piece for p in res.patches])
    assert g1 <= 1e-6
    size = np.ptp(sample_faces([face], 20), axis=0).max()
    # both ways by OCCT projection: the face to the patches, the patches to the face
    to_patches, to_face = FaceSet(faces), FaceSet([face])     # built once: each build samples every face
    d1 = max(to_patches.distance(x) for x in sample_faces([face], 18))
    d2 = max(to_face.distance(x) for x in sample_faces(faces, 10))
    assert max(d1, d2) <= 1e-9 * size
    shell, valid = sew(faces)
    assert valid
    kinds = {p.kind for p in res.patches}
    assert kinds == ({"cylinder"} if kind == "cylinder" else {"cone"})
    print(f"{kind}: {len(res.patches)} patches, measured {max(d1, d2):.3g} ({max(d1, d2) / size:.2g} of the size)")


@pytest.mark.slow
def test_rulings_that_turn_are_split_into_pieces():
    """§6: rulings turning by 150 degrees cannot all cross one pair of planes; the surface is cut into
    pieces, each between its own planes, and every piece is within the tolerance."""
    def c0(v):
        v = np.atleast_1d(v)
        return np.column_stack([4 * v, np.zeros_like(v), np.zeros_like(v)])

    def dc0(v):
        v = np.atleast_1d(v)
        return np.column_stack([np.full_like(v, 4.0), np.zeros_like(v), np.zeros_like(v)])
    phi = np.radians(150.0)

    def c1(v):
        v = np.atleast_1d(v)
        return c0(v) + np.column_stack([np.zeros_like(v), np.sin(phi * v), np.cos(phi * v)])

    def dc1(v):
        v = np.atleast_1d(v)
        return dc0(v) + phi * np.column_stack([np.zeros_like(v), np.cos(phi * v), -np.sin(phi * v)])
    tol = 0.01
    res = cone_spline(c0, dc0, c1, dc1, tol, 0.1)
    assert len(res.pieces) >= 2 and res.bound <= tol and res.notes
    faces = cone_faces(res)
    _check_patches(faces, [p.piece for p in res.patches])

    def ends(v):
        return c0(v), c1(v)
    d1, d2 = _measured(faces, ends, 14)
    # the pieces' planes cover the whole surface: every point of it is near a patch, and every patch
    # point is near the surface extended along its rulings (each piece spans its own planes)
    assert d1 <= tol
    # (each patch against its own piece's extension: no nearer than to the nearest piece's, so stricter)
    for k, piece in enumerate(res.pieces):
        own = [f for f, p in zip(faces, res.patches) if p.piece == k]
        assert to_lines(sample_faces(own, 8), piece.rulings).max() <= tol
