"""What every ask/tell teacher shares: the checks of its arguments, the core's teacher behind it
(``_core.AskTell``, built from a kind and its parameters), its history, its saving (pickle and
``save``/``load_selector``) and its identity (``ownership``). Each teacher is a subclass in its
own file, naming its kind and its parameters."""


from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Any, Protocol, runtime_checkable

import numpy as np

from .. import _core
from ..errors import InputError, ParameterError, StorageError
from ..files import MAX_TEACHER_BYTES, as_path, check_flag, read_bounded, starts_with, write_file
from ..values import as_numbers as _numbers
from ..values import plain
from . import copies, ownership

# Every teacher's parameters and defaults are the core's (one declaration): each class below
# takes exactly those of its kind, with those defaults (tests/core/test_stub.py checks it).
DEFAULTS: dict[str, dict[str, Any]] = _core.teacher_defaults()

#: The first bytes of a teacher saved by ``save(path)``.
MAGIC = b"saggriac-teacher\n"

#: Names of the mode codes in ``history()["asked_mode"]`` and ``last_mode``.
MODES = {0: "initial", 1: "interest", 2: "global", 3: "lowest_competence", 4: "random", 5: "external"}


@runtime_checkable
class GoalSelectorProtocol(Protocol):
    """What the run loop needs from a goal selector (built-in or written in Python)."""

    low: np.ndarray
    high: np.ndarray

    def sample(self) -> np.ndarray: ...

    def update(self, goal: np.ndarray, competence: float) -> Any: ...


def _vector(name: str, value: Any, dim: int | None = None) -> np.ndarray:
    arr = np.ascontiguousarray(_numbers(name, value))
    if arr.ndim != 1 or (dim is not None and arr.shape[0] != dim):
        want = f"shape ({dim},)" if dim is not None else "a 1-D array"
        raise InputError(f"{name} must have {want}; got shape {arr.shape}.")
    return arr


