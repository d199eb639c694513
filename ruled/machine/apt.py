"""APT CL data: a wire's synchronized path for a commercial wire post (``apt-sync``), and a flank-milling tool
path (``apt``).

apt-sync, in the machine frame (X = p . e1, Y = p . e2, Z the height along the machine axis)::

    SET/UPPER,h1,LOWER,h0            the guide planes' heights
    GOTO/x,y,h0,i,j,k                the lower guide's point and the wire's unit direction (lower to upper)
    SYNCTR                           the next GOTO is synchronized with the one before: both guides arrive together

Flank milling, in the part's coordinates: the 7-parameter cutter ``CUTTER/d,r,e,f,a,b,h`` (d the diameter at the
tip, r the corner radius, e = d/2 - r and f = r the corner's centre, a = 0 the bottom's angle, b the side's taper
from the axis, h the length), ``MULTAX/ON`` and ``GOTO/x,y,z,i,j,k``: the tip centre and the tool axis at every
CL point.
"""

from __future__ import annotations

import numpy as np

from ruled.core.errors import BadInputError
from ruled.machine.posts import Post
from ruled.machine.program import comment_text, metadata, num, scale, sig


def _head(post: Post, title: str, words: list, units: str) -> list:
    lines = [comment_text(w, post.comment) for w in words]
    return [ln for ln in lines if ln] + [f"PARTNO/{_partno(title)}", "UNITS/MM" if units == "mm" else "UNITS/INCHES"]


def _partno(title: str) -> str:
    return " ".join(title.upper().replace(",", " ").replace("/", " ").split())[:66] or "RULED"


def apt_sync_lines(path, post: Post, units: str = "mm", side=None, title: str = "") -> list:
    """apt-sync's lines of an XYUV path (see the module)."""
    if path.mode != "xyuv":
        raise BadInputError("apt-sync is written for XYUV contours; flank paths use the post apt")
    k = scale(units)
    dec = post.decimals + (1 if units == "inch" else 0)
    h0, h1 = (h * k for h in path.planes)
    m = path.moves * k
    lo = np.column_stack([m[:, :2], np.full(len(m), h0)])
    d = np.column_stack([m[:, 2:] - m[:, :2], np.full(len(m), h1 - h0)])
    d /= np.linalg.norm(d, axis=1)[:, None]
    name = title or "ruled wire path"
    words = [f"{name}: ruled XYUV wire path, post {post.name}", *metadata(path, post, units, None, side),
             f"GOTO/x,y,z,i,j,k: the lower guide on the plane z = {num(h0, dec)} and the wire's direction to the "
             f"upper guide at z = {num(h1, dec)}, in the machine frame; SYNCTR: both guides arrive together",
             f"{path.stats.get('sync_points', len(m))} synchronized points, chord tolerance "
             f"{sig(path.chord_tol * k, 6)}, kerf {sig(path.radius * k, 6)}"
             + (f" {side}" if side else "")]
    out = _head(post, name, words, units) + ["MULTAX/ON", f"SET/UPPER,{num(h1, dec)},LOWER,{num(h0, dec)}",
                                             f"FEDRAT/{sig(path.feed, 7)}", "RAPID"]
    for i, (p, a) in enumerate(zip(lo, d)):
        if i >= 2:
            out.append("SYNCTR")
        out.append("GOTO/" + ",".join(num(x, dec) for x in p) + "," + ",".join(num(x, 9) for x in a))
    return out + ["FINI"]


def cutter(path, units: str = "mm", corner_radius: float = 0.0) -> tuple:
    """The 7 parameters (d, r, e, f, a, b, h) of the flank tool in the output units: a flat end (r = 0, e = d/2)
    or a corner radius r (e = d/2 - r, f = r), the side's taper b from the axis, the length h the longest tool."""
    k = scale(units)
    d = 2.0 * path.radius * k
    r = corner_radius * k
    if r > 0.5 * d:
        raise BadInputError(f"the corner radius «corner_radius={corner_radius:g}» is larger than the tool's radius "
                            f"{path.radius:g}")
    h = path.flute * k
    return d, r, 0.5 * d - r, r, 0.0, path.taper_deg, h


def flank_apt_lines(path, post: Post, units: str = "mm", title: str = "", corner_radius: float = 0.0) -> list:
    """The flank APT's lines of a flank path (see the module)."""
    if path.mode != "flank":
        raise BadInputError("APT flank CL data is written for flank paths; XYUV contours use a wire post")
    k = scale(units)
    dec = post.decimals + (1 if units == "inch" else 0)
    name = title or "ruled flank path"
    from ruled import __version__
    words = [f"{name}: ruled flank milling CL data, post {post.name}",
             f"ruled {__version__} post={post.name} machine=flank units={units}",
             "GOTO/x,y,z,i,j,k: the tool's tip centre and its axis (tip to shank) in the part's coordinates"]
    out = _head(post, "RULED FLANK " + name, words, units) + [
        "MULTAX/ON", "CUTTER/" + ",".join(num(x, dec) for x in cutter(path, units, corner_radius)),
        f"FEDRAT/{sig(path.feed, 7)}"]
    for p, a in zip(path.lower * k, path.axes):
        out.append("GOTO/" + ",".join(num(x, dec) for x in p) + "," + ",".join(num(x, 9) for x in a))
    return out + ["FINI"]


__all__ = ["apt_sync_lines", "flank_apt_lines", "cutter"]
