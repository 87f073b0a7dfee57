"""Which teacher a bench run uses, how it is built for a task, and the guard every call to it goes
through: a bound on each call's time, goals checked against the space, and competences mapped
into the range the teacher takes.

A teacher is a built-in one by name (``saggriac.teachers.available()``, read at each call, so a
new built-in teacher is benched with no edit here) or a user's class by import path,
``pkg.mod:Class`` or ``path/to/file.py:Class``; ``NAME@low`` or ``NAME@high`` is that teacher
given expert knowledge of each task at that level (:mod:`saggriac.bench.expert`). The class
follows saggriac's teacher protocol: ``Class(low, high, seed=s, **params)`` for a box or
``Class(n_tasks, seed=s, **params)`` for a task list, ``sample()`` and ``update(goal,
competence)``; its ``spaces`` class attribute says which spaces it takes (("box",) if it has
none), and its ``competence_range`` the competences it expects ((0, 1) if it has none).
"""

from __future__ import annotations

import hashlib
import importlib
import importlib.util
import math
import re
import signal
import sys
import threading
import time
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Iterator

import numpy as np

from ..errors import ParameterError, SaggriacError
from ..teachers import RandomSelector, available
from . import expert
from .goal_log import GoalLog

#: The teacher every other one is compared with (paired by seed).
REFERENCE = "random"
#: The name of a task's own oracle as a teacher (:class:`GuardedOracle`; the evidence runner's).
ORACLE = "oracle"
#: Seconds one call of a teacher (sample or update) may take before the run is stopped.
CALL_TIMEOUT = 30.0
SPACES = ("box", "tasks")


class TeacherError(SaggriacError):
    """A teacher failed in a bench run: it raised, took too long, or asked a goal outside the
    space. The message names the teacher, the task and the seed."""


class _Hang(BaseException):
    """Raised by the alarm inside a call that took too long (a BaseException, so that a
    teacher's own ``except Exception`` does not swallow it)."""


@dataclass(frozen=True)
class TeacherSpec:
    """A teacher as the bench names it: ``ref`` (a built-in name or an import path), the
    keyword parameters it is built with, and the expert knowledge it is given of each task
    (``level``: "" for none, or one of ``expert.LEVELS``)."""

    ref: str
    params: tuple[tuple[str, Any], ...] = ()
    level: str = ""

    @property
    def builtin(self) -> bool:
        return ":" not in self.ref

    @property
    def label(self) -> str:
        """The name on the leaderboard: the ref, the parameters if any, and ``@level`` if given
        expert knowledge (a plain teacher's label is the one it had before levels existed)."""
        plain = self.ref if not self.params else f"{self.ref}[{','.join(f'{k}={v!r}' for k, v in self.params)}]"
        return f"{plain}@{self.level}" if self.level else plain

    @property
    def slug(self) -> str:
        """A folder name for the teacher's runs: the label in plain characters, and a digest
        when that changed it or it is long; ``@level`` after it."""
        base = TeacherSpec(self.ref, self.params).label
        plain = re.sub(r"[^A-Za-z0-9_.=+-]+", "_", base)
        if plain != base or len(plain) > 60:
            plain = f"{plain[:40]}-{hashlib.sha256(base.encode()).hexdigest()[:10]}"
        return f"{plain}@{self.level}" if self.level else plain

    def expert_function(self) -> Callable[[expert.Knowledge], dict[str, Any]] | None:
        """How this teacher takes expert knowledge (``expert.BUILTIN`` for a built-in teacher,
        its class's ``expert_params`` for a user's), or None if it takes none."""
        return expert.params_function(self.load(), self.ref, self.builtin)

    def variants(self) -> list["TeacherSpec"]:
        """This teacher at each expert level, if it takes expert knowledge (else none)."""
        if self.level or self.expert_function() is None:
            return []
        return [TeacherSpec(self.ref, self.params, level) for level in expert.LEVELS]

    def load(self) -> type:
        """The teacher's class."""
        if self.builtin:
            return available()[self.ref]
        module, _, name = self.ref.rpartition(":")
        if module.endswith(".py"):
            path = Path(module)
            key = "saggriac_bench_user_" + hashlib.sha256(str(path).encode()).hexdigest()[:12]
            mod = sys.modules.get(key)
            if mod is None:
                spec = importlib.util.spec_from_file_location(key, path)
                if spec is None or spec.loader is None:
                    raise ParameterError(f"The '--teacher' parameter of saggriac bench names the file {module!r}, which cannot be imported.", "teacher", self.ref)
                mod = importlib.util.module_from_spec(spec)
                sys.modules[key] = mod
                try:
                    spec.loader.exec_module(mod)
                except BaseException:
                    del sys.modules[key]
                    raise
        else:
            mod = importlib.import_module(module)
        cls = getattr(mod, name, None)
        if not isinstance(cls, type):
            raise ParameterError(f"The '--teacher' parameter of saggriac bench must name a class ('module:Class'). Got {self.ref!r}: {module} has no class {name!r}.", "teacher", self.ref)
        return cls

    def spaces(self) -> tuple[str, ...]:
        """The spaces the teacher takes (its class's ``spaces``, else ("box",))."""
        cls = self.load()
        value = getattr(cls, "spaces", ("box",))
        spaces = (value,) if isinstance(value, str) else tuple(value)
        if not spaces or any(s not in SPACES for s in spaces):
            raise ParameterError(f"The 'spaces' attribute of the teacher {self.label} must be a tuple of 'box' and/or 'tasks'. Got {value!r} instead.", "spaces", repr(value))
        return spaces

    @property
    def told(self) -> str:
        """What the teacher asks to be told (its class's ``told``): "competence" unless it wants
        a score only some tasks' learners have (saggriac.bench.value_loss)."""
        return getattr(self.load(), "told", "competence")

    def takes(self, space: str) -> bool:
        """Whether the bench runs this teacher on a task of ``space`` (the reference, random,
        runs on task lists too: uniform over the tasks; expert knowledge is of box tasks)."""
        if self.level:
            return space == "box" and space in self.spaces()
        return space in self.spaces() or (self.ref == REFERENCE and not self.params)


