"""Cone splines (Yang & Yang 2006), the planar building blocks: conic arcs, the shared weight,
tangent rules, parallel polygons and Theorem 1, checked against closed-form geometry."""
import numpy as np
import pytest

from ruled.cone.conic import (
    barycentric,
    choose_tangent,
    conic,
    locally_convex,
    reflect,
    shared_weight,
    tangent_lines_meet,
)
from ruled.cone.fatarc import generators_concurrent, hausdorff_2d, parallel_step
from ruled.examples import cone_examples


def test_conic_points_satisfy_the_implicit_form_and_the_weight_is_recovered():
    rng = np.random.default_rng(0)
    for _ in range(20):
        A, R, B = rng.normal(size=(3, 2))
        w = rng.uniform(0.2, 5.0)
        t = np.linspace(0.02, 0.98, 40)
        X = conic(A, R, B, w, t)
        tau = barycentric(X, A, R, B)
        assert np.allclose(tau.sum(axis=1), 1.0)
        assert np.allclose(4 * w * w * tau[:, 0] * tau[:, 2], tau[:, 1] ** 2, atol=1e-12)
        # a similar triangle (parallel sides) with the same weight: the shared weight comes back
        k, off = rng.uniform(0.3, 2.0), rng.normal(size=2)
        Y = conic(k * A + off, k * R + off, k * B + off, w, t[::3])
        assert shared_weight((A, R, B), X, (k * A + off, k * R + off, k * B + off), Y) == pytest.approx(w, rel=1e-10)


def test_circular_arc_weight():
    # isosceles control triangle with base angle a: the weight cos(a) gives a circular arc
    a = 0.7
    A, B = np.array([-1.0, 0.0]), np.array([1.0, 0.0])
    R = np.array([0.0, np.tan(a)])
    X = conic(A, R, B, np.cos(a), np.linspace(0, 1, 50))
    centre = np.array([0.0, -1.0 / np.tan(a)])
    r = np.linalg.norm(X - centre, axis=1)
    assert np.abs(r - r[0]).max() <= 1e-12
    assert shared_weight((A, R, B), X[5:-5], None, []) == pytest.approx(np.cos(a), rel=1e-10)
    assert shared_weight((A, R, B), np.array([[5.0, 5.0]]), None, []) == 2.0     # nothing inside: the default


def test_chosen_tangents_are_locally_convex():
    rng = np.random.default_rng(1)
    n = 0
    for _ in range(300):
        A = rng.normal(size=2)
        ang = rng.uniform(-1.2, 1.2)                  # the incoming tangent turns less than 90 deg to the chord
        U = rng.normal(size=2)
        U /= np.linalg.norm(U)
        B = A + rng.uniform(0.1, 2) * U
        c, s = np.cos(ang), np.sin(ang)
        TA = np.array([c * U[0] - s * U[1], s * U[0] + c * U[1]])
        if abs(ang) < 1e-3:
            continue
        V = rng.normal(size=2)
        T = choose_tangent(A, TA, B, V)
        assert T is not None and locally_convex(A, TA, B, T)
        n += 1
        if locally_convex(A, TA, B, V / np.linalg.norm(V)):
            assert np.allclose(T, V / np.linalg.norm(V))
    assert n > 250


def test_reflection_and_tangent_intersection():
    U = np.array([1.0, 0.0])
    assert np.allclose(reflect([0.6, 0.8], U), [0.6, -0.8])
    X, s, u = tangent_lines_meet([0, 0], [1, 1], [2, 0], [1, -1])
    assert np.allclose(X, [1, 1]) and s > 0 and u < 0
    assert tangent_lines_meet([0, 0], [1, 0], [0, 1], [2, 0]) is None


def test_parallel_step_on_a_cone_section_keeps_the_parameters_together():
    # b1 = 1.5 b0 about the apex's projection: the parallel line through b1(v) meets b1 at the same
    # parameter as the new point on b0
    def b0(v):
        v = np.atleast_1d(v)
        th = 3.0 * v
        return np.stack([(0.5 + v) * np.cos(th), (0.5 + v) * np.sin(th)], axis=1)

    def b1(v):
        return 1.5 * b0(v)
    v = vb = 0.0
    for _ in range(8):
        st = parallel_step(b0, b1, v, vb, 0.1)
        assert st.collapsed == -1
        assert st.vb == pytest.approx(st.v, abs=1e-12) or st.v == pytest.approx(st.vb, abs=1e-12)
        c0 = b0(np.array([v, st.v]))
        c1 = b1(np.array([vb, st.vb]))
        d0, d1 = c0[1] - c0[0], c1[1] - c1[0]
        assert abs(d0[0] * d1[1] - d0[1] * d1[0]) <= 1e-12 * np.linalg.norm(d0) * np.linalg.norm(d1)
        v, vb = st.v, st.vb


