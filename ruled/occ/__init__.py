"""The only part of Ruled that imports OCP (OCCT): reading faces, building result
faces, STEP, and the independent error measure."""

from .convert import (container_to_bspline, container_to_face, face_to_container, face_surface_type,
                      bspline_surface_to_container)
from .io import face_area, faces_of, get_face, list_faces, read_shape, write_step
from .measure import Hausdorff, hausdorff

__all__ = ["container_to_bspline", "container_to_face", "face_to_container", "face_surface_type",
           "bspline_surface_to_container", "face_area", "faces_of", "get_face", "list_faces", "read_shape",
           "write_step", "Hausdorff", "hausdorff"]
