"""Bodies read out of robot models that other packages ship, kept here as numbers so that
presets run without those packages (and without any call into them per micro-action).

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

__all__ = ["PUSHER_CHAIN", "PUSHER_SCALE"]