def test_fat_conic_arc_of_a_true_cone_is_developable():
    # a circular cone: sections at z = 0 (radius 1) and z = 1 (radius 0.6) about the z axis
    ang = np.array([0.0, 0.5, 1.0])
    P = np.stack([np.cos(ang), np.sin(ang), np.zeros(3)], axis=1)
    Q = np.stack([0.6 * np.cos(ang), 0.6 * np.sin(ang), np.ones(3)], axis=1)
    assert generators_concurrent(P, Q)
    Q2 = Q.copy()
    Q2[1, 0] += 1e-3
    assert not generators_concurrent(P, Q2)
    # a cylinder: parallel generators
    assert generators_concurrent(P, P + [0.0, 0.0, 1.0])
    # the planar fat conic arc: control triangles from the end tangents are similar (Theorem 2)
    t0 = np.array([0.0, 1.0])
    t1 = np.array([-np.sin(1.0), np.cos(1.0)])
    A0, A1 = P[0, :2], P[2, :2]
    B0, B1 = Q[0, :2], Q[2, :2]
    R = tangent_lines_meet(A0, t0, A1, t1)[0]
    Rb = tangent_lines_meet(B0, t0, B1, t1)[0]
    for (x, y), (xb, yb) in (((A0, R), (B0, Rb)), ((R, A1), (Rb, B1)), ((A0, A1), (B0, B1))):
        d, db = y - x, yb - xb
        assert abs(d[0] * db[1] - d[1] * db[0]) <= 1e-12
    w = np.cos(0.5)                                   # the circular arcs' weight (base angle 0.5)
    X = conic(A0, R, A1, w, np.linspace(0, 1, 30))
    assert np.abs(np.linalg.norm(X, axis=1) - 1).max() <= 1e-12
    # the 30-point polyline against the dense arc: the largest chord sag, 1 - cos(half the largest step)
    phi = np.arctan2(X[:, 1], X[:, 0])
    sag = 1 - np.cos(0.5 * np.diff(phi).max())
    assert hausdorff_2d(X, conic(A0, R, A1, w, np.linspace(0, 1, 3000))) == pytest.approx(sag, rel=1e-2)


def _spiral():
    return cone_examples()[0][1:5]


def test_fat_conic_fit_of_the_spiral_boundaries():
    from ruled.cone.fatarc import fit_fat_conic, patch_surface
    b0, db0, b1, db1 = _spiral()
    arcs = fit_fat_conic(b0, db0, b1, db1, 1e-3, 0.5)
    assert arcs[0].v[0] == 0.0 and arcs[-1].v[1] == 1.0 and arcs[-1].vb[1] == 1.0
    for a, b in zip(arcs[:-1], arcs[1:]):
        assert a.v[1] == b.v[0] and a.vb[1] == b.vb[0]
        assert np.allclose(a.A[2], b.A[0]) and np.allclose(a.B[2], b.B[0])
    for arc in arcs:
        # Theorem 2: parallel sides (similar triangles), one weight; measured boundary error within tol
        for i, j in ((0, 1), (1, 2), (0, 2)):
            d, db = arc.A[j] - arc.A[i], arc.B[j] - arc.B[i]
            assert abs(d[0] * db[1] - d[1] * db[0]) <= 1e-9 * (np.linalg.norm(d) * np.linalg.norm(db) + 1e-300)
        t = np.linspace(0, 1, 2001)
        dense0 = b0(np.linspace(*arc.v, 2001))
        dense1 = b1(np.linspace(*arc.vb, 2001))
        e = max(hausdorff_2d(conic(*arc.A, arc.w, t), dense0), hausdorff_2d(conic(*arc.B, arc.w, t), dense1))
        assert e <= arc.err + 2e-7 and arc.err <= 1e-3     # 2001-point polylines sag by up to 1.2e-7 here
        # Theorem 1 on the lifted patch: the three generator lines meet at one point
        S = patch_surface(arc, 0.0, 1.0)
        assert generators_concurrent(S.poles[0], S.poles[1])
    # tangent smooth: the normals of neighbouring patches agree along their common ruling
    u = np.linspace(0, 1, 7)
    for a, b in zip(arcs[:-1], arcs[1:]):
        na = patch_surface(a).normals(u, np.ones(7))
        nb = patch_surface(b).normals(u, np.zeros(7))
        assert np.abs(np.cross(na, nb)).max() <= 1e-9
    assert len(arcs) <= 7                              # the paper's count
    print(f"spiral, tol 1e-3, step 0.5: {len(arcs)} fat arcs (the paper: 7)")


