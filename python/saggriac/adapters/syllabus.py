"""Any saggriac teacher as a Syllabus curriculum (the optional extra ``pip install "saggriac[syllabus]"``).

Syllabus (Sullivan et al., "Syllabus: Portable Curricula for Reinforcement Learning Agents",
2024) connects a curriculum in the training process with environments in other processes: the
environments' wrapper asks the curriculum for each episode's task and reports each episode's
return and task progress back. :class:`SelectorCurriculum` is such a curriculum whose tasks are
chosen by a saggriac selector:

* over a ``BoxTaskSpace`` (a 1-D ``gymnasium.spaces.Box``), by any box teacher whose bounds are
  the box's: :class:`saggriac.SaggRiacSelector`, ``RiacSelector``, ``AlpGmmSelector``,
  ``CovarGmmSelector``, ``AdrSelector``, ``SpdlSelector``, ``GoalGanSelector``, ``RandomSelector``;
* over a finite task space of n tasks, by a task-list teacher with n tasks
  (:class:`saggriac.DiscreteLpSelector`, :class:`saggriac.PlrSelector`,
  :class:`saggriac.TsclSelector`): a ``DiscreteTaskSpace``, a ``MultiDiscreteTaskSpace``, or a
  ``TupleTaskSpace`` of such spaces. A multi-part space is flattened into one list of
  n = the product of its parts' sizes (:class:`FlatTasks`, ``curriculum.flat_tasks``): the
  teacher chooses an index, and the curriculum hands out the task space's encoding of that task
  (a tuple, or one int where the space was built with ``flatten=True``) and maps each reported
  task back to its index.

A Gymnasium space is taken in place of Syllabus's task space: ``Box`` (1-D) as a
``BoxTaskSpace``, ``Discrete`` as a ``DiscreteTaskSpace``, ``MultiDiscrete`` as a
``MultiDiscreteTaskSpace`` and a ``Tuple`` of these as a ``TupleTaskSpace``. Syllabus 0.7 has no
``Dict`` task space: a ``Dict`` is refused (a ``TupleTaskSpace`` with ``space_names`` is
Syllabus's way to name the parts).

At each episode's end the teacher is told a competence: the episode's task progress
(``competence="progress"``, Syllabus's ``info["task_completion"]``, the default), its return
(``"return"``), or what a function of ``(episode_return, length, task, progress)`` gives. Task
progress reported in the middle of an episode is counted, as Syllabus's curricula do, but not
told. The teacher's own generator draws every task; Syllabus's ``random_start_tasks`` (drawn from
numpy's global generator) is refused: the mixture teachers have their own ``bootstrap``.

Pickling the curriculum pickles its teacher, which then continues with the same tasks.

:class:`GoalTaskWrapper` is the environment side for saggriac's own goal environments
(``saggriac/...-v0``): a task is a goal in the environment's goal box, its task space a
``BoxTaskSpace`` over that box, and its task progress 1 + eq. 7's competence, in [0, 1].
"""

from __future__ import annotations

from typing import Any, Callable

try:
    import gymnasium
    from syllabus.core import Curriculum, TaskWrapper
    from syllabus.task_space import BoxTaskSpace, DiscreteTaskSpace, MultiDiscreteTaskSpace, TaskSpace, TupleTaskSpace
except ImportError:  # pragma: no cover - depends on the installation
    raise ImportError('saggriac.adapters.syllabus needs Syllabus: pip install "saggriac[syllabus]"') from None

import numpy as np

from ..teachers.competence import competence as _competence
from ..errors import ConformanceError, InputError, ParameterError
from ..teachers import TaskListSelector
from .gym.goals import check_goal_taken, sample_batch

COMPETENCES = ("progress", "return")


