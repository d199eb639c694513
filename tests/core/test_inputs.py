"""Every container and option refuses a bad field on construction, in one line that names it (issue 22)."""
import os

import numpy as np
import pytest

from ruled.core.errors import BadInputError
from ruled.core.nurbs import Curve, Surface
from ruled.core.region import Region
from ruled.fit.options import FitOptions
from ruled.machine.paths import MachineOptions
from ruled.split.partition import SplitOptions

KNOTS = [0, 0, 0, 1, 1, 1]


def _surface(**change):
    x, y = np.meshgrid(np.linspace(0, 1, 3), np.linspace(0, 1, 3), indexing="ij")
    args = dict(poles=np.stack([x, y, 0.1 * x * y], axis=2), knots_u=KNOTS, knots_v=KNOTS, degree_u=2,
                degree_v=2, weights=None)
    args.update(change)
    return Surface(**args)


def _curve(**change):
    args = dict(poles=[[0, 0], [0.5, 0.2], [1, 0]], knots=KNOTS, degree=2, weights=None)
    args.update(change)
    return Curve(**args)


def _weights(corner):
    w = np.ones((3, 3))
    w[1, 1] = corner
    return w


SURFACES = [
    (dict(weights=_weights(np.nan)), "surface weights contain NaN or infinite values; repair the model"),
    (dict(weights=_weights(np.inf)), "surface weights contain NaN or infinite values; repair the model"),
    (dict(weights=_weights(-1.0)), "surface weights must be positive (the smallest is -1)"),
    (dict(weights=_weights(1e-300)), "surface weights range over a ratio of 1e+300 (more than 1e+06): the surface "
                                     "is degenerate there and no error can be certified; rebuild it with moderate "
                                     "weights"),
    (dict(weights=_weights(1e-8)), "surface weights range over a ratio of 1e+08 (more than 1e+06): the surface "
                                   "is degenerate there and no error can be certified; rebuild it with moderate "
                                   "weights"),
    (dict(knots_u=[0, 0, 0, np.nan, 1, 1]), "surface u knots contain NaN or infinite values; repair the model"),
    (dict(degree_u=2.7), "surface u degree must be a whole number from 1 to 25, not 2.7"),
    (dict(degree_v=0), "surface v degree must be a whole number from 1 to 25, not 0"),
    (dict(poles=np.zeros((3, 3, 3)) + 1j), "surface poles must be real numbers, not complex ones"),
    (dict(poles=np.full((3, 3, 3), 1e300)), "surface poles reach 1e+300, beyond 1e+15: double precision cannot "
                                            "resolve the model there; scale the model down or move it nearer the "
                                            "origin"),
    (dict(poles=[["a"] * 3] * 3), "surface poles must be numbers"),
]


@pytest.mark.parametrize("change, message", SURFACES, ids=[m[:40] for _, m in SURFACES])
def test_a_bad_surface_field_is_named_in_one_line(change, message):
    with pytest.raises(BadInputError) as err:
        _surface(**change)
    assert str(err.value) == message


CURVES = [
    (dict(poles=[[0, 0], [np.nan, 0.2], [1, 0]]), "curve poles contain NaN or infinite values; repair the model"),
    (dict(weights=[1, -2, 1]), "curve weights must be positive (the smallest is -2)"),
    (dict(weights=[1, 1]), "curve weights must have shape (3,), got (2,)"),
    (dict(degree=2.5), "curve degree must be a whole number from 1 to 25, not 2.5"),
    (dict(knots=[0, 0, 0, 1, 1, np.inf]), "curve knots contain NaN or infinite values; repair the model"),
    (dict(knots=[0, 0, 1, 0, 1, 1]), "curve: knot vector is not non-decreasing; sort the knots"),
]


@pytest.mark.parametrize("change, message", CURVES, ids=[m[:40] for _, m in CURVES])
def test_a_bad_curve_field_is_named_in_one_line(change, message):
    with pytest.raises(BadInputError) as err:
        _curve(**change)
    assert str(err.value) == message


def test_whole_float_degrees_and_moderate_weights_are_accepted_and_evaluate_as_given():
    S = _surface(degree_u=2.0, weights=_weights(1e-5))
    assert S.degree_u == 2 and isinstance(S.degree_u, int)
    # the rational corner weight pulls the middle towards the corners: S(0.5, 0.5) = sum w B P / sum w B
    B = np.array([0.25, 0.5, 0.25])
    W = _weights(1e-5) * np.outer(B, B)
    expect = np.einsum("ij,ijk->k", W, _surface().poles) / W.sum()
    assert np.allclose(S(0.5, 0.5)[0], expect, atol=1e-14)


