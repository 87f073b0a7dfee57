"""A task list for deep RL (the ``minigrid`` extra): Stable-Baselines3's PPO learns MiniGrid's
SimpleCrossing mazes (walls, the agent top left, the goal bottom right) while the teacher chooses
the level of every training episode, and is scored on held-back levels it never trained on, as
Prioritized Level Replay's paper scores generalisation (Jiang, Grefenstette & Rocktäschel, ICML
2021).

A level is a (size, crossings, layout seed) triple: MiniGrid's ``CrossingEnv`` reset with that
seed always draws the same maze. ``GRADES`` are the difficulties, easy to hard; each grade has
``PER_GRADE`` training levels (the first distinct layouts from seed ``1000 * grade``) and as many
held-back ones (the first layouts from seed ``1000 * grade + 500`` that no training level of the
grade has). The policy sees the agent's 7 x 7 view, one-hot by object type, and not the level's
index: the index rides in the observation's ``desired_goal`` only so that
:class:`saggriac.adapters.sb3.TeacherCallback` can check that each episode played the level the
teacher chose (and refuse otherwise), and the features extractor drops it.

The teacher is told the episode's success (the goal square reached), or, for a teacher whose
class says ``told = "positive_value_loss"`` (:class:`saggriac.bench.value_loss.PlrValueLoss`),
PLR's score read from PPO's rollouts by the adapter. The score is the policy's mean MiniGrid
return (1 - 0.9 steps / max_steps when it reaches the goal, else 0) over the held-back levels, one
episode each, its actions sampled with the scoring's own generator (the same draws for every run;
greedy policies loop against walls: docs/evidence/minigrid.md).

The observations are MiniGrid's, computed from arrays (:mod:`saggriac.bench.minigrid_view`).
"""

from __future__ import annotations

from collections import deque
from typing import Any, Callable, ClassVar

import numpy as np

from ..errors import ParameterError
from ..files import check_flag
from .tasks import BenchTask, register

#: The grades, easy to hard: an empty room of that side (the agent anywhere, facing any way; the
#: goal in the far corner), or a SimpleCrossing maze (side, wall crossings). Fixed by the pilot's
#: rule (docs/evidence/minigrid.md).
GRADES: tuple[tuple[str, int, int], ...] = (("empty", 5, 0), ("empty", 7, 0), ("crossing", 7, 1), ("crossing", 9, 1), ("crossing", 9, 2), ("crossing", 11, 3))
PER_GRADE = 8
#: The seed of the scoring's action draws (one for every run).
EVAL_SEED = 20261207
#: MiniGrid's object types (minigrid.core.constants.OBJECT_TO_IDX has 11).
N_OBJECTS = 11
VIEW = 7
#: PPO: rl-baselines3-zoo's MiniGrid settings (8 environments, 128 steps each per rollout,
#: minibatches of 64, 10 epochs, lr 2.5e-4, GAE lambda 0.95, no entropy bonus), one process.
N_ENVS = 8
PPO_KWARGS = dict(n_steps=128, batch_size=64, n_epochs=10, learning_rate=2.5e-4, gae_lambda=0.95, gamma=0.99, ent_coef=0.0, clip_range=0.2)
#: What a task tells its teacher: the episode's success, or PLR's positive value loss.
TELLS = ("competence", "positive_value_loss")
#: The oracle moves to the next grade when the mean success of the grade's last ORACLE_WINDOW
#: training episodes reaches ORACLE_BAR.
ORACLE_WINDOW, ORACLE_BAR = 40, 0.7


def _grade_env(grade: int) -> Any:
    """MiniGrid's environment of ``GRADES[grade]``; its reset with a layout seed draws the level."""
    from minigrid.core.world_object import Wall
    from minigrid.envs import CrossingEnv, EmptyEnv

    from .minigrid_view import ArrayView

    kind, size, crossings = GRADES[grade]
    env = EmptyEnv(size=size, agent_start_pos=None) if kind == "empty" else CrossingEnv(size=size, num_crossings=crossings, obstacle_type=Wall)
    # MiniGrid's observation, computed from arrays (the same to the element, a third of the step).
    env.gen_obs = ArrayView(env)
    return env


def _layout(env: Any, seed: int) -> bytes:
    """The level drawn by ``seed``: the grid, where the agent starts and which way it faces."""
    env.reset(seed=seed)
    return env.grid.encode().tobytes() + bytes([*map(int, env.agent_pos), int(env.agent_dir)])


