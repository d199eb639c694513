"""A wall's face that is no exact four-sided patch (its contour edges are not two opposite sides of its surface,
or it is planar with curved joints: a drafted plane meeting a drafted cone at a sharp corner of the profile,
along a curve): the patch S o Omega of the Coons map of its four sides, the bottom contour edges, a joint, the
top contour edges and the other joint (ruled.fit.face.coons), sampled into a bicubic B-spline whose deviation from
the face, as bounded by its edges, is carried into the wall's bound (ruled.fit.face.fit.sided_patch).  Hosts
give the face's Region and which of its outer loop's edges lie on each contour."""

from __future__ import annotations

from ruled.core.errors import BadInputError, DegenerateFaceError
from ruled.core.region import Region, Sides


def _run(region: Region, ids, name, which: str) -> list:
    """The loop edges ids (a contiguous run of the loop) in loop order."""
    n = region.size
    ids = set(int(k) for k in ids)
    start = next((k for k in ids if (k - 1) % n not in ids), None)
    out: list = []
    k = start
    while k is not None and k in ids and k not in out:
        out.append(k)
        k = (k + 1) % n
    if not ids or len(out) != len(ids):
        raise BadInputError(f"face {name} of the wall: its {which} contour edges are not one run of its boundary; "
                            f"a wall's face runs from the bottom contour to the top one")
    return out


def contour_sides(region: Region, bottom, top, name="") -> Sides:
    """The face's four sides: side 0 its bottom contour edges (loop indices), side 2 its top ones, sides 1
    and 3 the loop's edges between them (its joints with the next and the previous face)."""
    n = region.size
    B, T = _run(region, bottom, name, "bottom"), _run(region, top, name, "top")
    if set(B) & set(T):
        raise BadInputError(f"face {name} of the wall has an edge on both contours; a wall's face runs from the "
                            f"bottom contour to the top one")

    def between(last: int, first: int) -> list:
        out, k = [], (last + 1) % n
        while k != first:
            out.append(k)
            k = (k + 1) % n
        return out

    def whole(k: int):
        a, b = region.loop[k].domain
        return (k, a, b)
    sides = (B, between(B[-1], T[0]), T, between(T[-1], B[0]))
    return Sides(tuple(tuple(whole(k) for k in s) for s in sides), tuple(region.joint_angles()),
                 "the wall's contours and the face's joints")


def contour_patch(region: Region, bottom, top, name=""):
    """The face as the sampled Coons patch of its contour sides (ruled.fit.face.patch.FacePatch: its surface
    runs along s from side 3 to side 1 and along t from the bottom contour to the top one, its deviation
    from the bounded face).  Refused in one line where the map folds."""
    from ruled.fit.face.coons import coons_map
    from ruled.fit.face.fit import sided_patch
    sides = contour_sides(region, bottom, top, name)
    try:
        # (the sampled patch's deviation is taken at eight points a span: ruled.fit.face.sampled.dense_deviation)
        return sided_patch(region, sides, coons_map(region, sides))
    except DegenerateFaceError as exc:
        raise BadInputError(f"face {name} of the wall cannot be mapped from its bottom contour edges to its top "
                            f"ones ({exc}); fit it alone («one_face»)") from None


__all__ = ["contour_sides", "contour_patch"]
