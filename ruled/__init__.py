"""Ruled: optimal ruled-surface fitting for CAD faces.

House rule: this package (the engine) imports no CAD host.  numpy and scipy
only; OCP (OCCT) is imported only in ``ruled.occ`` (and by the command line
and the CadQuery entry points through it); FreeCAD only in ``workbench/``.
Data crosses every boundary as plain arrays in small frozen containers.
"""

from .errors import (BadInputError, CancelledError, DegenerateFaceError, InfeasibleError, RuledError,
                     TooBigError)
from .fit import Direction, FitOptions, FitResult, Method, Metric, Objective, fit_surface
from .facefit import FacePatch, face_patch, fit_region
from .nurbs import Curve, Surface
from .region import Region

__version__ = "0.1.0"

__all__ = ["Surface", "Curve", "Region", "FacePatch", "face_patch", "fit_region",
           "FitOptions", "FitResult", "Objective", "Direction", "Method", "Metric", "fit_surface",
           "RuledError", "BadInputError", "DegenerateFaceError", "InfeasibleError", "TooBigError",
           "CancelledError", "__version__"]
