"""PointMaze as bench tasks (the ``sb3`` extra and Gymnasium-Robotics): a goal space with walls.

Gymnasium-Robotics' PointMaze (after D4RL's maze2d; Fu et al. 2020) is a ball of radius 0.1
pushed by a force in a maze of unit cells. The teacher chooses the goal of every training
episode of Stable-Baselines3's PPO (its defaults, 4 environments in one process, one torch
thread, the code of :func:`saggriac.bench.rl.train_learner`) in the goal box spanned by the centres
of the maze's free cells. Part of that box is wall: a goal deep in a wall can be asked and never
reached, and the reachable set (the free cells, less the ball's radius along the walls) is not
convex. The episode starts in a fixed cell (the map's ``"r"``), with PointMaze's noise of a
quarter cell; the reward is PointMaze's dense one, exp(-distance), and the task never ends early
(``continuing_task=True``, so an episode is ``EPISODE_STEPS`` steps).

PointMaze ignores ``reset(options={"goal": ...})``; the teacher's goal reaches the agent through
:class:`saggriac.adapters.gym.GoalSlot` with ``goal_via="observation"``: it is the observation's
``desired_goal``, and the reward, ``info["is_success"]`` (within PointMaze's 0.45) and
``info["distance"]`` are computed for it. The teacher is told the closeness
``max(0, 1 - final distance / the goal box's diagonal)``.

The score (higher is better) is the share of ``N_TEST`` held-back test goals, uniform over the
reachable set (one fixed set), that the deterministic policy ends within 0.45 of, every budget /
10 steps. :meth:`MazeTask.own_measures` gives the run's own measures at each scoring: the mean
final distance to the test goals, the goals asked so far and the share of them (all; the last
200) in the reachable set. The oracle (:class:`MazeOracle`) asks goals uniform over the
reachable set.
"""

from __future__ import annotations

import time
from typing import Any, Callable, ClassVar

import numpy as np

from .expert import Knowledge
from .rl import run_seeds, train_learner
from .tasks import BenchTask, register

#: The maps: Gymnasium-Robotics' U_MAZE and MEDIUM_MAZE (1 a wall, 0 free) with the start cell
#: "r" fixed at one end, and "g" the cell of the environment's own goal (the first episode of
#: each environment pursues it, before the teacher's first goal; TeacherCallback tells nothing of it).
MAPS: dict[str, list[list[Any]]] = {
    "umaze": [
        [1, 1, 1, 1, 1],
        [1, "r", 0, 0, 1],
        [1, 1, 1, 0, 1],
        [1, "g", 0, 0, 1],
        [1, 1, 1, 1, 1],
    ],
    "medium": [
        [1, 1, 1, 1, 1, 1, 1, 1],
        [1, "r", 0, 1, 1, 0, 0, 1],
        [1, 0, 0, 1, 0, 0, 0, 1],
        [1, 1, 0, 0, 0, 1, 1, 1],
        [1, 0, 0, 1, 0, 0, 0, 1],
        [1, 0, 1, 0, 0, 1, 0, 1],
        [1, 0, 0, 0, 1, 0, "g", 1],
        [1, 1, 1, 1, 1, 1, 1, 1],
    ],
}
#: Steps per episode: half of Gymnasium-Robotics' registered limits (300, 600). At the ball's top
#: speed, 0.052 a step (measured), crossing the U (6 cells of path) takes about 120 steps.
EPISODE_STEPS = {"umaze": 150, "medium": 300}
#: PointMaze's own success distance, and its ball's radius (assets/point/point.xml).
SUCCESS = 0.45
BALL = 0.1
N_TEST = 100
TEST_SEED = 20261207  # one test set (and one start per test goal) for every run
#: The share of the teacher's last goals the focus measure reads (as docs/rl_curriculum.md's).
LAST_GOALS = 200


class Maze:
    """A map's geometry, without MuJoCo: unit cells, centred on the origin as PointMaze places
    them (cell (i, j) at x = j + 0.5 - width / 2, y = height / 2 - i - 0.5)."""

    def __init__(self, name: str) -> None:
        self.name = name
        self.map = MAPS[name]
        grid = np.array([[c == 1 for c in row] for row in self.map])
        self.walls = self.centres(np.argwhere(grid))
        self.free_cells = self.centres(np.argwhere(~grid))
        #: The goal box: the extent of the free cells' centres.
        self.low, self.high = self.free_cells.min(axis=0), self.free_cells.max(axis=0)
        self.start = self.centres(np.argwhere(np.array([[c == "r" for c in row] for row in self.map])))[0]

    def centres(self, cells: np.ndarray) -> np.ndarray:
        h, w = len(self.map), len(self.map[0])
        return np.column_stack([cells[:, 1] + 0.5 - w / 2, h / 2 - cells[:, 0] - 0.5]).astype(np.float64)

    def wall_distance(self, points: Any) -> np.ndarray:
        """Each point's distance to the nearest wall (0 inside one)."""
        p = np.atleast_2d(np.asarray(points, dtype=np.float64))
        gap = np.maximum(np.abs(p[:, None, :] - self.walls[None, :, :]) - 0.5, 0.0)
        return np.sqrt((gap**2).sum(axis=2)).min(axis=1)

    def reachable(self, points: Any) -> np.ndarray:
        """Whether the ball's centre can be at each point: in a free cell and at least its
        radius from every wall (the maze is closed by walls, so this is inside it)."""
        return self.wall_distance(points) >= BALL

    def uniform_reachable(self, rng: np.random.Generator, n: int) -> np.ndarray:
        """``n`` points uniform over the reachable set within the goal box, by rejection."""
        out = np.empty((0, 2))
        while len(out) < n:
            g = rng.uniform(self.low, self.high, size=(4 * n, 2))
            out = np.concatenate([out, g[self.reachable(g)]])
        return out[:n]

    def reachable_share(self, n: int = 200_000, seed: int = 0) -> float:
        """The share of the goal box the ball can be in (Monte Carlo)."""
        g = np.random.default_rng(seed).uniform(self.low, self.high, size=(n, 2))
        return float(self.reachable(g).mean())