def _int_param(owner: str, name: str, value: Any, low: int, high: int) -> int:
    """An int argument in [low, high) (a seed, a batch size): numpy ints are taken, floats and
    bools refused (never truncated), and the range is checked here so the core's fixed-width
    ints never overflow."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not low <= int(value) < high:
        raise ParameterError(f"The '{name}' parameter of {owner} must be an int in [{low}, 2**{high.bit_length() - 1}). Got {value!r} instead.", name, repr(value))
    return int(value)


class AskTellSelector:
    """The base of every ask/tell teacher: a subclass names its kind (``_kind``, a teacher of the
    core's) and its parameters; everything else is here."""

    _kind = ""
    #: The competences the teacher takes (saggriac.testing.check_goal_selector tells these).
    competence_range = (-1.0, 0.0)
    #: The goal spaces the teacher takes: "box" (built as ``cls(low, high, seed=s)``) or "tasks"
    #: (a task list, built as ``cls(n_tasks, seed=s)``). The bench reads it, for a user's class too.
    spaces: tuple[str, ...] = ("box",)
    #: What the teacher's goal modes mean (``MODES`` names), as the share of goals logged under
    #: each name by ``saggriac.analysis.teacher_readings``; modes not listed are not counted apart.
    mode_shares: dict[str, str] = {}
    #: Which reader of ``saggriac.analysis.readings`` logs its state (None: only the shares).
    reading: str | None = None

    def __init__(self, low: Any, high: Any, seed: int, **params: Any) -> None:
        owner = type(self).__name__
        lo, hi = _vector("low", low), _vector("high", high)
        seed = _int_param(owner, "seed", seed, 0, 2**64)
        # numpy scalars and arrays as the numbers and lists they stand for; the core checks each
        # value's type and rule, a list's values per dimension each against the single number's
        # (crates/saggriac-py/src/teachers.rs, config/rules.rs): one check, one message.
        self._inner = _core.AskTell(self._kind, lo.tolist(), hi.tolist(), seed, {k: plain(v) for k, v in params.items()})
        self.last_mode: str | None = None
        self.last_region: int | None = None

    def check_competences(self, lo: float, hi: float, whence: str) -> None:
        """Refuse (ParameterError) a threshold that competences in [lo, hi], told by ``whence``,
        can never meet, or always meet: ADR's ``t_low`` / ``t_high``, SPDL's ``delta``, Goal
        GAN's ``success_threshold``. A run, ``TeacherCallback`` and ``SelectorCurriculum`` call
        it with the competences they tell, so that a teacher never sits still without a word."""
        owner = f"{type(self).__name__}.check_competences"
        for name, value in (("lo", lo), ("hi", hi)):
            # The thresholds' messages quote [lo, hi]: a NaN or a string there would blame them.
            # -inf is a bound (TeacherCallback's distances lie in [-inf, 0]); NaN bounds nothing.
            if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)) or math.isnan(value):
                raise ParameterError(f"The '{name}' parameter of {owner} must be a float, not NaN (the competences lie in [lo, hi]). Got {value!r} instead.", name, repr(value))
        if lo > hi:
            raise ParameterError(f"The 'lo' parameter of {owner} must be a float <= hi (the competences lie in [lo, hi]). Got lo={lo!r}, hi={hi!r} instead.", "lo", repr(lo))
        if not isinstance(whence, str):
            raise ParameterError(f"The 'whence' parameter of {owner} must be a str (who tells the competences). Got {whence!r} instead.", "whence", repr(whence))
        self._inner.check_competences(float(lo), float(hi), whence)

    def get_params(self) -> dict[str, Any]:
        """The teacher's parameters by name, as it was built (defaults included; a task-list
        teacher's ``n_tasks`` too)."""
        return dict(self._inner.params())

    @property
    def seed(self) -> int:
        """The seed of the teacher's generator."""
        return int(self._inner.seed)

    @property
    def dim(self) -> int:
        return self._inner.dim

    @property
    def low(self) -> np.ndarray:
        return self._inner.low

    @property
    def high(self) -> np.ndarray:
        return self._inner.high

    def sample(self) -> np.ndarray:
        """Next goal (1-D array). Its mode and region are in ``last_mode`` / ``last_region``."""
        goal, mode, region = self._inner.sample()
        self.last_mode = MODES[mode]
        self.last_region = None if region < 0 else region
        return goal

    def sample_batch(self, n: int) -> np.ndarray:
        """``n`` goals at once, shape (n, dim): as n calls of ``sample()`` without updates."""
        n = _int_param(f"{type(self).__name__}.sample_batch", "n", n, 0, 2**63)
        return self._inner.sample_batch(n)

    def update(self, goal: Any, competence: float) -> int | None:
        """Report the competence obtained for ``goal``. Returns the region that recorded it."""
        g = _vector("goal", goal, self.dim)
        c = _numbers("competence", competence)
        if c.ndim != 0:
            raise InputError(f"competence must be one float; got shape {c.shape}.")
        r = self._inner.update(g, float(c))
        return None if r < 0 else int(r)

    def update_batch(self, goals: Any, competences: Any) -> np.ndarray:
        """Report many competences at once (goals shape (n, dim)). A bad row changes nothing."""
        g = np.ascontiguousarray(_numbers("goals", goals))
        c = np.ascontiguousarray(_numbers("competences", competences))
        if g.ndim != 2 or c.ndim != 1 or g.shape[0] != c.shape[0]:
            raise InputError(f"goals must have shape (n, {self.dim}) and competences shape (n,); got {g.shape} and {c.shape}.")
        return self._inner.update_batch(g, c)

    def regions(self) -> dict[str, np.ndarray]:
        """Every region (inner nodes too): bounds, interest, measurements, split, depth."""
        return self._inner.regions()

    def leaves(self) -> dict[str, np.ndarray]:
        """The current leaves only: the regions goals are drawn from."""
        r = self.regions()
        keep = r["is_leaf"]
        return {k: v[keep] for k, v in r.items()}

    @property
    def n_regions(self) -> int:
        """Number of leaves (1 before the first split)."""
        return max(1, int(self.regions()["is_leaf"].sum()))

    def history(self) -> dict[str, np.ndarray]:
        """What was asked (goal, mode, region) and told (goal, competence, region), in order."""
        return self._inner.history()

    def __repr__(self) -> str:
        return f"{type(self).__name__}(dim={self.dim}, seed={self.seed}, regions={self.n_regions})"

    def __new__(cls, *args: Any, **kwargs: Any) -> "AskTellSelector":
        obj = super().__new__(cls)
        obj._identity = ownership.new_identity()  # see teachers/ownership.py; pickle keeps it
        copies.mark_new(obj)
        return obj

    # Saving: pickle goes through the core's own encoding, so a restored teacher asks exactly
    # the goals the original would have asked next. The copy keeps the teacher's identity (a
    # teacher sent to a worker is the same teacher); copy.copy/deepcopy make a new teacher.
    def __getstate__(self) -> dict[str, Any]:
        state = {"teacher": bytes(self._inner.save()), "last_mode": self.last_mode, "last_region": self.last_region, "identity": self._identity}
        copy_of = copies.on_pickle(self)  # sent to another process: which copy it is
        if copy_of is not None:
            state["copy_of"] = copy_of
        return state

    def __deepcopy__(self, memo: dict[int, Any]) -> "AskTellSelector":
        state = self.__getstate__()
        del state["identity"]
        state.pop("copy_of", None)
        obj = type(self).__new__(type(self))
        obj.__setstate__(state)
        return obj

    def __copy__(self) -> "AskTellSelector":
        return self.__deepcopy__({})  # no shallow copy: a teacher's state is one object

    def __setstate__(self, state: dict[str, Any]) -> None:
        inner = _core.AskTell.restore(state["teacher"])
        if inner.kind != self._kind:
            raise InputError(f"The saved teacher is a {inner.kind!r} teacher, not a {type(self).__name__}.")
        self._inner = inner
        self.last_mode, self.last_region = state["last_mode"], state["last_region"]
        if "identity" in state:
            self._identity = state["identity"]
            copies.on_unpickle(self, state.get("copy_of"))

    def save(self, path: str | os.PathLike[str], overwrite: bool = False) -> Path:
        """Write the teacher (parameters, state, history) to the file ``path``, atomically;
        :func:`load_selector` reads it back. An existing file is replaced only with
        ``overwrite=True``, and only if it is a teacher file saggriac saved: a link, a device, a
        FIFO or any other file is refused before anything is written."""
        owner = f"{type(self).__name__}.save"
        overwrite = check_flag(overwrite, "overwrite", owner)
        path = as_path(path, "path", owner)
        if path.is_dir() and not path.is_symlink():
            raise StorageError(f"{path} is a folder; give the path of a file to save the teacher to.")
        data = MAGIC + bytes(self._inner.save())
        return write_file(path, lambda tmp: tmp.write_bytes(data), what="a teacher", overwrite=overwrite, ours=starts_with(MAGIC))


