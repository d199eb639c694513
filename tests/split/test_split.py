"""The split DP (Wang & Elber §4, 4D: P, Q and M-points): against brute force on small tables, the
numba kernel against its NumPy twin, the M-curve's moves, the memory refusal; the line metrics
against an independent sampled distance."""
import itertools

import numpy as np
import pytest

from ruled.core.errors import TooBigError
from ruled.split.mcurve import MOVES, SplitTables, m_grid, path_score, row_scores, split_dp, split_tables


def _brute(A, B, objective):
    """Every path from a first-column state to a last-column state by the moves, enumerated."""
    n, _, d = A.shape
    fwd = [tuple(m) for m in MOVES]
    best = np.inf

    def cost(s):
        i, j, a, b = s
        return max(A[i, a, b], B[j, a, b])

    def walk(s, acc):
        nonlocal best
        if s[:3] == (n - 1, n - 1, n - 1):
            best = min(best, acc)
        for di, dj, da, db in fwd:
            t = (s[0] + di, s[1] + dj, s[2] + da, s[3] + db)
            if t[0] < n and t[1] < n and t[2] < n and 0 <= t[3] < d:
                c = cost(t)
                walk(t, max(acc, c) if objective == "max" else acc + c)
    for b in range(d):
        walk((0, 0, 0, b), cost((0, 0, 0, b)))
    return best


def _tables(rng, n, d):
    return SplitTables(np.linspace(0, 1, n), np.linspace(0.2, 0.8, d), rng.uniform(0, 1, (n, n, d)),
                       rng.uniform(0, 1, (n, n, d)))


@pytest.mark.parametrize("objective", ["sum", "max"])
@pytest.mark.parametrize("n,d", [(2, 2), (3, 2), (3, 3)])
def test_split_dp_equals_brute_force(objective, n, d):
    rng = np.random.default_rng(n * 10 + d)
    for _ in range(3):
        T = _tables(rng, n, d)
        r = split_dp(T, objective)
        assert r.score == pytest.approx(_brute(T.A, T.B, objective), rel=1e-12)
        assert r.score == pytest.approx(path_score(T, r.path, objective), rel=1e-12)
        steps = np.diff(r.path, axis=0)
        assert all(tuple(s) in {tuple(m) for m in MOVES} for s in steps)
        assert tuple(r.path[0, :3]) == (0, 0, 0) and tuple(r.path[-1, :3]) == (n - 1, n - 1, n - 1)


@pytest.mark.skipif(not __import__("ruled.core.jit", fromlist=["AVAILABLE"]).AVAILABLE, reason="numba not installed")
def test_kernel_and_numpy_twin_agree(monkeypatch):
    from ruled.core import jit
    rng = np.random.default_rng(5)
    T = _tables(rng, 7, 3)
    T.A[2, 3] = T.A[2, 2]                                 # ties
    for objective in ("sum", "max"):
        fast = split_dp(T, objective)
        monkeypatch.setattr(jit, "enabled", lambda: False)
        slow = split_dp(T, objective)
        monkeypatch.undo()
        assert fast.score == slow.score and np.array_equal(fast.path, slow.path)


@pytest.mark.parametrize("objective", ["sum", "max"])
@pytest.mark.parametrize("numba", [True, False])
def test_row_scores_are_each_rows_own_split(objective, numba, monkeypatch):
    """All rows' best iso splits in one sweep: each the brute force of its row's tables alone."""
    from ruled.core import jit
    if not numba:
        monkeypatch.setattr(jit, "enabled", lambda: False)
    elif not jit.AVAILABLE:
        pytest.skip("numba not installed")
    rng = np.random.default_rng(11)
    for n, d in ((3, 3), (4, 2)):
        T = _tables(rng, n, d)
        got = row_scores(T, objective)
        want = [_brute(T.A[:, :, b:b + 1], T.B[:, :, b:b + 1], objective) for b in range(d)]
        np.testing.assert_allclose(got, want, rtol=1e-12)


@pytest.mark.slow
def test_tables_are_line_metrics_of_the_rulings():
    """Each table entry is the distance of its segment to the surface: checked against dense samples
    of the surface (brute force) for a few entries."""
    from ruled.examples import elber_ex1
    S = elber_ex1()
    n, d = 6, 3
    T = split_tables(S, n, d)
    u, vl = m_grid(S, n, d)
    _, _, v0, v1 = S.domain
    g = np.linspace(0, 1, 301)
    Uu, Vv = np.meshgrid(g, g, indexing="ij")
    cloud = S(Uu.ravel(), Vv.ravel())
    G = cloud.reshape(301, 301, 3)
    h = 0.5 * max(np.linalg.norm(np.diff(G, axis=0), axis=2).max(), np.linalg.norm(np.diff(G, axis=1), axis=2).max())
    for (i, a, b) in itertools.product((0, 3, 5), (1, 4), (0, 2)):
        P, M = S(np.array([u[i]]), np.array([v0]))[0], S(np.array([u[a]]), np.array([vl[b]]))[0]
        t = np.linspace(0, 1, 41)[1:-1]
        X = P + t[:, None] * (M - P)
        dd = np.sqrt(((X[:, None, :] - cloud[None]) ** 2).sum(axis=2)).min(axis=1).max()
        # the table: projections of 9 samples (both it and the cloud overestimate a point's distance a
        # little), the maximum of 39 samples nearly reached (the line metric is a sampled maximum)
        assert 0.9 * (dd - h) <= T.A[i, a, b] <= 1.001 * dd + 1e-5     # h: the cloud's resolution
    # an exactly ruled surface (bilinear): every ruling P_i M and M Q_j joining equal u lies on it
    from ruled.core.nurbs import Surface
    P = np.array([[(0, 0, 0), (0, 1, 0.2)], [(1, 0, 0.3), (1, 1, -0.1)]], float)
    Sb = Surface(P, [0, 0, 1, 1], [0, 0, 1, 1], 1, 1)
    Tb = split_tables(Sb, 5, 2)
    for a in range(5):
        assert Tb.A[a, a].max() <= 1e-12 and Tb.B[a, a].max() <= 1e-12