class MazeOracle:
    """Goals uniform over the maze's reachable set within the goal box, drawn from ``seed``; told
    competences, it ignores them: the curriculum of pure focus, every goal possible and none
    preferred."""

    def __init__(self, geometry: Maze, seed: int) -> None:
        self.geometry, self.low, self.high = geometry, geometry.low.copy(), geometry.high.copy()
        self._rng = np.random.default_rng(seed)

    def sample(self) -> np.ndarray:
        return self.geometry.uniform_reachable(self._rng, 1)[0]

    def update(self, goal: Any, competence: float) -> None:
        return None


def make_env(name: str, goal_via: str = "observation") -> Any:
    """One PointMaze of the map ``name`` with the dense reward, taking goals through GoalSlot
    (``goal_via="options"`` only to show that PointMaze ignores them)."""
    from gymnasium.wrappers import TimeLimit
    from gymnasium_robotics.envs.maze.point_maze import PointMazeEnv

    from ..adapters.gym import GoalSlot

    env = PointMazeEnv(maze_map=MAPS[name], reward_type="dense", continuing_task=True)
    return TimeLimit(GoalSlot(env, goal_via=goal_via, success=SUCCESS if goal_via == "observation" else None), EPISODE_STEPS[name])


def test_goals(maze: Maze) -> np.ndarray:
    """The held-back test goals: N_TEST uniform over the reachable set, one set for every run."""
    return maze.uniform_reachable(np.random.default_rng(TEST_SEED), N_TEST)


#: Evaluation environments, one set per map and process (building one compiles a MuJoCo model,
#: 0.14 s); every test episode resets them with its own seed, so reuse changes nothing.
_EVAL_ENVS: dict[str, list[Any]] = {}
EVAL_BATCH = 25


