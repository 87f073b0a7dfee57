"""``Config.teacher_params``: the parameters of the teacher a run takes in place of SAGG-RIAC's
high level, as a read-only mapping (a Config is frozen and hashable), checked for form here and
for names and values by the core, against the chosen teacher."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from ..errors import ParameterError
from ..values import plain


class TeacherParams(Mapping):
    """``Config.teacher_params``: a read-only dict of a teacher's parameters, hashable (so a
    Config stays hashable), equal to the dict of the same items, printed as that dict."""

    __slots__ = ("_items", "_dict")

    def __init__(self, params: Mapping[str, Any]) -> None:
        self._items = tuple(sorted(params.items()))
        self._dict = dict(self._items)

    def __getitem__(self, key: str) -> Any:
        return self._dict[key]

    def __iter__(self) -> Any:
        return iter(self._dict)

    def __len__(self) -> int:
        return len(self._dict)

    def __hash__(self) -> int:
        return hash(self._items)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Mapping) and self._dict == dict(other.items())

    def __repr__(self) -> str:
        return repr(self._dict)

    def __reduce__(self) -> Any:
        return (TeacherParams, (self._dict,))

    def __deepcopy__(self, memo: Any) -> TeacherParams:
        return self  # read-only


def teacher_params(params: Any) -> TeacherParams:
    """``teacher_params`` from a dict (a TOML table, a run.json object); the core checks the
    names and values against the chosen teacher. A list of pairs is refused: the docs and every
    record show a dict, and a list is also what a mistyped dict literal gives."""
    if isinstance(params, Mapping):
        items = [(n, plain(v)) for n, v in params.items()]
    else:
        raise ParameterError(f"The 'teacher_params' parameter of Config must be a dict of the teacher's parameters, such as {{'fit_rate': 100}}. Got {params!r} instead.", "teacher_params", repr(params))
    for name, value in items:
        # Values of any type go to the core, which tells a wrong one its parameter's rule (one
        # check, one message); only the names must be names here.
        if not isinstance(name, str):
            raise ParameterError(f"The 'teacher_params' parameter of Config must map parameter names (str) to values. Got {name!r}: {value!r} instead.", "teacher_params", repr(params))
    if len({n for n, _ in items}) != len(items):
        raise ParameterError(f"The 'teacher_params' parameter of Config must name each parameter once. Got {params!r} instead.", "teacher_params", repr(params))
    return TeacherParams(dict(items))
