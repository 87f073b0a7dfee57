"""A saggriac goal selector as the teacher of a goal-conditioned Gymnasium environment.

Each episode's goal is asked of the selector when the episode starts, and the selector is told
the episode's competence (eq. 7 of Baranes & Oudeyer 2010, through :func:`saggriac.competence`:
the final distance to the goal against the starting one) when it ends, terminated or truncated.
An episode cut short by a reset is not told. The environment must have a dict observation with
``achieved_goal`` and ``desired_goal`` (the Gymnasium-Robotics layout), as ``saggriac/...-v0``.

* :class:`SelectorGoals` wraps one environment. The goal reaches it through
  ``reset(options={"goal": g})`` (``goal_via="options"``, as saggriac's environments read it) or
  by replacing ``desired_goal`` in every observation and recomputing the reward with the
  environment's ``compute_reward`` (``goal_via="observation"``, for any goal environment).
* :class:`VectorSelectorGoals` wraps a vector environment (``gymnasium.make_vec``,
  ``SyncVectorEnv``, ``AsyncVectorEnv``; autoreset on the next step, Gymnasium's default). It asks
  and tells in batches (``sample_batch``/``update_batch``) and hands each sub-environment its next
  goal through ``set_attr("next_goal", ...)``: saggriac's environments read it on reset; wrap
  others in :class:`GoalSlot`.
* :class:`GoalSlot` gives any goal environment a ``next_goal`` read on reset, passed on through
  ``options={"goal": g}`` or, with ``goal_via="observation"``, put in the observations (the
  route of an environment that ignores ``options["goal"]``, such as Gymnasium-Robotics'
  PointMaze), so that SB3's :class:`saggriac.adapters.sb3.TeacherCallback` can choose its goals.

On the observation route the environment still pursues its own goal inside: the wrapper replaces
``desired_goal``, recomputes the reward (and the end, where the environment has
``compute_terminated``) with the environment's ``compute_reward`` for the teacher's goal, moves
the environment's success flags and ``distance`` for its own goal to ``"<key>_env_goal"`` and
puts the teacher's goal's in their place (``info["distance"]``: from ``achieved_goal`` to it).
"""

from __future__ import annotations

from typing import Any

import gymnasium
import numpy as np

from ...teachers.competence import competence
from ...errors import ConformanceError, ParameterError
from ...files import check_flag
from ...teachers import ownership

GOAL_VIA = ("options", "observation")


class _Scoring:
    """The competence parameters of a wrapper, checked once."""

    def __init__(self, min_c: float, eps_c: float, kind: str, reach: float | None) -> None:
        self.kw = dict(min_c=min_c, eps_c=eps_c, kind=kind, reach=reach)
        competence(np.zeros(1), np.zeros(1), np.ones(1), **self.kw)  # raises ParameterError on a bad value

    def __call__(self, goal: np.ndarray, reached: np.ndarray, start: np.ndarray) -> Any:
        return competence(goal, reached, start, **self.kw)


def check_goal_taken(wanted: np.ndarray, obs: dict[str, Any], owner: str, how: str) -> None:
    """The environment must pursue the goal it was given: its desired_goal after the reset."""
    got = np.asarray(obs["desired_goal"], dtype=np.float64)
    if got.shape != wanted.shape or not np.allclose(got, wanted, rtol=1e-6, atol=1e-6 * (1.0 + float(np.max(np.abs(wanted))))):
        raise ConformanceError(
            f"{owner} asked the environment for the goal {np.round(wanted, 6).tolist()} through {how}, but after reset its desired_goal is "
            f"{np.round(got, 6).tolist()}: the environment does not take goals that way (Gymnasium-Robotics' PointMaze, for one, reads "
            "options['goal_cell']), and the teacher would be told competences for goals that were never pursued. Give the environment a way to "
            "take the goal, or use goal_via='observation' where the environment's reward and success come from compute_reward."
        )


def _check_goal_space(space: Any, owner: str) -> None:
    if not isinstance(space, gymnasium.spaces.Dict) or not {"achieved_goal", "desired_goal"} <= set(space.spaces):
        raise ConformanceError(f"{owner} needs a goal-conditioned environment: a Dict observation space with 'achieved_goal' and 'desired_goal'; got {space}.")