def _levels(grade: int, start: int, avoid: set[bytes], n: int) -> tuple[list[int], set[bytes]]:
    """The first ``n`` seeds from ``start`` whose layouts are new (not in ``avoid``, nor repeated)."""
    env = _grade_env(grade)
    seeds, seen = [], set(avoid)
    s = start
    while len(seeds) < n:
        key = _layout(env, s)
        if key not in seen:
            seen.add(key)
            seeds.append(s)
        s += 1
    return seeds, seen - avoid


def level_lists() -> tuple[list[tuple[int, int]], list[tuple[int, int]]]:
    """(training levels, held-back levels), each a list of (grade, layout seed), grade by grade."""
    train, held = [], []
    for g in range(len(GRADES)):
        seeds, layouts = _levels(g, 1000 * g, set(), PER_GRADE)
        train += [(g, s) for s in seeds]
        held += [(g, s) for s in _levels(g, 1000 * g + 500, layouts, PER_GRADE)[0]]
    return train, held


def encode(image: np.ndarray) -> np.ndarray:
    """The agent's view (MiniGrid's 7 x 7 x 3 image) as one-hot object types, flat."""
    return np.eye(N_OBJECTS, dtype=np.float32)[image[..., 0]].reshape(-1)


def make_level_env(levels: list[tuple[int, int]]) -> Any:
    """The environment whose episodes play ``levels[i]``, i handed in by ``set_next_goal([i])``
    before the reset (level 0 until one is). The observation is {"image": the view, encoded;
    "desired_goal": [i]}; info["is_success"] says whether the goal was reached."""
    import gymnasium

    class LevelEnv(gymnasium.Env):
        def __init__(self) -> None:
            self.levels = list(levels)
            self.envs = {g: _grade_env(g) for g in sorted({g for g, _ in self.levels})}
            n = len(self.levels)
            self.observation_space = gymnasium.spaces.Dict(
                {
                    "image": gymnasium.spaces.Box(0.0, 1.0, (VIEW * VIEW * N_OBJECTS,), np.float32),
                    "desired_goal": gymnasium.spaces.Box(0.0, float(n - 1), (1,), np.float64),
                }
            )
            self.action_space = self.envs[self.levels[0][0]].action_space
            self.next_goal: Any = None
            self.level = 0
            self.env: Any = None

        def set_next_goal(self, goal: Any) -> None:
            self.next_goal = goal

        def _index(self, goal: Any) -> int:
            g = np.asarray(goal, dtype=np.float64).reshape(-1)
            if g.size != 1 or not np.isfinite(g[0]) or g[0] != int(g[0]) or not 0 <= g[0] < len(self.levels):
                raise ParameterError(f"The 'goal' of the MiniGrid level list must be one level index, an int in [0, {len(self.levels)}). Got {goal!r} instead.", "goal", repr(goal))
            return int(g[0])

        def _obs(self, obs: dict[str, Any]) -> dict[str, Any]:
            return {"image": encode(obs["image"]), "desired_goal": np.array([float(self.level)])}

        def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None) -> tuple[Any, dict[str, Any]]:
            super().reset(seed=seed)
            if self.next_goal is not None:
                self.level, self.next_goal = self._index(self.next_goal), None
            grade, layout = self.levels[self.level]
            self.env = self.envs[grade]
            obs, info = self.env.reset(seed=layout)
            return self._obs(obs), {**info, "level": self.level}

        def step(self, action: Any) -> tuple[Any, float, bool, bool, dict[str, Any]]:
            obs, reward, terminated, truncated, info = self.env.step(action)
            return self._obs(obs), float(reward), terminated, truncated, {**info, "is_success": bool(reward > 0), "level": self.level}

    return LevelEnv()


def image_extractor() -> type:
    """SB3's features extractor that reads the view and drops ``desired_goal`` (the level's index,
    which a policy scored on held-back levels must not see)."""
    import torch
    from stable_baselines3.common.torch_layers import BaseFeaturesExtractor

    class ImageOnly(BaseFeaturesExtractor):
        def __init__(self, observation_space: Any) -> None:
            super().__init__(observation_space, int(observation_space["image"].shape[0]))

        def forward(self, observations: dict[str, Any]) -> Any:
            return torch.flatten(observations["image"], 1)

    return ImageOnly


