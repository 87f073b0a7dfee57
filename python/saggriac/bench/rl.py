"""Deep RL as bench tasks (the ``sb3`` extra): a Stable-Baselines3 learner with its defaults
learns to reach goals with a 3-joint arm while the teacher chooses the goal of every training
episode. The learner is PPO (on-policy; the task of the first registered deep-RL study,
docs/rl_curriculum.md, whose script benchmarks/rl_curriculum.py runs through the functions here)
or SAC (off-policy, a replay buffer; plain, without HER, so the teacher alone picks the goals:
docs/evidence/sac.md). Either way: 4 environments in one process, one torch thread, episodes of
50 steps, the teacher told the closeness ``max(0, 1 - final distance / reach)``. The score is
minus the deterministic policy's mean final distance on 200 test goals uniform in the arm's
reachable disc (higher is better), every budget / 10 steps.
"""

from __future__ import annotations

import math
from typing import Any, Callable, ClassVar

import numpy as np

from ..bodies.environments import PlanarArm
from ..errors import ConformanceError, ParameterError
from .arm import EASY_REACH
from .expert import Knowledge
from .oracle import OracleTeacher
from .tasks import BenchTask, register

#: The arm, fixed by the first study's protocol: reach 1, goals in [-2, 2]^2 (a fifth reachable).
ARM = dict(n_joints=3, arm_length=1.0, joint_limit=math.pi, max_joint_step=0.2, goal_low=(-2.0, -2.0), goal_high=(2.0, 2.0))
#: A goal counts as reached within this distance (the study's pilot moved sparse's to 0.3).
THRESHOLDS = {"dense": 0.2, "sparse": 0.3}
EPISODE_STEPS = 50
N_ENVS = 4
N_TEST = 200
TEST_SEED = 20261203  # one test set for every run
#: The learners :func:`train` takes: SB3's PPO (the first study's) and SAC.
LEARNERS = ("ppo", "sac")


def make_env(reward: str, threshold: float, joints: str = "limited") -> Any:
    """The study's arm; ``joints="free"`` the same arm with joints that turn for ever (no limit
    to fold onto: GoalArmEnv's ``joints``)."""
    from gymnasium.wrappers import TimeLimit

    from ..adapters.gym import GoalArmEnv

    arm = ARM if joints == "limited" else {k: v for k, v in ARM.items() if k != "joint_limit"}
    return TimeLimit(GoalArmEnv(**arm, distance_threshold=threshold, reward_type=reward, joints=joints), EPISODE_STEPS)


def arm_reach() -> float:
    """The arm's reach, as its environment gives it (1 here)."""
    return float(make_env("dense", THRESHOLDS["dense"]).unwrapped.reach)


def arm_config() -> Any:
    """The arm as a saggriac Config, for its reachable set (the oracle's)."""
    from ..config import Config

    return Config(body="planar_arm", **{k: ARM[k] for k in ("n_joints", "arm_length", "joint_limit", "goal_low", "goal_high")})


#: Where a policy that drives every joint to its limit (+-pi) leaves the tip, whatever the goal:
#: with links of a third of the arm, out along pi, back along 2 pi, out again along 3 pi.
FOLD_TIP = (-ARM["arm_length"] / 3, 0.0)


def folded(runs: Any) -> Any:
    """Whether each run's final policy is the fold (``runs``: a DataFrame with final_distance):
    its mean final distance to the test goals is that of the tip held at FOLD_TIP (to 1e-9),
    which no policy that moves with the goal gives."""
    fold = float(np.mean(np.linalg.norm(test_goals(arm_reach()) - np.array(FOLD_TIP), axis=1)))
    return (runs["final_distance"] - fold).abs() < 1e-9


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


def evaluate(model: Any, goals: np.ndarray, reward: str, threshold: float, joints: str = "limited", extra: dict[str, float] | None = None) -> tuple[float, float]:
    """The deterministic policy from the rest pose towards every goal at once (one batched
    forward pass per step): the share of goals within the threshold at the episode's end, and
    the mean final distance. ``extra``, if given, gets ``tip_spread``: the largest distance of a
    final tip from their mean (0 for a goal-blind policy, one that ends at one tip whatever the
    goal, as the fold does)."""
    envs = [make_env(reward, threshold, joints).unwrapped for _ in goals]
    obs = [e.reset(options={"goal": g})[0] for e, g in zip(envs, goals)]
    info: list[dict] = []
    for _ in range(EPISODE_STEPS):
        batch = {k: np.stack([o[k] for o in obs]) for k in obs[0]}
        actions, _ = model.predict(batch, deterministic=True)
        steps = [e.step(a) for e, a in zip(envs, actions)]
        obs = [s[0] for s in steps]
        info = [s[4] for s in steps]
    if extra is not None:
        tips = np.array([o["achieved_goal"] for o in obs])
        extra["tip_spread"] = float(np.linalg.norm(tips - tips.mean(axis=0), axis=1).max())
    return float(np.mean([i["is_success"] for i in info])), float(np.mean([i["distance"] for i in info]))


