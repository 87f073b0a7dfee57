"""A saggriac teacher for Stable-Baselines3 (extra ``sb3``): one teacher, in the main process, for
any vector environment SB3 trains on, ``SubprocVecEnv`` included.

:class:`TeacherCallback` is an SB3 callback. It hands every sub-environment its next goal through
``VecEnv.env_method("set_next_goal", g)`` (saggriac's goal environments and
:class:`saggriac.gym.GoalSlot` have it; else ``set_attr(goal_attr, g)``), read on reset, reads the end of each episode from the step's ``dones`` and
``infos``, checks that the environment pursued the goal it was given, and tells the teacher the
episode's competence. A teacher captured by the workers instead would be copied into each of them
and the one in the main process told nothing; saggriac's wrappers refuse such copies.

SB3 resets a sub-environment as soon as its episode ends, so the goal of episode k + 1 is handed
out while episode k runs; the first episode of each sub-environment pursues the environment's own
goal and is not told.
"""

from __future__ import annotations

from typing import Any, Callable

import numpy as np

from .errors import ConformanceError, ParameterError
from .gym.goals import _check_fits, _check_goal_shape, _check_goal_taken, _refuse_worker_copy

try:
    from stable_baselines3.common.callbacks import BaseCallback
except ImportError as e:  # pragma: no cover - exercised without the extra
    raise ImportError(f'saggriac.sb3 needs Stable-Baselines3, which is not installed ({e}). Install it with: pip install "saggriac[sb3]"') from e

COMPETENCES = ("success", "distance")


class TeacherCallback(BaseCallback):
    """Let ``teacher`` (anything with ``sample()`` and ``update(goal, competence)``) choose the
    goal of every episode of the model's vector environment.

    ``competence`` says what the teacher is told when an episode ends: ``"success"`` (1.0 if the
    final ``info["is_success"]`` is true, else 0.0), ``"distance"`` (minus the final
    ``info["distance"]``) or a function of the final ``info``. ``goal_attr`` is the attribute the
    environments read their next goal from. ``history`` lists (goal, competence) as told."""

    def __init__(self, teacher: Any, competence: str | Callable[[dict[str, Any]], float] = "success", goal_attr: str = "next_goal", verbose: int = 0) -> None:
        super().__init__(verbose)
        if not (callable(getattr(teacher, "sample", None)) and callable(getattr(teacher, "update", None))):
            raise ConformanceError(f"TeacherCallback needs a teacher with sample() and update(goal, competence); got {teacher!r}.")
        _refuse_worker_copy(teacher, "TeacherCallback")
        if not callable(competence) and competence not in COMPETENCES:
            raise ParameterError(f"The 'competence' parameter of TeacherCallback must be one of {', '.join(map(repr, COMPETENCES))} or a function of an episode's final info. Got {competence!r} instead.", "competence", repr(competence))
        if not isinstance(goal_attr, str) or not goal_attr:
            raise ParameterError(f"The 'goal_attr' parameter of TeacherCallback must be an attribute name. Got {goal_attr!r} instead.", "goal_attr", repr(goal_attr))
        self.teacher = teacher
        self.competence = competence
        self.goal_attr = goal_attr
        self.history: list[tuple[np.ndarray, float]] = []
        self._queued: list[np.ndarray] = []
        self._by_method = False
        self._current: list[np.ndarray | None] = []

    def _score(self, info: dict[str, Any]) -> float:
        if callable(self.competence):
            return float(self.competence(info))
        key = "is_success" if self.competence == "success" else "distance"
        if key not in info:
            raise ConformanceError(f"TeacherCallback(competence={self.competence!r}) reads info[{key!r}] at the end of an episode, and this environment's info has only {sorted(info)}; pass competence=a function of the info.")
        return float(bool(info[key])) if key == "is_success" else -float(info[key])

    def _hand_out(self, i: int) -> None:
        goal = _check_goal_shape(np.asarray(self.teacher.sample(), dtype=np.float64), self.training_env.observation_space["desired_goal"], "TeacherCallback")
        if self._by_method:
            # env_method finds the method through every wrapper; set_attr would set it on the
            # outermost wrapper (SB3's Monitor), where the environment never reads it.
            self.training_env.env_method("set_next_goal", goal, indices=[i])
        else:
            self.training_env.set_attr(self.goal_attr, goal, indices=[i])
        self._queued[i] = goal

    def _on_training_start(self) -> None:
        env = self.training_env
        if "desired_goal" not in getattr(env.observation_space, "spaces", {}):
            raise ConformanceError(f"TeacherCallback needs a goal-conditioned environment: a Dict observation space with 'desired_goal'; got {env.observation_space}.")
        _check_fits(self.teacher, env.observation_space["desired_goal"], "TeacherCallback")
        self._by_method = self.goal_attr == "next_goal" and env.has_attr("set_next_goal")
        if not (self._by_method or env.has_attr(self.goal_attr)):
            raise ConformanceError(f"The environments have no '{self.goal_attr}' attribute to take their next goal from; wrap each in saggriac.gym.GoalSlot (it reads it on reset and passes options={{'goal': ...}}).")
        n = env.num_envs
        self._queued = [np.empty(0)] * n
        self._current = [None] * n
        for i in range(n):
            self._hand_out(i)

    def _on_step(self) -> bool:
        dones = self.locals["dones"]
        infos = self.locals["infos"]
        new_obs = self.locals.get("new_obs")
        for i in np.flatnonzero(dones):
            finished = self._current[i]
            if finished is not None:
                c = self._score(infos[i])
                self.teacher.update(finished, c)
                self.history.append((finished, c))
            # The sub-environment has already reset, with the goal queued for it.
            self._current[i] = self._queued[i]
            if new_obs is not None:
                _check_goal_taken(self._queued[i], {"desired_goal": np.asarray(new_obs["desired_goal"])[i]}, f"TeacherCallback (sub-environment {i})", f"set_attr({self.goal_attr!r}, ...)")
            self._hand_out(i)
        return True


__all__ = ["TeacherCallback"]
