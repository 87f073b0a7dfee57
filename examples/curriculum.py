"""SAGG-RIAC as a curriculum teacher for a learner written in Python (no arm at all).

The toy learner can only make progress in the left strip x < 0.3 of the goal space [0, 1]^2:
there its competence at a goal is minus the distance to the nearest goal it has practised, so
practice helps. Everywhere else the outcome is noise it can never learn. A good teacher spends
its goals where competence progresses.

    python examples/curriculum.py [--goals 3000] [--seed 0]
"""

import argparse

import numpy as np

import saggriac


class ToyLearner:
    """Skill at a goal grows with the practice it got nearby, but only in the strip x < 0.3."""

    def __init__(self, seed: int, noise: float) -> None:
        self.rng = np.random.default_rng(seed)
        self.noise = noise
        self.practised = np.empty((0, 2))

    def attempt(self, goal: np.ndarray) -> float:
        """Competence in [-1, 0] (higher is better), as in the paper's eq. 7."""
        if goal[0] >= 0.3:
            # Unlearnable: a poor outcome whatever the practice, with some noise.
            return float(np.clip(-0.9 + self.rng.normal(0.0, self.noise), -1.0, 0.0))
        near = int(np.sum(np.linalg.norm(self.practised - goal, axis=1) < 0.1)) if len(self.practised) else 0
        self.practised = np.vstack([self.practised, goal])
        return -1.0 / (1.0 + 0.2 * near)


def run(teacher, n_goals: int, seed: int, noise: float) -> float:
    learner = ToyLearner(seed, noise)
    for _ in range(n_goals):
        goal = teacher.sample()
        teacher.update(goal, learner.attempt(goal))
    asked = teacher.history()["asked_goal"]
    return float(np.mean(asked[n_goals // 2 :, 0] < 0.3))


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--goals", type=int, default=3000)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--noise", type=float, default=0.02, help="std of the unlearnable outcome (default 0.02)")
    a = p.parse_args()
    sagg = saggriac.SaggRiacSelector([0, 0], [1, 1], seed=a.seed)
    share_sagg = run(sagg, a.goals, a.seed, a.noise)
    share_random = run(saggriac.RandomSelector([0, 0], [1, 1], seed=a.seed), a.goals, a.seed, a.noise)
    print(f"share of goals in the learnable strip (second half): SAGG-RIAC {share_sagg:.2f}, random {share_random:.2f}")
    leaves = sagg.leaves()
    print(f"SAGG-RIAC split the space into {len(leaves['interest'])} regions; the most interesting:")
    order = np.argsort(-leaves["interest"])[:3]
    for i in order:
        print(f"  x in [{leaves['low'][i][0]:.2f}, {leaves['high'][i][0]:.2f}], y in [{leaves['low'][i][1]:.2f}, {leaves['high'][i][1]:.2f}]: interest {leaves['interest'][i]:.3f}")


if __name__ == "__main__":
    main()