def _take_selector(selector: Any, goal_space: Any, owner: str, allow_copy: Any) -> None:
    """A wrapper's selector must ask and be told, be this wrapper's alone (unless a copy is
    allowed) and fit the environment's goals."""
    if not (callable(getattr(selector, "sample", None)) and callable(getattr(selector, "update", None))):
        raise ConformanceError(f"{owner} needs a selector with sample() and update(goal, competence); got {selector!r}.")
    check_flag(allow_copy, "allow_copy", owner)
    ownership.claim(selector, owner, allow_copy)
    check_fits(selector, goal_space, owner)


def check_fits(teacher: Any, goal_space: Any, owner: str) -> None:
    """A teacher's goal box must have the environment's goal dimension and lie within its
    desired_goal bounds (where they are finite): found before training, not as a numpy
    traceback or an environment's refusal at some later reset."""
    low, high = getattr(teacher, "low", None), getattr(teacher, "high", None)
    if low is None or high is None:
        return  # a teacher without a box: each goal is checked when it is handed out
    low, high = np.asarray(low, dtype=np.float64).reshape(-1), np.asarray(high, dtype=np.float64).reshape(-1)
    shape = tuple(goal_space.shape)
    if (low.size,) != shape:
        raise ParameterError(f"{owner}: the teacher's goals have {low.size} dimension(s) (its box is {low.tolist()} to {high.tolist()}), and the environment's desired_goal has shape {shape}: give the teacher a box of the environment's goal dimension.", "teacher", repr(teacher))
    env_low, env_high = np.asarray(goal_space.low, dtype=np.float64).reshape(-1), np.asarray(goal_space.high, dtype=np.float64).reshape(-1)
    outside = (low < env_low) | (high > env_high)
    if outside.any():
        raise ParameterError(f"{owner}: the teacher's goal box {low.tolist()} to {high.tolist()} leaves the environment's desired_goal bounds {env_low.tolist()} to {env_high.tolist()} (dimension(s) {np.flatnonzero(outside).tolist()}): the environment would refuse or clip such goals. Give the teacher a box within those bounds.", "teacher", repr(teacher))


def check_goal_shape(goal: np.ndarray, goal_space: Any, owner: str) -> np.ndarray:
    """One goal handed out: the environment's goal shape, finite."""
    if goal.shape != tuple(goal_space.shape) or not np.all(np.isfinite(goal)):
        raise ConformanceError(f"{owner}: the teacher's sample() gave {goal.tolist()!r}, and the environment's goals are {tuple(goal_space.shape)} finite floats.")
    return goal


#: Keys of an environment's info that speak of the success of its own goal.
SUCCESS_KEYS = ("is_success", "success")


def _success_rule(success: Any, env: gymnasium.Env, owner: str) -> Any:
    """goal_via="observation": how the teacher's goal's success is decided. None: the
    environment's ``distance_threshold`` (Gymnasium-Robotics' Fetch, saggriac's arms) where it
    has one, else unknown; a number: that distance; a function of (achieved, desired); False: no
    flag."""
    if success is False:
        return False
    if success is None:
        t = getattr(env.unwrapped, "distance_threshold", None)
        if isinstance(t, (int, float, np.integer, np.floating)) and not isinstance(t, bool) and np.isfinite(t) and t > 0:
            return float(t)
        return None
    if callable(success):
        return success
    if isinstance(success, (int, float, np.integer, np.floating)) and not isinstance(success, (bool, np.bool_)) and np.isfinite(success) and success > 0:
        return float(success)
    raise ParameterError(f"The 'success' parameter of {owner} must be a distance > 0, a function of (achieved_goal, desired_goal), False or None. Got {success!r} instead.", "success", repr(success))


