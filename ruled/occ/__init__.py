"""The only part of Ruled that imports OCP (OCCT): reading faces, building result
faces, STEP, and the independent error measure."""

from ruled.core.lazy import lazy_getattr

_LAZY = {"container_to_bspline": "convert", "container_to_face": "convert", "face_to_container": "convert",
         "face_surface_type": "convert", "bspline_surface_to_container": "convert", "face_area": "io",
         "faces_of": "io", "get_face": "io", "list_faces": "io", "read_shape": "io", "write_step": "io",
         "Hausdorff": "measure", "hausdorff": "measure"}


__getattr__ = lazy_getattr(__name__, _LAZY, globals())


__all__ = ["container_to_bspline", "container_to_face", "face_to_container", "face_surface_type",
           "bspline_surface_to_container", "face_area", "faces_of", "get_face", "list_faces", "read_shape",
           "write_step", "Hausdorff", "hausdorff"]
