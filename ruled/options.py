"""The options of a fit (numpy only, so that the command line checks them before the engine loads)."""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum
from typing import Optional

import numpy as np

from .errors import BadInputError, positive


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


@dataclass(frozen=True)
class FitOptions:
    """Options of a fit; defaults live here and nowhere else.

    4D only: ``elevations`` m (levels -m..m, default 10, i.e. 21 levels), ``step``
    tau (model units; default: the 2D result's measured distance spread over the
    m levels), ``metric``, and ``memory_cap`` (bytes; default 80 % of the free
    memory) beyond which a table is refused."""

    samples: int = 40
    objective: Objective = Objective.SUM
    max_error: Optional[float] = None
    direction: Direction = Direction.AUTO
    refine: bool = True
    points_per_ruling: int = 9
    method: Method = Method.D2
    elevations: Optional[int] = None
    step: Optional[float] = None
    metric: Metric = Metric.LSAD
    memory_cap: Optional[float] = None

    def checked(self) -> "FitOptions":
        if not isinstance(self.samples, (int, np.integer)) or self.samples < 3:
            raise BadInputError(f"--samples {self.samples} is too small; use at least 3 (40 is a good start)")
        if self.max_error is not None:
            positive("--max-error", self.max_error)
        if self.elevations is not None and (not isinstance(self.elevations, (int, np.integer))
                                            or not 0 <= self.elevations <= 200):
            raise BadInputError(f"--elevations {self.elevations} must be a whole number of levels from 0 to 200 "
                                f"(10 gives 21 levels)")
        if self.step is not None:
            positive("--step", self.step)
        if self.memory_cap is not None:
            positive("--memory-cap", self.memory_cap / 2.0 ** 20, "a size in MiB")
        try:
            method, metric = Method(self.method), Metric(self.metric)
            objective, direction = Objective(self.objective), Direction(self.direction)
        except ValueError as exc:
            raise BadInputError(f"{exc}; see 'ruled fit --help'") from None
        return FitOptions(int(self.samples), objective, self.max_error, direction, self.refine,
                          self.points_per_ruling, method, None if self.elevations is None else int(self.elevations),
                          self.step, metric, self.memory_cap)


__all__ = ["Direction", "FitOptions", "Method", "Metric", "Objective"]
