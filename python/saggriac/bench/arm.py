"""The paper's learner as bench tasks: the arm learning its inverse model, with the teacher as its
high level (``saggriac.run(config, seed, goal_selector=...)``). The score is the negated mean
reaching error on the run's held-back test goals (higher is better), at each evaluation.

The teacher is told what the run tells its own high level, a competence in [min_c, 0] =
[-1, 0], mapped into the teacher's ``competence_range`` (the identity for SAGG-RIAC's), and it is
seeded as the run seeds its own high level (``saggriac.seeding.selector_seed``): SAGG-RIAC here
asks exactly the goals of ``saggriac.run`` with ``condition="sagg_riac"``.
"""

from __future__ import annotations

from typing import Any, Callable, ClassVar

import numpy as np

from ..config import Config
from ..seeding import selector_seed
from .tasks import BenchTask, register
from .teachers import TeacherError


class _HighLevel:
    """The bench's guarded teacher as the run's goal selector."""

    def __init__(self, low: np.ndarray, high: np.ndarray, ask: Callable[[], Any], tell: Callable[[Any, float], None], min_c: float) -> None:
        self.low, self.high = low, high
        self.ask, self.tell, self.min_c = ask, tell, min_c
        self.error: BaseException | None = None

    def sample(self) -> np.ndarray:
        try:
            return self.ask()
        except TeacherError as e:
            self.error = e
            raise

    def update(self, goal: Any, competence: float) -> None:
        try:
            # [min_c, 0] -> [0, 1], which the guard maps into the teacher's own range.
            self.tell(goal, (float(competence) - self.min_c) / -self.min_c)
        except TeacherError as e:
            self.error = e
            raise


class ArmTask(BenchTask):
    """An arm of ``preset``, ``budget`` steps, ``evals`` evaluations on its test goals."""

    space = "box"
    preset: ClassVar[str] = "exp1"
    evals: ClassVar[int] = 10
    settings: ClassVar[dict[str, Any]] = {}

    @classmethod
    def child_seeds(cls, seed: int) -> tuple[int, int]:
        """(teacher's seed, the run's root seed): the teacher is seeded as the run's own high level."""
        return selector_seed(seed), seed

    def __init__(self, seed: int) -> None:
        super().__init__(seed)
        self.config = Config.from_preset(self.preset, n_evals=self.evals, **self.settings)
        self.low, self.high = np.asarray(self.config.goal_low, float), np.asarray(self.config.goal_high, float)

    def play(self, ask: Callable[[], Any], tell: Callable[[Any, float], None], budget: int) -> list[tuple[int, float]]:
        from ..runs.runner import run

        high_level = _HighLevel(self.low, self.high, ask, tell, self.config.min_c)
        config = self.config.replace(n_steps=budget) if hasattr(self.config, "replace") else Config.from_dict({**self.config.to_dict(), "n_steps": budget})
        try:
            result = run(config, seed=self.seed, goal_selector=high_level, threads=1)
        except Exception:
            if high_level.error is not None:
                raise high_level.error from None
            raise
        m = result.metrics
        m = m[m.step > 0]
        return [(int(s), -float(e)) for s, e in zip(m.step, m.reach_error)]


@register
class ArmEpisodic(ArmTask):
    name, preset, unit = "arm-episodic", "explauto", "movements"
    learner = "15-joint arm, episodic (explauto)"
    budgets = {"quick": 2_000, "standard": 5_000, "full": 20_000}
    measures = "helping a real learner: goals that teach the arm's inverse model most per movement; about a fifth of the box (its corners) is out of reach"


@register
class ArmExp1(ArmTask):
    name, preset, unit = "arm-exp1", "exp1", "micro-actions"
    learner = "15-joint arm, micro-actions (exp1)"
    budgets = {"quick": 20_000, "standard": 50_000, "full": 50_000}
    measures = "the paper's own setting: few goals (one per movement of many micro-actions), each costly; about a fifth of the box (its corners) is out of reach"
