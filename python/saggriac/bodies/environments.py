"""Environments written in Python, and the typed spaces that describe their bounds.

The run loop (in Rust) needs only this from an environment, Gymnasium-style:

* ``joint_space``: a :class:`Box` of the joint angles (symmetric limits, one per joint);
* ``reset(*, seed=None, options=None) -> (theta, x)``: back to rest, or, with
  ``options={"theta": theta}``, placed at once in that configuration (a whole movement in the
  episodic paradigm; the evaluation also uses it to measure test configurations). ``seed`` comes
  once, before the run, from the run's root seed;
* ``step(dtheta) -> (theta, x)``: one micro-action; the loop reads the realised change from the
  returned ``theta``.

``theta`` has one float per joint, ``x`` is the end-effector position: one float per dimension
of the task space (1 to 3; the run's goal space ``goal_low``/``goal_high`` has the same
dimension). Optional: ``action_space`` and ``task_space`` boxes, for documentation and checks.
:func:`saggriac.testing.check_environment` tells whether an object conforms.
"""

from __future__ import annotations

import math
from typing import Any, Protocol, runtime_checkable

import numpy as np

from ..errors import InputError, ParameterError
from ..values import as_numbers


class Box:
    """A box of floats: ``low <= v <= high`` elementwise (a minimal ``gymnasium.spaces.Box``)."""

    def __init__(self, low: Any, high: Any, shape: tuple[int, ...] | None = None) -> None:
        lo = np.asarray(low, dtype=np.float64)
        hi = np.asarray(high, dtype=np.float64)
        if shape is not None:
            lo = np.broadcast_to(lo, shape).copy()
            hi = np.broadcast_to(hi, shape).copy()
        if lo.shape != hi.shape or not np.all(np.isfinite(lo)) or not np.all(np.isfinite(hi)) or not np.all(lo <= hi):
            raise ValueError(f"Box needs finite low <= high of one shape; got low={lo!r}, high={hi!r}.")
        self.low, self.high = lo, hi
        self.shape = lo.shape
        self.dtype = np.dtype(np.float64)

    def contains(self, v: Any) -> bool:
        a = np.asarray(v, dtype=np.float64)
        return a.shape == self.shape and bool(np.all(a >= self.low) and np.all(a <= self.high))

    def sample(self, rng: np.random.Generator) -> np.ndarray:
        return rng.uniform(self.low, self.high)

    def __repr__(self) -> str:
        return f"Box(low={self.low.tolist()}, high={self.high.tolist()})"


@runtime_checkable
class Environment(Protocol):
    joint_space: Box

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None) -> tuple[np.ndarray, np.ndarray]: ...

    def step(self, dtheta: np.ndarray) -> tuple[np.ndarray, np.ndarray]: ...


def joint_vector(name: str, value: Any, n: int) -> list[float]:
    """``value`` as n finite floats, or an InputError naming ``name``: a wrong length, a
    non-finite value, strings or bools are refused before a body's state changes."""
    try:
        arr = as_numbers(name, value)
    except InputError:
        raise InputError(f"{name} must be {n} finite floats (one per joint); got {value!r}.") from None
    out = arr.tolist() if arr.shape == (n,) else None
    # Checked on the list: on a body's every micro-action this is cheaper than numpy's isfinite.
    if out is None or not all(map(math.isfinite, out)):
        raise InputError(f"{name} must be {n} finite floats (one per joint); got {np.array2string(arr, threshold=8)} (shape {arr.shape}).")
    return out


def within_limits(name: str, theta: list[float], limit: float) -> list[float]:
    """``theta`` (finite floats, as :func:`joint_vector` gives them) if every joint is in
    ``[-limit, limit]``, else an InputError naming the first joint beyond: a placement is taken
    as asked or refused, never moved to another configuration without a word. A float32 space's
    rounding is let through and clipped (the wording is GoalArmEnv's and GymBody's)."""
    slack = limit * 1e-6 + 1e-12
    bad = [i for i, v in enumerate(theta) if abs(v) > limit + slack]
    if bad:
        i = bad[0]
        raise InputError(f"{name} must lie within the joint limits [-{limit:g}, {limit:g}]; joint {i} is {theta[i]:g} ({len(bad)} joint(s) beyond).")
    return [min(max(v, -limit), limit) for v in theta]


def joint_step(theta: Any, dtheta: Any, max_joint_step: float, limit: float) -> np.ndarray:
    """The built-in arms' micro-action: ``dtheta`` scaled down (direction kept) so that no joint
    moves more than ``max_joint_step``, added to ``theta``, clipped to ``[-limit, limit]``; the
    core's arithmetic, operation for operation. A ``dtheta`` of the wrong length, or not finite,
    is refused (the caller's state is not touched)."""
    d = joint_vector("dtheta", dtheta, len(theta))
    max_abs = max((abs(v) for v in d), default=0.0)
    scale = max_joint_step / max_abs if max_abs > max_joint_step else 1.0
    return np.array([min(max(float(t) + v * scale, -limit), limit) for t, v in zip(theta, d)])


