"""The presets: the paper's experiments and the tasks beyond it, as values of :class:`Config`.

The ``pusher`` preset's body is read out of a robot model another package ships, kept here as
numbers so that the preset runs without that package (and without any call into it per
micro-action).

``PUSHER_CHAIN`` is the 7-joint arm of Gymnasium's MuJoCo Pusher (``pusher_v5.xml``, Gymnasium
1.4.0), ``saggriac.bodies.mujoco_arm.pusher_chain()``: its shoulder at the origin and its
lengths scaled by ``PUSHER_SCALE`` so that it reaches 50, the length of the paper's arm, and every
task-space parameter keeps the meaning it has for that arm (one unit is 0.821 / 50 m = 1.642 cm).
One row per joint, from the shoulder to the wrist: the body's position and orientation
(quaternion w, x, y, z) in the previous joint's frame, the hinge's anchor and axis, its range
(radians); then the end effector (``tips_arm``). ``tests/bodies/test_mujoco_arm.py`` checks these numbers
against the model and the kinematics against ``mj_kinematics``.
"""

from __future__ import annotations

import math
from typing import Any

#: Model metres to the units in which the Pusher's arm reaches 50 (its links: 0.1 + 0.4 + 0.321 m).
PUSHER_SCALE = 50.0 / 0.821

# fmt: off
PUSHER_CHAIN: tuple[float, ...] = (
    0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, -2.2854, 1.714602,
    6.090133982947625, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, -0.5236, 1.3963,
    0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -1.5, 1.7,
    24.3605359317905, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, -2.3213, 0.0,
    0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -1.5, 1.5,
    19.549330085261875, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, -1.094, 0.0,
    0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -1.5, 1.5,
    0.0, 0.0, 0.0,
)
# fmt: on


# The paper's experiments (section IV.B); every other value is our documented choice.
PRESETS: dict[str, dict[str, Any]] = {
    "exp1": dict(n_steps=50_000, goal_low=(0.0, -50.0), goal_high=(50.0, 50.0), q=20),
    "exp2": dict(n_steps=200_000, goal_low=(0.0, -150.0), goal_high=(150.0, 150.0), q=100),
    # The task explauto's SAGG-RIAC tutorial runs: episodic, 15 joints, limits +-pi, goals in
    # [-50, 50]^2 (test goals: the reachable disk of radius 50).
    "explauto": dict(
        paradigm="episodic",
        n_steps=50_000,
        joint_limit=math.pi,
        goal_low=(-50.0, -50.0),
        goal_high=(50.0, 50.0),
        # The distance itself, not eq. 7 against a start every movement shares (rest): chosen
        # by the sensitivity study (docs/sensitivity.md), 4 % lower final error for SAGG-RIAC.
        competence="absolute",
    ),
    # Beyond the paper: experiment 1 with the arm in space. The goal space is the box around
    # the half ball in front of the base, x >= 0 (test goals: that half ball, radius 50).
    "arm3d": dict(
        body="spatial_arm",
        n_steps=50_000,
        goal_low=(0.0, -50.0, -50.0),
        goal_high=(50.0, 50.0, 50.0),
        q=20,
    ),
    # Beyond the paper: the 7-joint arm of Gymnasium's MuJoCo Pusher, natively (saggriac.bodies;
    # docs/mujoco.md), shoulder at the origin, scaled to reach 50 as the paper's arm does. Its
    # joints span their ranges in [-1, 1]; a micro-action moves each by at most 2 % of its
    # half-range. The goal box, the cube of side 120 around the shoulder, is wider than the
    # reach: about a fifth of it is reachable.
    "pusher": dict(
        body="chain",
        chain=PUSHER_CHAIN,
        joint_limit=1.0,
        max_joint_step=0.02,
        n_steps=50_000,
        goal_low=(-60.0, -60.0, -60.0),
        goal_high=(60.0, 60.0, 60.0),
        q=20,
    ),
}

__all__ = ["PRESETS", "PUSHER_CHAIN", "PUSHER_SCALE"]
