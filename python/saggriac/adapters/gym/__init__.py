"""saggriac and Gymnasium (the optional extra ``pip install "saggriac[gymnasium]"``).

``import saggriac.adapters.gym`` registers saggriac's arms as goal-conditioned environments, so that
``gymnasium.make("saggriac/PlanarArm-v0")`` works (``gymnasium.make("saggriac.adapters.gym:saggriac/PlanarArm-v0")``
imports this module itself):

* ``saggriac/PlanarArm-v0``: the paper's 15-joint planar arm, goals in the box around its reach;
* ``saggriac/PlanarArmExp1-v0``, ``saggriac/PlanarArmExp2-v0``: the same arm with the goal
  spaces S' of the paper's experiments 1 ([0, 50] x [-50, 50]) and 2 ([0, 150] x [-150, 150]);
* ``saggriac/SpatialArm-v0``: the 15-joint arm in space, 3-D goals.

Episodes end by truncation after 100 steps (``max_episode_steps``). Also here:
:class:`GymBody` (any Gymnasium environment as a saggriac body), :class:`SelectorGoals` and
:class:`VectorSelectorGoals` (a saggriac selector choosing the episodes' goals). See docs/gymnasium.md.
"""

from __future__ import annotations

try:
    import gymnasium
except ImportError:  # pragma: no cover - depends on the installation
    raise ImportError('saggriac.adapters.gym needs Gymnasium: pip install "saggriac[gymnasium]"') from None

from .arm_env import GoalArmEnv
from .body import GymBody
from .goals import GoalSlot, SelectorGoals, VectorSelectorGoals

MAX_EPISODE_STEPS = 100

ENVIRONMENTS = {
    "saggriac/PlanarArm-v0": {"body": "planar_arm"},
    "saggriac/PlanarArmExp1-v0": {"body": "planar_arm", "goal_low": (0.0, -50.0), "goal_high": (50.0, 50.0)},
    "saggriac/PlanarArmExp2-v0": {"body": "planar_arm", "goal_low": (0.0, -150.0), "goal_high": (150.0, 150.0)},
    "saggriac/SpatialArm-v0": {"body": "spatial_arm"},
}


def _register() -> None:
    for env_id, kwargs in ENVIRONMENTS.items():
        if env_id not in gymnasium.registry:
            gymnasium.register(env_id, entry_point="saggriac.adapters.gym.arm_env:GoalArmEnv", kwargs=kwargs, max_episode_steps=MAX_EPISODE_STEPS)


_register()

__all__ = ["GoalArmEnv", "GymBody", "SelectorGoals", "VectorSelectorGoals", "GoalSlot", "ENVIRONMENTS", "MAX_EPISODE_STEPS"]
