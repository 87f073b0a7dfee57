"""Deep RL as bench tasks (the ``sb3`` extra): Stable-Baselines3's PPO, with its defaults, learns
to reach goals with a 3-joint arm while the teacher chooses the goal of every training episode.
This is the task of the first registered deep-RL study (docs/rl_curriculum.md), whose script
(benchmarks/rl_curriculum.py) runs through the functions here: 4 environments in one process,
one torch thread, episodes of 50 steps, the teacher told the closeness ``max(0, 1 - final
distance / reach)``. The score is minus the deterministic policy's mean final distance on 200
test goals uniform in the arm's reachable disc (higher is better), every budget / 10 steps.
"""

from __future__ import annotations

import math
from typing import Any, Callable, ClassVar

import numpy as np

from ..bodies.environments import PlanarArm
from .arm import EASY_REACH
from .expert import Knowledge
from .tasks import BenchTask, register

#: The arm, fixed by the first study's protocol: reach 1, goals in [-2, 2]^2 (a fifth reachable).
ARM = dict(n_joints=3, arm_length=1.0, joint_limit=math.pi, max_joint_step=0.2, goal_low=(-2.0, -2.0), goal_high=(2.0, 2.0))
#: A goal counts as reached within this distance (the study's pilot moved sparse's to 0.3).
THRESHOLDS = {"dense": 0.2, "sparse": 0.3}
EPISODE_STEPS = 50
N_ENVS = 4
N_TEST = 200
TEST_SEED = 20261203  # one test set for every run


def make_env(reward: str, threshold: float) -> Any:
    from gymnasium.wrappers import TimeLimit

    from ..adapters.gym import GoalArmEnv

    return TimeLimit(GoalArmEnv(**ARM, distance_threshold=threshold, reward_type=reward), EPISODE_STEPS)


def arm_reach() -> float:
    """The arm's reach, as its environment gives it (1 here)."""
    return float(make_env("dense", THRESHOLDS["dense"]).unwrapped.reach)


def test_goals(reach: float) -> np.ndarray:
    """N_TEST goals uniform in the disc of radius ``reach`` (the arm's reachable set), by rejection
    from the goal box."""
    rng = np.random.default_rng(TEST_SEED)
    low, high = np.asarray(ARM["goal_low"]), np.asarray(ARM["goal_high"])
    out: list[np.ndarray] = []
    while len(out) < N_TEST:
        g = rng.uniform(low, high)
        if np.linalg.norm(g) <= reach:
            out.append(g)
    return np.array(out)


def evaluate(model: Any, goals: np.ndarray, reward: str, threshold: float) -> tuple[float, float]:
    """The deterministic policy from the rest pose towards every goal at once (one batched
    forward pass per step): the share of goals within the threshold at the episode's end, and
    the mean final distance."""
    envs = [make_env(reward, threshold).unwrapped for _ in goals]
    obs = [e.reset(options={"goal": g})[0] for e, g in zip(envs, goals)]
    info: list[dict] = []
    for _ in range(EPISODE_STEPS):
        batch = {k: np.stack([o[k] for o in obs]) for k in obs[0]}
        actions, _ = model.predict(batch, deterministic=True)
        steps = [e.step(a) for e, a in zip(envs, actions)]
        obs = [s[0] for s in steps]
        info = [s[4] for s in steps]
    return float(np.mean([i["is_success"] for i in info])), float(np.mean([i["distance"] for i in info]))


def run_seeds(seed: int) -> tuple[int, int, int]:
    """(PPO's seed, the environments' seed, the teacher's seed): children of SeedSequence(seed)."""
    model, env, teacher = (int(s.generate_state(1)[0]) for s in np.random.SeedSequence(seed).spawn(3))
    return model, env, teacher


def train(reward: str, threshold: float, teacher: Any, seed: int, steps: int, every: int, on_score: Callable[[int, Any, Any], None]) -> None:
    """PPO trained for ``steps`` environment steps on the arm with ``reward`` and success
    ``threshold``, with ``teacher`` choosing its goals (through
    :class:`saggriac.adapters.sb3.TeacherCallback`), seeded from ``seed`` (:func:`run_seeds`);
    ``on_score(step, model, callback)`` at step 0 and every ``every`` steps, the last at ``steps``."""
    reach = arm_reach()
    train_ppo(lambda: make_env(reward, threshold), lambda info: max(0.0, 1.0 - info["distance"] / reach), teacher, seed, steps, every, on_score)