def _success_for_teacher(info: dict[str, Any], rule: Any, achieved: np.ndarray, goal: np.ndarray, owner: str) -> dict[str, Any]:
    """goal_via="observation": the environment computed its success flags for its own goal, not
    the teacher's; they are kept under "<key>_env_goal" so that nothing (SB3's success rate, a
    competence="success") reads them as the teacher's goal's, and ``info["is_success"]`` (and
    the environment's own key) says whether the teacher's goal is reached."""
    own = [k for k in SUCCESS_KEYS if k in info]
    info = dict(info)
    if "distance" in info:
        info["distance_env_goal"] = info.pop("distance")
    info["distance"] = float(np.linalg.norm(np.asarray(achieved, dtype=np.float64) - goal))
    for k in own:
        info[f"{k}_env_goal"] = info.pop(k)
    if rule is False or (not own and rule is None):
        return info
    if rule is None:
        raise ConformanceError(
            f"{owner}(goal_via='observation'): the environment reports {own[0]!r} for its own goal, and saggriac cannot tell the success of the "
            "teacher's goal (the environment has no distance_threshold). Pass success=the distance that counts as reached (PointMaze: 0.45), "
            "success=a function of (achieved_goal, desired_goal), or success=False for no success flag."
        )
    ok = bool(rule(achieved, goal)) if callable(rule) else bool(np.linalg.norm(np.asarray(achieved, dtype=np.float64) - goal) <= rule)
    for k in dict.fromkeys(["is_success", *own]):
        info[k] = ok
    return info


def _goal_in_observation(obs: dict[str, Any], goal: np.ndarray, space: Any) -> dict[str, Any]:
    """goal_via="observation": the observation with the teacher's goal as its desired_goal."""
    obs = dict(obs)
    obs["desired_goal"] = goal.astype(space.dtype, copy=True)
    return obs


def _step_for_goal(env: gymnasium.Env, goal: np.ndarray, rule: Any, owner: str, obs: dict[str, Any], reward: Any, terminated: bool, info: dict[str, Any]) -> tuple[dict[str, Any], float, bool, dict[str, Any]]:
    """goal_via="observation": a step of ``env`` as it would be for ``goal``. The environment's
    own reward and end test used its own goal: both are recomputed for the teacher's goal
    (compute_terminated where the environment has it)."""
    obs = _goal_in_observation(obs, goal, env.observation_space["desired_goal"])
    base = env.unwrapped
    reward = float(base.compute_reward(obs["achieved_goal"], obs["desired_goal"], info))
    if callable(getattr(base, "compute_terminated", None)):
        terminated = bool(base.compute_terminated(obs["achieved_goal"], obs["desired_goal"], info))
    info = _success_for_teacher(info, rule, np.asarray(obs["achieved_goal"], dtype=np.float64), goal, owner)
    return obs, reward, terminated, info


def sample_batch(selector: Any, n: int) -> np.ndarray:
    if hasattr(selector, "sample_batch"):
        return np.asarray(selector.sample_batch(n), dtype=np.float64)
    return np.array([np.asarray(selector.sample(), dtype=np.float64) for _ in range(n)])


def _update_batch(selector: Any, goals: np.ndarray, comps: np.ndarray) -> None:
    if hasattr(selector, "update_batch"):
        selector.update_batch(goals, comps)
    else:
        for g, c in zip(goals, comps):
            selector.update(g, float(c))