def run_seeds(seed: int) -> tuple[int, int, int]:
    """(PPO's seed, the environments' seed, the teacher's seed): children of SeedSequence(seed)."""
    model, env, teacher = (int(s.generate_state(1)[0]) for s in np.random.SeedSequence(seed).spawn(3))
    return model, env, teacher


def make_model(learner: str, env: Any, seed: int) -> Any:
    """SB3's ``learner`` ("ppo" or "sac") with its default hyperparameters and MultiInputPolicy,
    on the CPU, seeded with ``seed``, its logger silenced (else SB3 leaves a folder in /tmp per
    run). SAC's replay buffer is SB3's plain one: no HER, whose relabelled goals no teacher chose."""
    from stable_baselines3 import PPO, SAC
    from stable_baselines3.common.logger import Logger

    if learner not in LEARNERS:
        raise ParameterError(f"The 'learner' parameter of train must be one of {', '.join(map(repr, LEARNERS))}. Got {learner!r} instead.", "learner", repr(learner))
    cls = PPO if learner == "ppo" else SAC
    model = cls("MultiInputPolicy", env, seed=seed, device="cpu", verbose=0)
    model.set_logger(Logger(folder=None, output_formats=[]))
    return model


def check_replay_goals(model: Any, callback: Any) -> int:
    """That the teacher's goals are what an off-policy model trained on: every episode in the
    model's replay buffer (but the first of each sub-environment, which pursues the environment's
    own goal) pursued, at every one of its transitions, a goal the teacher was asked, and every
    episode the teacher was told about is in the buffer with its goal. Raises ConformanceError
    (a goal not applied, or a competence told of an episode never trained on) and refuses a
    buffer that is not SB3's plain one (HER relabels goals). The number of episodes checked."""
    from stable_baselines3.common.buffers import DictReplayBuffer

    buf = getattr(model, "replay_buffer", None)
    if type(buf) is not DictReplayBuffer:
        raise ConformanceError(f"The deep-RL arm checks that {type(model).__name__} trains on the teacher's goals in SB3's plain DictReplayBuffer; its replay buffer is {type(buf).__name__}, which may replace them (HER relabels goals), so the teacher would be told competences of goals the learner did not train on.")
    rows = buf.buffer_size if buf.full else buf.pos
    order = np.roll(np.arange(buf.buffer_size), -buf.pos) if buf.full else np.arange(rows)
    goals, dones = buf.observations["desired_goal"][order], buf.dones[order]
    dtype = goals.dtype
    stored: list[tuple] = []
    for i in range(goals.shape[1]):
        ends = np.flatnonzero(dones[:-1, i]) + 1
        for k, (a, b) in enumerate(zip(np.r_[0, ends], np.r_[ends, rows])):
            g = goals[a:b, i]
            if len(g) and not (g == g[0]).all():
                raise ConformanceError(f"{type(model).__name__}'s replay buffer holds an episode of sub-environment {i} (rows {a}-{b - 1}) whose goal changes within it: a goal was applied in the middle of an episode.")
            if k > 0 and len(g):
                stored.append(tuple(g[0]))
    told = [tuple(np.asarray(g, dtype)) for g, _ in callback.history]
    running = [tuple(np.asarray(g, dtype)) for g in callback._current if g is not None]
    missing = sorted(set(told) - set(stored))
    extra = sorted(set(stored) - set(told) - set(running))
    if missing or extra or len(stored) < len(told):
        raise ConformanceError(f"{type(model).__name__}'s replay buffer does not hold the teacher's episodes: {len(told)} told, {len(stored)} stored; told but never stored: {len(missing)} (first {missing[:2]}); stored with a goal the teacher did not give: {len(extra)} (first {extra[:2]}).")
    return len(stored)


def train(reward: str, threshold: float, teacher: Any, seed: int, steps: int, every: int, on_score: Callable[[int, Any, Any], None], learner: str = "ppo", joints: str = "limited") -> None:
    """``learner`` (:data:`LEARNERS`) trained for ``steps`` environment steps on the arm with
    ``reward`` and success ``threshold`` (``joints``: :func:`make_env`'s), with ``teacher``
    choosing its goals, told the closeness ``max(0, 1 - final distance / reach)``: the studies'
    arm through :func:`train_learner`."""
    reach = arm_reach()
    train_learner(lambda: make_env(reward, threshold, joints), lambda info: max(0.0, 1.0 - info["distance"] / reach), teacher, seed, steps, every, on_score, learner)


