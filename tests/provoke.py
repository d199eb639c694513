"""Results broken on purpose, to show that the front doors' own checks catch them (issue 34).  Plain NumPy
and the engine's containers only: freecadcmd imports it too."""

from __future__ import annotations

from dataclasses import replace

import numpy as np


def folded(S):
    """S (clamped in u) run forward and then back over itself: the same points, so the same distance from
    anything, with twice the area (a result that covers the face twice over)."""
    p, K, P = S.degree_u, np.asarray(S.knots_u), np.asarray(S.poles)
    a, b = K[0], K[-1]
    inner = K[p + 1:-p - 1]
    knots = np.concatenate([[a] * (p + 1), inner, [b] * p, (2 * b - inner)[::-1], [2 * b - a] * (p + 1)])
    poles = np.concatenate([P, P[::-1][1:]])
    w = None if S.weights is None else np.concatenate([S.weights, S.weights[::-1][1:]])
    return type(S)(poles, knots, S.knots_v, p, S.degree_v, w)


def folding(fit):
    """fit (ruled.fit.face.fit.fit_region) made to return its result, and every other candidate, folded over
    itself (their bounds still true)."""
    def fold(c):
        return c if c is None or isinstance(c, str) else replace(c, surface=folded(c.surface))

    def fit_folded(*a, **k):
        res = fit(*a, **k)
        return replace(res, best=fold(res.best), candidates={d: fold(c) for d, c in res.candidates.items()},
                       other=fold(res.other))
    return fit_folded


def fold_results(module) -> None:
    """module.fit_region folding its results, for good (a sitecustomize, a FreeCAD script)."""
    module.fit_region = folding(module.fit_region)