class SelectorGoals(gymnasium.Wrapper):
    """Goals of ``env``'s episodes asked of ``selector`` (anything with ``sample()`` and
    ``update(goal, competence)``, such as :class:`saggriac.SaggRiacSelector`). The competence
    parameters mean what they mean in :class:`saggriac.Config`; ``reach`` is needed only for
    ``competence="absolute"``. ``info["competence"]`` holds the value told at an episode's end.

    With ``goal_via="observation"``, ``info["is_success"]`` says whether the teacher's goal is
    reached, by ``success``: a distance, a function of (achieved_goal, desired_goal), or None for
    the environment's ``distance_threshold``; the environment's flags for its own goal move to
    ``"<key>_env_goal"``. ``allow_copy=True`` lets a copy of a teacher that another process also
    uses through a saggriac wrapper run here (see :mod:`saggriac.teachers.ownership`); without it
    such a copy is refused, since the copies would each learn alone."""

    def __init__(self, env: gymnasium.Env, selector: Any, *, goal_via: str = "options", min_c: float = -1.0, eps_c: float = -0.05, competence: str = "relative", reach: float | None = None, success: Any = None, allow_copy: bool = False) -> None:
        super().__init__(env)
        _check_goal_space(env.observation_space, "SelectorGoals")
        if goal_via not in GOAL_VIA:
            raise ParameterError(f"The 'goal_via' parameter of SelectorGoals must be one of {', '.join(map(repr, GOAL_VIA))}. Got {goal_via!r} instead.", "goal_via", repr(goal_via))
        _take_selector(selector, env.observation_space["desired_goal"], "SelectorGoals", allow_copy)
        self.selector, self.goal_via, self.allow_copy = selector, goal_via, allow_copy
        self._score = _Scoring(min_c, eps_c, competence, reach)
        self._success = _success_rule(success, env, "SelectorGoals") if goal_via == "observation" else False
        self._goal: np.ndarray | None = None
        self._start: np.ndarray | None = None
        self._open = False

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None) -> tuple[Any, dict[str, Any]]:
        ownership.claim(self.selector, "SelectorGoals", self.allow_copy)
        self._goal = check_goal_shape(np.asarray(self.selector.sample(), dtype=np.float64), self.observation_space["desired_goal"], "SelectorGoals")
        if self.goal_via == "options":
            options = {**(options or {}), "goal": self._goal}
        obs, info = self.env.reset(seed=seed, options=options)
        if self.goal_via == "options":
            check_goal_taken(self._goal, obs, "SelectorGoals", "reset(options={'goal': ...})")
        self._start = np.asarray(obs["achieved_goal"], dtype=np.float64).copy()
        self._open = True
        if self.goal_via == "observation":
            info = _success_for_teacher(info, self._success, self._start, self._goal, "SelectorGoals")
            obs = _goal_in_observation(obs, self._goal, self.observation_space["desired_goal"])
        return obs, info

    def step(self, action: Any) -> tuple[Any, Any, bool, bool, dict[str, Any]]:
        obs, reward, terminated, truncated, info = self.env.step(action)
        if self.goal_via == "observation":
            obs, reward, terminated, info = _step_for_goal(self.env, self._goal, self._success, "SelectorGoals", obs, reward, terminated, info)
        if (terminated or truncated) and self._open:
            c = self._score(self._goal, np.asarray(obs["achieved_goal"], dtype=np.float64), self._start)
            self.selector.update(self._goal, c)
            info = {**info, "competence": c}
            self._open = False
        return obs, reward, terminated, truncated, info


class GoalSlot(gymnasium.Wrapper):
    """Gives a goal environment a ``next_goal`` attribute, read (and cleared) on reset: what
    :class:`VectorSelectorGoals` sets and :class:`saggriac.adapters.sb3.TeacherCallback` hands
    out. With ``goal_via="options"`` the environment's ``reset`` gets it as ``options["goal"]``;
    with ``goal_via="observation"`` it is put in the observations until the next reset, and the
    reward, the end and ``info["is_success"]`` (by ``success``, as in :class:`SelectorGoals`) and
    ``info["distance"]`` follow it (see the module's text). A reset without a next goal keeps the
    environment's own."""

    def __init__(self, env: gymnasium.Env, *, goal_via: str = "options", success: Any = None) -> None:
        super().__init__(env)
        if goal_via not in GOAL_VIA:
            raise ParameterError(f"The 'goal_via' parameter of GoalSlot must be one of {', '.join(map(repr, GOAL_VIA))}. Got {goal_via!r} instead.", "goal_via", repr(goal_via))
        self.goal_via = goal_via
        self.next_goal: np.ndarray | None = None
        self._goal: np.ndarray | None = None
        if goal_via == "observation":
            _check_goal_space(env.observation_space, "GoalSlot")
            self._success = _success_rule(success, env, "GoalSlot")

    def set_next_goal(self, goal: Any) -> None:
        """Set ``next_goal`` (what ``env_method("set_next_goal", g)`` calls through wrappers)."""
        self.next_goal = goal

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None) -> tuple[Any, dict[str, Any]]:
        goal, self.next_goal = self.next_goal, None
        if self.goal_via == "options":
            if goal is not None:
                options = {**(options or {}), "goal": goal}
            return self.env.reset(seed=seed, options=options)
        obs, info = self.env.reset(seed=seed, options=options)
        self._goal = None if goal is None else check_goal_shape(np.asarray(goal, dtype=np.float64), self.observation_space["desired_goal"], "GoalSlot")
        if self._goal is None:
            return obs, info
        info = _success_for_teacher(info, self._success, np.asarray(obs["achieved_goal"], dtype=np.float64), self._goal, "GoalSlot")
        return _goal_in_observation(obs, self._goal, self.observation_space["desired_goal"]), info

    def step(self, action: Any) -> tuple[Any, Any, bool, bool, dict[str, Any]]:
        obs, reward, terminated, truncated, info = self.env.step(action)
        if self._goal is not None:
            obs, reward, terminated, info = _step_for_goal(self.env, self._goal, self._success, "GoalSlot", obs, reward, terminated, info)
        return obs, reward, terminated, truncated, info


