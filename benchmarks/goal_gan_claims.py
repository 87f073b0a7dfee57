"""Goal GAN against its paper's own claims (Florensa, Held, Geng & Abbeel, ICML 2018), on a task
built for them: a U-shaped maze in [-1, 1]^2, as the paper's Ant maze (Sec. 5.2, Fig. 3-4).

The learner reaches a goal with a probability set by the goal's distance from the start along the
maze (geodesic, around the wall): 1 up to its reach R - 0.1, 0 beyond R + 0.1, linear between;
a goal inside the wall is never reached. It learns only from what it can just do: a success on a
goal it reaches with probability at most 0.9 extends R by ``lr`` (a goal always reached, or never,
teaches nothing: the paper's reason for goals of intermediate difficulty). Each goal the teacher
asks is attempted once and told 1 or 0.

The paper's two claims, measured here for Goal GAN and for uniform goals (``RandomSelector``):

- the share of asked goals of intermediate difficulty (the learner's true success probability
  in [0.1, 0.9] when the goal is asked, the paper's R_min and R_max) rises above uniform's;
- coverage (the mean success probability over the maze's free cells, the paper's metric) grows,
  and faster than with uniform goals.

    python benchmarks/goal_gan_claims.py [--seeds 5] [--goals 6000] [--windows 6]

tests/teachers/test_goal_gan_claims.py runs a shorter version and checks both claims.
"""

from __future__ import annotations

import argparse
import time
from collections import deque
from typing import Callable, Iterable

import numpy as np

import saggriac

#: The maze's grid: N x N cells over [-1, 1]^2; the wall fills x < WALL_X, |y| < WALL_HALF.
N, WALL_X, WALL_HALF = 40, 0.5, 0.3
START = (-0.8, -0.7)
BAND = 0.1  # half-width of the band of intermediate success around the reach
R_MIN, R_MAX = 0.1, 0.9


def _centres() -> np.ndarray:
    return -1.0 + (np.arange(N) + 0.5) * (2.0 / N)


def _cell(goal: np.ndarray) -> tuple[int, int]:
    i = np.clip(((np.asarray(goal) + 1.0) * N / 2.0).astype(int), 0, N - 1)
    return int(i[0]), int(i[1])


def maze() -> tuple[np.ndarray, np.ndarray]:
    """(free, distance): which cells are free of the wall, and each free cell's geodesic distance
    from the start along the maze (4-neighbour steps; inf in the wall)."""
    c = _centres()
    x, y = np.meshgrid(c, c, indexing="ij")
    free = ~((x < WALL_X) & (np.abs(y) < WALL_HALF))
    dist = np.full((N, N), np.inf)
    s = _cell(np.array(START))
    dist[s] = 0.0
    todo = deque([s])
    step = 2.0 / N
    while todo:
        i, j = todo.popleft()
        for di, dj in ((1, 0), (-1, 0), (0, 1), (0, -1)):
            a, b = i + di, j + dj
            if 0 <= a < N and 0 <= b < N and free[a, b] and dist[a, b] == np.inf:
                dist[a, b] = dist[i, j] + step
                todo.append((a, b))
    return free, dist


class MazeLearner:
    """The learner of the module's docstring: reach ``reach`` grows by ``lr`` with each success
    on a goal it reaches with probability <= R_MAX."""

    def __init__(self, seed: int, reach: float = 0.3, lr: float = 0.004) -> None:
        self.free, self.dist = maze()
        self.reach, self.lr = reach, lr
        self.rng = np.random.default_rng(seed)

    def p_cells(self) -> np.ndarray:
        return np.clip((self.reach + BAND - self.dist) / (2 * BAND), 0.0, 1.0)  # inf -> 0

    def p(self, goal: np.ndarray) -> float:
        return float(self.p_cells()[_cell(goal)])

    def attempt(self, goal: np.ndarray) -> float:
        p = self.p(goal)
        success = self.rng.random() < p
        if success and p <= R_MAX:
            self.reach += self.lr
        return float(success)

    def coverage(self) -> float:
        """The mean success probability over the maze's free cells."""
        return float(self.p_cells()[self.free].mean())


