"""A small learner trained on Gymnasium vector environments whose goals a saggriac selector picks.

    pip install "saggriac[gymnasium]"
    python examples/gymnasium_curriculum.py [--envs 8] [--episodes 400] [--seed 0]

The environment is ``saggriac/PlanarArmExp2-v0``: the paper's 15-joint arm with the goal space of
its experiment 2, nine times the reachable area. The learner is a nearest-neighbour inverse model:
it remembers every (end-effector position, joint angles) pair it visits, and for a goal it heads,
in joint space, for the remembered angles whose position was closest to the goal, with some
exploration noise. The teacher is either SAGG-RIAC's region tree or uniform goals; both go
through :class:`saggriac.adapters.gym.VectorSelectorGoals`. At the end, each learner is tested on goals
uniform in the reachable half-disk, heading for them the same way without noise.
"""

from __future__ import annotations

import argparse
import time

import gymnasium
import numpy as np
from scipy.spatial import cKDTree

import saggriac as sg
import saggriac.adapters.gym  # noqa: F401  (registers saggriac/...-v0)


class NearestNeighbourReacher:
    """Heads for the remembered joint angles whose position was closest to the goal."""

    def __init__(self, n_joints: int, max_step: float, noise: float, rng: np.random.Generator) -> None:
        self.xs: list[np.ndarray] = []
        self.thetas: list[np.ndarray] = []
        self.tree: cKDTree | None = None
        self.max_step, self.noise, self.rng, self.n = max_step, noise, rng, n_joints
        self.targets: np.ndarray | None = None

    def remember(self, x: np.ndarray, theta: np.ndarray) -> None:
        self.xs.extend(x)
        self.thetas.extend(theta)

    def refit(self) -> None:
        self.tree = cKDTree(np.array(self.xs))

    def aim(self, goals: np.ndarray, which: np.ndarray | None = None) -> None:
        """Pick the joint-space targets for the goals (of the environments ``which``)."""
        _, idx = self.tree.query(goals)
        t = np.array(self.thetas)[idx]
        if self.targets is None or which is None:
            self.targets = t
        else:
            self.targets[which] = t[which]

    def act(self, theta: np.ndarray, explore: bool) -> np.ndarray:
        d = self.targets - theta
        if explore:
            d = d + self.rng.normal(0.0, self.noise, d.shape)
        return np.clip(d, -self.max_step, self.max_step)


def train(teacher: str, n_envs: int, episodes: int, seed: int) -> float:
    steps = gymnasium.spec("saggriac/PlanarArmExp2-v0").max_episode_steps
    venv = gymnasium.make_vec("saggriac/PlanarArmExp2-v0", num_envs=n_envs, vectorization_mode="sync", action_scale="joint")
    low, high = [0.0, -150.0], [150.0, 150.0]
    selector = sg.SaggRiacSelector(low, high, seed=seed) if teacher == "sagg_riac" else sg.RandomSelector(low, high, seed=seed)
    env = saggriac.adapters.gym.VectorSelectorGoals(venv, selector)
    rng = np.random.default_rng(seed)
    learner = NearestNeighbourReacher(15, 0.05, 0.05, rng)
    obs, _ = env.reset(seed=seed)
    learner.remember(obs["achieved_goal"], obs["observation"])
    learner.refit()
    learner.aim(obs["desired_goal"])
    for t in range(episodes // n_envs * (steps + 1)):
        obs, _, term, trunc, info = env.step(learner.act(obs["observation"], explore=True))
        learner.remember(obs["achieved_goal"], obs["observation"])
        starting = np.isfinite(info["competence"])  # episodes end together here; refit then
        if starting.any() or t % (steps + 1) == steps:
            learner.refit()
            learner.aim(obs["desired_goal"])
    env.close()
    # Test: goals uniform in the reachable half-disk, reached from rest without noise.
    test_rng = np.random.default_rng(12345)
    r, a = 50.0 * np.sqrt(test_rng.uniform(0, 1, 64)), test_rng.uniform(-np.pi / 2, np.pi / 2, 64)
    goals = np.stack([r * np.cos(a), r * np.sin(a)], axis=1)
    tenv = gymnasium.make("saggriac/PlanarArmExp2-v0", action_scale="joint").unwrapped
    errors = []
    for g in goals:
        o, _ = tenv.reset(options={"goal": g})
        learner.aim(g[None, :])
        for _ in range(steps):
            o, *_ = tenv.step(learner.act(o["observation"][None, :], explore=False)[0])
        errors.append(np.linalg.norm(o["achieved_goal"] - g))
    return float(np.mean(errors))


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--envs", type=int, default=8)
    p.add_argument("--episodes", type=int, default=400)
    p.add_argument("--seed", type=int, default=0)
    a = p.parse_args()
    for teacher in ("sagg_riac", "random"):
        t0 = time.perf_counter()
        err = train(teacher, a.envs, a.episodes, a.seed)
        print(f"{teacher:10s}: mean test error {err:6.2f} (arm length 50) after {a.episodes} episodes, {time.perf_counter() - t0:.1f} s")


if __name__ == "__main__":
    main()