def test_a_region_refuses_fields_of_the_wrong_kind():
    curve3 = _curve(poles=[[0, 0, 0], [1, 0, 0], [1, 1, 0]])
    cases = [(lambda: Region(_surface(), (curve3,)), "the face's boundary must be given as 2D (u, v) curves"),
             (lambda: Region(_surface(), (_curve(),), holes=((curve3,),)),
              "the face's boundary must be given as 2D (u, v) curves"),
             (lambda: Region(_surface(), (_curve(),), edges3d=(_curve(),)),
              "the face's 3D edges must be given as 3D curves (or None where unknown)"),
             (lambda: Region(np.zeros((3, 3, 3)), (_curve(),)), "a region's surface must be a Surface, not ndarray")]
    for make, message in cases:
        with pytest.raises(BadInputError) as err:
            make()
        assert str(err.value) == message


OPTIONS = [
    (lambda: FitOptions(points_per_ruling=0),
     "points_per_ruling=0 must be a whole number of points from 2 to 1000 (9 is the default)"),
    (lambda: FitOptions(points_per_ruling=-3),
     "points_per_ruling=-3 must be a whole number of points from 2 to 1000 (9 is the default)"),
    (lambda: FitOptions(memory_cap=float("inf")),
     "memory_cap must be a positive finite number (a size in MiB), not inf"),
    (lambda: FitOptions(samples=40.5), "samples=40.5 must be a whole number of at least 3 (40 is a good start)"),
    (lambda: FitOptions(max_error=float("nan")),
     "max_error must be a positive finite number (a distance in model units), not nan"),
    (lambda: FitOptions(method="3d"), "'3d' is not a valid Method; see help(ruled.FitOptions)"),
    (lambda: SplitOptions(memory_cap=-1.0),
     "memory_cap must be a positive finite number (a size in MiB), not -9.53674e-07"),
    (lambda: SplitOptions(interior=0), "interior=0 must be a whole number of M-rows, at least 1 (10 is the paper's)"),
    (lambda: MachineOptions(taper_deg="steep"), "taper_deg must be from 0 to 45 degrees (the tool's half angle), not "
                                                "'steep'"),
    (lambda: MachineOptions(max_points=10.5), "max_points=10.5 must be a whole number from 100 to 100000000"),
    (lambda: MachineOptions(kerf=float("inf")),
     "kerf must be zero or a positive finite number (a distance in model units), not inf"),
]


@pytest.mark.parametrize("make, message", OPTIONS, ids=[m[:40] for _, m in OPTIONS])
def test_a_bad_option_is_refused_on_construction(make, message):
    with pytest.raises(BadInputError) as err:
        make()
    assert str(err.value) == message


def test_an_exact_fit_of_a_rational_face_with_moderate_weights_is_certified():
    """A bilinear face (exactly ruled) with weights 1e-5..1: the bound is finite and small, not NaN."""
    from ruled.fit.surface import fit_surface
    x, y = np.meshgrid(np.linspace(0, 1, 3), np.linspace(0, 1, 3), indexing="ij")
    S = Surface(np.stack([x, y, x * y], axis=2), KNOTS, KNOTS, 2, 2, _weights(1e-5))
    r = fit_surface(S, FitOptions(samples=12))
    assert np.isfinite(r.error_bound) and np.isfinite(r.surface.poles).all()


@pytest.mark.parametrize("code, why", [("ENOSPC", "the disk is full; free some space or write elsewhere"),
                                       ("EROFS", "the file system is read-only; write elsewhere")])
def test_a_write_that_fails_says_why_in_one_line_and_leaves_nothing(tmp_path, code, why):
    import errno

    from ruled.core.errors import RuledError
    from ruled.core.outputs import atomic
    target = tmp_path / "out.step"
    with pytest.raises(RuledError) as err:
        with atomic(str(target)) as tmp:
            open(tmp, "w").write("half a file")
            raise OSError(getattr(errno, code), os.strerror(getattr(errno, code)))
    assert str(err.value) == f"cannot write {target}: {why}"
    assert list(tmp_path.iterdir()) == []
