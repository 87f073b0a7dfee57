"""Any Gymnasium environment as a saggriac body (the protocol of ``saggriac.bodies.environments``).

saggriac's learner needs joint angles, the end effector's position and a way to change the
joints by a small amount. A Gymnasium environment has observations and actions of its own
meaning, so :class:`GymBody` is told how to read and how to move:

* ``theta(env, obs)`` and ``position(env, obs)``: the joint angles and the end effector, from the
  latest observation or from the environment's state (``env`` is the environment given);
* how to move, one of two ways:
  - by default, ``env.step(dtheta)``: for environments whose action is a joint change (such as
    ``saggriac/PlanarArm-v0``). The environment bounds the change itself;
  - ``set_joints(env, theta) -> obs``: put the joints at ``theta`` directly (kinematics only, as
    saggriac's own arms; for a torque- or velocity-controlled simulator). GymBody then bounds the
    change as the built-in arms do: scaled down (direction kept) so that no joint moves more than
    ``max_joint_step``, then clipped to the limits;
* ``place(env, theta) -> obs``: put the body in configuration ``theta`` at once (the episodic
  paradigm and the evaluation use it). Default: ``set_joints`` if given, else a reset with
  ``options={"theta": theta}``.

``reach`` (optional): the radius of the ball about the origin the end effector reaches, if you
know it; else saggriac measures the body before a run (saggriac.bodies.scale).

Joint limits must be symmetric and equal, ``[-joint_limit, joint_limit]`` (the core's rule);
map other ranges in ``theta`` and ``set_joints``/``place``. Episode ends (terminated, truncated) are ignored: saggriac's learning is one long life.
"""

from __future__ import annotations

import math
from typing import Any, Callable

import numpy as np

from ...bodies.environments import Box, joint_step, joint_vector
from .arm_env import within_limits
from ...errors import InputError, ParameterError

Reader = Callable[[Any, Any], Any]


def _reset_to(env: Any, theta: np.ndarray) -> Any:
    return env.reset(options={"theta": theta})[0]


class GymBody:
    """A saggriac body backed by the Gymnasium environment ``env``; see the module's text for
    ``theta``, ``position``, ``set_joints`` and ``place``."""

    def __init__(
        self,
        env: Any,
        *,
        theta: Reader,
        position: Reader,
        joint_limit: float,
        max_joint_step: float,
        set_joints: Callable[[Any, np.ndarray], Any] | None = None,
        place: Callable[[Any, np.ndarray], Any] | None = None,
        reach: float | None = None,
    ) -> None:
        for name, fn in (("theta", theta), ("position", position), ("set_joints", set_joints), ("place", place)):
            if fn is not None and not callable(fn):
                raise ParameterError(f"The '{name}' parameter of GymBody must be a function. Got {fn!r} instead.", name, repr(fn))
        for name, v in (("joint_limit", joint_limit), ("max_joint_step", max_joint_step)):
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v <= 0:
                raise ParameterError(f"The '{name}' parameter of GymBody must be a finite number > 0. Got {v!r} instead.", name, repr(v))
        if reach is not None and (isinstance(reach, bool) or not isinstance(reach, (int, float)) or not math.isfinite(reach) or reach <= 0):
            raise ParameterError(f"The 'reach' parameter of GymBody must be a finite number > 0 or None (measured). Got {reach!r} instead.", "reach", repr(reach))
        # Declared only when given: saggriac.bodies.scale measures a body without the attribute.
        if reach is not None:
            self.reach = float(reach)
        self.env = env
        self._theta_of, self._position_of = theta, position
        self._set_joints = set_joints
        self._place = place or set_joints or _reset_to
        self.joint_limit, self.max_joint_step = float(joint_limit), float(max_joint_step)
        obs, _ = env.reset()
        self.theta = self._read_theta(obs)
        x = self._read_position(obs)
        n = len(self.theta)
        self.joint_space = Box(-self.joint_limit, self.joint_limit, (n,))
        self.action_space = Box(-self.max_joint_step, self.max_joint_step, (n,))
        self.task_dim = len(x)

    def __repr__(self) -> str:
        env = getattr(getattr(self.env, "spec", None), "id", None) or type(self.env).__name__
        moves = "set_joints" if self._set_joints is not None else "env.step"
        reach = f", reach={self.reach:g}" if hasattr(self, "reach") else ""
        return f"GymBody({env}, joints={len(self.theta)}, task_dim={self.task_dim}, joint_limit={self.joint_limit:g}, max_joint_step={self.max_joint_step:g}, moves by {moves}{reach})"

    def _read_theta(self, obs: Any) -> np.ndarray:
        t = np.asarray(self._theta_of(self.env, obs), dtype=np.float64).reshape(-1)
        if t.size == 0 or not np.all(np.isfinite(t)):
            raise InputError(f"GymBody's theta() must return finite joint angles; got {t.tolist()}.")
        return t

    def _read_position(self, obs: Any) -> np.ndarray:
        x = np.asarray(self._position_of(self.env, obs), dtype=np.float64).reshape(-1)
        if not 1 <= x.size <= 3 or not np.all(np.isfinite(x)):
            raise InputError(f"GymBody's position() must return 1 to 3 finite coordinates; got {x.tolist()}.")
        return x

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None) -> tuple[np.ndarray, np.ndarray]:
        if options and "theta" in options:
            if seed is not None:
                self.env.reset(seed=seed)
            theta = joint_vector("GymBody.reset(options={'theta': ...})", options["theta"], len(self.theta))
            obs = self._place(self.env, within_limits("GymBody.reset(options={'theta': ...})", np.asarray(theta), self.joint_limit))
        else:
            obs, _ = self.env.reset(seed=seed)
        self.theta = self._read_theta(obs)
        return self.theta.copy(), self._read_position(obs)

    def step(self, dtheta: Any) -> tuple[np.ndarray, np.ndarray]:
        if self._set_joints is None:
            obs = self.env.step(dtheta)[0]
        else:
            # The built-in arms' arithmetic, so that a kinematic body moves as they do.
            obs = self._set_joints(self.env, joint_step(self.theta, dtheta, self.max_joint_step, self.joint_limit))
        self.theta = self._read_theta(obs)
        return self.theta.copy(), self._read_position(obs)
