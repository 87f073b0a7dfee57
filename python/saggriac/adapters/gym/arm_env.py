"""saggriac's arms as goal-conditioned Gymnasium environments.

The observation is a dict in the layout of Gymnasium-Robotics' goal environments:
``observation`` (the joint angles), ``achieved_goal`` (the end effector's position) and
``desired_goal`` (the episode's goal). An action is a joint change, bounded by
``max_joint_step`` per joint; it moves the arm exactly as a micro-action of a saggriac run does
(the same arithmetic as the built-in arm, bit for bit). ``compute_reward`` works on batches, for
goal relabelling (hindsight experience replay).

An episode's goal comes from ``reset(options={"goal": g})``, else from the ``next_goal``
attribute (set by a vector wrapper through ``set_attr``), else uniform in the goal box.
"""

from __future__ import annotations

import math
from typing import Any

import gymnasium
import numpy as np
from gymnasium import spaces

from ...bodies.environments import PlanarArm, SpatialArm, joint_step
from ...errors import InputError, ParameterError
from ...values import as_numbers

BODIES = {"planar_arm": PlanarArm, "spatial_arm": SpatialArm}
REWARDS = ("sparse", "dense")
JOINTS = ("limited", "free")
# "normalized": actions in [-1, 1], times max_joint_step; "joint": the joint change itself.
ACTION_SCALES = ("normalized", "joint")
# reset() options this environment reads; vector environments add "reset_mask" themselves.
OPTIONS = ("goal", "theta", "reset_mask")


