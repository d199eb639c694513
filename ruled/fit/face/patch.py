"""The face as a patch a fit runs on, and what every fit of a face shares: its size, its patch's deviation
added to the bounds, and the iso-parametric check (ruled.fit.face.fit pins the rulings to the face's corners;
ruled.fit.face.trimfit runs the rails past the face)."""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Optional

import numpy as np

from ruled.core.nurbs import Surface
from ruled.core.progress import Progress
from ruled.core.region import Region, Sides
from ruled.fit.fit2d import GRID_COARSE, GRID_FINE, FitResult, iso_fit, recertify

PATCH_TOL = 1e-6         # the sampled patch's target deviation from S o Omega, a fraction of the face's size
PATCH_ACCEPT = 1e-4      # kept when the surface's creases (C0 knot lines) keep the patch from the target
PATCH_MAX_SPANS = 192
EDGE_MARGIN = 1.05       # sampled distances between a face's 3D edges and its surface, raised by 5 %


@dataclass(frozen=True)
class FacePatch:
    """The face as a four-sided patch: ``surface`` (the input surface itself when ``identity``),
    its deviation from the bounded face, the region and its sides."""

    region: Region
    surface: Surface
    deviation: float
    identity: bool
    sides: Optional[Sides] = None
    direction: Optional[str] = None    # forced by the given rails
    spans: tuple = (0, 0)
    face_size: float = 0.0
    warnings: tuple = ()
    edge_gap: float = 0.0              # part of deviation: the face's edges lie off its surface by up to this
    hole_span: float = 0.0             # part of deviation: the spanning part over holes is this near the face
    mask: Optional[object] = None      # an extended patch (ruled.fit.face.extend): the face in its (s, t), trimmed
    extension: Optional[dict] = None   # how far the extended patch's rails run past the face
    own: bool = False                  # the face's own surface, whole (exactly ruled along an iso direction)
    box: bool = False                  # the face's own surface, whole, as the patch (own, or any surface)
    skew: Optional[float] = None       # a parallelogram along the face's straightest direction (its angle, degrees)
    plane: bool = False                # a rectangle of the plane of a planar face (ruled.fit.face.plane)
    inscribed: bool = False            # the surface's whole rectangle for a face inscribed in it (face.inscribed)
    fold: Optional[tuple] = None       # a closed face folded onto its mid-surface (face.fold): (axis, a, b)

    @property
    def trimmed(self) -> bool:
        return self.mask is not None

    def rails(self, direction: str) -> tuple:
        """The loop edges of the two rails of the fit along direction ('u' or 'v' of the patch)."""
        if self.fold is not None:         # (the rails are the fold lines, inside the face: no loop edge)
            return (), ()
        if self.box or self.skew is not None or self.plane:   # the loop edges on the patch's rails (t = 0 and 1)
            on = [(float(st[:, 1].max()) <= 1e-4, float(st[:, 1].min()) >= 1.0 - 1e-4)
                  for st in getattr(self.mask, "edges")]
            return tuple(tuple(k for k, o in enumerate(on) if o[i]) for i in (0, 1))
        if self.sides is not None:
            return self.sides.rails(direction)
        # the rectangle: the loop edges on its v-min / v-max (direction v) or u-min / u-max sides
        sides = self.region.rect_sides() or []
        return tuple(tuple(k for k, (n, _) in enumerate(sides) if n == f"{direction}{i}") for i in (0, 1))

    @property
    def how(self) -> str:
        if self.own:
            return "the face's own surface, exactly ruled along its iso lines, trimmed by the face's edges"
        if self.plane:
            return "the face is planar: rulings across a rectangle of its plane, trimmed by the face's edges"
        if self.skew is not None:
            return (f"rulings across a parallelogram of its surface's domain along the face's straightest direction "
                    f"({self.skew:.3g} degrees from its u lines), trimmed by the face's edges")
        if self.box:
            return ("no four-sided map of the face: rulings between the iso lines bounding its own surface, "
                    "trimmed by the face's edges")
        if self.trimmed:
            return f"rails past the face ({self.sides.how}), trimmed by the face's edges"
        if self.fold is not None:
            return (f"closed across {'uv'[self.fold[0]]}: both sides folded onto one ruled surface through its "
                    f"middle, its rails on the fold lines")
        if self.inscribed:
            return "its surface's whole (u, v) rectangle, untrimmed, the face inscribed in it"
        return "the face is its surface's whole (u, v) rectangle" if self.identity else self.sides.how


