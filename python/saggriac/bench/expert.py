"""Expert knowledge for the teachers that take it, at TeachMyAgent's levels (Romac, Portelas,
Hofmann & Oudeyer, ICML 2021; docs/bench.md, "Expert knowledge").

A box task declares what an expert could tell a teacher about it (:meth:`BenchTask.expert_knowledge`):
``easy``, the region where the learner can make progress from the start (TeachMyAgent's initial
distribution of easy tasks), and ``target``, the region its score is measured on (the target
distribution), both boxes in the task's own coordinates. A level turns into a :class:`Knowledge`:

- ``high``: what the task declares;
- ``low``: nothing about the task but its box: ``easy`` is a box centred at a point drawn
  uniformly in the task's box from the run's seed, 0.4 of each width wide (TeachMyAgent's
  random initial Gaussian, sd 10 % of each range, read as centre +- 2 sd), and ``target`` the
  whole box (TeachMyAgent's default target);
- no knowledge is the plain teacher with its defaults: today's runs and labels.

One function per teacher turns a Knowledge into the teacher's own parameters (``adr_params``,
``spdl_params``, ``goal_gan_params``; positions in [0, 1] of each width from ``low``, widths and
standard deviations in box widths, one value per dimension). A user's teacher opts in with an
``expert_params(knowledge) -> dict`` static method on its class: the bench then runs it at each
level too. The variants are named ``TEACHER@low`` and ``TEACHER@high``.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

#: The levels a teacher is run at besides its plain self (no knowledge), least first.
LEVELS = ("low", "high")
#: The low level's start: its width in box widths (TeachMyAgent: sd 10 % of each range; 4 sd).
LOW_WIDTH = 0.4
#: A region read as a Gaussian: its centre, and this share of its width as sd (TeachMyAgent's
#: target over the whole space: sd a quarter of each range).
SD_PER_WIDTH = 0.25


@dataclass(frozen=True)
class Region:
    """A box ``[low, high]`` in a task's own coordinates (it may stick out of the task's box)."""

    low: np.ndarray
    high: np.ndarray

    @classmethod
    def of(cls, low: Any, high: Any) -> "Region":
        return cls(np.asarray(low, dtype=np.float64), np.asarray(high, dtype=np.float64))

    @property
    def centre(self) -> np.ndarray:
        return (self.low + self.high) / 2

    @property
    def width(self) -> np.ndarray:
        return self.high - self.low


@dataclass(frozen=True)
class Knowledge:
    """What an expert tells a teacher about a task whose goals lie in the box [low, high]:
    ``easy`` (where the learner makes progress from the start) and ``target`` (where the score
    is measured). :meth:`position` and :meth:`share` put them in box units."""

    low: np.ndarray
    high: np.ndarray
    easy: Region
    target: Region

    def position(self, point: np.ndarray) -> list[float]:
        """A point as a position in [0, 1] of each width from ``low`` (clipped to the box)."""
        return np.clip((point - self.low) / (self.high - self.low), 0.0, 1.0).tolist()

    def share(self, width: np.ndarray, lo: float = 0.0, hi: float = 1.0) -> list[float]:
        """A width as a share of each of the box's widths, within [lo, hi]."""
        return np.clip(width / (self.high - self.low), lo, hi).tolist()


def adr_params(k: Knowledge) -> dict[str, Any]:
    """ADR starts from one task, the easy region's centre (TeachMyAgent gives its ADR the mean
    of the initial distribution; the paper's phi^0 is one calibrated environment)."""
    return {"initial": k.position(k.easy.centre), "initial_width": 0.0}


def spdl_params(k: Knowledge) -> dict[str, Any]:
    """SPDL's initial distribution on the easy region and its target on the target region,
    each a Gaussian of the region's centre and a quarter of its width as sd."""
    return {
        "init_mean": k.position(k.easy.centre),
        "init_std": k.share(SD_PER_WIDTH * k.easy.width, 1e-4, 10.0),
        "target_mean": k.position(k.target.centre),
        "target_std": k.share(SD_PER_WIDTH * k.target.width, 1e-4, 10.0),
    }


def goal_gan_params(k: Knowledge) -> dict[str, Any]:
    """Goal GAN's first goals uniform in the easy region (TeachMyAgent pretrains its GAN on
    draws of the initial distribution; the paper starts from goals the first policy reaches)."""
    return {"initial": k.position(k.easy.centre), "initial_width": k.share(k.easy.width)}


#: The built-in teachers that take expert knowledge, and the function that gives it to each.
BUILTIN: dict[str, Callable[[Knowledge], dict[str, Any]]] = {"adr": adr_params, "spdl": spdl_params, "goal_gan": goal_gan_params}


def params_function(cls: type, ref: str, builtin: bool) -> Callable[[Knowledge], dict[str, Any]] | None:
    """How the teacher ``ref`` (its class ``cls``) takes expert knowledge, or None if it takes none."""
    if builtin:
        return BUILTIN.get(ref)
    fn = getattr(cls, "expert_params", None)
    return fn if callable(fn) else None


def split_level(text: str) -> tuple[str, str]:
    """``"adr@high"`` -> ("adr", "high"); a text without a trailing ``@word`` -> (text, "")."""
    base, sep, level = text.rpartition("@")
    if sep and base and re.fullmatch(r"[A-Za-z]+", level):
        return base, level
    return text, ""


def knowledge(task: Any, level: str, seed: int) -> Knowledge:
    """The Knowledge a teacher is given at ``level`` on ``task`` (built for the run whose root
    seed is ``seed``): the task's declaration at high; at low a start drawn from the run's seed
    (the third child of its SeedSequence; the teacher and the task have the first two)."""
    low, high = np.asarray(task.low, dtype=np.float64), np.asarray(task.high, dtype=np.float64)
    if level == "high":
        k = task.expert_knowledge()
        if not isinstance(k, Knowledge):
            raise TypeError(f"the task {task.name!r} declares no expert knowledge (its expert_knowledge() gave {k!r})")
        return k
    if level == "low":
        rng = np.random.default_rng(np.random.SeedSequence(int(seed), spawn_key=(2,)))
        centre = rng.uniform(low, high)
        half = LOW_WIDTH / 2 * (high - low)
        return Knowledge(low, high, Region.of(centre - half, centre + half), Region.of(low, high))
    raise ValueError(f"the expert level must be one of {', '.join(LEVELS)}; got {level!r}")
