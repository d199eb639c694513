"""A face's split job (``ruled split``, ``ruled.cq.split_face``): the best split of the face in two
(ruled.occ.split.split_of_face), kept only where it is better than not splitting: where the worse of its two
fits (its certified bound against the face, the surface it splits' deviation from the face included) is not
below the bound of the face's own fit as ``ruled fit`` returns it, the job says that the face needs no split and
returns that fit."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Optional


@dataclass
class SplitJob:
    split: Any                 # ruled.occ.split.FaceSplit: every candidate, built, fitted and measured
    whole: Any                 # ruled.jobs.face.FaceFit: the face's fit unsplit, as 'ruled fit' returns it
    bound: float               # the chosen split's certified bound against the face (its worse side's)
    kept: bool                 # the split is better than not splitting

    @property
    def verdict(self) -> Optional[str]:
        """What the report and the doors say when the split is not kept (None when it is)."""
        if self.kept:
            return None
        return (f"the face needs no split: its fit is {self.whole.bound:.4g} (the best split's worse side is "
                f"{self.bound:.4g})")


def split_job(face, opts=None, progress=None, measure_samples: int = 30, fit: Any = None) -> SplitJob:
    """Split the face (a TopoDS_Face) and compare the split with the face's fit (fit: that fit, a FaceFit or a
    RuledFit of ruled.cq, when the user has it; else fitted here as 'ruled fit' fits it)."""
    from dataclasses import replace

    from ruled.jobs.face import face_fit_of
    from ruled.occ.split import split_of_face
    from ruled.split.partition import SplitOptions
    opts = (opts or SplitOptions()).checked()
    fs = split_of_face(face, opts, progress, measure_samples)
    whole = face_fit_of(face, fit, replace(opts.fit, ends="auto").checked(), progress,
                        measure_samples=measure_samples)
    e = fs.edge_bounds().get(fs.chosen, 0.0)
    bound = float(fs.result.candidates[fs.chosen].bound + e + fs.deviation)
    return SplitJob(fs, whole, bound, bound < whole.bound)


__all__ = ["SplitJob", "split_job"]