def evaluate(model: Any, levels: list[tuple[int, int]], greedy: bool = False) -> tuple[float, float]:
    """The policy on each of ``levels`` once, all at once (one batched forward pass per step):
    (mean MiniGrid return, share of levels solved). Its actions are drawn from the policy with a
    generator of its own seeded EVAL_SEED (the same draws for every run, and PPO's torch
    generator untouched), or the most likely ones with ``greedy``."""
    greedy = check_flag(greedy, "greedy", "evaluate")
    import torch

    rng = np.random.default_rng(EVAL_SEED)
    envs = [_grade_env(g) for g, _ in levels]
    obs = [e.reset(seed=s)[0] for e, (_, s) in zip(envs, levels)]
    returns = np.zeros(len(envs))
    live = np.ones(len(envs), bool)
    while live.any():
        idx = np.flatnonzero(live)
        batch = {"image": np.stack([encode(obs[i]["image"]) for i in idx]), "desired_goal": np.zeros((len(idx), 1))}
        with torch.no_grad():
            tensor, _ = model.policy.obs_to_tensor(batch)
            probs = model.policy.get_distribution(tensor).distribution.probs.numpy().astype(np.float64)
        if greedy:
            actions = probs.argmax(axis=1)
        else:
            # Inverse-CDF draws: one uniform per level and step, whatever the policy.
            u = rng.random(len(envs))[idx]
            actions = np.minimum((probs.cumsum(axis=1) < u[:, None] * probs.sum(axis=1, keepdims=True)).sum(axis=1), probs.shape[1] - 1)
        for i, a in zip(idx, actions):
            obs[i], r, term, trunc, _ = envs[i].step(int(a))
            returns[i] += r
            live[i] = not (term or trunc)
    return float(returns.mean()), float(np.mean(returns > 0))


def run_seeds(seed: int) -> tuple[int, int, int]:
    """(PPO's seed, the environments' seed, the teacher's seed): children of SeedSequence(seed)."""
    model, env, teacher = (int(s.generate_state(1)[0]) for s in np.random.SeedSequence(seed).spawn(3))
    return model, env, teacher


class _AskTell:
    """The bench's guarded teacher as the goal selector TeacherCallback drives: a level index as a
    1-D goal, and every finished episode's outcome recorded for the oracle."""

    def __init__(self, ask: Callable[[], Any], tell: Callable[[Any, float], None], n: int) -> None:
        self.low, self.high = np.zeros(1), np.full(1, float(n - 1))
        self.ask, self.tell = ask, tell

    def sample(self) -> Any:
        return np.array([float(self.ask())])

    def update(self, goal: Any, competence: float) -> None:
        self.tell(int(np.asarray(goal).reshape(-1)[0]), competence)


def told_by(tell: Callable[[Any, float], None]) -> str:
    """What the teacher behind the bench's ``tell`` wants told (the guard's ``told``)."""
    return getattr(getattr(tell, "__self__", None), "told", "competence")