def _positive(name: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or value <= 0:
        raise ParameterError(f"The '{name}' parameter of GoalArmEnv must be a finite number > 0. Got {value!r} instead.", name, repr(value))
    return float(value)


def _point(name: str, value: Any, dim: int) -> np.ndarray:
    try:
        a = as_numbers(f"'{name}'", value)
    except InputError:
        raise InputError(f"'{name}' must be {dim} finite floats (strings and bools are refused, not converted); got {value!r}.") from None
    if a.shape != (dim,) or not np.all(np.isfinite(a)):
        raise InputError(f"'{name}' must be {dim} finite floats; got {value!r}.")
    return a


def within_limits(name: str, theta: np.ndarray, limit: float) -> np.ndarray:
    """``theta`` if every joint is in [-limit, limit] (a float32 space's rounding let through,
    then clipped), else an InputError: placing a body elsewhere than asked without a word
    would evaluate it at the wrong configuration."""
    slack = limit * 1e-6 + 1e-12
    bad = np.flatnonzero(np.abs(theta) > limit + slack)
    if bad.size:
        i = int(bad[0])
        raise InputError(f"{name} must lie within the joint limits [-{limit:g}, {limit:g}]; joint {i} is {float(theta[i]):g} ({bad.size} joint(s) beyond).")
    return np.clip(theta, -limit, limit)


class GoalArmEnv(gymnasium.Env):
    """A saggriac arm reaching for goals. ``body`` is ``"planar_arm"`` (2-D goals) or
    ``"spatial_arm"`` (3-D); the arm's parameters mean what they mean in :class:`saggriac.Config`.
    ``goal_low``/``goal_high`` bound the goals (default: the box around the arm's reach);
    a goal is reached within ``distance_threshold`` (default: 1 % of the arm's length).
    ``reward_type="sparse"`` gives -1 until the goal is reached and 0 there; ``"dense"`` gives
    minus the distance. ``joints="limited"`` (the default) clips each angle to
    [-``joint_limit``, ``joint_limit``], as saggriac's arms do; ``"free"`` lets each joint turn
    for ever, its angle kept in [-pi, pi) (``joint_limit`` is then not used, and must be left
    unset): an arm with no limit to fold onto, for checking what a deep-RL student's folding onto
    its limits does to a study (docs/rl_curriculum.md, "the fold")."""

    metadata = {"render_modes": ["human", "rgb_array"], "render_fps": 25}

    def __init__(
        self,
        body: str = "planar_arm",
        n_joints: int = 15,
        arm_length: float = 50.0,
        link_lengths: Any = None,
        joint_limit: float | None = None,
        max_joint_step: float = 0.05,
        goal_low: Any = None,
        goal_high: Any = None,
        distance_threshold: float | None = None,
        reward_type: str = "sparse",
        render_mode: str | None = None,
        action_scale: str = "normalized",
        joints: str = "limited",
    ) -> None:
        if body not in BODIES:
            raise ParameterError(f"The 'body' parameter of GoalArmEnv must be one of {', '.join(map(repr, BODIES))}. Got {body!r} instead.", "body", repr(body))
        if isinstance(n_joints, bool) or not isinstance(n_joints, int) or n_joints < 1:
            raise ParameterError(f"The 'n_joints' parameter of GoalArmEnv must be an int >= 1. Got {n_joints!r} instead.", "n_joints", repr(n_joints))
        if link_lengths is not None:
            lengths = list(link_lengths) if not isinstance(link_lengths, (str, bytes)) else None
            if not lengths or any(isinstance(v, bool) or not isinstance(v, (int, float, np.floating)) or not math.isfinite(v) or v <= 0 for v in lengths):
                raise ParameterError(f"The 'link_lengths' parameter of GoalArmEnv must be a list of finite floats > 0. Got {link_lengths!r} instead.", "link_lengths", repr(link_lengths))
        arm_length = _positive("arm_length", arm_length)
        if joints not in JOINTS:
            raise ParameterError(f"The 'joints' parameter of GoalArmEnv must be one of {', '.join(map(repr, JOINTS))}. Got {joints!r} instead.", "joints", repr(joints))
        if joints == "free" and joint_limit is not None:
            raise ParameterError(f"The 'joint_limit' parameter of GoalArmEnv must be left unset with joints='free' (free joints have no limit; their angles are kept in [-pi, pi)). Got {joint_limit!r} instead.", "joint_limit", repr(joint_limit))
        joint_limit = math.pi if joints == "free" else (math.pi / 2 if joint_limit is None else _positive("joint_limit", joint_limit))
        if joint_limit > math.pi:
            raise ParameterError(f"The 'joint_limit' parameter of GoalArmEnv must be at most pi. Got {joint_limit!r} instead.", "joint_limit", repr(joint_limit))
        max_joint_step = _positive("max_joint_step", max_joint_step)
        if reward_type not in REWARDS:
            raise ParameterError(f"The 'reward_type' parameter of GoalArmEnv must be one of {', '.join(map(repr, REWARDS))}. Got {reward_type!r} instead.", "reward_type", repr(reward_type))
        if action_scale not in ACTION_SCALES:
            raise ParameterError(f"The 'action_scale' parameter of GoalArmEnv must be one of {', '.join(map(repr, ACTION_SCALES))}. Got {action_scale!r} instead.", "action_scale", repr(action_scale))
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ParameterError(f"The 'render_mode' parameter of GoalArmEnv must be None, 'human' or 'rgb_array'. Got {render_mode!r} instead.", "render_mode", repr(render_mode))
        self.body = body
        self.joints = joints
        self.arm = BODIES[body](n_joints=n_joints, arm_length=arm_length, link_lengths=link_lengths, joint_limit=joint_limit, max_joint_step=max_joint_step)
        self.reach = float(sum(self.arm.lengths))
        dim = self.arm.task_dim
        n = len(self.arm.lengths)
        low = np.full(dim, -self.reach) if goal_low is None else np.asarray(goal_low, dtype=np.float64)
        high = np.full(dim, self.reach) if goal_high is None else np.asarray(goal_high, dtype=np.float64)
        for name, v in (("goal_low", low), ("goal_high", high)):
            if v.shape != (dim,) or not np.all(np.isfinite(v)):
                raise ParameterError(f"The '{name}' parameter of GoalArmEnv must be {dim} finite floats for body {body!r}. Got {v.tolist()!r} instead.", name, repr(v.tolist()))
        if not np.all(low < high):
            raise ParameterError(f"The 'goal_low' parameter of GoalArmEnv must be below 'goal_high' in every dimension. Got {low.tolist()} and {high.tolist()}.", "goal_low", repr(low.tolist()))
        self.distance_threshold = 0.01 * self.reach if distance_threshold is None else _positive("distance_threshold", distance_threshold)
        self.reward_type = reward_type
        self.render_mode = render_mode
        self._view: Any = None
        self.goal_space = spaces.Box(low, high, dtype=np.float64)
        self.action_scale = action_scale
        if action_scale == "normalized":
            # What deep-RL libraries expect (SB3's checker asks for it): [-1, 1] in float32, one
            # unit being max_joint_step.
            self.action_space = spaces.Box(-1.0, 1.0, (n,), dtype=np.float32)
        else:
            self.action_space = spaces.Box(-max_joint_step, max_joint_step, (n,), dtype=np.float64)
        self.observation_space = spaces.Dict(
            {
                "observation": spaces.Box(-joint_limit, joint_limit, (n,), dtype=np.float64),
                "achieved_goal": spaces.Box(-self.reach, self.reach, (dim,), dtype=np.float64),
                "desired_goal": spaces.Box(low, high, dtype=np.float64),
            }
        )
        self.next_goal: np.ndarray | None = None
        self._theta, self._x = self.arm.reset()
        self._goal = (low + high) / 2

    def _obs(self) -> dict[str, np.ndarray]:
        return {"observation": self._theta.copy(), "achieved_goal": self._x.copy(), "desired_goal": self._goal.copy()}

    def _info(self) -> dict[str, Any]:
        d = float(np.linalg.norm(self._x - self._goal))
        return {"distance": d, "is_success": d <= self.distance_threshold}

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
        super().reset(seed=seed)
        options = dict(options or {})
        unknown = sorted(set(options) - set(OPTIONS))
        if unknown:
            raise InputError(f"GoalArmEnv.reset() does not know the option(s) {unknown}; it reads {list(OPTIONS[:2])}.")
        dim = self.goal_space.shape[0]
        if options.get("goal") is not None:
            goal = _point("options['goal']", options["goal"], dim)
        elif self.next_goal is not None:
            goal = _point("next_goal", self.next_goal, dim)
        else:
            goal = self.np_random.uniform(self.goal_space.low, self.goal_space.high)
        self.next_goal = None
        lo, hi = self.goal_space.low, self.goal_space.high
        if np.any(goal < lo) or np.any(goal > hi):
            # Outside the goal box the observation would leave observation_space.
            raise InputError(f"GoalArmEnv.reset(): the goal {goal.tolist()} lies outside the environment's goal box [{lo.tolist()}, {hi.tolist()}]; a teacher must choose goals in that box.")
        if options.get("theta") is not None:
            theta = within_limits("GoalArmEnv.reset(options={'theta': ...})", _point("options['theta']", options["theta"], len(self.arm.lengths)), self.arm.joint_limit)
            self._theta, self._x = self.arm.reset(options={"theta": theta})
        else:
            self._theta, self._x = self.arm.reset()
        self._goal = goal
        if self.render_mode == "human":
            self.render()
        return self._obs(), self._info()

    def step(self, action: Any) -> tuple[dict[str, np.ndarray], float, bool, bool, dict[str, Any]]:
        try:
            a = as_numbers("GoalArmEnv.step()'s action", action)
        except InputError:
            raise InputError(f"GoalArmEnv.step() needs {self.action_space.shape[0]} finite joint changes (numbers: strings and bools are refused, not converted); got {action!r}.") from None
        if a.shape != self.action_space.shape or not np.all(np.isfinite(a)):
            raise InputError(f"GoalArmEnv.step() needs {self.action_space.shape[0]} finite joint changes; got {action!r}.")
        if self.action_scale == "normalized":
            a = a * self.arm.max_joint_step
        if self.joints == "free":
            # The arm's own micro-action without its clip, then each angle wrapped into [-pi, pi).
            theta = joint_step(self._theta, a, self.arm.max_joint_step, math.inf)
            self._theta = np.mod(theta + math.pi, 2 * math.pi) - math.pi
            self.arm.theta = self._theta.copy()
            self._x = self.arm.forward(self._theta)
        else:
            self._theta, self._x = self.arm.step(a)
        info = self._info()
        reward = float(self.compute_reward(self._x, self._goal, info))
        terminated = bool(self.compute_terminated(self._x, self._goal, info))
        truncated = bool(self.compute_truncated(self._x, self._goal, info))
        if self.render_mode == "human":
            self.render()
        return self._obs(), reward, terminated, truncated, info

    def compute_reward(self, achieved_goal: Any, desired_goal: Any, info: Any) -> Any:
        """Reward of reaching ``achieved_goal`` when ``desired_goal`` was wanted; both may be
        batches (one point per row), for relabelling. ``info`` is not read."""
        a, g = as_numbers("achieved_goal", achieved_goal), as_numbers("desired_goal", desired_goal)
        dim = self.goal_space.shape[0]
        # One point each, or batches of the same number of rows (or one point against a batch).
        ok = a.ndim in (1, 2) and g.ndim in (1, 2) and a.shape[-1] == dim and g.shape[-1] == dim and (a.ndim == 1 or g.ndim == 1 or a.shape == g.shape)
        if not ok:
            raise InputError(
                f"GoalArmEnv.compute_reward() needs achieved_goal and desired_goal of shape ({dim},) or (n, {dim}) with the same n; "
                f"got achieved_goal of shape {a.shape} and desired_goal of shape {g.shape}."
            )
        d = np.linalg.norm(a - g, axis=-1)
        if self.reward_type == "dense":
            return -d
        return -(d > self.distance_threshold).astype(np.float64)

    def set_next_goal(self, goal: Any) -> None:
        """The goal of the next episode (read on reset): a method, so that vector environments'
        ``env_method`` reaches it through any wrappers (``set_attr`` sets the outermost one)."""
        self.next_goal = None if goal is None else _point("next_goal", goal, self.goal_space.shape[0])

    def compute_terminated(self, achieved_goal: Any, desired_goal: Any, info: Any) -> Any:
        """Whether the episode ends (Gymnasium-Robotics' goal-environment API): never, as in
        Fetch, since reaching a goal is a state to hold; ``TimeLimit`` ends episodes by
        truncation. Batches give one False per row."""
        a = np.asarray(achieved_goal, dtype=np.float64)
        return False if a.ndim <= 1 else np.zeros(a.shape[:-1], dtype=bool)

    def compute_truncated(self, achieved_goal: Any, desired_goal: Any, info: Any) -> Any:
        """Whether the episode is cut short by the environment itself: never (the step limit is
        ``TimeLimit``'s). Batches give one False per row."""
        a = np.asarray(achieved_goal, dtype=np.float64)
        return False if a.ndim <= 1 else np.zeros(a.shape[:-1], dtype=bool)

    def render(self) -> np.ndarray | None:
        """``"rgb_array"``: an image (H, W, 3) of the arm, its reach, the goal and the distance
        threshold (a 3-D arm seen from above and from the side). ``"human"``: the same in a
        matplotlib window, updated at every step."""
        if self.render_mode is None:
            gymnasium.logger.warn("GoalArmEnv.render() was called without a render_mode; pass render_mode='rgb_array' or 'human' to gymnasium.make.")
            return None
        from .render import ArmView

        if self._view is None:
            self._view = ArmView(self, interactive=self.render_mode == "human")
        return self._view.draw(self._theta, self._goal)

    def close(self) -> None:
        if self._view is not None:
            self._view.close()
            self._view = None