def parse_teacher(text: str, params: dict[str, Any] | None = None) -> TeacherSpec:
    """The spec of ``--teacher TEXT``: a built-in name, ``pkg.mod:Class`` or ``file.py:Class`` (made
    absolute, so that workers elsewhere in the tree find it), with ``@low`` or ``@high`` for that
    teacher given expert knowledge at the level. Its class is loaded here, so that a wrong name
    fails before anything runs."""
    if not isinstance(text, str) or not text.strip():
        raise ParameterError(f"The '--teacher' parameter of saggriac bench must be a built-in teacher's name ({', '.join(available())}) or an import path 'pkg.mod:Class'. Got {text!r} instead.", "teacher", repr(text))
    text, level = expert.split_level(text.strip())
    if level and level not in expert.LEVELS:
        raise ParameterError(f"The '--teacher' parameter of saggriac bench takes an expert level after '@': {' or '.join(expert.LEVELS)}. Got {level!r} in {text + '@' + level!r}.", "teacher", f"{text}@{level}")
    if ":" in text:
        module, _, name = text.rpartition(":")
        if not module or not name.isidentifier():
            raise ParameterError(f"The '--teacher' parameter of saggriac bench must be 'pkg.mod:Class' or 'path/file.py:Class'. Got {text!r} instead.", "teacher", text)
        if module.endswith(".py"):
            path = Path(module).expanduser().resolve()
            if not path.is_file():
                raise ParameterError(f"The '--teacher' parameter of saggriac bench names the file {module!r}, which does not exist (looked for {path}).", "teacher", text)
            text = f"{path}:{name}"
    elif text not in available():
        raise ParameterError(f"The '--teacher' parameter of saggriac bench must be a built-in teacher's name ({', '.join(available())}) or an import path 'pkg.mod:Class'. Got {text!r} instead.", "teacher", text)
    items = tuple(sorted((params or {}).items()))
    spec = TeacherSpec(text, items, level)
    spec.spaces()  # imports the class: a wrong path fails here
    if level and spec.expert_function() is None:
        takers = ", ".join(expert.BUILTIN)
        raise ParameterError(f"The teacher {text} of saggriac bench takes no expert knowledge, so it has no '@{level}': the built-in ones that do are {takers}, and a class of yours does by an expert_params(knowledge) static method (docs/bench.md).", "teacher", f"{text}@{level}")
    return spec


