"""DP against brute-force enumeration of all monotone paths on small tables."""
import numpy as np
import pytest

from ruled.core.errors import InfeasibleError
from ruled.fit.dp import dp2d as dp


def _all_paths(ni, nj):
    """Every path from (0,0) to (ni-1,nj-1) with moves (1,0), (0,1), (1,1)."""
    def rec(i, j):
        if (i, j) == (ni - 1, nj - 1):
            yield [(i, j)]
            return
        for di, dj in ((1, 1), (1, 0), (0, 1)):
            a, b = i + di, j + dj
            if a < ni and b < nj:
                for rest in rec(a, b):
                    yield [(i, j)] + rest
    yield from rec(0, 0)


def _score(C, path, objective):
    c = np.array([C[i, j] for i, j in path])
    return c.sum() if objective == "sum" else c.max()


@pytest.mark.parametrize("objective", ["sum", "max"])
def test_open_dp_is_globally_optimal(objective, rng):
    for n in (3, 4, 5, 6):
        for _ in range(5):
            C = rng.uniform(0, 1, (n, n))
            res = dp.solve(C, False, objective)
            best = min(_score(C, p, objective) for p in _all_paths(n, n))
            assert abs(res.score - best) < 1e-12
            assert abs(_score(C, [tuple(x) for x in res.path], objective) - best) < 1e-12
            assert tuple(res.path[0]) == (0, 0) and tuple(res.path[-1]) == (n - 1, n - 1)
            steps = np.diff(res.path, axis=0)
            assert ((steps >= 0) & (steps <= 1)).all() and (steps.sum(axis=1) >= 1).all()


@pytest.mark.parametrize("objective", ["sum", "max"])
def test_closed_dp_is_optimal_over_all_shifts(objective, rng):
    for n in (3, 4, 5):
        for _ in range(4):
            C = rng.uniform(0, 1, (n, n))
            res = dp.solve(C, True, objective)
            best = np.inf
            for s in range(n):
                Cs = C[(s + np.arange(n + 1))[:, None] % n, np.arange(n + 1)[None, :] % n]
                best = min(best, min(_score(Cs, p, objective) for p in _all_paths(n + 1, n + 1)))
            assert abs(res.score - best) < 1e-12
            first, last = res.path[0], res.path[-1]
            # first and last ruling are the same line: one full turn on both boundaries
            assert last[0] - first[0] == n and last[1] - first[1] == n


def test_max_error_constraint_and_infeasibility_message(rng):
    n = 6
    C = rng.uniform(0.5, 1.0, (n, n))
    C[np.arange(n), np.arange(n)] = 0.1
    res = dp.solve(C, False, "sum", max_error=0.2)
    assert np.all(C[res.path[:, 0], res.path[:, 1]] <= 0.2)
    minimax = min(_score(C, p, "max") for p in _all_paths(n, n))
    C[2, 2] = 0.9
    minimax = min(_score(C, p, "max") for p in _all_paths(n, n))
    with pytest.raises(InfeasibleError) as exc:
        dp.solve(C, False, "sum", max_error=0.2)
    msg = str(exc.value)
    assert f"{minimax:.6g}" in msg and "\n" not in msg


def test_numba_and_numpy_dp_agree(rng, monkeypatch):
    from ruled.core import jit
    if not jit.AVAILABLE:
        pytest.skip("numba is not installed")
    for closed in (False, True):
        for objective in ("sum", "max"):
            C = np.round(rng.uniform(0, 1, (23, 23)), 2)  # many ties
            a = dp.solve(C, closed, objective)
            monkeypatch.setattr(jit, "AVAILABLE", False)
            b = dp.solve(C, closed, objective)
            monkeypatch.setattr(jit, "AVAILABLE", True)
            assert np.array_equal(a.path, b.path)
            assert a.score == b.score


def test_closed_dp_in_batches_equals_one_batch(rng):
    C = np.round(rng.uniform(0, 1, (17, 17)), 2)
    for objective in ("sum", "max"):
        one = dp.solve_closed(C, objective)
        many = dp.solve_closed(C, objective, batch_bytes=1)  # one shifted table at a time
        assert np.array_equal(one.path, many.path) and one.score == many.score
