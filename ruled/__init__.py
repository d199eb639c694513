"""Ruled: optimal ruled-surface fitting for CAD faces.

House rule: this package (the engine) imports no CAD host.  numpy and scipy
only; OCP (OCCT) is imported only in ``ruled.occ`` (and by the command line
and the CadQuery entry points through it); FreeCAD only in ``workbench/``.
Data crosses every boundary as plain arrays in small frozen containers.
"""

from ruled.core.errors import (
    BadInputError,
    CancelledError,
    DegenerateFaceError,
    FiguresError,
    InfeasibleError,
    RuledError,
    ToleranceError,
    TooBigError,
)
from ruled.core.lazy import lazy_getattr

__version__ = "0.1.0"

# the public API, imported on first use: `ruled --help` and argument errors answer before numpy,
# scipy and the numba kernels are loaded
_LAZY = {"Direction": "fit.options", "FitOptions": "fit.options", "FitResult": "fit.fit2d", "Method": "fit.options",
         "Metric": "fit.options", "Objective": "fit.options", "fit_surface": "fit.surface", "FacePatch": "fit.face.fit",
         "face_patch": "fit.face.fit", "fit_region": "fit.face.fit", "Curve": "core.nurbs", "Surface": "core.nurbs",
         "Region": "core.region", "SplitOptions": "split.partition", "split_face": "split.partition",
         "partition": "split.partition", "CurveOnSurface": "curves.curve_on_surface",
         "approximate": "curves.curve_on_surface", "ConeSpline": "cone.conespline",
         "cone_spline_of_surface": "cone.surface", "MachineOptions": "machine.paths", "machine_path": "machine.flank",
         "join_patches": "machine.chain"}


__getattr__ = lazy_getattr(__name__, _LAZY, globals())


def __dir__() -> list:
    return sorted(set(globals()) | set(_LAZY))


__all__ = ["Surface", "Curve", "Region", "FacePatch", "face_patch", "fit_region",
           "FitOptions", "FitResult", "Objective", "Direction", "Method", "Metric", "fit_surface",
           "RuledError", "BadInputError", "DegenerateFaceError", "InfeasibleError", "TooBigError", "FiguresError",
           "CancelledError", "ToleranceError", "SplitOptions", "split_face", "partition", "CurveOnSurface",
           "approximate", "ConeSpline", "cone_spline_of_surface", "MachineOptions", "machine_path", "join_patches",
           "__version__"]