def train_learner(make: Callable[[], Any], competence: Callable[[dict], float], teacher: Any, seed: int, steps: int, every: int, on_score: Callable[[int, Any, Any], None], learner: str = "ppo") -> None:
    """SB3's ``learner`` (:data:`LEARNERS`) with its defaults trained for ``steps`` environment
    steps on N_ENVS environments ``make()`` in one process, with ``teacher`` choosing their goals
    and told ``competence(final info)`` (through :class:`saggriac.adapters.sb3.TeacherCallback`),
    seeded from ``seed`` (:func:`run_seeds`); ``on_score(step, model, callback)`` at step 0 and
    every ``every`` steps, the last at ``steps``. An off-policy learner's replay buffer is checked
    at the end (:func:`check_replay_goals`). The goal arm's and PointMaze's tasks."""
    import torch
    from stable_baselines3.common.callbacks import BaseCallback, CallbackList
    from stable_baselines3.common.vec_env import DummyVecEnv

    from ..adapters.sb3 import TeacherCallback

    if learner not in LEARNERS:
        raise ParameterError(f"The 'learner' parameter of train must be one of {', '.join(map(repr, LEARNERS))}. Got {learner!r} instead.", "learner", repr(learner))
    torch.set_num_threads(1)
    model_seed, env_seed, _ = run_seeds(seed)
    env = DummyVecEnv([make] * N_ENVS)
    env.seed(env_seed)
    model = make_model(learner, env, model_seed)
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
    if learner != "ppo":
        check_replay_goals(model, callback)


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
    """An SB3 learner (``algorithm``: "ppo" or "sac") on the goal arm; ``reward`` is "dense"
    (minus the distance) or "sparse" (-1 until reached). Not in the quick tier: one run takes
    minutes of CPU. Its oracle asks goals uniform over what the arm reaches
    (:class:`saggriac.bench.oracle.OracleTeacher`, the deep-RL studies' oracle); its own measures
    at each scoring are the final distance and success on the test goals, the share of the
    teacher's last 200 goals in reach, the episodes told, and the untrained policy's distance and
    success (start_distance, start_success: the same at every scoring)."""

    space = "box"
    reward: ClassVar[str] = "dense"
    algorithm: ClassVar[str] = "ppo"
    #: PPO's cost on this arm: the second study's runs took 57-63 CPU s per 120,000 steps
    #: (docs/rl_curriculum.md, "Cost").
    cpu_per_unit: ClassVar[float | None] = 60.0 / 120_000
    #: GoalArmEnv's joints: "limited" (the studies' arm) or "free" (no limit to fold onto).
    joints: ClassVar[str] = "limited"
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
        self._measures: list[dict[str, float]] = []
        self._oracle: OracleTeacher | None = None

    def oracle_teacher(self, seed: int) -> OracleTeacher:
        """Goals uniform over the arm's reachable disc, drawn from ``seed`` (the run's teacher
        seed): the deep-RL studies' oracle, so a bench run of it is the study's run."""
        return OracleTeacher(arm_config(), seed)

    def oracle(self) -> Any:
        """A goal of :meth:`oracle_teacher` seeded with this run's teacher seed."""
        if self._oracle is None:
            self._oracle = self.oracle_teacher(self.child_seeds(self.seed)[0])
        return self._oracle.sample()

    def expert_knowledge(self) -> Knowledge:
        """easy: the box of side a fifth of the reach about the tip at rest; target: the box of
        the reachable disc, where the test goals are (:func:`test_goals`). The arm is
        GoalArmEnv's (a PlanarArm), read here without Gymnasium."""
        arm = PlanarArm(**{k: ARM[k] for k in ("n_joints", "arm_length", "joint_limit", "max_joint_step")})
        tip, reach = arm.reset()[1], arm.reach
        return self.knowledge((tip - EASY_REACH * reach, tip + EASY_REACH * reach), (np.maximum(self.low, -reach), np.minimum(self.high, reach)))

    def play(self, ask: Callable[[], Any], tell: Callable[[Any, float], None], budget: int) -> list[tuple[int, float]]:
        reach = arm_reach()
        goals = test_goals(reach)
        curve: list[tuple[int, float]] = []
        self._measures = []

        start: dict[str, float] = {}

        def score(step: int, model: Any, callback: Any) -> None:
            extra: dict[str, float] = {}
            success, distance = evaluate(model, goals, self.reward, THRESHOLDS[self.reward], self.joints, extra)
            if step == 0:
                start.update(start_distance=distance, start_success=success)
                return
            curve.append((step, -distance))
            recent = np.array([g for g, _ in callback.history[-200:]]).reshape(-1, len(self.low))
            share = float(np.mean(np.linalg.norm(recent, axis=1) <= reach)) if len(recent) else float("nan")
            self._measures.append(dict(distance=distance, success=success, reachable_share=share, episodes=float(len(callback.history)), tip_spread=extra["tip_spread"], **start))

        train(self.reward, THRESHOLDS[self.reward], _AskTell(ask, tell), self.seed, budget, max(1, budget // self.points), score, self.algorithm, self.joints)
        return curve

    def own_measures(self) -> list[dict[str, float]]:
        return list(self._measures)

    @classmethod
    def notes(cls, runs: Any) -> list[str]:
        """How many of each teacher's runs end folded (:func:`folded`; ``runs`` has the own
        measures at the end as final_distance, ...)."""
        if not len(runs):
            return []
        fold = folded(runs)
        counts = ", ".join(f"{t} {int(fold[runs['teacher'] == t].sum())}/{int((runs['teacher'] == t).sum())}" for t in dict.fromkeys(runs["teacher"]))
        return [f"Runs whose final policy folds the arm onto its joint limits (the tip at ({FOLD_TIP[0]:.4g}, 0) for every goal): {counts}."]


@register
class RlArmDense(RlArm):
    name, reward = "rl-arm-dense", "dense"
    study_seeds = tuple(range(500, 524))  # the second deep-RL study's (docs/rl_curriculum.md)
    learner = "PPO (SB3), 3-joint goal arm, dense reward"
    measures = "helping a deep-RL student: the first registered study's task (docs/rl_curriculum.md), where goals out of reach (four fifths of the box) teach nothing"


@register
class RlArmSparse(RlArm):
    name, reward = "rl-arm-sparse", "sparse"
    study_seeds = tuple(range(600, 612))
    learner = "PPO (SB3), 3-joint goal arm, sparse reward"
    measures = "the same with a sparse reward, where PPO tends to fold the arm onto its joint limits unless its goals keep it out of the fold (docs/rl_curriculum.md)"


@register
class RlArmSacDense(RlArm):
    name, reward, algorithm = "rl-arm-sac-dense", "dense", "sac"
    study_seeds = tuple(range(900, 924))  # the SAC study's (docs/figures/evidence/sac/protocol.json)
    cpu_per_unit = 3.956e-3  # the SAC study's pilot (docs/evidence/sac.md)
    learner = "SAC (SB3, no HER), 3-joint goal arm, dense reward"
    measures = "whether the deep-RL verdicts are the task's or PPO's: the same task with an off-policy learner that replays its past episodes (docs/evidence/sac.md)"
    #: The budget the SAC study's pilot fixed (docs/evidence/sac.md), in both tiers.
    budgets = {"quick": None, "standard": 20_000, "full": 20_000}


@register
class RlArmSacSparse(RlArm):
    name, reward, algorithm = "rl-arm-sac-sparse", "sparse", "sac"
    study_seeds = tuple(range(950, 962))
    cpu_per_unit = 3.956e-3
    learner = "SAC (SB3, no HER), 3-joint goal arm, sparse reward"
    measures = "the same with a sparse reward (does SAC fold the arm as PPO does?)"
    budgets = {"quick": None, "standard": 20_000, "full": 20_000}


#: A final policy whose tips for all test goals lie within this of their mean ignores the goal.
GOAL_BLIND = 1e-6


@register
class RlArmFreeSparse(RlArm):
    name, reward, joints = "rl-arm-free-sparse", "sparse", "free"
    learner = "PPO (SB3), 3-joint goal arm with free joints, sparse reward"
    measures = "whether the sparse verdicts are the fold's: the same arm with joints that turn for ever, no limit to fold onto (docs/rl_curriculum.md, free joints)"

    @classmethod
    def notes(cls, runs: Any) -> list[str]:
        """How many of each teacher's runs end goal-blind (one tip for every test goal), the free
        arm's analogue of the fold (``runs`` has the own measures at the end as final_tip_spread)."""
        if not len(runs) or "final_tip_spread" not in runs:
            return []
        blind = runs["final_tip_spread"] < GOAL_BLIND
        counts = ", ".join(f"{t} {int(blind[runs['teacher'] == t].sum())}/{int((runs['teacher'] == t).sum())}" for t in dict.fromkeys(runs["teacher"]))
        return [f"Runs whose final policy ends at one tip whatever the goal (goal-blind; the free joints cannot fold): {counts}."]
