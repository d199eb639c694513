"""The 4D dynamic program: brute force on small tables, the 2D program at m = 0, twins, closed paths."""

import numpy as np
import pytest

from ruled.core import jit, sampling
from ruled.core.distance import ruling_distances
from ruled.core.errors import InfeasibleError
from ruled.core.sampling import PATTERNS
from ruled.examples import elber_ex1, elber_ex2
from ruled.fit.dp import dp2d as dp
from ruled.fit.dp import dp4d, metrics4d
from ruled.fit.dp.kernels import MOVES


def _tables(S, n, m, tau, closed=False, sshb=True, ns=12):
    smp = sampling.elevated_samples(S, n, m, tau, closed)
    if sshb:
        feet = metrics4d.ruling_feet(S, smp, ns)
        terms = metrics4d.patch_terms(S, smp, feet)
        return smp, dp4d.Tables(True, n, 2 * m + 1, None, metrics4d.sshb_ruling_tables(smp, feet), terms)
    feet = metrics4d.ruling_feet(S, smp, 9, edges=False)
    return smp, dp4d.Tables(False, n, 2 * m + 1, metrics4d.lsad_tables(smp, feet))


def _move_cost(T, a, b):
    """Independent evaluation of one move's (cost, weighted cost) from the tables."""
    di, dj, dk, dl = (int(x) for x in (b - a))
    if not T.sshb:
        w = float(T.lc[b[0], b[1], b[2], b[3]])
        return w, w
    pat = PATTERNS.index((di, dj))
    cur = tuple(float(x[tuple(b)]) for x in T.ruling)
    prev = tuple(float(x[tuple(a)]) for x in T.ruling)
    w = metrics4d.sshb_move(T.terms, prev, cur, pat, b[0], b[1], b[2], b[3], dk, dl)
    return w, float(T.terms.area[pat, b[0], b[1]]) * w


def _brute_force(T, objective):
    """Every monotone path of the 15 moves from (0, 0, k0, l0) to (n-1, n-1, k, l): the best
    (objective, secondary) in lexicographic order."""
    n, K = T.n, T.K
    best = (np.inf, np.inf)
    moves = [np.array(mv) for mv in MOVES]

    def walk(node, prim, sec):
        nonlocal best
        if node[0] == n - 1 and node[1] == n - 1:
            if prim < best[0] - 1e-12 or (abs(prim - best[0]) <= 1e-12 and sec < best[1]):
                best = (prim, sec)
            return
        for mv in moves:
            nxt = node + mv
            if nxt[0] >= n or nxt[1] >= n or not (0 <= nxt[2] < K) or not (0 <= nxt[3] < K):
                continue
            w, ws = _move_cost(T, node, nxt)
            if objective == "sum":
                walk(nxt, prim + ws, sec + ws)
            else:
                walk(nxt, max(prim, w), sec + ws)

    for k0 in range(K):
        for l0 in range(K):
            start = np.array([0, 0, k0, l0])
            c0 = 0.0 if T.sshb else float(T.lc[0, 0, k0, l0])
            walk(start, c0, c0)
    return best


@pytest.mark.parametrize("sshb", [True, False])
@pytest.mark.parametrize("objective", ["sum", "max"])
@pytest.mark.parametrize("make,n,m", [pytest.param(elber_ex1, 4, 1, marks=pytest.mark.slow), (elber_ex2, 3, 2)])
def test_dp_equals_brute_force(sshb, objective, make, n, m):
    _, T = _tables(make(), n, m, 0.01, sshb=sshb)
    res = dp4d.solve_open(T, objective)
    p, s = _brute_force(T, objective)
    assert res.score == pytest.approx(p, rel=1e-9, abs=1e-15)
    # the sum that breaks ties of the max objective is a tie-break, not part of the optimum (a
    # lexicographic max-then-sum does not decompose into a DP); it can only be larger
    assert res.secondary >= s * (1 - 1e-9)
    # and the returned path really has that value
    costs = [_move_cost(T, a, b) for a, b in zip(res.path[:-1], res.path[1:])]
    start = 0.0 if sshb else float(T.lc[tuple(res.path[0])])
    value = start + sum(c[1] for c in costs) if objective == "sum" else max([start] + [c[0] for c in costs])
    assert value == pytest.approx(p, rel=1e-9, abs=1e-15)


