"""The size of a user's body, which a run's length parameters and test goals follow.

saggriac's own arms know their reach (the ball of that radius about the origin, their base). A
body that declares ``reach`` (a float > 0: the radius of the ball about the origin it reaches,
as :class:`saggriac.environments.PlanarArm` does) is taken at its word. Any other body is
measured: it is placed at :data:`CLOUD_SIZE` configurations drawn uniformly in its joint space
(one fixed generator, so the measure is the body's, not the run's), and

* its **reach** is half the largest distance between two of the positions it took (the
  diameter is searched among the positions farthest along :data:`DIRECTIONS` fixed directions,
  which finds it within a fraction of a percent);
* its **test goals** are drawn from those positions, spread evenly over the grid cells of the
  goal box they fall in, wherever the body's base is (as for a MuJoCo chain).

``v``, ``eps_max`` and ``eval_tolerance`` left unset are then that reach over 100, 500 and 5000
(:data:`saggriac.config.LENGTH_DIVISORS`). Uniform configurations seldom stretch a body with
many joints, so a measured reach is a lower bound, the closer the fewer the joints: declare
``reach`` when you know it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .errors import ConformanceError
from .seeding import FIXED

#: Placements made to measure a body without a declared reach.
CLOUD_SIZE = 10_000
#: Directions along which the extreme positions are kept for the diameter, per dimension.
DIRECTIONS = 256
#: The generator of the configurations (fixed: a body's size does not depend on the run's seed).
CLOUD_SEED = FIXED["body_measure"]


@dataclass
class BodyScale:
    """A body's reach and where it came from: ``"declared"`` (its ``reach`` attribute) or
    ``"measured"`` (then ``configs`` and ``positions`` hold the placements)."""

    reach: float
    source: str
    configs: np.ndarray | None = None
    positions: np.ndarray | None = None

    def summary(self, lengths: dict[str, float]) -> dict[str, Any]:
        """What run.json records: the reach, its source, and the lengths the run used."""
        return {"reach": self.reach, "source": self.source, **lengths}


def declared_reach(env: Any) -> float | None:
    """The ``reach`` a body declares, checked; None if it declares none."""
    r = getattr(env, "reach", None)
    if r is None:
        return None
    if isinstance(r, bool) or not isinstance(r, (int, float, np.floating)) or not math.isfinite(r) or r <= 0:
        raise ConformanceError(f"environment.reach must be a finite float > 0 (the radius of the ball about the origin that the body reaches); got {r!r}.")
    return float(r)


def _directions(m: int) -> np.ndarray:
    if m == 1:
        return np.ones((1, 1))
    if m == 2:
        a = np.pi * np.arange(DIRECTIONS) / DIRECTIONS
        return np.stack([np.cos(a), np.sin(a)], axis=1)
    # Fibonacci points on a half sphere (a direction and its opposite give the same extremes).
    i = np.arange(DIRECTIONS) + 0.5
    z = i / DIRECTIONS
    phi = np.pi * (1 + 5**0.5) * i
    r = np.sqrt(1 - z**2)
    d = np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)
    return np.concatenate([d, np.zeros((DIRECTIONS, m - 3))], axis=1) if m > 3 else d


def diameter(points: np.ndarray) -> float:
    """The largest distance between two of ``points`` (k, m), searched among the points
    farthest along fixed directions (exact in 1-D)."""
    proj = points @ _directions(points.shape[1]).T
    idx = np.unique(np.concatenate([proj.argmax(axis=0), proj.argmin(axis=0)]))
    c = points[idx]
    return float(np.sqrt(((c[:, None, :] - c[None, :, :]) ** 2).sum(axis=-1).max()))


def measure(env: Any, low: np.ndarray, high: np.ndarray, m: int) -> BodyScale:
    """Place ``env`` at CLOUD_SIZE uniform configurations in [low, high] and measure its reach
    (``m``: the task space's dimension)."""
    rng = np.random.default_rng(CLOUD_SEED)
    configs = rng.uniform(low, high, (CLOUD_SIZE, len(low)))
    positions = np.empty((CLOUD_SIZE, m))
    for i, t in enumerate(configs):
        out = env.reset(options={"theta": t})
        try:
            x = np.asarray(out[1], dtype=np.float64)
        except (TypeError, ValueError, IndexError, KeyError):
            raise ConformanceError(f"environment.reset(options={{'theta': t}}) must return a pair (theta, x); got {out!r}.") from None
        if x.shape != (m,) or not np.all(np.isfinite(x)):
            raise ConformanceError(f"environment.reset(options={{'theta': t}}) must return x as {m} finite floats (the goal space is {m}-D); got {x.tolist()!r} at theta = {t.tolist()}.")
        positions[i] = x
    d = diameter(positions)
    if not d > 0:
        raise ConformanceError(f"The environment's end effector did not move over {CLOUD_SIZE} configurations across its joint space (always at {positions[0].tolist()}): saggriac cannot learn to reach with it.")
    return BodyScale(reach=d / 2, source="measured", configs=configs, positions=positions)


def body_scale(env: Any, low: np.ndarray, high: np.ndarray, m: int) -> BodyScale:
    """The declared reach of ``env`` if it has one, else its measured one."""
    r = declared_reach(env)
    return BodyScale(reach=r, source="declared") if r is not None else measure(env, low, high, m)


__all__ = ["BodyScale", "body_scale", "declared_reach", "diameter", "measure", "CLOUD_SIZE", "DIRECTIONS", "CLOUD_SEED"]