@register
class RlMiniGrid(BenchTask):
    """PPO on MiniGrid SimpleCrossing mazes given as a list of levels; scored on held-back levels.
    Not in the quick tier: a run takes minutes of CPU."""

    name = "rl-minigrid"
    study_seeds = tuple(range(1300, 1333))  # docs/figures/evidence/minigrid/protocol.json
    space = "tasks"
    learner = "PPO (SB3), MiniGrid SimpleCrossing mazes, a list of levels"
    measures = "helping a deep-RL student generalise: levels of six grades to choose from, scored on mazes it never trained on (docs/evidence/minigrid.md)"
    requires = ("minigrid", 'the minigrid extra: pip install "saggriac[minigrid]"')
    unit = "environment steps"
    points = 10
    tells: ClassVar[tuple[str, ...]] = TELLS
    budgets = {"quick": None, "standard": 160_000, "full": 160_000}  # the pilot fixed B (docs/evidence/minigrid.md)
    cpu_per_unit = 0.797e-3  # the pilot's CPU seconds per step (docs/evidence/minigrid.md)

    @classmethod
    def child_seeds(cls, seed: int) -> tuple[int, int]:
        """(teacher's seed, the run's seed), as the deep-RL arm's (:func:`run_seeds`)."""
        return run_seeds(seed)[2], seed

    def __init__(self, seed: int) -> None:
        super().__init__(seed)
        self.train_levels, self.held_levels = level_lists()
        self.n_tasks = len(self.train_levels)
        self.grade_of = np.array([g for g, _ in self.train_levels])
        # The recent successes of each grade's training episodes, for the oracle.
        self.recent = [deque(maxlen=ORACLE_WINDOW) for _ in GRADES]
        self.grade = 0
        self._turn = 0
        self._measured: list[dict[str, float]] = []

    def record(self, level: int, success: bool) -> None:
        """A training episode on ``level`` ended (what the oracle reads)."""
        self.recent[self.grade_of[level]].append(bool(success))

    def grades_at_bar(self) -> int:
        """The grades whose last ORACLE_WINDOW training episodes succeeded ORACLE_BAR of the time
        (whatever the teacher)."""
        return sum(len(r) == ORACLE_WINDOW and float(np.mean(r)) >= ORACLE_BAR for r in self.recent)

    def oracle(self) -> int:
        """The hand-written easy-to-hard order: the current grade's levels in turn; the next grade
        once the grade's last ORACLE_WINDOW episodes succeed ORACLE_BAR of the time."""
        r = self.recent[self.grade]
        if self.grade < len(GRADES) - 1 and len(r) == ORACLE_WINDOW and np.mean(r) >= ORACLE_BAR:
            self.grade += 1
        levels = np.flatnonzero(self.grade_of == self.grade)
        self._turn += 1
        return int(levels[self._turn % len(levels)])

    def own_measures(self) -> list[dict[str, float]]:
        """At each scoring: the share of held-back levels solved, and how many grades the
        student's recent training episodes pass the oracle's bar on (:meth:`grades_at_bar`)."""
        return list(self._measured)

    def play(self, ask: Callable[[], Any], tell: Callable[[Any, float], None], budget: int) -> list[tuple[int, float]]:
        told = told_by(tell)
        if told not in TELLS:
            raise ParameterError(f"The teacher's 'told' of the task {self.name!r} must be one of {TELLS}. Got {told!r} instead.", "told", repr(told))
        curve: list[tuple[int, float]] = []
        self._measured = []

        def score(step: int, model: Any) -> None:
            if step > 0:
                mean_return, solved = evaluate(model, self.held_levels)
                curve.append((step, mean_return))
                self._measured.append({"solved": solved, "grades_at_bar": float(self.grades_at_bar())})

        train(self, _AskTell(ask, tell, self.n_tasks), told, budget, max(1, budget // self.points), score)
        return curve


def train(task: RlMiniGrid, teacher: _AskTell, told: str, steps: int, every: int, on_score: Callable[[int, Any], None]) -> None:
    """PPO trained for ``steps`` environment steps on ``task``'s training levels, ``teacher``
    choosing each episode's level through :class:`saggriac.adapters.sb3.TeacherCallback` and told
    the success (``told="competence"``) or the positive value loss; ``on_score(step, model)``
    every ``every`` steps, the last at ``steps``."""
    import torch
    from stable_baselines3 import PPO
    from stable_baselines3.common.callbacks import BaseCallback, CallbackList
    from stable_baselines3.common.logger import Logger
    from stable_baselines3.common.vec_env import DummyVecEnv

    from ..adapters.sb3 import TeacherCallback

    torch.set_num_threads(1)
    model_seed, env_seed, _ = run_seeds(task.seed)
    env = DummyVecEnv([lambda: make_level_env(task.train_levels)] * N_ENVS)
    env.seed(env_seed)
    model = PPO("MultiInputPolicy", env, seed=model_seed, device="cpu", verbose=0, policy_kwargs=dict(features_extractor_class=image_extractor()), **PPO_KWARGS)
    model.set_logger(Logger(folder=None, output_formats=[]))  # else SB3 leaves a folder in /tmp per run
    callback = TeacherCallback(teacher, competence="positive_value_loss" if told == "positive_value_loss" else "success")

    class Watch(BaseCallback):
        """Every finished episode's success for the oracle; the scores; the stop at the budget."""

        def __init__(self) -> None:
            super().__init__()
            self.next_score = every

        def _on_step(self) -> bool:
            for i in np.flatnonzero(self.locals["dones"]):
                info = self.locals["infos"][i]
                task.record(int(info["level"]), bool(info["is_success"]))
            t = self.num_timesteps
            if t >= self.next_score or t >= steps:
                on_score(t, model)
                self.next_score = (t // every + 1) * every
            # Stop at the budget: PPO would otherwise finish its rollout and update once more,
            # a cost no scoring sees.
            return t < steps

    model.learn(steps, callback=CallbackList([callback, Watch()]))
