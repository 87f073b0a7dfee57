"""The size of a user's body, which a run's length parameters and test goals follow.

saggriac's own arms know their reach (the ball of that radius about the origin, their base). A
body that declares ``reach`` (a float > 0: the radius of the ball about the origin it reaches,
as :class:`saggriac.bodies.environments.PlanarArm` does) is taken at its word. Any other body is
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

A declared reach must be within the bounds of every length (``saggriac.config.REACH_RULE``), and
it is checked against a quick measurement (:data:`QUICK_SIZE` placements): a :class:`ReachWarning`
says so when it is below the measured half-span (positions farther apart than the ball allows) or
more than :data:`REACH_FACTOR` times it (a reach ten times the body's left 41 of 100 test goals
unreached, said only in run.json).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..config import REACH_RULE, reach_ok
from ..errors import ConformanceError
from ..seeding import FIXED

#: Placements made to measure a body without a declared reach.
CLOUD_SIZE = 10_000
#: Directions along which the extreme positions are kept for the diameter, per dimension.
DIRECTIONS = 256
#: The generator of the configurations (fixed: a body's size does not depend on the run's seed).
CLOUD_SEED = FIXED["body_measure"]
#: Placements of the quick measurement a declared reach is compared with (a few ms for saggriac's arms).
QUICK_SIZE = 300
#: A declared reach more than this many times the quick measurement is warned about. Uniform
#: configurations seldom stretch a long arm: the quick half-span of saggriac's 15-joint arm is
#: 0.82 of its reach (0.49 with limits of +-pi, 0.43 with 100 joints); ten times the body's is
#: the audit's mistake.
REACH_FACTOR = 5.0


class ReachWarning(UserWarning):
    """A body's declared reach is far from what a quick measurement of the body gives."""


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
    if isinstance(r, bool) or not isinstance(r, (int, float, np.integer, np.floating)) or not reach_ok(float(r)):
        raise ConformanceError(f"environment.reach must be {REACH_RULE}: the radius of the ball about the origin that the body reaches; got {r!r}.")
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


def measure(env: Any, low: np.ndarray, high: np.ndarray, m: int, size: int = CLOUD_SIZE) -> BodyScale:
    """Place ``env`` at ``size`` uniform configurations in [low, high] and measure its reach
    (``m``: the task space's dimension)."""
    rng = np.random.default_rng(CLOUD_SEED)
    configs = rng.uniform(low, high, (size, len(low)))
    positions = np.empty((size, m))
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
        raise ConformanceError(f"The environment's end effector did not move over {size} configurations across its joint space (always at {positions[0].tolist()}): saggriac cannot learn to reach with it.")
    if not reach_ok(d / 2):
        raise ConformanceError(f"The environment's measured reach (half the largest distance between its positions over {size} configurations) must be {REACH_RULE}; got {d / 2:g}.")
    return BodyScale(reach=d / 2, source="measured", configs=configs, positions=positions)


def check_declared(env: Any, reach: float, low: np.ndarray, high: np.ndarray, m: int) -> float | None:
    """Warn (ReachWarning) when ``reach`` is below the half-span of QUICK_SIZE placements of
    ``env`` or more than REACH_FACTOR times it; the measured half-span is returned (None if the
    body cannot be measured: the run's own checks then say why, at the call that fails)."""
    try:
        measured = measure(env, low, high, m, QUICK_SIZE).reach
    except ConformanceError:
        return None
    ratio = reach / measured
    if ratio < 1 - 1e-9:
        warnings.warn(
            f"environment.reach = {reach:g} is {1 / ratio:.3g} times smaller than the body's span: {QUICK_SIZE} placements at uniform configurations "
            f"put its end effector {2 * measured:g} apart, which a ball of radius {reach:g} cannot hold. The run's lengths (v, eps_max, eval_tolerance) "
            "and test goals follow the declared reach: check it, or delete the attribute to have the body measured.",
            ReachWarning,
            stacklevel=4,
        )
    elif ratio > REACH_FACTOR:
        warnings.warn(
            f"environment.reach = {reach:g} is {ratio:.3g} times the half-span of {QUICK_SIZE} placements of the body at uniform configurations ({measured:g}); "
            f"saggriac's own arms measure 0.4 to 1 times their reach this way. The run's lengths (v, eps_max, eval_tolerance) and test goals follow the "
            "declared reach, and goals beyond the body's would count as unreached: check it, or delete the attribute to have the body measured.",
            ReachWarning,
            stacklevel=4,
        )
    return measured


def body_scale(env: Any, low: np.ndarray, high: np.ndarray, m: int) -> BodyScale:
    """The declared reach of ``env`` if it has one, else its measured one."""
    r = declared_reach(env)
    if r is None:
        return measure(env, low, high, m)
    check_declared(env, r, low, high, m)
    return BodyScale(reach=r, source="declared")


__all__ = ["BodyScale", "ReachWarning", "body_scale", "check_declared", "declared_reach", "diameter", "measure", "CLOUD_SIZE", "CLOUD_SEED", "DIRECTIONS", "QUICK_SIZE", "REACH_FACTOR"]