def _check_box(task_space: BoxTaskSpace, selector: Any) -> None:
    space = task_space.gym_space
    if not isinstance(space, gymnasium.spaces.Box) or len(space.shape) != 1:
        raise ConformanceError(f"SelectorCurriculum needs a BoxTaskSpace over a 1-D gymnasium Box; got {space}.")
    if isinstance(selector, TaskListSelector):
        raise ConformanceError(f"SelectorCurriculum: a {type(selector).__name__} chooses among a task list; use it with a DiscreteTaskSpace.")
    low, high = np.asarray(space.low, dtype=np.float64), np.asarray(space.high, dtype=np.float64)
    dim = getattr(selector, "dim", None)
    if dim != space.shape[0]:
        raise ParameterError(f"The 'selector' parameter of SelectorCurriculum must choose {space.shape[0]}-D tasks, the task space's; it chooses {dim}-D ones.", "selector", repr(selector))
    s_low, s_high = np.asarray(selector.low, dtype=np.float64), np.asarray(selector.high, dtype=np.float64)
    if not (np.array_equal(s_low, low) and np.array_equal(s_high, high)):
        raise ParameterError(
            f"The 'selector' parameter of SelectorCurriculum must have the task space's bounds: low {low.tolist()}, high {high.tolist()}; "
            f"it has low {s_low.tolist()}, high {s_high.tolist()}.",
            "selector",
            repr(selector),
        )


def _zero_start(space: gymnasium.spaces.Space) -> None:
    start = np.asarray(getattr(space, "start", 0))
    if np.any(start != 0):
        raise ParameterError(f"The 'task_space' parameter of SelectorCurriculum must count its values from 0, as Syllabus's task spaces do; got {space} (start {start.tolist()}).", "task_space", repr(space))


def as_task_space(space: Any) -> TaskSpace:
    """Syllabus's task space for a Gymnasium space (a Syllabus task space as it is): ``Box``
    (1-D) -> ``BoxTaskSpace``, ``Discrete`` -> ``DiscreteTaskSpace``, ``MultiDiscrete`` ->
    ``MultiDiscreteTaskSpace``, ``Tuple`` of these -> ``TupleTaskSpace``."""
    if isinstance(space, TaskSpace):
        return space
    if isinstance(space, gymnasium.spaces.Box):
        return BoxTaskSpace(space)
    if isinstance(space, gymnasium.spaces.Discrete):
        _zero_start(space)
        return DiscreteTaskSpace(space)
    if isinstance(space, gymnasium.spaces.MultiDiscrete):
        _zero_start(space)
        if space.nvec.ndim != 1:
            raise ParameterError(f"The 'task_space' parameter of SelectorCurriculum must be a MultiDiscrete of one row of sizes, as Syllabus's MultiDiscreteTaskSpace; got nvec of shape {space.nvec.shape}.", "task_space", repr(space))
        return MultiDiscreteTaskSpace(space)
    if isinstance(space, gymnasium.spaces.Tuple):
        return TupleTaskSpace(tuple(as_task_space(s) for s in space.spaces))
    if isinstance(space, gymnasium.spaces.Dict):
        raise ConformanceError(f"SelectorCurriculum: Syllabus has no task space for a gymnasium Dict ({space}); give a TupleTaskSpace of its parts (space_names=... names them) or a Tuple space.")
    raise ConformanceError(f"SelectorCurriculum takes a Syllabus task space or a gymnasium Box, Discrete, MultiDiscrete or Tuple of these; got {space!r}.")


