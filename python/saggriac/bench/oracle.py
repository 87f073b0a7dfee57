"""The oracle of a body's goal space: goals uniform over what the body reaches. It sees the body,
not the learner: the curriculum of pure focus, every goal possible and none preferred, the
reference of the deep-RL studies (docs/rl_curriculum.md) for what focus alone buys."""

from __future__ import annotations

from typing import Any

import numpy as np


class OracleTeacher:
    """Goals uniform over what the body reaches: uniform in the goal box of ``config``, kept if
    saggriac's reachable set of the body (:class:`saggriac.bodies.reachable.ReachableSet`) holds them.
    It is told competences and ignores them."""

    def __init__(self, config: Any, seed: int) -> None:
        from ..bodies.reachable import ReachableSet

        self.low, self.high = np.asarray(config.goal_low, float), np.asarray(config.goal_high, float)
        self._contains = ReachableSet(config).contains
        self._rng = np.random.default_rng(seed)
        if not self._contains(self._rng.uniform(self.low, self.high, (100_000, len(self.low)))).any():
            raise ValueError(f"OracleTeacher: the body of {config!r} reaches none of 100,000 points of its goal box; there is nothing to draw from.")

    def sample(self) -> np.ndarray:
        while True:
            batch = self._rng.uniform(self.low, self.high, (64, len(self.low)))
            inside = np.flatnonzero(self._contains(batch))
            if inside.size:
                return batch[inside[0]].copy()

    def update(self, goal: Any, competence: float) -> None:
        return None
