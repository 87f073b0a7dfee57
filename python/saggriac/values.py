"""Numbers given by a user (goals, competences, bounds, actions, positions), taken as they are:
strings, bools and objects are refused rather than converted ('0.5' -> 0.5, True -> 1.0)."""

from __future__ import annotations

from typing import Any

import numpy as np

from .errors import InputError

_KINDS = {"b": "bools", "U": "strings", "S": "bytes", "O": "objects that are not all numbers", "c": "complex numbers"}


def as_numbers(name: str, value: Any) -> np.ndarray:
    """``value`` as a float64 array (0-d for a scalar), or an InputError naming ``name``."""
    if isinstance(value, np.ndarray) and value.dtype == np.float64:
        return value  # the common case, and the hot one (a body's every micro-action)
    if value is None or isinstance(value, (str, bytes)):
        raise InputError(f"{name} must be an array of floats; got {value!r}.")
    try:
        raw = np.asarray(value)
    except (TypeError, ValueError) as e:
        raise InputError(f"{name} must be an array of floats; got {value!r}.") from e
    if raw.dtype.kind not in "iuf":
        what = _KINDS.get(raw.dtype.kind, f"values of type {raw.dtype}")
        raise InputError(f"{name} must be an array of floats; got {what}: {value!r}.")
    if isinstance(value, (list, tuple)) and _holds_bool(value):
        # numpy makes [0.5, True] a float array: the bool would become 1.0 without a word.
        raise InputError(f"{name} must be an array of floats; got bools among numbers: {value!r}.")
    return raw.astype(np.float64, copy=False)


def _holds_bool(value: Any) -> bool:
    if isinstance(value, (bool, np.bool_)):
        return True
    return isinstance(value, (list, tuple)) and any(map(_holds_bool, value))


def plain(value: Any) -> Any:
    """numpy scalars and arrays as the Python values they stand for (lists keep their type; a
    0-d array is its one value)."""
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.item() if value.ndim == 0 else [plain(v) for v in value.tolist()]
    if isinstance(value, (list, tuple)):
        return type(value)(plain(v) for v in value)
    return value