class FlatTasks:
    """A finite Syllabus task space as one list of tasks 0..n-1, the indices a task-list teacher
    chooses, with the map between an index and the space's encoding of its task (what the
    environments decode). A ``MultiDiscreteTaskSpace`` and a ``TupleTaskSpace`` list their tasks
    in C order, last part fastest, as ``numpy.ravel_multi_index`` (and Syllabus's ``flatten=True``
    encoding) does."""

    def __init__(self, task_space: TaskSpace) -> None:
        self.task_space = task_space
        if isinstance(task_space, DiscreteTaskSpace):
            self.sizes: tuple[int, ...] = (int(task_space.num_tasks),)
            self.parts: tuple[FlatTasks, ...] | None = None
        elif isinstance(task_space, MultiDiscreteTaskSpace):
            self.sizes, self.parts = tuple(int(n) for n in task_space.gym_space.nvec), None
        elif isinstance(task_space, TupleTaskSpace):
            for i, part in enumerate(task_space.task_spaces):
                if not isinstance(part, (DiscreteTaskSpace, MultiDiscreteTaskSpace, TupleTaskSpace)):
                    raise ConformanceError(f"SelectorCurriculum over a TupleTaskSpace needs parts that are lists of tasks (Discrete, MultiDiscrete or Tuple task spaces); part {i} is a {type(part).__name__}.")
            self.parts = tuple(FlatTasks(part) for part in task_space.task_spaces)
            self.sizes = tuple(len(p) for p in self.parts)
        else:
            raise ConformanceError(f"SelectorCurriculum: a {type(task_space).__name__} is not a list of tasks.")
        self.n = int(np.prod(self.sizes, dtype=np.int64))
        if self.n < 1:
            raise ParameterError(f"The 'task_space' parameter of SelectorCurriculum must hold at least one task; its parts have {list(self.sizes)}.", "task_space", repr(task_space))
        # Syllabus's flatten=True: the encoding is the index itself (sub-spaces follow a Tuple's).
        self.flat = isinstance(task_space, DiscreteTaskSpace) or bool(getattr(task_space, "flatten", False))

    def __len__(self) -> int:
        return self.n

    def encoding(self, index: int) -> Any:
        """The task space's encoding of task ``index``."""
        if self.flat:
            return int(index)
        digits = np.unravel_index(int(index), self.sizes)
        if self.parts is None:
            return tuple(int(d) for d in digits)
        return tuple(part.encoding(int(d)) for part, d in zip(self.parts, digits))

    def index(self, encoding: Any) -> int:
        """The index of the task the space encodes as ``encoding``."""
        try:
            if self.flat:
                i = _whole(encoding)
            else:
                items = tuple(encoding)
                if len(items) != len(self.sizes):
                    raise ValueError(f"{len(items)} parts, not {len(self.sizes)}")
                digits = [_whole(e) if self.parts is None else self.parts[k].index(e) for k, e in enumerate(items)]
                if any(not 0 <= d < n for d, n in zip(digits, self.sizes)):
                    raise ValueError("a part out of range")
                i = int(np.ravel_multi_index(digits, self.sizes))
        except (TypeError, ValueError) as e:
            raise InputError(f"SelectorCurriculum: {encoding!r} is not an encoding of a task of {type(self.task_space).__name__} {list(self.sizes)} ({e}).") from None
        if not 0 <= i < self.n:
            raise InputError(f"SelectorCurriculum: {encoding!r} is not an encoding of a task of {type(self.task_space).__name__} {list(self.sizes)} (index {i} outside [0, {self.n})).")
        return i

    def task(self, index: int) -> Any:
        """Task ``index`` as the environments see it (the space's decoding of its encoding)."""
        return self.task_space.decode(self.encoding(index))


def _whole(value: Any) -> int:
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{value!r} is not an int")
    return int(value)


def _check_list(flat: FlatTasks, selector: Any) -> None:
    name = type(flat.task_space).__name__
    if not isinstance(selector, TaskListSelector):
        raise ConformanceError(f"SelectorCurriculum over a {name} needs a task-list teacher (saggriac.DiscreteLpSelector, saggriac.PlrSelector, saggriac.TsclSelector); got {type(selector).__name__}.")
    n = selector.n_tasks
    if n != flat.n:
        sizes = "" if len(flat.sizes) == 1 else f" ({' x '.join(map(str, flat.sizes))})"
        raise ParameterError(f"The 'selector' parameter of SelectorCurriculum must have the task space's {flat.n} tasks{sizes}; it has {n}.", "selector", repr(selector))