def competence_map(cls: type, label: str) -> Callable[[float], float]:
    """c in [0, 1] (what the tasks tell) mapped linearly into the class's ``competence_range``."""
    value = getattr(cls, "competence_range", (0.0, 1.0))
    try:
        lo, hi = (float(v) for v in value)
    except (TypeError, ValueError):
        lo, hi = math.nan, math.nan
    if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
        raise ParameterError(f"The 'competence_range' attribute of the teacher {label} must be two finite floats lo < hi. Got {value!r} instead.", "competence_range", repr(value))
    if (lo, hi) == (0.0, 1.0):
        return float
    return lambda c: lo + c * (hi - lo)


class Guarded:
    """A teacher built for one task and seed, every call bounded and checked."""

    def __init__(self, spec: TeacherSpec, task: Any, seed: int, timeout: float = CALL_TIMEOUT, run_seed: int | None = None) -> None:
        self._setup(spec, task, seed, timeout, run_seed)
        cls = spec.load()
        self.tell_map = competence_map(cls, spec.label)
        #: What the teacher is told: "competence" (the default), or a score only some tasks'
        #: learners have (their ``tells``; saggriac.bench.value_loss).
        self.told = getattr(cls, "told", "competence")
        tells = getattr(task, "tells", ("competence",))
        if self.told not in tells:
            raise TeacherError(f"The {self.where} asks to be told {self.told!r} (its class's 'told'), and the task tells only {', '.join(map(repr, tells))}.")
        params = dict(spec.params)
        if spec.level:
            # Expert knowledge of the task at the level, as the teacher's own parameters.
            known = self._call("was given expert knowledge", lambda: self._expert_params(spec, task, seed if run_seed is None else run_seed))
            params.update(known)
        if task.space == "box":
            make: Callable[[], Any] = lambda: cls(task.low.copy(), task.high.copy(), seed=seed, **params)
        elif task.space in spec.spaces():
            make = lambda: cls(task.n_tasks, seed=seed, **params)
        else:  # the reference on a task list: uniform over the tasks
            n = task.n_tasks
            make = lambda: RandomSelector([0.0], [float(n)], seed=seed)
            self.to_task = lambda g: min(int(np.asarray(g, float).reshape(-1)[0]), n - 1)
            self.tell_map = lambda c: c - 1.0
        self.teacher = self._call("was built", make)

    def _setup(self, spec: TeacherSpec, task: Any, seed: int, timeout: float, run_seed: int | None) -> None:
        self.spec, self.task, self.seed, self.timeout = spec, task, seed, timeout
        # Messages name the run's seed (the bench's), not the teacher's child of it.
        self.where = f"teacher {spec.label} on task {task.name!r}, seed {seed if run_seed is None else run_seed}"
        self.calls = 0
        low, high = getattr(task, "low", None), getattr(task, "high", None)
        self._finite_box = low is not None and high is not None and bool(np.isfinite(low).all() and np.isfinite(high).all())
        #: Seconds spent inside the teacher's sample and update (the board's teacher_us_per_goal).
        self.teacher_seconds = 0.0
        #: The goals asked, as the task gets them (the figures of goals over time).
        self.log = GoalLog()
        self.to_task: Callable[[Any], Any] | None = None
        self.tell_map: Callable[[float], float] = float
        #: What the teacher is told: "competence", or a score only some tasks' learners have.
        self.told = "competence"

    @staticmethod
    def _expert_params(spec: TeacherSpec, task: Any, run_seed: int) -> dict[str, Any]:
        fn = spec.expert_function()
        if fn is None:
            raise TypeError("it takes no expert knowledge")
        known = fn(expert.knowledge(task, spec.level, run_seed))
        if not isinstance(known, dict):
            raise TypeError(f"its expert_params gave {known!r}, not a dict of keyword parameters")
        clash = sorted(set(known) & {k for k, _ in spec.params})
        if clash:
            raise TypeError(f"the parameters {clash} are given both by --teacher-param and by the expert knowledge")
        return known

    def _call(self, what: str, work: Callable[[], Any]) -> Any:
        # Set by alarm_handler (main thread only); reading the handler back cost more than the call.
        bounded = _ALARM.active
        try:
            if bounded:
                signal.setitimer(signal.ITIMER_REAL, self.timeout)
            try:
                return work()
            finally:
                if bounded:
                    signal.setitimer(signal.ITIMER_REAL, 0)
        except _Hang:
            raise TeacherError(f"The {self.where} took more than {self.timeout:g} s in one call (it {what}; call {self.calls}). Raise the bound with --timeout if it is only slow.") from None
        except Exception as e:
            raise TeacherError(f"The {self.where} raised {type(e).__name__}: {e} (when it {what}; call {self.calls}).") from e

    def ask(self) -> Any:
        """The next goal, checked: an array in the box, or a task's index."""
        self.calls += 1
        start = time.perf_counter()
        raw = self._call("was asked a goal (sample)", self.teacher.sample)
        self.teacher_seconds += time.perf_counter() - start
        self.last_raw = raw
        goal = self.to_task(raw) if self.to_task is not None else self._checked(raw)
        self.log.add(goal)
        return goal

    def tell(self, goal: Any, competence: float) -> None:
        """Tell the competence in [0, 1] reached at ``goal``, mapped into the teacher's range. A
        task list's teacher is told the goal as it gave it (an index, or ``[index]``)."""
        told = self.last_raw if self.task.space == "tasks" else goal
        start = time.perf_counter()
        self._call("was told a competence (update)", lambda: self.teacher.update(told, self.tell_map(competence)))
        self.teacher_seconds += time.perf_counter() - start

    def _checked(self, raw: Any) -> Any:
        task = self.task
        if task.space == "tasks":
            g = np.asarray(raw)
            ok = g.size == 1 and np.issubdtype(g.dtype, np.number) and np.isfinite(g).all()
            i = float(g.reshape(-1)[0]) if ok else math.nan
            if not (ok and i == int(i) and 0 <= i < task.n_tasks):
                raise TeacherError(f"The {self.where} asked the goal {raw!r} (call {self.calls}), which is not a task index: the goals are ints in [0, {task.n_tasks}).")
            return int(i)
        try:
            g = np.asarray(raw, dtype=np.float64)
        except (TypeError, ValueError):
            g = np.full(0, math.nan)
        # One pass: NaN fails both comparisons, and in a finite box so does an infinity.
        if g.shape != task.low.shape or not ((g >= task.low) & (g <= task.high)).all() or not (self._finite_box or np.isfinite(g).all()):
            raise TeacherError(f"The {self.where} asked the goal {raw!r} (call {self.calls}), which is outside the space: the goals are {task.low.size} floats in the box low={task.low.tolist()}, high={task.high.tolist()}.")
        return g


