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

from .. import _core
from ..bodies.environments import PlanarArm, SpatialArm
from ..bodies.reachable import CHAIN_GRID, ReachableSet
from ..config import Config
from ..seeding import selector_seed
from .expert import Knowledge
from .tasks import TIERS, BenchTask, register
from .teachers import TeacherError

#: The easy region about the tip at rest: a box of this share of the reach on each side.
EASY_REACH = 0.1


def rest_tip(config: Config) -> np.ndarray:
    """Where the tip of the arm of ``config`` is at rest (every joint at 0): straight along +x
    for the built-in arms, the middle of every joint's range for a chain."""
    if config.chain is not None:
        n = len(_core.chain_link_lengths(list(config.chain)))
        return np.asarray(_core.chain_forward(list(config.chain), np.zeros((1, n))), float)[0, : len(config.goal_low)]
    body = SpatialArm if config.body == "spatial_arm" else PlanarArm
    arm = body(n_joints=config.n_joints, arm_length=config.arm_length, link_lengths=config.link_lengths, joint_limit=config.joint_limit, max_joint_step=config.max_joint_step)
    return arm.reset()[1]


def reachable_box(config: Config) -> tuple[np.ndarray, np.ndarray]:
    """The box that holds the test goals of ``config``: the ball of its reach about the base
    within the goal box, or a chain's reachable set (the cells of saggriac.bodies.reachable's
    grid that its sample reached)."""
    low, high = np.asarray(config.goal_low, float), np.asarray(config.goal_high, float)
    occupied = ReachableSet(config).occupied
    if occupied is None:
        return np.maximum(low, -config.reach), np.minimum(high, config.reach)
    cells = np.argwhere(occupied)
    step = (high - low) / CHAIN_GRID
    return low + cells.min(axis=0) * step, low + (cells.max(axis=0) + 1) * step


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

    def expert_knowledge(self) -> Knowledge:
        """easy: the box of side a fifth of the reach about the tip at rest (kept in the goal
        box: the 15 links' sum may pass 50 by a rounding), where goals need the smallest
        movements; target: the box of the test goals (:func:`reachable_box`)."""
        tip, half = np.clip(rest_tip(self.config), self.low, self.high), EASY_REACH * self.config.reach
        return self.knowledge((tip - half, tip + half), reachable_box(self.config))

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


#: The arm tasks: (name, preset, settings, unit, budgets by tier, learner, what it measures).
#: Reachable shares measured on 20,000 uniform goals with saggriac.bodies.reachable.ReachableSet.
ARMS = (
    ("arm-episodic", "explauto", {}, "movements", (2_000, 5_000, 20_000), "15-joint arm, episodic (explauto)", "helping a real learner: goals that teach the arm's inverse model most per movement; about a fifth of the box (its corners) is out of reach"),
    ("arm-exp1", "exp1", {}, "micro-actions", (20_000, 50_000, 50_000), "15-joint arm, micro-actions (exp1)", "the paper's own setting: few goals (one per movement of many micro-actions), each costly; about a fifth of the box (its corners) is out of reach"),
    ("arm-exp2", "exp2", {}, "micro-actions", (20_000, 50_000, 200_000), "15-joint arm, micro-actions, exp2 box (exp2)", "the paper's experiment 2: a goal box of which 91 % is out of reach (the arm reaches 9 % of [0, 150] x [-150, 150]), so a teacher must find the reachable part and leave the rest alone"),
    ("arm-3d", "arm3d", {}, "micro-actions", (20_000, 50_000, 100_000), "15-joint arm in 3-D space, micro-actions (arm3d)", "the same learner with a 3-D goal space: more room to spread goals over; the arm reaches about half (52 %) of the box"),
    ("arm-100", "explauto", {"n_joints": 100}, "movements", (2_000, 5_000, 20_000), "100-joint arm, episodic (explauto)", "a very redundant body (100 joints for a 2-D goal): the inverse model is learnt in a 100-D motor space, where each movement teaches less about its neighbours; the arm reaches 78 % of the box"),
    ("arm-pusher", "pusher", {}, "micro-actions", (20_000, 50_000, 100_000), "MuJoCo Pusher's 7-joint arm as a chain, 3-D goals (pusher)", "a robot arm modelled by others (Gymnasium's MuJoCo Pusher: its joint ranges and offsets, stepped as a chain without MuJoCo), in a 3-D goal box of which it reaches 19 %"),
)

for _name, _preset, _settings, _unit, _budgets, _learner, _measures in ARMS:
    _attrs = dict(name=_name, preset=_preset, settings=_settings, unit=_unit, budgets=dict(zip(TIERS, _budgets)), learner=_learner, measures=_measures)
    register(type("".join(p.capitalize() for p in _name.split("-")), (ArmTask,), _attrs))