def test_m0_line_metric_is_the_2d_program():
    S = elber_ex2()
    n = 30
    smp, T = _tables(S, n, 0, 1.0, sshb=False)
    I, J = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    cost2d = ruling_distances(S, smp.u[I.ravel()], smp.u[J.ravel()], 9, 3)[1].reshape(n, n)
    assert np.allclose(T.lc[:, :, 0, 0], cost2d, rtol=1e-6, atol=1e-12)
    for objective in ("sum", "max"):
        r2 = dp.solve_open(T.lc[:, :, 0, 0].astype(float), objective)
        r4 = dp4d.solve_open(T, objective)
        assert r4.score == pytest.approx(r2.score, rel=1e-12)
        assert np.array_equal(r4.path[:, :2], r2.path)
        assert np.all(r4.path[:, 2:] == 0)


@pytest.mark.skipif(not jit.AVAILABLE, reason="numba is not installed")
@pytest.mark.parametrize("sshb", [True, False])
@pytest.mark.parametrize("objective", ["sum", "max"])
def test_numba_and_numpy_give_identical_tables_and_paths(monkeypatch, sshb, objective):
    S = elber_ex2()
    smp = sampling.elevated_samples(S, 12, 2, 0.01, False)
    feet = metrics4d.ruling_feet(S, smp, 10, edges=sshb)
    fast = metrics4d.sshb_ruling_tables(smp, feet) if sshb else metrics4d.lsad_tables(smp, feet)
    T = (dp4d.Tables(True, 12, 5, None, fast, metrics4d.patch_terms(S, smp, feet)) if sshb
         else dp4d.Tables(False, 12, 5, fast))
    a = dp4d._fill(T, objective == "max", False, 0, 12)
    monkeypatch.setattr(jit, "enabled", lambda: False)
    slow = metrics4d.sshb_ruling_tables(smp, feet) if sshb else metrics4d.lsad_tables(smp, feet)
    for x, y in zip(fast if sshb else [fast], slow if sshb else [slow]):
        assert np.array_equal(x, y)
    b = dp4d._fill(T, objective == "max", False, 0, 12)
    for x, y in zip(a, b):
        assert np.array_equal(x, y)


def test_closed_paths_return_to_their_first_ruling():
    rng = np.random.default_rng(3)
    n, K = 8, 5
    lc = rng.uniform(0.1, 1.0, (n, n, K, K)).astype(np.float32)
    T = dp4d.Tables(False, n, K, lc)
    for objective in ("sum", "max"):
        res = dp4d.solve_closed(T, objective)
        first, last = res.path[0], res.path[-1]
        assert last[0] - first[0] == n and last[1] - first[1] == n
        assert first[2] == last[2] and first[3] == last[3]
        assert np.all(np.diff(res.path[:, 0]) >= 0) and np.all(np.diff(res.path[:, 1]) >= 0)


def test_max_error_forbids_costly_moves_or_says_what_is_achievable():
    _, T = _tables(elber_ex1(), 10, 2, 0.01, sshb=False)
    best = dp4d.solve_open(T, "max").max_cost
    res = dp4d.solve(T, False, "sum", max_error=best * 1.0001)
    assert res.max_cost <= best * 1.0001
    with pytest.raises(InfeasibleError, match="best achievable"):
        dp4d.solve(T, False, "sum", max_error=best * 0.5)


def test_closed_start_can_be_fixed_and_then_always_has_a_path():
    rng = np.random.default_rng(5)
    n, K = 6, 5
    lc = rng.uniform(0.1, 1.0, (n, n, K, K)).astype(np.float32)
    T = dp4d.Tables(False, n, K, lc, start=2 * K + 2)
    res = dp4d.solve_closed(T, "sum")
    assert np.isfinite(res.score)
    assert tuple(res.path[0, 2:]) == (2, 2) and tuple(res.path[-1, 2:]) == (2, 2)