def test_split_dp_refuses_tables_beyond_the_memory_cap():
    T = _tables(np.random.default_rng(0), 20, 4)
    with pytest.raises(TooBigError, match="MiB"):
        split_dp(T, memory_cap=1000.0)


def _brute_elevated(A, B, objective):
    """Every path over (i, j, a, b) and the elevation levels (ep, eq, em): a point that moves may take
    any level, one that stays keeps its own."""
    n, mp, _, d, mm = A.shape
    mq = B.shape[1]
    best = np.inf

    def cost(s):
        i, j, a, b, ep, eq, em = s
        return max(A[i, ep, a, b, em], B[j, eq, a, b, em])

    def walk(s, acc):
        nonlocal best
        if s[:3] == (n - 1, n - 1, n - 1):
            best = min(best, acc)
        for di, dj, da, db in (tuple(m) for m in MOVES):
            i, j, a, b = s[0] + di, s[1] + dj, s[2] + da, s[3] + db
            if not (i < n and j < n and a < n and 0 <= b < d):
                continue
            for ep in (range(mp) if di else (s[4],)):
                for eq in (range(mq) if dj else (s[5],)):
                    for em in (range(mm) if da else (s[6],)):
                        t = (i, j, a, b, ep, eq, em)
                        c = cost(t)
                        walk(t, max(acc, c) if objective == "max" else acc + c)
    for s0 in itertools.product((0,), (0,), (0,), range(d), range(mp), range(mq), range(mm)):
        walk(s0, cost(s0))
    return best


@pytest.mark.parametrize("objective", ["sum", "max"])
@pytest.mark.parametrize("n,d,mp,mm", [(2, 2, 2, 2), (3, 1, 2, 1), pytest.param(3, 2, 1, 3, marks=pytest.mark.slow),
                                       pytest.param(3, 1, 2, 2, marks=pytest.mark.slow)])
def test_elevated_split_dp_equals_brute_force(objective, n, d, mp, mm):
    """5D (M elevated, mp = 1) and 7D (P, Q and M elevated) against every path."""
    rng = np.random.default_rng(n * 100 + d * 10 + mp + mm)
    T = SplitTables(np.linspace(0, 1, n), np.linspace(0.2, 0.8, d), rng.uniform(0, 1, (n, mp, n, d, mm)),
                    rng.uniform(0, 1, (n, mp, n, d, mm)))
    r = split_dp(T, objective)
    assert r.score == pytest.approx(_brute_elevated(T.A, T.B, objective), rel=1e-12)
    assert r.score == pytest.approx(path_score(T, r.path, objective, r.levels), rel=1e-12)
    for s0, s1, l0, l1 in zip(r.path[:-1], r.path[1:], r.levels[:-1], r.levels[1:]):
        mv = tuple(s1 - s0)
        assert mv in {tuple(m) for m in MOVES}
        for moved, k in ((mv[0], 0), (mv[1], 1), (mv[2], 2)):   # a point that stays keeps its level
            assert moved or l0[k] == l1[k]


@pytest.mark.skipif(not __import__("ruled.core.jit", fromlist=["AVAILABLE"]).AVAILABLE, reason="numba not installed")
def test_elevated_kernel_and_numpy_twin_agree(monkeypatch):
    from ruled.core import jit
    rng = np.random.default_rng(9)
    A = np.round(rng.uniform(0, 1, (6, 3, 6, 3, 2)), 1)     # rounded: many ties
    B = np.round(rng.uniform(0, 1, (6, 2, 6, 3, 2)), 1)
    T = SplitTables(np.linspace(0, 1, 6), np.linspace(0.2, 0.8, 3), A, B)
    for objective in ("sum", "max"):
        fast = split_dp(T, objective)
        monkeypatch.setattr(jit, "enabled", lambda: False)
        slow = split_dp(T, objective)
        monkeypatch.undo()
        assert fast.score == slow.score
        assert np.array_equal(fast.path, slow.path) and np.array_equal(fast.levels, slow.levels)


@pytest.mark.parametrize("dims", [5, 7])
def test_elevated_split_of_a_face(dims):
    """5D and 7D splits end to end (lifted tables, the DP, the side fits): the DP's path carries its
    levels, and the kept split is much better than one strip."""
    from ruled import FitOptions
    from ruled.examples import elber_ex2
    from ruled.split.partition import SplitOptions, split_curves, split_face, whole_fit
    opts = SplitOptions(samples=12, interior=4, dims=dims, levels=1, fit=FitOptions(samples=16))
    res = split_face(elber_ex2(), opts)
    assert set(res.candidates) == {"optimal", "best-iso", "iso-0.5"}
    assert res.best().bound < 0.6 * res.whole.bound
    So, _, whole = whole_fit(elber_ex2(), opts.fit)
    T = split_tables(So, 12, 4, dims=dims, levels=1, step=whole.bound / 3)
    assert T.A.shape == (12, 3 if dims == 7 else 1, 12, 4, 3)
    r = split_dp(T, "max")
    assert r.levels.shape == (len(r.path), 3) and r.score == pytest.approx(path_score(T, r.path, "max", r.levels))
    assert split_curves(So, whole.strip, whole.side, opts, whole.bound)[1].shape == (12, 2)
