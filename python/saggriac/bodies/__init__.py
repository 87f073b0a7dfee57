"""Bodies: what a learner moves and how its size is known.

``environments`` (the protocol a body follows and saggriac's own arms, ``PlanarArm`` and
``SpatialArm``), ``mujoco_arm`` (an arm read out of a MuJoCo model, with the ``mujoco`` extra), ``scale`` (a user's body measured: its reach and the lengths that follow it) and ``reachable``
(the task space a built-in body reaches, for the evaluation and the figures).

Only ``environments`` loads with the package, and the Pusher's arm kept as numbers
(``PUSHER_CHAIN``, the ``pusher`` preset's: ``saggriac.config.presets``).
"""

from importlib import import_module
from typing import Any

from .environments import Box, Environment, PlanarArm, SpatialArm
from ..config.presets import PUSHER_CHAIN, PUSHER_SCALE

_LAZY = {"MujocoArm": "mujoco_arm", "pusher_arm": "mujoco_arm", "ReachableSet": "reachable", "BodyScale": "scale", "ReachWarning": "scale", "body_scale": "scale"}


def __getattr__(name: str) -> Any:
    if name not in _LAZY:
        raise AttributeError(f"module 'saggriac.bodies' has no attribute {name!r}")
    value = getattr(import_module(f".{_LAZY[name]}", __name__), name)
    globals()[name] = value
    return value


__all__ = ["Box", "Environment", "PlanarArm", "SpatialArm", "PUSHER_CHAIN", "PUSHER_SCALE", *_LAZY]
