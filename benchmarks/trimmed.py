"""Trimmed-face benchmark, run by ``benchmarks/run.py --suite trimmed``.

What fitting the face as bounded by its edges adds to a fit, per face at the defaults: reading the
face's boundary (pcurves, 3D edges), grouping it into four sides, the Coons map and its fold check,
sampling the face's own patch, the iso-parametric check between the rails and the area check, on
kj66 blade faces 1, 6 and 8 (trimmed to 8–18 % of their surfaces).  Target: at most 0.3 s added per
face.  Also the whole fit of each face and, for comparison, the fit of its surface's UV rectangle (the
untrimmed path, unchanged).  Warm, best of 3.
"""

from __future__ import annotations

import os
import time

from cone import _best

from ruled import FitOptions, fit_surface
from ruled.fit.face.fit import face_patch, with_iso
from ruled.occ.io import get_face
from ruled.occ.region import face_region, fit_face

TARGET_ADDED_S = 0.3
DATA = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "tests", "data",
                    "kj66_impeller.step")


def bench_trimmed() -> None:
    print("== trimmed faces: kj66 blade faces, defaults (40 samples, 2d)")
    opts = FitOptions()
    for k in (1, 6, 8):
        face = get_face(DATA, k)
        region = face_region(face)
        t_region = _best(lambda: face_region(face))
        t_patch = _best(lambda: face_patch(region))
        patch = face_patch(region)
        res = fit_surface(patch.surface, opts)
        t_iso = _best(lambda: with_iso(res))
        t0 = time.perf_counter()
        fit_face(face, opts)
        t_whole = time.perf_counter() - t0
        t_rect = _best(lambda: fit_surface(region.surface, opts))
        added = t_region + t_patch + t_iso
        print(f"   face {k}: boundary {t_region:.3f} s, patch {t_patch:.3f} s ({patch.spans[0]}x{patch.spans[1]} "
              f"spans), iso check {t_iso:.3f} s: added {added:.3f} s (target {TARGET_ADDED_S} s, ratio "
              f"{added / TARGET_ADDED_S:.2f}); whole fit {t_whole:.2f} s; the rectangle's fit {t_rect:.2f} s")
