"""NURBS containers and vectorized evaluation.

A :class:`Surface` or :class:`Curve` holds plain arrays only: poles, optional
weights, *full* knot vectors (every knot repeated by its multiplicity), degrees
and periodic flags.  A periodic object is stored unwrapped: the knot vector is
extended by one period on each side and the first ``degree`` poles repeat at
the end, so that evaluation is the ordinary (unclamped) B-spline algorithm on
the parameter range ``[knots[p], knots[-p-1]]``.

Evaluation follows Piegl & Tiller (The NURBS Book, A2.2/A2.3 for the basis and
its derivatives, A4.4 for rational derivatives), vectorized over many
parameters at once.  Only NumPy is used, and only functions present in
NumPy 1.24, so that FreeCAD 0.20's Python gives the same numbers.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from ruled.core import jit, kernels
from ruled.core.basis import _as_f64, _deriv_net, basis_derivatives, find_spans, refine_axis, taylor_table
from ruled.core.checks import MAX_COORD, positive_weights, real_array, whole_degree
from ruled.core.errors import BadInputError

_CHUNK = 40000


def _check_knots(knots: np.ndarray, degree: int, n_poles: int, name: str) -> None:
    if knots.ndim != 1 or knots.shape[0] != n_poles + degree + 1:
        raise BadInputError(
            f"{name}: knot vector has {knots.shape[0]} entries, expected poles + degree + 1 = "
            f"{n_poles + degree + 1}; pass the full knot vector (each knot repeated by its multiplicity)"
        )
    if np.any(np.diff(knots) < 0):
        raise BadInputError(f"{name}: knot vector is not non-decreasing; sort the knots")
    if not knots[degree] < knots[-degree - 1]:
        raise BadInputError(f"{name}: the parameter range [knots[p], knots[-p-1]] is empty")


@dataclass(frozen=True)
class Curve:
    """A (rational) B-spline curve of plain arrays.

    poles (n, d), weights (n,) or None, knots (n+p+1,) full, degree p.
    """

    poles: np.ndarray
    knots: np.ndarray
    degree: int
    weights: Optional[np.ndarray] = None
    periodic: bool = False
    _hom: np.ndarray = field(default=None, repr=False, compare=False)
    _tab_cache: np.ndarray = field(default=None, repr=False, compare=False)

    def __post_init__(self):
        P = real_array(self.poles, "curve poles", MAX_COORD)
        if P.ndim == 1:
            P = P[:, None]
        if P.ndim != 2:
            raise BadInputError(f"curve poles must have shape (n, dim), got {P.shape}")
        object.__setattr__(self, "poles", P)
        object.__setattr__(self, "knots", real_array(self.knots, "curve knots"))
        object.__setattr__(self, "degree", whole_degree(self.degree, "curve"))
        if self.weights is not None:
            object.__setattr__(self, "weights", positive_weights(self.weights, P.shape[:1], "curve"))
        _check_knots(self.knots, self.degree, self.poles.shape[0], "curve")
        w = np.ones(P.shape[0]) if self.weights is None else self.weights
        object.__setattr__(self, "_hom", np.ascontiguousarray(np.concatenate([P * w[:, None], w[:, None]], axis=1)))

    @property
    def _tab(self):
        """Taylor table of the numba evaluator, built on first use."""
        if self._tab_cache is None and jit.AVAILABLE:
            object.__setattr__(self, "_tab_cache", taylor_table(self.knots, self.degree))
        return self._tab_cache

    @property
    def domain(self) -> tuple[float, float]:
        return float(self.knots[self.degree]), float(self.knots[-self.degree - 1])

    @property
    def rational(self) -> bool:
        return self.weights is not None

    def evaluate(self, t, nder: int = 0) -> list[np.ndarray]:
        """Points and derivatives: a list [C, C', C''][: nder+1], each (N, d)."""
        t = np.atleast_1d(_as_f64(t)).ravel()
        p = self.degree
        n = self.poles.shape[0]
        if jit.enabled() and nder <= 2:
            out = np.empty((t.shape[0], nder + 1, self.poles.shape[1]))
            kernels.curve_eval(self._hom, self.knots, self._tab, p, t, nder, out)
            return [out[:, k] for k in range(nder + 1)]
        spans = find_spans(self.knots, p, n, t)
        B = basis_derivatives(self.knots, p, spans, t, nder)
        idx = spans[:, None] - p + np.arange(p + 1)[None, :]
        Bt = np.transpose(B, (1, 0, 2))                      # (N, K, p+1): every order in one product
        if self.weights is None:
            D = np.matmul(Bt, self.poles[idx])
            return [D[:, k] for k in range(nder + 1)]
        D = np.matmul(Bt, self._hom[idx])                    # homogeneous (N, K, d+1)
        return _rational_curve_ders([D[:, k, :-1] for k in range(nder + 1)], [D[:, k, -1] for k in range(nder + 1)])

    def __call__(self, t) -> np.ndarray:
        return self.evaluate(t, 0)[0]


def _rational_curve_ders(A, w):
    out = [A[0] / w[0][:, None]]
    if len(A) > 1:
        out.append((A[1] - w[1][:, None] * out[0]) / w[0][:, None])
    if len(A) > 2:
        out.append((A[2] - 2.0 * w[1][:, None] * out[1] - w[2][:, None] * out[0]) / w[0][:, None])
    return out


@dataclass(frozen=True)
class Derivs:
    """Surface point and derivatives at N parameters, each (N, 3); missing orders are None."""

    P: np.ndarray
    Su: Optional[np.ndarray] = None
    Sv: Optional[np.ndarray] = None
    Suu: Optional[np.ndarray] = None
    Suv: Optional[np.ndarray] = None
    Svv: Optional[np.ndarray] = None

    def normals(self) -> np.ndarray:
        """Unit normals Su x Sv / |Su x Sv| (N, 3); zero where the surface is singular."""
        n = np.cross(self.Su, self.Sv)
        ln = np.linalg.norm(n, axis=1)
        return n / np.where(ln > 0, ln, 1.0)[:, None]


@dataclass(frozen=True)
class Surface:
    """A tensor-product (rational) B-spline surface of plain arrays.

    poles (nu, nv, 3); weights (nu, nv) or None; knots_u (nu+pu+1,), knots_v
    (nv+pv+1,) full; degrees; periodic flags (stored unwrapped, see module doc).
    """

    poles: np.ndarray
    knots_u: np.ndarray
    knots_v: np.ndarray
    degree_u: int
    degree_v: int
    weights: Optional[np.ndarray] = None
    periodic_u: bool = False
    periodic_v: bool = False
    _hom: np.ndarray = field(default=None, repr=False, compare=False)
    _tabs: tuple = field(default=None, repr=False, compare=False)

    def __post_init__(self):
        poles = real_array(self.poles, "surface poles", MAX_COORD)
        if poles.ndim != 3 or poles.shape[2] != 3:
            raise BadInputError(f"surface poles must have shape (nu, nv, 3), got {poles.shape}")
        object.__setattr__(self, "poles", poles)
        object.__setattr__(self, "knots_u", real_array(self.knots_u, "surface u knots"))
        object.__setattr__(self, "knots_v", real_array(self.knots_v, "surface v knots"))
        object.__setattr__(self, "degree_u", whole_degree(self.degree_u, "surface u"))
        object.__setattr__(self, "degree_v", whole_degree(self.degree_v, "surface v"))
        if self.weights is not None:
            w = positive_weights(self.weights, poles.shape[:2], "surface")
            if np.all(w == w.flat[0]):
                w = None
            object.__setattr__(self, "weights", w)
        _check_knots(self.knots_u, self.degree_u, poles.shape[0], "surface u")
        _check_knots(self.knots_v, self.degree_v, poles.shape[1], "surface v")
        if self.weights is None:
            hom = np.concatenate([poles, np.ones(poles.shape[:2] + (1,))], axis=2)
        else:
            hom = np.concatenate([poles * self.weights[..., None], self.weights[..., None]], axis=2)
        object.__setattr__(self, "_hom", np.ascontiguousarray(hom))
        if jit.AVAILABLE:
            object.__setattr__(self, "_tabs", (taylor_table(self.knots_u, self.degree_u),
                                               taylor_table(self.knots_v, self.degree_v)))

    # ------------------------------------------------------------------ properties
    @property
    def rational(self) -> bool:
        return self.weights is not None

    @property
    def domain(self) -> tuple[float, float, float, float]:
        """(u0, u1, v0, v1)."""
        pu, pv = self.degree_u, self.degree_v
        return (float(self.knots_u[pu]), float(self.knots_u[-pu - 1]),
                float(self.knots_v[pv]), float(self.knots_v[-pv - 1]))

    def diagonal(self) -> float:
        """Diagonal of the bounding box of the poles (the scale of the surface)."""
        P = self.poles.reshape(-1, 3)
        return float(np.linalg.norm(P.max(axis=0) - P.min(axis=0)))

    def transposed(self) -> "Surface":
        """The same surface with u and v exchanged."""
        w = None if self.weights is None else self.weights.T
        return Surface(np.transpose(self.poles, (1, 0, 2)), self.knots_v, self.knots_u,
                       self.degree_v, self.degree_u, w, self.periodic_v, self.periodic_u)

    def interior_knots(self, direction: str) -> np.ndarray:
        """Distinct knot values strictly inside the domain in 'u' or 'v'."""
        if direction == "u":
            k, p = self.knots_u, self.degree_u
        else:
            k, p = self.knots_v, self.degree_v
        a, b = k[p], k[-p - 1]
        kk = np.unique(k)
        return kk[(kk > a) & (kk < b)]

    def creases(self, axis: int) -> np.ndarray:
        """The knot values strictly inside the domain along axis (0: u, 1: v) where the surface is only C0
        across (multiplicity >= degree): its creases, if the poles make them."""
        knots, p = (self.knots_u, self.degree_u) if axis == 0 else (self.knots_v, self.degree_v)
        a, b = (self.domain[0], self.domain[1]) if axis == 0 else (self.domain[2], self.domain[3])
        kv, mult = np.unique(knots, return_counts=True)
        return kv[(mult >= p) & (kv > a) & (kv < b)]

    # ------------------------------------------------------------------ evaluation
    def evaluate(self, u, v, nder: int = 0) -> Derivs:
        """Points and partial derivatives up to total order ``nder`` (0, 1 or 2).

        u, v: arrays (N,) (broadcast together).  Returns :class:`Derivs`, each (N, 3).
        """
        u, v = np.broadcast_arrays(np.atleast_1d(_as_f64(u)), np.atleast_1d(_as_f64(v)))
        u = np.ascontiguousarray(u.ravel())
        v = np.ascontiguousarray(v.ravel())
        N = u.shape[0]
        if jit.enabled() and nder <= 2:
            out = np.empty((N, 6, 3))
            kernels.surface_eval(self._hom, self.knots_u, self.knots_v, self._tabs[0], self._tabs[1],
                                 self.degree_u, self.degree_v, u, v, nder, out)
            if nder == 0:
                return Derivs(out[:, 0])
            if nder == 1:
                return Derivs(out[:, 0], out[:, 1], out[:, 2])
            return Derivs(out[:, 0], out[:, 1], out[:, 2], out[:, 3], out[:, 4], out[:, 5])
        if N > _CHUNK:
            parts = [self.evaluate(u[s:s + _CHUNK], v[s:s + _CHUNK], nder) for s in range(0, N, _CHUNK)]
            return Derivs(*[None if getattr(parts[0], f) is None else
                            np.concatenate([getattr(q, f) for q in parts])
                            for f in ("P", "Su", "Sv", "Suu", "Suv", "Svv")])
        pu, pv = self.degree_u, self.degree_v
        nu, nv = self.poles.shape[:2]
        su = find_spans(self.knots_u, pu, nu, u)
        sv = find_spans(self.knots_v, pv, nv, v)
        Bu = basis_derivatives(self.knots_u, pu, su, u, min(nder, pu))
        Bv = basis_derivatives(self.knots_v, pv, sv, v, min(nder, pv))
        iu = su[:, None] - pu + np.arange(pu + 1)[None, :]
        iv = sv[:, None] - pv + np.arange(pv + 1)[None, :]
        H = self._hom[iu[:, :, None], iv[:, None, :]]  # (N, pu+1, pv+1, 4)
        # contract v first, every derivative order at once (batched matrix products, faster than einsum):
        # T[n, r, m, c] = sum_s Bv[m, n, s] H[n, r, s, c], then Aall[n, k, m, c] = sum_r Bu[k, n, r] T[n, r, m, c]
        Ku, Kv = Bu.shape[0], Bv.shape[0]
        T = np.matmul(np.transpose(Bv, (1, 0, 2))[:, None], H)
        Aall = np.matmul(np.transpose(Bu, (1, 0, 2)), T.reshape(N, pu + 1, Kv * 4)).reshape(N, Ku, Kv, 4)

        def A(k, m):
            if k >= Ku or m >= Kv:
                return np.zeros((N, 4))
            return Aall[:, k, m]

        orders = [(0, 0)]
        if nder >= 1:
            orders += [(1, 0), (0, 1)]
        if nder >= 2:
            orders += [(2, 0), (1, 1), (0, 2)]
        Aw = {o: A(*o) for o in orders}
        w = {o: Aw[o][:, 3] for o in orders}
        P = Aw[(0, 0)][:, :3] / w[(0, 0)][:, None]
        if nder == 0:
            return Derivs(P)
        w0 = w[(0, 0)][:, None]
        Su = (Aw[(1, 0)][:, :3] - w[(1, 0)][:, None] * P) / w0
        Sv = (Aw[(0, 1)][:, :3] - w[(0, 1)][:, None] * P) / w0
        if nder == 1:
            return Derivs(P, Su, Sv)
        Suu = (Aw[(2, 0)][:, :3] - 2.0 * w[(1, 0)][:, None] * Su - w[(2, 0)][:, None] * P) / w0
        Svv = (Aw[(0, 2)][:, :3] - 2.0 * w[(0, 1)][:, None] * Sv - w[(0, 2)][:, None] * P) / w0
        Suv = (Aw[(1, 1)][:, :3] - w[(1, 0)][:, None] * Sv - w[(0, 1)][:, None] * Su
               - w[(1, 1)][:, None] * P) / w0
        return Derivs(P, Su, Sv, Suu, Suv, Svv)

    def __call__(self, u, v) -> np.ndarray:
        return self.evaluate(u, v, 0).P

    def normals(self, u, v) -> np.ndarray:
        """Unit normals (N, 3)."""
        return self.evaluate(u, v, 1).normals()

    def iso_curve(self, direction: str, value: float) -> Curve:
        """The exact iso-parametric curve: direction 'u' gives C(u) = S(u, value)."""
        if direction == "v":
            return self.transposed().iso_curve("u", value)
        pv = self.degree_v
        nv = self.poles.shape[1]
        sv = find_spans(self.knots_v, pv, nv, np.array([value]))
        Bv = basis_derivatives(self.knots_v, pv, sv, np.array([value]), 0)[0, 0]
        H = self._hom[:, sv[0] - pv: sv[0] + 1, :]
        Hc = np.einsum("s,rsc->rc", Bv, H)
        w = Hc[:, 3]
        weights = None if self.weights is None else w
        return Curve(Hc[:, :3] / w[:, None], self.knots_u, self.degree_u, weights, self.periodic_u)

    # ------------------------------------------------------------------ bounds
    def subdivided(self, pieces_u: int, pieces_v: int, extra_u=None, extra_v=None) -> "Surface":
        """The same surface with each knot span split into pieces, and knots inserted at extra_u, extra_v
        (Boehm insertion): its per-span derivative bounds are local to smaller pieces, hence tighter
        (cached; not periodic any more)."""
        plain = (extra_u is None or len(extra_u) == 0) and (extra_v is None or len(extra_v) == 0)
        if pieces_u <= 1 and pieces_v <= 1 and plain:
            return self
        cache = self.__dict__.get("_sub_cache")
        if cache is None:
            cache = {}
            object.__setattr__(self, "_sub_cache", cache)
        key = (pieces_u, pieces_v) + (() if plain else (np.asarray(extra_u, float).tobytes(),
                                                        np.asarray(extra_v, float).tobytes()))
        if key not in cache:
            H, ku = refine_axis(self._hom, self.knots_u, self.degree_u, pieces_u, 0, extra_u)
            H, kv = refine_axis(H, self.knots_v, self.degree_v, pieces_v, 1, extra_v)
            w = H[..., 3]
            cache[key] = Surface(H[..., :3] / w[..., None], ku, kv, self.degree_u, self.degree_v,
                                 None if self.weights is None else w)
        return cache[key]

    def derivative_bounds(self) -> dict:
        """Rigorous per-span bounds of |S_u|, |S_v|, |S_uu|, |S_uv|, |S_vv|.

        Returns a dict with arrays (nu - pu, nv - pv) indexed by span (i - pu,
        j - pv), plus 'spans_u'/'spans_v', the knot spans' start indices.  The
        bounds use the convex-hull property of the derivative control nets of
        the homogeneous surface and, for rational surfaces, the quotient rule
        with the smallest local weight.  Computed once per surface (the arrays are shared: read only).
        """
        cached = self.__dict__.get("_db2_cache")
        if cached is None:
            cached = self._derivative_bounds()
            for a in cached.values():
                a.flags.writeable = False
            object.__setattr__(self, "_db2_cache", cached)
        return cached

    def third_derivative_bounds(self) -> dict:
        """Rigorous per-span bounds of the third derivatives |S_uuu|, |S_uuv|, |S_uvv|, |S_vvv| (same
        layout and caching as derivative_bounds; the quotient rule continued to third order)."""
        cached = self.__dict__.get("_db3_cache")
        if cached is None:
            cached = self._derivative_bounds(3)
            for a in cached.values():
                a.flags.writeable = False
            object.__setattr__(self, "_db3_cache", cached)
        return cached

    def _derivative_bounds(self, order: int = 2) -> dict:
        pu, pv = self.degree_u, self.degree_v
        H = self._hom
        nets = {}
        for a in range(order + 1):
            for b in range(order + 1 - a):
                D = H
                ku, kv = self.knots_u, self.knots_v
                for s in range(a):
                    D, ku = _deriv_net(D, ku, pu - s, axis=0)
                for s in range(b):
                    D, kv = _deriv_net(D, kv, pv - s, axis=1)
                nets[(a, b)] = D
        nu, nv = H.shape[:2]
        win = np.lib.stride_tricks.sliding_window_view
        loc = win(self.poles, (pu + 1, pv + 1), axis=(0, 1))  # (nu-pu, nv-pv, 3, pu+1, pv+1)
        lo = loc.min(axis=(3, 4))
        hi = loc.max(axis=(3, 4))
        c = 0.5 * (lo + hi)
        Sm = np.linalg.norm(hi - lo, axis=2) * 0.5
        if self.weights is None:
            wmin = np.ones((nu - pu, nv - pv))
        else:
            wmin = win(self.weights, (pu + 1, pv + 1), axis=(0, 1)).min(axis=(2, 3))
        hd, wd = {}, {}
        for (a, b), D in nets.items():
            if (a, b) == (0, 0):
                continue
            if a > pu or b > pv:
                hd[(a, b)] = np.zeros_like(wmin)
                wd[(a, b)] = np.zeros_like(wmin)
                continue
            Dl = win(D, (pu - a + 1, pv - b + 1), axis=(0, 1))  # (nu-pu, nv-pv, 4, ., .)
            d3 = Dl[:, :, :3] - c[:, :, :, None, None] * Dl[:, :, 3:4]
            hd[(a, b)] = np.sqrt((d3 ** 2).sum(axis=2)).max(axis=(2, 3))
            wd[(a, b)] = np.abs(Dl[:, :, 3]).max(axis=(2, 3))
        # w (S - c) = H - c w, differentiated (Leibniz), |S - c| <= Sm and w >= wmin on the span
        S1u = (hd[(1, 0)] + wd[(1, 0)] * Sm) / wmin
        S1v = (hd[(0, 1)] + wd[(0, 1)] * Sm) / wmin
        Suu = (hd[(2, 0)] + 2 * wd[(1, 0)] * S1u + wd[(2, 0)] * Sm) / wmin
        Svv = (hd[(0, 2)] + 2 * wd[(0, 1)] * S1v + wd[(0, 2)] * Sm) / wmin
        Suv = (hd[(1, 1)] + wd[(1, 0)] * S1v + wd[(0, 1)] * S1u + wd[(1, 1)] * Sm) / wmin
        if order == 2:
            return {"Su": S1u, "Sv": S1v, "Suu": Suu, "Suv": Suv, "Svv": Svv}
        Suuu = (hd[(3, 0)] + 3 * wd[(1, 0)] * Suu + 3 * wd[(2, 0)] * S1u + wd[(3, 0)] * Sm) / wmin
        Svvv = (hd[(0, 3)] + 3 * wd[(0, 1)] * Svv + 3 * wd[(0, 2)] * S1v + wd[(0, 3)] * Sm) / wmin
        Suuv = (hd[(2, 1)] + 2 * wd[(1, 0)] * Suv + wd[(2, 0)] * S1v + wd[(0, 1)] * Suu
                + 2 * wd[(1, 1)] * S1u + wd[(2, 1)] * Sm) / wmin
        Suvv = (hd[(1, 2)] + 2 * wd[(0, 1)] * Suv + wd[(0, 2)] * S1u + wd[(1, 0)] * Svv
                + 2 * wd[(1, 1)] * S1v + wd[(1, 2)] * Sm) / wmin
        return {"Suuu": Suuu, "Suuv": Suuv, "Suvv": Suvv, "Svvv": Svvv}


