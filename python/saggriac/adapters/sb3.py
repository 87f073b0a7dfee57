"""A saggriac teacher for Stable-Baselines3 (extra ``sb3``): one teacher, in the main process, for
any vector environment SB3 trains on, ``SubprocVecEnv`` included.

:class:`TeacherCallback` is an SB3 callback. It hands every sub-environment its next goal through
``VecEnv.env_method("set_next_goal", g)`` (saggriac's goal environments and
:class:`saggriac.adapters.gym.GoalSlot` have it; else ``set_attr(goal_attr, g)``), read on reset, reads the end of each episode from the step's ``dones`` and
``infos``, checks that the environment pursued the goal it was given, and tells the teacher the
episode's competence. A teacher captured by the workers instead would be copied into each of them
and the one in the main process told nothing; saggriac's wrappers refuse such copies.

SB3 resets a sub-environment as soon as its episode ends, so the goal of episode k + 1 is handed
out while episode k runs; the first episode of each sub-environment pursues the environment's own
goal and is not told.

PLR's published scores (Jiang, Grefenstette & Rocktäschel, ICML 2021) come from the learner's
value function rather than from a competence: with ``competence="positive_value_loss"`` or
``"value_l1"`` the callback reads, at the end of each rollout, the generalised advantage
estimates (GAE) SB3's on-policy algorithms (PPO, A2C) keep in their rollout buffer, and tells the
teacher each episode's mean GAE clipped at 0, or mean |GAE|, over the episode's steps in that
rollout, as the authors' code does (an episode still running when the rollout ends is scored on
its steps so far, and its remaining steps form the next rollout's first piece).

The callback records what the teacher does through SB3's logger (``teacher/...``, beside SB3's
own in stdout, CSV, TensorBoard and so W&B): the numbers its paper plots
(:func:`saggriac.analysis.teacher_readings`) and, every ``figure_every`` rollouts, the picture of
its goals (:func:`saggriac.analysis.plot_teacher`). Given SB3's ``CheckpointCallback`` as
``save_with``, it saves the teacher beside every model checkpoint (:func:`teacher_path` names the
file), so that a resumed training continues the same teacher, and its counts with it.
"""

from __future__ import annotations

import os
import re
from pathlib import Path
from typing import Any, Callable

import numpy as np

from ..analysis.readings import kind_of, teacher_readings
from ..errors import ConformanceError, ParameterError
from ..files import check_flag
from .gym.goals import check_fits, check_goal_shape, check_goal_taken
from ..teachers import AskTellSelector, ownership

try:
    from stable_baselines3.common.buffers import RolloutBuffer
    from stable_baselines3.common.callbacks import BaseCallback, CheckpointCallback
    from stable_baselines3.common.logger import Figure
    from stable_baselines3.common.vec_env import VecEnvWrapper
except ImportError as e:  # pragma: no cover - exercised without the extra
    raise ImportError(f'saggriac.adapters.sb3 needs Stable-Baselines3, which is not installed ({e}). Install it with: pip install "saggriac[sb3]"') from e

COMPETENCES = ("success", "distance")
#: PLR's scores from an on-policy model's rollouts: an episode's mean GAE clipped at 0 (the
#: positive value loss) or its mean |GAE| (the L1 value loss).
VALUE_LOSSES = ("positive_value_loss", "value_l1")
#: The range of what each competence tells: a teacher's thresholds are checked against it.
TOLD = {"success": (0.0, 1.0), "distance": (-float("inf"), 0.0)}

#: Per-dimension or per-task readings are shown on stdout when there are at most this many of
#: them (CSV and TensorBoard always get them all).
STDOUT_ITEMS = 16
#: A per-dimension (``low_0``) or per-task (``task_3/share``) reading.
_ITEM = re.compile(r"(^task_\d+/|_\d+$)")
#: Outputs that cannot show a list (SB3 writes an array as a histogram in TensorBoard) or a figure.
_NO_ARRAYS = ("stdout", "log", "csv")
_NO_FIGURES = ("stdout", "log", "csv", "json")


