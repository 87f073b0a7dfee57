"""Any saggriac teacher as a Syllabus curriculum (the optional extra ``pip install "saggriac[syllabus]"``).

Syllabus (Sullivan et al., "Syllabus: Portable Curricula for Reinforcement Learning Agents",
2024) connects a curriculum in the training process with environments in other processes: the
environments' wrapper asks the curriculum for each episode's task and reports each episode's
return and task progress back. :class:`SelectorCurriculum` is such a curriculum whose tasks are
chosen by a saggriac selector:

* over a ``BoxTaskSpace`` (a 1-D ``gymnasium.spaces.Box``), by any box teacher whose bounds are
  the box's: :class:`saggriac.SaggRiacSelector`, ``RiacSelector``, ``AlpGmmSelector``,
  ``CovarGmmSelector``, ``AdrSelector``, ``SpdlSelector``, ``GoalGanSelector``, ``RandomSelector``;
* over a ``DiscreteTaskSpace`` of n tasks, by a task-list teacher with n tasks
  (:class:`saggriac.DiscreteLpSelector`, :class:`saggriac.PlrSelector`).

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
    from syllabus.task_space import BoxTaskSpace, DiscreteTaskSpace
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


def _check_discrete(task_space: DiscreteTaskSpace, selector: Any) -> None:
    if not isinstance(selector, TaskListSelector):
        raise ConformanceError(f"SelectorCurriculum over a DiscreteTaskSpace needs a task-list teacher (saggriac.DiscreteLpSelector, saggriac.PlrSelector); got {type(selector).__name__}.")
    n = selector.n_tasks
    if n != task_space.num_tasks:
        raise ParameterError(f"The 'selector' parameter of SelectorCurriculum must have the task space's {task_space.num_tasks} tasks; it has {n}.", "selector", repr(selector))


def _task_index(task: Any, idx: int) -> int:
    return idx


class SelectorCurriculum(Curriculum):
    """A Syllabus ``Curriculum`` whose tasks ``selector`` chooses (see the module's help)."""

    def __init__(self, task_space: Any, selector: Any, *, competence: str | Callable[[float, int, Any, float], float] = "progress", **curriculum_kwargs: Any) -> None:
        if isinstance(task_space, BoxTaskSpace):
            _check_box(task_space, selector)
            self._discrete = False
        elif isinstance(task_space, DiscreteTaskSpace):
            _check_discrete(task_space, selector)
            self._discrete = True
        else:
            raise ConformanceError(f"SelectorCurriculum needs a Syllabus BoxTaskSpace or DiscreteTaskSpace; got {type(task_space).__name__}.")
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
        if self._discrete:
            return [int(g[0]) for g in goals]
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
        super().update_on_episode(episode_return, length, task, progress, env_id=env_id)
        c = self._competence(episode_return, length, task, float(progress))
        goal = np.atleast_1d(np.asarray(task, dtype=np.float64))
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