def test_trimmed_arc_is_the_patch_between_the_inner_planes():
    from ruled.cone.fatarc import fit_fat_conic, patch_surface, trim_arc
    b0, db0, b1, db1 = _spiral()
    arc = fit_fat_conic(b0, db0, b1, db1, 1e-3, 0.5)[2]
    # the paper's extended form: planes at 0 and 1, the original surface between 0.2 and 0.8
    full = patch_surface(arc, 0.0, 1.0)
    cut = patch_surface(trim_arc(arc, 0.2, 0.8), 0.2, 0.8)
    u, v = np.meshgrid(np.linspace(0, 1, 9), np.linspace(0, 1, 11), indexing="ij")
    X = cut(u.ravel(), v.ravel())
    Y = full(0.2 + 0.6 * u.ravel(), v.ravel())
    assert np.abs(X - Y).max() <= 1e-12
    # the trimmed sides keep a real control triangle each
    for row in (0, 1):
        assert np.linalg.norm(cut.poles[row, 1] - cut.poles[row, 0]) > 0


def paper_examples():
    """The paper's examples 2 and 3 (extended boundaries, heights 1 and 3): (name, b0, db0, b1, db1,
    tol, step, height, the paper's count)."""
    return cone_examples()[1:]


@pytest.mark.parametrize("case", paper_examples(), ids=lambda c: "example " + c[0])
def test_paper_examples_2_and_3_stay_within_the_error_estimate(case):
    from ruled.cone.fatarc import fit_fat_conic, patch_surface
    name, b0, db0, b1, db1, tol, step, height, paper = case
    arcs = fit_fat_conic(b0, db0, b1, db1, tol, step, h1=height)
    assert arcs[-1].v[1] == 1.0 and arcs[-1].vb[1] == 1.0
    assert max(a.err for a in arcs) <= tol
    assert len(arcs) <= paper
    for arc in arcs:
        S = patch_surface(arc, 0.0, height)
        assert generators_concurrent(S.poles[0], S.poles[1])
    print(f"example {name}: {len(arcs)} fat arcs (the paper: {paper}), largest eq. 9 error "
          f"{max(a.err for a in arcs):.4g} for tolerance {tol}")


@pytest.mark.skipif(not __import__("ruled.core.jit", fromlist=["AVAILABLE"]).AVAILABLE, reason="numba not installed")
@pytest.mark.parametrize("case", cone_examples(), ids=lambda c: "example " + c[0])
def test_numba_and_numpy_twins_fit_the_same_arcs(case, monkeypatch):
    """The kernels (cone/kernels.py) and their NumPy twins in fatarc.py give bit-identical fits."""
    from ruled.cone.fatarc import fit_fat_conic
    from ruled.core import jit
    name, b0, db0, b1, db1, tol, step, height, _ = case
    fast = fit_fat_conic(b0, db0, b1, db1, tol, step, h1=height)
    monkeypatch.setattr(jit, "enabled", lambda: False)
    slow = fit_fat_conic(b0, db0, b1, db1, tol, step, h1=height)
    assert len(fast) == len(slow)
    for a, b in zip(fast, slow):
        assert np.array_equal(a.A, b.A) and np.array_equal(a.B, b.B)
        assert (a.w, a.v, a.vb, a.err) == (b.w, b.v, b.vb, b.err)


def test_cone_spline_of_two_boundary_curves_given_directly():
    """Two rational B-spline half circles in parallel planes (radii 3 and 2, centres offset): an oblique
    circular cone; the cone spline reproduces it, apex where the similar triangles put it."""
    from ruled.cone.conespline import cone_spline_of_curves
    from ruled.core.nurbs import Curve
    c = np.array([(1, 0), (1, 1), (0, 1), (-1, 1), (-1, 0)], float)
    w = np.array([1, np.sqrt(0.5), 1, np.sqrt(0.5), 1])
    k = [0, 0, 0, .5, .5, 1, 1, 1]
    C0 = Curve(np.column_stack([3 * c, np.zeros(5)]), k, 2, w)
    C1 = Curve(np.column_stack([2 * c + [1.0, 0.5], np.full(5, 4.0)]), k, 2, w)
    res = cone_spline_of_curves(C0, C1, 1e-7)
    assert len(res.patches) <= 2 and res.bound <= 1e-7
    apex = np.array([3.0, 1.5, 12.0])                  # X with C1 - X = (2/3)(C0 - X)
    for p in res.patches:
        assert p.kind == "cone" and np.abs(p.apex - apex).max() <= 1e-6
        # the patch lies on the cone: the section at height z is the circle of the similar triangles
        u, v = np.meshgrid(np.linspace(0, 1, 5), np.linspace(0, 1, 9), indexing="ij")
        X = p.surface(u.ravel(), v.ravel())
        z = X[:, 2]
        r_expected = 3 * (12 - z) / 12                 # radius of the section at height z about the axis line
        centre = np.column_stack([3 - 3 * (12 - z) / 12, 1.5 - 1.5 * (12 - z) / 12])
        assert np.abs(np.linalg.norm(X[:, :2] - centre, axis=1) - r_expected).max() <= 1e-7
