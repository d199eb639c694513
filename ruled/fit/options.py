"""The options of a fit (numpy only, so that the command line checks them before the engine loads)."""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum
from typing import Any, Optional

import numpy as np

from ruled.core.errors import BadInputError, positive, whole


class Objective(str, Enum):
    SUM = "sum"
    MAX = "max"


class Method(str, Enum):
    D2 = "2d"   # rulings between boundary samples (Elber)
    D4 = "4d"   # ruling ends lifted along the surface normal too (Wang & Elber)


class Metric(str, Enum):
    SSHB = "sshb"   # surface–bilinear Hausdorff bound of each patch (certified)
    LSAD = "lsad"   # one-sided line–surface distance of each ruling (cheaper)


class Direction(str, Enum):
    AUTO = "auto"
    U = "u"   # rulings run along u, joining the u-min and u-max boundaries
    V = "v"   # rulings run along v, joining the v-min and v-max boundaries


class Ends(str, Enum):
    AUTO = "auto"          # the one with the smaller certified bound
    PINNED = "pinned"      # the end rulings at the face's corners (the rails are two of its sides)
    TRIMMED = "trimmed"    # the rails run past the face and the result is trimmed by its edges


@dataclass(frozen=True)
class FitOptions:
    """Options of a fit; defaults live here and nowhere else.

    4D only: ``elevations`` m (levels -m..m, default 10, i.e. 21 levels), ``step``
    tau (model units; default: the 2D result's measured distance spread over the
    m levels), ``metric``, and ``memory_cap`` (bytes; default 80 % of the free
    memory) beyond which a table is refused."""

    samples: int = 40
    objective: Objective = Objective.SUM       # each enumeration also takes its value as a str
    max_error: Optional[float] = None
    direction: Direction = Direction.AUTO
    refine: bool = True
    points_per_ruling: int = 9
    method: Method = Method.D2
    elevations: Optional[int] = None
    step: Optional[float] = None
    metric: Metric = Metric.LSAD
    memory_cap: Optional[float] = None
    ends: Ends = Ends.PINNED     # the trimmed result is opt-in until its fit is as fast (issue 35)

    def __post_init__(self) -> None:
        """Validates every option on construction (one BadInputError line naming it) and normalises the
        enumerations and whole numbers in place."""
        put = object.__setattr__
        put(self, "samples", whole("samples", self.samples, 3, np.inf,
                                   "must be a whole number of at least 3 (40 is a good start)"))
        put(self, "points_per_ruling", whole("points_per_ruling", self.points_per_ruling, 2, 1000,
                                             "must be a whole number of points from 2 to 1000 (9 is the default)"))
        if self.max_error is not None:
            put(self, "max_error", positive("max_error", self.max_error))
        if self.elevations is not None:
            put(self, "elevations", whole("elevations", self.elevations, 0, 200,
                                          "must be a whole number of levels from 0 to 200 (10 gives 21 levels)"))
        if self.step is not None:
            put(self, "step", positive("lift_step", self.step))
        if self.memory_cap is not None:
            put(self, "memory_cap", positive("memory_cap", self.memory_cap / 2.0 ** 20, "a size in MiB") * 2.0 ** 20)
        try:
            for name, kind in (("method", Method), ("metric", Metric), ("objective", Objective),
                               ("direction", Direction), ("ends", Ends)):
                put(self, name, kind(getattr(self, name)))
        except ValueError as exc:
            raise BadInputError(f"{exc}; see «fit_help»") from None
        put(self, "refine", bool(self.refine))

    @classmethod
    def of(cls, **options: Any) -> "FitOptions":
        """FitOptions from keywords whose enumerations may be given as words ('sum', '4d'; each checked and
        normalised as the constructor does)."""
        return cls(**options)

    def checked(self) -> "FitOptions":
        """The options (validated on construction; kept for the callers that say so)."""
        return self


__all__ = ["Direction", "FitOptions", "Method", "Metric", "Objective"]