def teacher_path(model_path: str | os.PathLike[str]) -> Path:
    """The teacher saved beside the model checkpoint ``model_path`` by a :class:`TeacherCallback`
    with ``save_with=`` a ``CheckpointCallback``: ``rl_model_1000_steps.zip`` ->
    ``rl_model_teacher_1000_steps.saggriac`` (as SB3 names its replay buffer and VecNormalize
    files). Read it back with :func:`saggriac.load_selector`."""
    p = Path(model_path)
    m = re.fullmatch(r"(.*)_(\d+)_steps(\.zip)?", p.name)
    if m is None:
        raise ParameterError(f"The 'model_path' parameter of teacher_path must name a model saved by SB3's CheckpointCallback, '<prefix>_<steps>_steps.zip'. Got {str(model_path)!r} instead.", "model_path", repr(str(model_path)))
    return p.with_name(f"{m.group(1)}_teacher_{m.group(2)}_steps.saggriac")


def _raw_observations(venv: Any, new_obs: Any) -> tuple[Any, str]:
    """The observations as the environments gave them: a VecNormalize (any VecEnvWrapper with
    ``get_original_obs``) normalises what the callback sees, goals included."""
    raw, how, env = new_obs, "", venv
    while isinstance(env, VecEnvWrapper):
        if callable(getattr(env, "get_original_obs", None)):
            raw, how = env.get_original_obs(), f" (read before {type(env).__name__} through get_original_obs())"
        env = env.venv
    return raw, how


def _check_takes_scores(teacher: Any, competence: str) -> None:
    """A value loss is a score, not a competence: saggriac's teachers take it only as PLR's
    told score."""
    if not isinstance(teacher, AskTellSelector):
        return  # a user's teacher knows what it is told
    score = teacher.get_params().get("score")
    if score != "told":
        given = f" with score={score!r}" if score is not None else ""
        raise ParameterError(
            f"The 'competence' parameter of TeacherCallback is {competence!r}, a level's value loss (PLR's score, Jiang et al. 2021), which only "
            f"PlrSelector(score='told') takes as it is; {type(teacher).__name__}{given} would read it as a competence. Build the teacher with "
            "PlrSelector(n_tasks, score='told'), or tell competences ('success', 'distance' or a function of the final info).",
            "competence",
            repr(competence),
        )