class _SerialArm:
    """What the two arms share: joints, limits, rest pose, micro-actions."""

    task_dim = 2

    def __init__(self, n_joints: int = 15, arm_length: float = 50.0, link_lengths: Any = None, joint_limit: float = math.pi / 2, max_joint_step: float = 0.05) -> None:
        owner = type(self).__name__

        def number(name: str, v: Any, ok: Any, rule: str) -> float:
            if isinstance(v, bool) or not isinstance(v, (int, float, np.integer, np.floating)) or not math.isfinite(v) or not ok(v):
                raise ParameterError(f"The '{name}' parameter of {owner} must be {rule}. Got {v!r} instead.", name, repr(v))
            return float(v)

        if link_lengths is None:
            if isinstance(n_joints, bool) or not isinstance(n_joints, (int, np.integer)) or not 1 <= n_joints <= 10_000:
                raise ParameterError(f"The 'n_joints' parameter of {owner} must be an int in [1, 10000]. Got {n_joints!r} instead.", "n_joints", repr(n_joints))
            length = number("arm_length", arm_length, lambda v: v > 0, "a finite float > 0")
            self.lengths = [length / int(n_joints)] * int(n_joints)
            self._reach = length
        else:
            self.lengths = [number("link_lengths", v, lambda v: v > 0, "finite floats > 0") for v in np.atleast_1d(np.asarray(link_lengths, dtype=object))]
            if not self.lengths:
                raise ParameterError(f"The 'link_lengths' parameter of {owner} must be a non-empty list of floats > 0. Got {link_lengths!r} instead.", "link_lengths", repr(link_lengths))
            self._reach = float(sum(self.lengths))
        joint_limit = number("joint_limit", joint_limit, lambda v: v > 0, "a finite float > 0")
        max_joint_step = number("max_joint_step", max_joint_step, lambda v: v > 0, "a finite float > 0")
        n = len(self.lengths)
        self.joint_limit = float(joint_limit)
        self.max_joint_step = float(max_joint_step)
        self.joint_space = Box(-self.joint_limit, self.joint_limit, (n,))
        self.action_space = Box(-self.max_joint_step, self.max_joint_step, (n,))
        reach = sum(self.lengths)
        self.task_space = Box(-reach, reach, (self.task_dim,))
        self.theta = np.zeros(n)

    @property
    def reach(self) -> float:
        """The radius of the ball about the origin (the base) that the arm reaches, as
        ``Config.reach`` gives it: a run scales its length parameters and places its test goals
        by it (saggriac.bodies.scale)."""
        return self._reach

    def forward(self, theta: Any) -> np.ndarray:
        raise NotImplementedError

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None) -> tuple[np.ndarray, np.ndarray]:
        lim = self.joint_limit
        if options and "theta" in options:
            name = f"{type(self).__name__}.reset(options={{'theta': ...}})"
            self.theta = np.array(within_limits(name, joint_vector(name, options["theta"], len(self.lengths)), lim))
        else:
            self.theta = np.zeros(len(self.lengths))
        return self.theta.copy(), self.forward(self.theta)

    def step(self, dtheta: Any) -> tuple[np.ndarray, np.ndarray]:
        self.theta = joint_step(self.theta, dtheta, self.max_joint_step, self.joint_limit)
        return self.theta.copy(), self.forward(self.theta)


class PlanarArm(_SerialArm):
    """The paper's planar arm in pure Python: the built-in arm's arithmetic, operation for
    operation, so both give the same trajectory bit for bit. A starting point for your own
    bodies, and the reference the tests compare the Rust arm with.

    A micro-action is scaled down (direction kept) so that no joint moves more than
    ``max_joint_step``, then the angles are clipped to ``[-joint_limit, joint_limit]``.
    """

    task_dim = 2

    def forward(self, theta: Any) -> np.ndarray:
        phi, x, y = 0.0, 0.0, 0.0
        for length, t in zip(self.lengths, theta):
            phi += float(t)
            x += length * math.cos(phi)
            y += length * math.sin(phi)
        return np.array([x, y])


class SpatialArm(_SerialArm):
    """The arm in space (``body="spatial_arm"``) in pure Python, bit-identical to the built-in
    one. Joint i turns the link frame about its own z axis (yaw) for even i and its own y axis
    (pitch) for odd i; each link extends along the frame's x axis. Rest pose: straight along +x.
    The task space is (x, y, z).
    """

    task_dim = 3

    def forward(self, theta: Any) -> np.ndarray:
        e0, e1, e2 = [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]
        x = [0.0, 0.0, 0.0]
        for i, (length, t) in enumerate(zip(self.lengths, theta)):
            s, c = math.sin(float(t)), math.cos(float(t))
            if i % 2 == 0:
                e0, e1 = [c * a + s * b for a, b in zip(e0, e1)], [c * b - s * a for a, b in zip(e0, e1)]
            else:
                e0, e2 = [c * a - s * b for a, b in zip(e0, e2)], [s * a + c * b for a, b in zip(e0, e2)]
            x = [xk + length * ek for xk, ek in zip(x, e0)]
        return np.array(x)