def load_selector(path: str | os.PathLike[str]) -> AskTellSelector:
    """The teacher saved by ``save(path)``, as an instance of its class, continuing where it stopped."""
    path = as_path(os.fspath(path) if isinstance(path, os.PathLike) else path, "path", "load_selector", kind="file")
    try:
        data = read_bounded(path, "a saved teacher", MAX_TEACHER_BYTES)
    except (FileNotFoundError, NotADirectoryError) as e:
        raise StorageError(f"Cannot read {path}: {e.strerror or e}.") from None
    if not data.startswith(MAGIC):
        raise InputError(f"{path} is not a teacher saved by saggriac (it does not start with {MAGIC!r}).")
    inner = _core.AskTell.restore(data[len(MAGIC) :])
    cls = classes()[inner.kind]
    obj = cls.__new__(cls)
    obj._inner, obj.last_mode, obj.last_region = inner, None, None
    return obj

def _subclasses(cls: type) -> list[type]:
    return [d for c in cls.__subclasses__() for d in [c, *_subclasses(c)]]


def available() -> dict[str, type[AskTellSelector]]:
    """Every built-in teacher's class by its name (``Config(teacher=...)``, the CLI, saved
    teachers), in the core's registry order: the one list of teachers the rest reads."""
    found = classes()
    return {kind: found[kind] for kind in _core.teacher_defaults() if kind in found}


def classes() -> dict[str, type[AskTellSelector]]:
    """Each teacher's class, by kind: every subclass of AskTellSelector that names one (a new
    teacher is one more class, in its own file under teachers/)."""
    # A class names its own kind; a user's subclass of one of them (inheriting the kind) is not
    # the class a saved teacher of that kind comes back as.
    return {c._kind: c for c in _subclasses(AskTellSelector) if c.__dict__.get("_kind") and c.__module__.startswith(__package__ + ".")}