def train_ppo(make: Callable[[], Any], competence: Callable[[dict], float], teacher: Any, seed: int, steps: int, every: int, on_score: Callable[[int, Any, Any], None]) -> None:
    """PPO with its defaults trained for ``steps`` environment steps on N_ENVS environments
    ``make()`` in one process, with ``teacher`` choosing their goals and told
    ``competence(final info)`` (through :class:`saggriac.adapters.sb3.TeacherCallback`), seeded
    from ``seed`` (:func:`run_seeds`); ``on_score(step, model, callback)`` at step 0 and every
    ``every`` steps, the last at ``steps``. The goal arm's and PointMaze's tasks."""
    import torch
    from stable_baselines3 import PPO
    from stable_baselines3.common.callbacks import BaseCallback, CallbackList
    from stable_baselines3.common.logger import Logger
    from stable_baselines3.common.vec_env import DummyVecEnv

    from ..adapters.sb3 import TeacherCallback

    torch.set_num_threads(1)
    model_seed, env_seed, _ = run_seeds(seed)
    env = DummyVecEnv([make] * N_ENVS)
    env.seed(env_seed)
    model = PPO("MultiInputPolicy", env, seed=model_seed, device="cpu", verbose=0)
    model.set_logger(Logger(folder=None, output_formats=[]))  # else SB3 leaves a folder in /tmp per run
    callback = TeacherCallback(teacher, competence=competence)

    class Score(BaseCallback):
        def _on_step(self) -> bool:
            if self.num_timesteps % every == 0:
                on_score(self.num_timesteps, model, callback)
            # Stop at the budget: PPO would otherwise finish its rollout and update once more,
            # a cost no scoring sees.
            return self.num_timesteps < steps

    on_score(0, model, callback)
    model.learn(steps, callback=CallbackList([callback, Score()]))


class _AskTell:
    """The bench's guarded teacher as the goal selector TeacherCallback drives."""

    def __init__(self, ask: Callable[[], Any], tell: Callable[[Any, float], None]) -> None:
        self.low, self.high = np.asarray(ARM["goal_low"], float), np.asarray(ARM["goal_high"], float)
        self.ask, self.tell = ask, tell

    def sample(self) -> Any:
        return self.ask()

    def update(self, goal: Any, competence: float) -> None:
        self.tell(goal, competence)


class RlArm(BenchTask):
    """PPO on the goal arm; ``reward`` is "dense" (minus the distance) or "sparse" (-1 until
    reached). Not in the quick tier: one run takes about a minute of CPU at the standard budget."""

    space = "box"
    reward: ClassVar[str] = "dense"
    requires = ("stable_baselines3", "the sb3 extra: pip install \"saggriac[sb3]\"")
    unit = "environment steps"
    points = 10
    budgets = {"quick": None, "standard": 60_000, "full": 120_000}

    @classmethod
    def child_seeds(cls, seed: int) -> tuple[int, int]:
        """(teacher's seed, the run's seed): the first study's derivation (:func:`run_seeds`)."""
        return run_seeds(seed)[2], seed

    def __init__(self, seed: int) -> None:
        super().__init__(seed)
        self.low, self.high = np.asarray(ARM["goal_low"], float), np.asarray(ARM["goal_high"], float)

    def expert_knowledge(self) -> Knowledge:
        """easy: the box of side a fifth of the reach about the tip at rest; target: the box of
        the reachable disc, where the test goals are (:func:`test_goals`). The arm is
        GoalArmEnv's (a PlanarArm), read here without Gymnasium."""
        arm = PlanarArm(**{k: ARM[k] for k in ("n_joints", "arm_length", "joint_limit", "max_joint_step")})
        tip, reach = arm.reset()[1], arm.reach
        return self.knowledge((tip - EASY_REACH * reach, tip + EASY_REACH * reach), (np.maximum(self.low, -reach), np.minimum(self.high, reach)))

    def play(self, ask: Callable[[], Any], tell: Callable[[Any, float], None], budget: int) -> list[tuple[int, float]]:
        goals = test_goals(arm_reach())
        curve: list[tuple[int, float]] = []

        def score(step: int, model: Any, _callback: Any) -> None:
            if step > 0:
                curve.append((step, -evaluate(model, goals, self.reward, THRESHOLDS[self.reward])[1]))

        train(self.reward, THRESHOLDS[self.reward], _AskTell(ask, tell), self.seed, budget, max(1, budget // self.points), score)
        return curve


@register
class RlArmDense(RlArm):
    name, reward = "rl-arm-dense", "dense"
    learner = "PPO (SB3), 3-joint goal arm, dense reward"
    measures = "helping a deep-RL student: the first registered study's task (docs/rl_curriculum.md), where goals out of reach (four fifths of the box) teach nothing"


@register
class RlArmSparse(RlArm):
    name, reward = "rl-arm-sparse", "sparse"
    learner = "PPO (SB3), 3-joint goal arm, sparse reward"
    measures = "the same with a sparse reward, where PPO tends to fold the arm onto its joint limits unless its goals keep it out of the fold (docs/rl_curriculum.md)"
