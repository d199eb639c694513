"""Sub-element names as FreeCAD gives them: 'Face6' (0.20, 0.21), or on 1.0 with its topological naming a mapped
name whose last part is the indexed one (';#11f;:H4d1,F.Face6': a face of a PartDesign body).  The check and the
lookup use the indexed name; the link keeps what FreeCAD gave (its mapped name follows the face when the body
changes)."""

from __future__ import annotations

import re

_INDEXED = re.compile(r"(?:^|[.;:])((?:Face|Edge|Vertex)[1-9][0-9]*)$")


def short_name(sub: str) -> str:
    """The indexed name of a sub-element name ('Face6' of 'Face6' and of ';#11f;:H4d1,F.Face6'); the name itself
    where it has none."""
    m = _INDEXED.search(str(sub or ""))
    return m.group(1) if m else str(sub or "")


def is_face(sub: str) -> bool:
    return short_name(sub).startswith("Face")


def is_edge(sub: str) -> bool:
    return short_name(sub).startswith("Edge")


def element(shape, sub: str):
    """The shape's sub-element named sub (mapped or not)."""
    return shape.getElement(short_name(sub))


__all__ = ["short_name", "is_face", "is_edge", "element"]