def region_size(region: Region) -> float:
    """The diagonal of the bounding box of the face's boundary (dense samples of its image)."""
    S = region.surface
    pts = []
    for k, c in enumerate(region.loop):
        uv = region.uv(k, np.linspace(c.domain[0], c.domain[1], 33))
        pts.append(S(uv[:, 0], uv[:, 1]))
    P = np.concatenate(pts)
    return float(np.linalg.norm(P.max(axis=0) - P.min(axis=0)))


def with_deviation(res: FitResult, dev: float) -> FitResult:
    """The fit with every candidate's certified bound raised by the patch's deviation."""
    if dev == 0.0:
        return res

    def up(c):
        if isinstance(c, str) or c is None:
            return c
        return replace(c, certificate=replace(c.certificate, bound=c.certificate.bound + dev,
                                              map_deviation=c.certificate.map_deviation + dev))
    return replace(res, best=up(res.best), candidates={d: up(c) for d, c in res.candidates.items()},
                   other=up(res.other))


ISO_MARGIN = 1e-3


def with_iso(res: FitResult, progress: Progress = None) -> FitResult:
    """The fit, where in either direction the iso-parametric ruled surface between the same rails has
    the lower certified bound, with that surface instead (the DP's objective is a sum over its rulings,
    so the straight pairing can win on the largest distance): never worse than a CAD system's ruled
    surface between two opposite edges."""
    cands = dict(res.candidates)
    notes = list(res.notes)
    for d, c in res.candidates.items():
        if isinstance(c, str) or (c.method == "2d" and np.all(c.pairs[:, 0] == c.pairs[:, 1])):
            continue
        if progress is not None:
            progress(f"iso-parametric check ({d})", 0.0)
        # a coarse certificate first (an upper bound too), one-sided where it cannot beat the best bound
        # yet (c is among them) ...
        rival = min(o.error_bound for o in cands.values() if not isinstance(o, str))
        iso = iso_fit(c, GRID_COARSE, rival)
        # ... the fine one only where it may win by more than 0.1 %, and samples closer than the DP's fit
        # (a tie within that is not worth a fine certificate: either surface is as good)
        if iso is not None and iso.certificate.node_max < (1.0 - ISO_MARGIN) * min(rival, c.certificate.node_max):
            iso = recertify(iso, GRID_FINE, rival)
        if progress is not None:
            progress(f"iso-parametric check ({d})", 1.0)
        if iso is not None and iso.error_bound < c.error_bound:
            cands[d] = iso
            if c is res.best:
                notes.append(f"the iso-parametric ruled surface between the rails has the lower bound "
                             f"({iso.error_bound:.4g} against {c.error_bound:.4g} for the DP's pairing) and is "
                             f"the result")
    ok = [c for c in cands.values() if not isinstance(c, str)]
    best = min(ok, key=lambda c: c.error_bound)
    if best is res.best:
        return res
    if best.direction != res.best.direction and best.method == "iso":
        notes.append(f"the iso-parametric ruled surface along {best.direction} has the lowest bound "
                     f"({best.error_bound:.4g}) and is the result")
    return replace(res, best=best, candidates=cands, notes=tuple(notes),
                   other=res.best if res.other is None else res.other)


__all__ = ["FacePatch", "region_size", "with_deviation", "with_iso", "PATCH_TOL", "PATCH_ACCEPT", "PATCH_MAX_SPANS",
           "EDGE_MARGIN"]