def _task_index(task: Any, idx: int) -> int:
    return idx


class SelectorCurriculum(Curriculum):
    """A Syllabus ``Curriculum`` whose tasks ``selector`` chooses (see the module's help)."""

    def __init__(self, task_space: Any, selector: Any, *, competence: str | Callable[[float, int, Any, float], float] = "progress", **curriculum_kwargs: Any) -> None:
        task_space = as_task_space(task_space)
        #: The task list a task-list teacher chooses from (None over a box).
        self.flat_tasks: FlatTasks | None = None
        if isinstance(task_space, BoxTaskSpace):
            _check_box(task_space, selector)
        elif isinstance(task_space, (DiscreteTaskSpace, MultiDiscreteTaskSpace, TupleTaskSpace)):
            self.flat_tasks = FlatTasks(task_space)
            _check_list(self.flat_tasks, selector)
        else:
            raise ConformanceError(f"SelectorCurriculum needs a Syllabus BoxTaskSpace, DiscreteTaskSpace, MultiDiscreteTaskSpace or TupleTaskSpace; got {type(task_space).__name__}.")
        if not (callable(competence) or competence in COMPETENCES):
            raise ParameterError(f"The 'competence' parameter of SelectorCurriculum must be one of {', '.join(map(repr, COMPETENCES))} or a function; got {competence!r}.", "competence", repr(competence))
        if competence == "progress" and callable(getattr(selector, "check_competences", None)):
            selector.check_competences(0.0, 1.0, "SelectorCurriculum(competence='progress') tells")
        if curriculum_kwargs.get("random_start_tasks", 0):
            raise ParameterError(
                "The 'random_start_tasks' parameter of SelectorCurriculum must be 0: Syllabus draws start tasks from numpy's global generator; "
                f"give the saggriac teacher its own bootstrap instead. Got {curriculum_kwargs['random_start_tasks']!r}.",
                "random_start_tasks",
                repr(curriculum_kwargs["random_start_tasks"]),
            )
        super().__init__(task_space, **curriculum_kwargs)
        if curriculum_kwargs.get("task_names") is None:
            self.task_names = _task_index  # Syllabus's default is a lambda, which cannot be pickled
        self.selector = selector
        self.competence = competence
        self.told = 0

    def sample(self, k: int = 1) -> list[Any]:
        """``k`` tasks from the teacher, as the task space encodes them."""
        if isinstance(k, bool) or not isinstance(k, (int, np.integer)) or k < 1:
            raise ParameterError(f"The 'k' parameter of SelectorCurriculum.sample must be an int >= 1. Got {k!r} instead.", "k", repr(k))
        goals = sample_batch(self.selector, int(k))
        if self.flat_tasks is not None:
            return [self.flat_tasks.encoding(int(g[0])) for g in goals]
        # The bounds are values of the Box's dtype and rounding is monotone, so a goal inside
        # them stays inside after the cast.
        dtype = self.task_space.gym_space.dtype
        return [g.astype(dtype) for g in goals]

    def _competence(self, episode_return: float, length: int, task: Any, progress: float) -> float:
        if callable(self.competence):
            return float(self.competence(episode_return, length, task, progress))
        return float(progress if self.competence == "progress" else episode_return)

    def update_on_episode(self, episode_return: float, length: int, task: Any, progress: float | bool, env_id: int | None = None) -> None:
        """Tell the teacher the competence of the episode that ran ``task``."""
        goal = np.atleast_1d(np.asarray(task, dtype=np.float64)) if self.flat_tasks is None else np.array([float(self.flat_tasks.index(task))])
        super().update_on_episode(episode_return, length, task, progress, env_id=env_id)
        c = self._competence(episode_return, length, task, float(progress))
        self.selector.update(goal, c)
        self.told += 1

    def log_metrics(self, writer: Any, logs: list[Any] | None, step: int | None = None, log_n_tasks: int = -1) -> list[Any]:
        """The number of episodes told and, for teachers with regions, their number."""
        logs = [] if logs is None else logs
        if self.stat_recorder is not None:
            logs += self.stat_recorder.get_metrics(log_n_tasks=log_n_tasks)
        ours = [("curriculum/told", self.told)]
        if hasattr(self.selector, "n_regions"):
            ours.append(("curriculum/regions", self.selector.n_regions))
        logs += ours
        if writer is not None:
            for name, value in ours:
                if hasattr(writer, "add_scalar"):
                    writer.add_scalar(name, value, step)
                else:
                    writer.log({name: value})
        return logs


