"""The competence of reaching attempts, as a run scores them (Baranes & Oudeyer 2010, eq. 7 and
section II.D.1), for code outside a run: a Gymnasium wrapper, a user's own loop.

``competence(goal, reached, start)`` is -|goal - reached| / |start - goal|, clipped to ``min_c``
below and set to 0 above ``eps_c`` (reached). ``kind="absolute"`` divides by ``reach`` instead of
the starting distance. The arithmetic is the core's (``saggriac_core::competence``).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .. import _core
from ..errors import InputError
from ..values import as_numbers


def competence(goal: Any, reached: Any, start: Any, *, min_c: float = -1.0, eps_c: float = -0.05, kind: str = "relative", reach: float | None = None) -> float | np.ndarray:
    """Competence of one attempt (1-D arrays: a float) or of many (2-D arrays, one row per
    attempt: an array)."""
    arrays = []
    for name, v in (("goal", goal), ("reached", reached), ("start", start)):
        a = as_numbers(f"'{name}'", v)
        if a.ndim not in (1, 2) or a.shape[-1] == 0:
            raise InputError(f"'{name}' must be a point (1-D) or one point per row (2-D); got an array of shape {a.shape}.")
        # A NaN position would score as a failure (min_c) and hide the bug that made it.
        if not np.all(np.isfinite(a)):
            raise InputError(f"'{name}' must be finite; got {np.array2string(a, threshold=8)}.")
        arrays.append(a)
    one = arrays[0].ndim == 1
    rows = [np.ascontiguousarray(np.atleast_2d(a)) for a in arrays]
    out = _core.competence(*rows, float(min_c), float(eps_c), kind, float("nan") if reach is None else float(reach))
    return float(out[0]) if one else out


__all__ = ["competence"]