class GuardedOracle(Guarded):
    """The task's own oracle (``task.oracle_teacher(seed)``, :class:`saggriac.bench.tasks.BenchTask`)
    as the teacher named :data:`ORACLE`, every call bounded and its goals checked as any teacher's.
    Told competences in [0, 1], as the task gives them."""

    def __init__(self, task: Any, seed: int, timeout: float = CALL_TIMEOUT, run_seed: int | None = None) -> None:
        self._setup(TeacherSpec(ORACLE), task, seed, timeout, run_seed)
        if not task.has_oracle():
            raise TeacherError(f"The {self.where}: the task {task.name!r} has no oracle (its class overrides neither oracle nor oracle_teacher).")
        self.teacher = self._call("was built", lambda: task.oracle_teacher(seed))


@contextmanager
def alarm_handler() -> Iterator[None]:
    """While active, a Guarded call past its bound raises _Hang: a timer signal, so only in a
    process's main thread (where the bench's workers run its runs); elsewhere calls are unbounded."""
    if threading.current_thread() is not threading.main_thread() or not hasattr(signal, "setitimer"):
        yield
        return
    previous = signal.signal(signal.SIGALRM, _alarm)
    outer = _ALARM.active
    _ALARM.active = True
    try:
        yield
    finally:
        _ALARM.active = outer
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


class _AlarmState:
    """Whether alarm_handler's handler is installed (in this process's main thread)."""

    active = False


_ALARM = _AlarmState()


def _alarm(signum: int, frame: Any) -> None:
    raise _Hang()