class GoalTaskWrapper(TaskWrapper):
    """A saggriac goal environment as a Syllabus task environment: ``reset(new_task=goal)`` (or
    ``change_task``) sets the next episode's goal, checked to be in the goal box and to be the
    goal the environment then pursues; ``info["task_completion"]`` after each step is
    1 + C(goal, achieved, start) (eq. 7, clipped at ``min_c`` = -1 and set to 0 within ``eps_c``),
    from 0 (no closer than at the start) to 1 (reached). ``task_space`` is a ``BoxTaskSpace`` over
    the goal box, for :class:`SelectorCurriculum`."""

    def __init__(self, env: gymnasium.Env, *, eps_c: float = -0.05) -> None:
        super().__init__(env)
        space = getattr(env.unwrapped, "goal_space", None)
        if not isinstance(space, gymnasium.spaces.Box) or not callable(getattr(env.unwrapped, "set_next_goal", None)):
            raise ConformanceError(f"GoalTaskWrapper wraps saggriac's goal environments (saggriac/...-v0), which have a goal_space and take goals on reset; got {env}.")
        self.task_space = BoxTaskSpace(space)
        self._goal_space = space
        self._eps_c = eps_c
        _competence(np.zeros(1), np.zeros(1), np.ones(1), eps_c=eps_c)  # checks eps_c
        self.task = None
        self._start: np.ndarray | None = None

    def change_task(self, new_task: Any) -> None:
        goal = np.asarray(new_task, dtype=np.float64)
        if goal.shape != self._goal_space.shape or not np.all(np.isfinite(goal)) or not self._goal_space.contains(goal.astype(self._goal_space.dtype)):
            raise InputError(f"GoalTaskWrapper: a task is a goal in the environment's goal box [{self._goal_space.low.tolist()}, {self._goal_space.high.tolist()}]; got {new_task!r}.")
        self.task = goal

    def reset(self, new_task: Any = None, **kwargs: Any) -> tuple[Any, dict[str, Any]]:
        # Syllabus's base class reads a seed as a task when no task is given; a seed is a seed.
        if new_task is not None:
            self.change_task(new_task)
        options = dict(kwargs.pop("options", None) or {})
        if self.task is not None:
            options["goal"] = self.task
        obs, info = self.env.reset(options=options, **kwargs)
        if self.task is not None:
            check_goal_taken(self.task, obs, "GoalTaskWrapper", "reset(options={'goal': ...})")
        else:
            self.task = np.asarray(obs["desired_goal"], dtype=np.float64).copy()
        self._start = np.asarray(obs["achieved_goal"], dtype=np.float64).copy()
        self.task_completion = 0.0
        return self.observation(obs), {**info, "task_completion": 0.0, "task": self.task}

    def _task_completion(self, obs: Any, rew: Any, term: bool, trunc: bool, info: dict[str, Any]) -> float:
        c = _competence(np.asarray(obs["desired_goal"], dtype=np.float64), np.asarray(obs["achieved_goal"], dtype=np.float64), self._start, min_c=-1.0, eps_c=self._eps_c)
        return 1.0 + float(c)