def evaluate(model: Any, name: str, goals: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The deterministic policy from the start cell towards every test goal, EVAL_BATCH goals at
    a time (one batched forward pass per step), test goal k's episode reset with the seed
    TEST_SEED + k: whether each goal is reached (within SUCCESS) at the episode's end, and the
    final distances."""
    if name not in _EVAL_ENVS:
        _EVAL_ENVS[name] = [make_env(name) for _ in range(EVAL_BATCH)]
    envs = _EVAL_ENVS[name]
    success, distance = np.zeros(len(goals), bool), np.zeros(len(goals))
    for first in range(0, len(goals), EVAL_BATCH):
        batch = list(range(first, min(first + EVAL_BATCH, len(goals))))
        obs = []
        for e, k in zip(envs, batch):
            e.get_wrapper_attr("set_next_goal")(goals[k])
            obs.append(e.reset(seed=TEST_SEED + k)[0])
        info: list[dict] = []
        for _ in range(EPISODE_STEPS[name]):
            actions, _ = model.predict({key: np.stack([o[key] for o in obs]) for key in obs[0]}, deterministic=True)
            steps = [e.step(a) for e, a in zip(envs, actions)]
            obs, info = [s[0] for s in steps], [s[4] for s in steps]
        success[batch] = [i["is_success"] for i in info]
        distance[batch] = [i["distance"] for i in info]
    return success, distance


class _AskTell:
    """The bench's guarded teacher as the goal selector TeacherCallback drives; keeps the goals."""

    def __init__(self, ask: Callable[[], Any], tell: Callable[[Any, float], None], low: np.ndarray, high: np.ndarray) -> None:
        self.ask, self.tell, self.low, self.high = ask, tell, low, high
        self.goals: list[np.ndarray] = []

    def sample(self) -> Any:
        goal = self.ask()
        self.goals.append(np.asarray(goal, dtype=np.float64))
        return goal

    def update(self, goal: Any, competence: float) -> None:
        self.tell(goal, competence)


class MazeTask(BenchTask):
    """PPO in a PointMaze (see the module's text); ``maze`` names the map."""

    space = "box"
    maze: ClassVar[str] = "umaze"
    requires = (("stable_baselines3", "gymnasium_robotics"), 'the sb3 extra and Gymnasium-Robotics: pip install "saggriac[sb3]" gymnasium-robotics')
    unit = "environment steps"
    points = 10
    #: Set by the registered pilot's rules (docs/evidence/pointmaze.md): the study's budget on
    #: each map, for the standard and full tiers alike.
    budgets: ClassVar[dict[str, int | None]] = {"quick": None, "standard": 120_000, "full": 120_000}
    #: The pilot's CPU seconds per step at 200,000 steps (docs/evidence/pointmaze.md): 135.6 s
    #: a run on the medium maze (of which 23.4 scoring), 114.7 on the U-maze.
    cpu_per_unit: ClassVar[float | None] = 135.6 / 200_000

    @classmethod
    def child_seeds(cls, seed: int) -> tuple[int, int]:
        """(teacher's seed, the run's seed): as the deep-RL arm's (:func:`saggriac.bench.rl.run_seeds`)."""
        return run_seeds(seed)[2], seed

    def __init__(self, seed: int) -> None:
        super().__init__(seed)
        self.geometry = Maze(self.maze)
        self.low, self.high = self.geometry.low.copy(), self.geometry.high.copy()
        self.scale = float(np.linalg.norm(self.high - self.low))
        self._oracle: MazeOracle | None = None
        self._measures: list[dict[str, float]] = []

    def oracle_teacher(self, seed: int) -> MazeOracle:
        """The oracle as a teacher drawing from ``seed`` (the run's teacher seed)."""
        return MazeOracle(self.geometry, seed)

    def oracle(self) -> Any:
        """A goal of :meth:`oracle_teacher` seeded with this run's teacher seed."""
        if self._oracle is None:
            self._oracle = self.oracle_teacher(self.child_seeds(self.seed)[0])
        return self._oracle.sample()

    def expert_knowledge(self) -> Knowledge:
        """easy: the start cell less the ball's radius (a box of side 0.8 about its centre),
        where the first goals need the smallest movements; target: the goal box, which the
        reachable set where the test goals lie spans."""
        half = 0.5 - BALL
        return self.knowledge((self.geometry.start - half, self.geometry.start + half), (self.low, self.high))

    def competence(self, info: dict[str, Any]) -> float:
        """What the teacher is told at an episode's end: max(0, 1 - final distance / the goal
        box's diagonal)."""
        return max(0.0, 1.0 - float(info["distance"]) / self.scale)

    def play(self, ask: Callable[[], Any], tell: Callable[[Any, float], None], budget: int) -> list[tuple[int, float]]:
        goals = test_goals(self.geometry)
        teacher = _AskTell(ask, tell, self.low, self.high)
        curve: list[tuple[int, float]] = []
        self._measures = []
        scoring = 0.0

        def score(step: int, model: Any, _callback: Any) -> None:
            nonlocal scoring
            if step == 0:
                return
            cpu = time.process_time()
            success, distance = evaluate(model, self.maze, goals)
            scoring += time.process_time() - cpu
            curve.append((step, float(success.mean())))
            asked = np.array(teacher.goals).reshape(-1, 2)
            inside = self.geometry.reachable(asked) if len(asked) else np.zeros(0, bool)
            self._measures.append(
                dict(
                    distance=float(distance.mean()),
                    goals_asked=float(len(asked)),
                    goals_reachable=float(inside.mean()) if len(asked) else float("nan"),
                    reachable_share=float(inside[-LAST_GOALS:].mean()) if len(asked) else float("nan"),
                    scoring_cpu_seconds=scoring,
                )
            )

        train_learner(lambda: make_env(self.maze), self.competence, teacher, self.seed, budget, max(1, budget // self.points), score)
        return curve

    def own_measures(self) -> list[dict[str, float]]:
        """At each scoring: the mean final distance to the test goals, the goals the teacher was
        asked so far, the share of them in the reachable set (all; the last LAST_GOALS:
        reachable_share, as the deep-RL arm's), and the CPU seconds spent scoring so far."""
        return list(self._measures)


@register
class PointMazeUMaze(MazeTask):
    name, maze = "rl-pointmaze-umaze", "umaze"
    budgets = {"quick": None, "standard": 200_000, "full": 200_000}
    cpu_per_unit = 114.7 / 200_000
    learner = "PPO (SB3), PointMaze U-maze, dense reward"
    measures = "helping a deep-RL student where walls cut the goal box: 48 % of it the ball cannot be in, and the reachable set bends round a wall"


@register
class PointMazeMedium(MazeTask):
    name, maze = "rl-pointmaze-medium", "medium"
    study_seeds = tuple(range(1100, 1131))  # docs/figures/evidence/pointmaze/protocol.json
    learner = "PPO (SB3), PointMaze medium maze, dense reward"
    measures = "the same in Gymnasium-Robotics' medium maze (8 x 8 cells): longer paths, more walls inside the goal box"