class TeacherCallback(BaseCallback):
    """Let ``teacher`` (anything with ``sample()`` and ``update(goal, competence)``) choose the
    goal of every episode of the model's vector environment.

    ``competence`` says what the teacher is told when an episode ends: ``"success"`` (1.0 if the
    final ``info["is_success"]`` is true, else 0.0), ``"distance"`` (minus the final
    ``info["distance"]``) or a function of the final ``info``; or, for
    ``PlrSelector(score="told")`` behind an on-policy model (PPO, A2C), PLR's scores from the
    model's rollouts, told at each rollout's end: ``"positive_value_loss"`` (an episode's mean GAE
    clipped at 0) or ``"value_l1"`` (its mean |GAE|). ``goal_attr`` is the attribute the
    environments read their next goal from. ``history`` lists (goal, competence) as told.

    SB3's logger gets, at the end of every rollout, ``teacher/asked`` and ``teacher/told`` (the
    teacher's own totals, which a resumed teacher carries on), ``teacher/competence`` (mean of
    what was told since the last dump) and what the teacher's paper plots, over the goals since
    the last dump (:func:`saggriac.analysis.teacher_readings`: ADR's ranges, SPDL's mean, spread,
    KL and expected competence, Goal GAN's share of goals of intermediate difficulty, the regions
    and their interests, the tasks' shares...). A teacher that is not saggriac's gets the
    callback's own counts. ``figure_every=N`` adds ``teacher/goals``, the figure of
    :func:`saggriac.analysis.plot_teacher`, every N rollouts (TensorBoard only; an off-policy
    algorithm's rollout is its ``train_freq``). ``save_with`` takes SB3's ``CheckpointCallback``:
    the teacher is saved at each of its checkpoints, to :func:`teacher_path` of the model's file (whatever the
    order of the two in the callback list, and across learn() calls that reuse the checkpoint
    callback).
    ``allow_copy`` is :class:`saggriac.adapters.gym.SelectorGoals`'s."""

    def __init__(self, teacher: Any, competence: str | Callable[[dict[str, Any]], float] = "success", goal_attr: str = "next_goal", verbose: int = 0, *, save_with: CheckpointCallback | None = None, allow_copy: bool = False, figure_every: int | None = None) -> None:
        super().__init__(verbose)
        if figure_every is not None and (isinstance(figure_every, bool) or not isinstance(figure_every, (int, np.integer)) or figure_every < 1):
            raise ParameterError(f"The 'figure_every' parameter of TeacherCallback must be an int >= 1 (a figure every that many rollouts) or None. Got {figure_every!r} instead.", "figure_every", repr(figure_every))
        if not (callable(getattr(teacher, "sample", None)) and callable(getattr(teacher, "update", None))):
            raise ConformanceError(f"TeacherCallback needs a teacher with sample() and update(goal, competence); got {teacher!r}.")
        check_flag(allow_copy, "allow_copy", "TeacherCallback")
        if isinstance(competence, str) and competence in TOLD and callable(getattr(teacher, "check_competences", None)):
            teacher.check_competences(*TOLD[competence], f"TeacherCallback(competence={competence!r}) tells")
        ownership.claim(teacher, "TeacherCallback", allow_copy)
        if save_with is not None:
            if not isinstance(save_with, CheckpointCallback):
                raise ParameterError(f"The 'save_with' parameter of TeacherCallback must be Stable-Baselines3's CheckpointCallback (the teacher is saved at its checkpoints). Got {save_with!r} instead.", "save_with", repr(save_with))
            if not callable(getattr(teacher, "save", None)):
                raise ConformanceError(f"TeacherCallback(save_with=...) saves the teacher with its save(path) method, and {teacher!r} has none; give it one, or save the teacher yourself.")
        if not callable(competence) and competence not in COMPETENCES + VALUE_LOSSES:
            raise ParameterError(f"The 'competence' parameter of TeacherCallback must be one of {', '.join(map(repr, COMPETENCES + VALUE_LOSSES))} or a function of an episode's final info. Got {competence!r} instead.", "competence", repr(competence))
        if competence in VALUE_LOSSES:
            _check_takes_scores(teacher, competence)
        if not isinstance(goal_attr, str) or not goal_attr:
            raise ParameterError(f"The 'goal_attr' parameter of TeacherCallback must be an attribute name. Got {goal_attr!r} instead.", "goal_attr", repr(goal_attr))
        self.teacher = teacher
        self.competence = competence
        self.goal_attr = goal_attr
        self.save_with = save_with
        self.allow_copy = allow_copy
        if figure_every is not None and kind_of(teacher) is None:
            raise ParameterError(f"The 'figure_every' parameter of TeacherCallback draws one of saggriac's teachers (saggriac.analysis.plot_teacher reads its history), and {teacher!r} is not one; leave it out, or draw your teacher yourself. Got figure_every={figure_every!r} instead.", "figure_every", repr(figure_every))
        self.figure_every = None if figure_every is None else int(figure_every)
        self.asked = 0
        # The teacher's history when this callback started, the window of the next readings
        # (positions in it), what was seen at the previous reading, and the rollouts so far.
        self._kind = kind_of(teacher)
        self._start = (0, 0)
        self._window = (0, 0)
        self._last_read: tuple[int, int] | None = None
        self._rollouts = 0
        self.history: list[tuple[np.ndarray, float]] = []
        self._queued: list[np.ndarray] = []
        self._by_method = False
        self._current: list[np.ndarray | None] = []
        # With a value loss: each step of the rollout, the goal each sub-environment pursued and
        # whether its episode ended there.
        self._by_value_loss = isinstance(competence, str) and competence in VALUE_LOSSES
        self._step_goals: list[list[np.ndarray | None]] = []
        self._step_dones: list[np.ndarray] = []
        # save_with's own count at our previous step, and a save made ahead of it (step, its
        # count then, the file written, the file it becomes).
        self._ck_calls = 0
        self._ck_first = True
        self._pending: tuple[int, int, Path, Path] | None = None

    def _score(self, info: dict[str, Any]) -> float:
        if callable(self.competence):
            return float(self.competence(info))
        key = "is_success" if self.competence == "success" else "distance"
        if key not in info:
            raise ConformanceError(f"TeacherCallback(competence={self.competence!r}) reads info[{key!r}] at the end of an episode, and this environment's info has only {sorted(info)}; pass competence=a function of the info.")
        return float(bool(info[key])) if key == "is_success" else -float(info[key])

    def _hand_out(self, i: int) -> None:
        goal = check_goal_shape(np.asarray(self.teacher.sample(), dtype=np.float64), self.training_env.observation_space["desired_goal"], "TeacherCallback")
        self.asked += 1
        if self._by_method:
            # env_method finds the method through every wrapper; set_attr would set it on the
            # outermost wrapper (SB3's Monitor), where the environment never reads it.
            self.training_env.env_method("set_next_goal", goal, indices=[i])
        else:
            self.training_env.set_attr(self.goal_attr, goal, indices=[i])
        self._queued[i] = goal

    def _on_training_start(self) -> None:
        ownership.claim(self.teacher, "TeacherCallback", self.allow_copy)
        env = self.training_env
        if "desired_goal" not in getattr(env.observation_space, "spaces", {}):
            raise ConformanceError(f"TeacherCallback needs a goal-conditioned environment: a Dict observation space with 'desired_goal'; got {env.observation_space}.")
        check_fits(self.teacher, env.observation_space["desired_goal"], "TeacherCallback")
        self._by_method = self.goal_attr == "next_goal" and env.has_attr("set_next_goal")
        if not (self._by_method or env.has_attr(self.goal_attr)):
            raise ConformanceError(f"The environments have no '{self.goal_attr}' attribute to take their next goal from; wrap each in saggriac.adapters.gym.GoalSlot (it reads it on reset and passes options={{'goal': ...}}).")
        if self._by_value_loss and not isinstance(getattr(self.model, "rollout_buffer", None), RolloutBuffer):
            raise ConformanceError(
                f"TeacherCallback(competence={self.competence!r}) reads the advantages (GAE) an on-policy model (PPO, A2C) keeps in its rollout "
                f"buffer, and {type(self.model).__name__} has none; tell competences instead ('success', 'distance' or a function of the final info)."
            )
        if self.save_with is not None:
            self._ck_calls, self._ck_first, self._pending = self.save_with.n_calls, True, None
        if self._kind is not None:
            h = self.teacher.history()
            self._start = (len(h["asked_goal"]) - self.asked, len(h["told_goal"]) - len(self.history))
        self._window = self._counts()
        self._last_read = None
        n = env.num_envs
        self._queued = [np.empty(0)] * n
        self._current = [None] * n
        for i in range(n):
            self._hand_out(i)

    @property
    def _route(self) -> str:
        return "env_method('set_next_goal', ...)" if self._by_method else f"set_attr({self.goal_attr!r}, ...)"

    def _on_step(self) -> bool:
        dones = self.locals["dones"]
        infos = self.locals["infos"]
        new_obs = self.locals.get("new_obs")
        raw, how = (None, "") if new_obs is None or not np.any(dones) else _raw_observations(self.training_env, new_obs)
        if self._by_value_loss:
            self._step_goals.append(list(self._current))
            self._step_dones.append(np.asarray(dones, dtype=bool).copy())
        for i in np.flatnonzero(dones):
            finished = self._current[i]
            if finished is not None and not self._by_value_loss:
                c = self._score(infos[i])
                self.teacher.update(finished, c)
                self.history.append((finished, c))
                self.logger.record_mean("teacher/competence", c)
            # The sub-environment has already reset, with the goal queued for it.
            self._current[i] = self._queued[i]
            if raw is not None:
                check_goal_taken(self._queued[i], {"desired_goal": np.asarray(raw["desired_goal"])[i]}, f"TeacherCallback (sub-environment {i})", self._route + how)
            self._hand_out(i)
        if self.save_with is not None:
            self._save_with_checkpoint()
        return True

    def _teacher_file(self, steps: int) -> Path:
        ck = self.save_with
        return teacher_path(Path(ck.save_path) / f"{ck.name_prefix}_{steps}_steps.zip")

    def _save_with_checkpoint(self) -> None:
        """Save the teacher exactly when save_with saves its model: on save_with's own count of
        calls, which runs on across learn() calls, not on this callback's. Called once per step,
        after the teacher was told this step's episodes."""
        ck = self.save_with
        self._settle()
        called = ck.n_calls != self._ck_calls
        if called and ck.num_timesteps == self.num_timesteps:
            # It ran before this callback in this step, and has just saved its model or not.
            if ck.n_calls % ck.save_freq == 0:
                self.save(self._teacher_file(self.num_timesteps))
        elif (called or (self._ck_first and getattr(ck, "model", None) is self.model)) and (ck.n_calls + 1) % ck.save_freq == 0:
            # It runs after this callback in this step (or not at all, which the next step
            # shows): save now, under a hidden name, and keep it only if the model is saved.
            final = self._teacher_file(self.num_timesteps)
            ahead = final.with_name(f".{final.name}.pending")
            self.teacher.save(ahead, overwrite=True)
            self._pending = (self.num_timesteps, ck.n_calls + 1, ahead, final)
        self._ck_first = False
        self._ck_calls = ck.n_calls

    def _settle(self) -> None:
        """Keep the teacher saved ahead at the previous step if save_with then saved its model."""
        if self._pending is None:
            return
        steps, calls, ahead, final = self._pending
        self._pending = None
        if self.save_with.n_calls == calls and self.save_with.num_timesteps == steps:
            os.replace(ahead, final)
            if self.verbose >= 2:
                print(f"Saving the teacher to {final}")
        else:
            ahead.unlink(missing_ok=True)

    def _on_training_end(self) -> None:
        if self.save_with is not None:
            self._settle()

    def _on_rollout_start(self) -> None:
        self._step_goals, self._step_dones = [], []

    def _tell_value_losses(self) -> None:
        """Tell each episode's piece of this rollout its value loss, sub-environment by
        sub-environment and in time (the authors' order); the first episode of each
        sub-environment pursued the environment's own goal and is not told."""
        advantages = np.asarray(self.model.rollout_buffer.advantages, dtype=np.float64)
        steps = len(self._step_goals)
        if advantages.shape[0] != steps:
            raise ConformanceError(f"TeacherCallback(competence={self.competence!r}): the rollout buffer holds {advantages.shape[0]} steps and the callback saw {steps}; another callback stopped the rollout, or the buffer is not the model's.")
        clip = self.competence == "positive_value_loss"
        for env in range(len(self._current)):
            start = 0
            for t in range(steps):
                if not (self._step_dones[t][env] or t == steps - 1):
                    continue
                goal = self._step_goals[start][env]
                if goal is not None:
                    piece = advantages[start : t + 1, env]
                    score = float(np.mean(np.maximum(piece, 0.0) if clip else np.abs(piece)))
                    self.teacher.update(goal, score)
                    self.history.append((goal, score))
                    self.logger.record_mean(f"teacher/{self.competence}", score)
                start = t + 1
        self._step_goals, self._step_dones = [], []

    def _counts(self) -> tuple[int, int]:
        """What the teacher has been asked and told in all (its history's lengths, for saggriac's
        teachers: it carries on across a resume), from this callback's counts."""
        return self._start[0] + self.asked, self._start[1] + len(self.history)

    def _on_rollout_end(self) -> None:
        if self._by_value_loss:
            self._tell_value_losses()
        self._rollouts += 1
        counts = self._counts()
        # SB3 clears what was recorded when it writes the log: the next readings then cover what
        # came after the previous ones.
        dumped = "teacher/told" not in self.logger.name_to_value
        if dumped and self._last_read is not None:
            self._window = self._last_read
        figure = self.figure_every is not None and self._rollouts % self.figure_every == 0
        if dumped or counts != self._last_read or figure:
            self._record_readings(counts)
        if figure:
            from ..analysis.teacher_plots import plot_teacher

            self.logger.record("teacher/goals", Figure(plot_teacher(self.teacher), close=True), exclude=_NO_FIGURES)

    def _record_readings(self, counts: tuple[int, int]) -> None:
        readings = teacher_readings(self.teacher, *self._window) if self._kind is not None else {}
        readings.pop("competence", None)  # the callback's own mean of the same tells, since the last dump
        readings.setdefault("asked", counts[0])
        readings.setdefault("told", counts[1])
        items = [k for k in readings if _ITEM.search(k)]
        quiet = ("stdout", "log") if len(items) > STDOUT_ITEMS else None
        for key, value in readings.items():
            if isinstance(value, np.ndarray):
                self.logger.record(f"teacher/{key}", value, exclude=_NO_ARRAYS)
            else:
                self.logger.record(f"teacher/{key}", value, exclude=quiet if key in items else None)
        self._last_read = counts

    def save(self, path: str | os.PathLike[str]) -> Path:
        """Save the teacher to ``path`` (replacing an earlier save of it); read it back with
        :func:`saggriac.load_selector` and pass it to a new TeacherCallback to continue."""
        out = self.teacher.save(path, overwrite=True)
        if self.verbose >= 2:
            print(f"Saving the teacher to {out}")
        return out


__all__ = ["TeacherCallback", "teacher_path"]