class VectorSelectorGoals(gymnasium.vector.VectorWrapper):
    """Goals of every sub-environment of the vector environment ``env``, asked of ``selector`` in
    batches (see the module's text). ``info["competence"]`` holds, after a step, the competence told
    for each sub-environment whose episode ended there (NaN elsewhere)."""

    def __init__(self, env: gymnasium.vector.VectorEnv, selector: Any, *, min_c: float = -1.0, eps_c: float = -0.05, competence: str = "relative", reach: float | None = None, allow_copy: bool = False) -> None:
        super().__init__(env)
        _check_goal_space(env.single_observation_space, "VectorSelectorGoals")
        mode = env.metadata.get("autoreset_mode", gymnasium.vector.AutoresetMode.NEXT_STEP)
        if mode != gymnasium.vector.AutoresetMode.NEXT_STEP:
            raise ParameterError(f"VectorSelectorGoals needs a vector environment that resets on the next step (autoreset_mode=AutoresetMode.NEXT_STEP, Gymnasium's default); this one has {mode}.", "autoreset_mode", repr(mode))
        _take_selector(selector, env.single_observation_space["desired_goal"], "VectorSelectorGoals", allow_copy)
        self.selector, self.allow_copy = selector, allow_copy
        self._score = _Scoring(min_c, eps_c, competence, reach)
        n = env.num_envs
        self._goals = np.zeros((n,) + env.single_observation_space["desired_goal"].shape)
        self._starts = np.zeros_like(self._goals)
        self._restarting = np.zeros(n, dtype=bool)  # reset on this step (autoreset)

    def _hand_out(self, which: np.ndarray) -> None:
        """New goals for the sub-environments ``which``, read on their next reset."""
        ownership.claim(self.selector, "VectorSelectorGoals", self.allow_copy)
        new = sample_batch(self.selector, int(which.sum()))
        space = self.env.single_observation_space["desired_goal"]
        for g in new:
            check_goal_shape(g, space, "VectorSelectorGoals")
        self._goals[which] = new
        values: list[Any] = [None] * self.num_envs
        for i, g in zip(np.flatnonzero(which), new):
            values[i] = g
        self.env.set_attr("next_goal", values)

    def reset(self, *, seed: int | list[int] | None = None, options: dict[str, Any] | None = None) -> tuple[Any, dict[str, Any]]:
        self._hand_out(np.ones(self.num_envs, dtype=bool))
        obs, info = self.env.reset(seed=seed, options=options)
        self._check_taken(obs, np.ones(self.num_envs, dtype=bool))
        self._starts[:] = obs["achieved_goal"]
        self._restarting[:] = False
        return obs, info

    def _check_taken(self, obs: dict[str, Any], which: np.ndarray) -> None:
        for i in np.flatnonzero(which):
            check_goal_taken(self._goals[i], {"desired_goal": np.asarray(obs["desired_goal"])[i]}, f"VectorSelectorGoals (sub-environment {i})", "set_attr('next_goal', ...)")

    def step(self, actions: Any) -> tuple[Any, Any, Any, Any, dict[str, Any]]:
        obs, reward, terminated, truncated, info = self.env.step(actions)
        achieved = np.asarray(obs["achieved_goal"], dtype=np.float64)
        self._check_taken(obs, self._restarting)
        self._starts[self._restarting] = achieved[self._restarting]
        done = (np.asarray(terminated) | np.asarray(truncated)) & ~self._restarting
        comps = np.full(self.num_envs, np.nan)
        if done.any():
            comps[done] = self._score(self._goals[done], achieved[done], self._starts[done])
            _update_batch(self.selector, self._goals[done], comps[done])
            self._hand_out(done)
        self._restarting = done
        return obs, reward, terminated, truncated, {**info, "competence": comps}