def run(name: str, n_goals: int, seed: int, windows: int) -> dict[str, np.ndarray]:
    """Teach a MazeLearner with the teacher ``name`` for ``n_goals`` goals: per window of goals,
    the share of goals of intermediate difficulty when asked, and the coverage at 0 and at each
    window's end."""
    learner = MazeLearner(seed)
    teacher = make_teacher(name, seed, learner)
    goid = np.zeros(n_goals, dtype=bool)
    coverage = [learner.coverage()]
    edges = np.linspace(0, n_goals, windows + 1).round().astype(int)
    for k in range(n_goals):
        g = teacher.sample()
        goid[k] = R_MIN <= learner.p(g) <= R_MAX
        teacher.update(g, learner.attempt(g))
        if k + 1 in edges[1:]:
            coverage.append(learner.coverage())
    return {"goid": np.array([goid[a:b].mean() for a, b in zip(edges[:-1], edges[1:])]), "coverage": np.array(coverage), "reach": np.array(learner.reach)}


class Oracle:
    """The claims' upper reference: it sees the learner and asks a goal uniformly among the free
    cells of intermediate difficulty (uniform in the box when there is none). It shows that the
    task rewards what the paper claims Goal GAN finds."""

    def __init__(self, learner: MazeLearner, seed: int) -> None:
        self.learner, self.rng = learner, np.random.default_rng(seed)
        c = _centres()
        self.x, self.y = np.meshgrid(c, c, indexing="ij")

    def sample(self) -> np.ndarray:
        p = self.learner.p_cells()
        ok = np.flatnonzero(((p >= R_MIN) & (p <= R_MAX)).ravel())
        if ok.size == 0:
            return self.rng.uniform(-1.0, 1.0, 2)
        k = ok[self.rng.integers(ok.size)]
        half = 1.0 / N
        return np.array([self.x.ravel()[k], self.y.ravel()[k]]) + self.rng.uniform(-half, half, 2)

    def update(self, goal: np.ndarray, competence: float) -> None:
        pass


TEACHERS = ("goal_gan", "uniform", "oracle")


def make_teacher(name: str, seed: int, learner: MazeLearner) -> object:
    box = ([-1.0, -1.0], [1.0, 1.0])
    if name == "goal_gan":
        return saggriac.GoalGanSelector(*box, seed=seed)
    if name == "uniform":
        return saggriac.RandomSelector(*box, seed=seed)
    return Oracle(learner, seed)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--seeds", type=int, default=5)
    p.add_argument("--goals", type=int, default=6000)
    p.add_argument("--windows", type=int, default=6)
    a = p.parse_args()
    free, dist = maze()
    print(f"U-maze {N}x{N} over [-1, 1]^2: {free.sum()} free cells, longest path {dist[free].max():.2f}; seeds 0-{a.seeds - 1}, {a.goals} goals each")
    summarise(run_all(TEACHERS, run, a.seeds, a.goals, a.windows))


def run_all(names: Iterable[str], run: Callable[[str, int, int, int], dict[str, np.ndarray]], seeds: int, goals: int, windows: int) -> dict[str, list[dict[str, np.ndarray]]]:
    """``run(name, goals, seed, windows)`` for every seed and name, timed as it goes."""
    results: dict[str, list[dict[str, np.ndarray]]] = {name: [] for name in names}
    for seed in range(seeds):
        for name in results:
            t0 = time.perf_counter()
            results[name].append(run(name, goals, seed, windows))
            print(f"  seed {seed} {name:8s} {time.perf_counter() - t0:5.1f} s, final coverage {results[name][-1]['coverage'][-1]:.3f}", flush=True)
    return results


def summarise(results: dict[str, list[dict[str, np.ndarray]]]) -> None:
    """Each teacher's share of goals of intermediate difficulty and coverage, over seeds."""
    for name, rs in results.items():
        goid = np.array([r["goid"] for r in rs])
        cov = np.array([r["coverage"] for r in rs])
        print(f"{name}: share of goals of intermediate difficulty per window (mean +- sd over seeds)")
        print("   " + "  ".join(f"{m:.3f}+-{s:.3f}" for m, s in zip(goid.mean(0), goid.std(0))))
        print(f"{name}: coverage at 0 and after each window")
        print("   " + "  ".join(f"{m:.3f}+-{s:.3f}" for m, s in zip(cov.mean(0), cov.std(0))))
        print(f"{name}: per seed, share in the last window / final coverage: " + ", ".join(f"{g[-1]:.3f}/{c[-1]:.3f}" for g, c in zip(goid, cov)))


if __name__ == "__main__":
    main()
