"""The authors' Goal GAN, transcribed in PyTorch, on benchmarks/goal_gan_claims.py's U-maze: does
the published algorithm meet the claims that saggriac's Goal GAN meets only at first?

Transcribed from the algorithm as the authors' code runs it (Florensa's rllab-curriculum, as
TeachMyAgent's GoalGAN wraps it; TensorFlow 1 does not install here, so it is re-written, not
run): a generator of noise (dimension 2) through two ReLU layers of 256 and tanh, a discriminator
of two leaky-ReLU (0.1) layers of 128, Xavier initialisation, RMSProp (learning rate 0.001) for
both, batches of 64 labelled goals and 64 generated ones. The least-squares losses: the
discriminator's targets 2 * label - 1 for labelled goals (1 good, -1 bad) and -1 for generated
ones; the generator's target 1 (the code's, where the paper's text prints c = 0). Each generated
goal gets Gaussian noise of 0.05 of the box's width (state_noise_level, the value of the SPDL
authors' Goal GAN runs) and is clipped to the box; it is asked n_rollouts = 2 times; a goal is
good when its success rate is in [0.25, 0.75] (TeachMyAgent's bounds; with 2 attempts the same as
the paper's [0.1, 0.9]); goals succeeded more often join a buffer of old goals (kept 0.01 of
the box's diagonal apart) from which 20 % of the goals are replayed, with the same noise. Every
100 labelled goals that hold a good one, 250 iterations of training. Before the first goal the
GAN is trained for 500 iterations on 1,000 goals uniform in the box, all labelled good (the SPDL
authors' runs pretrain it so).

    python benchmarks/references/goal_gan_authors.py [--seeds 5] [--goals 6000] [--windows 6] [--ablations]

Prints, beside saggriac's GoalGanSelector and uniform goals on the same seeds, the same lines as
benchmarks/goal_gan_claims.py. Needs torch (the sb3 extra brings it).
"""

from __future__ import annotations

import argparse
import importlib.util
import sys
from collections import deque
from pathlib import Path

import numpy as np
import torch
from torch import nn

_CLAIMS = Path(__file__).resolve().parents[1] / "goal_gan_claims.py"
_spec = importlib.util.spec_from_file_location("goal_gan_claims", _CLAIMS)
claims = importlib.util.module_from_spec(_spec)
sys.modules["goal_gan_claims"] = claims
_spec.loader.exec_module(claims)


def _mlp(sizes: list[int], hidden: nn.Module, out: nn.Module | None) -> nn.Sequential:
    layers: list[nn.Module] = []
    for i, (a, b) in enumerate(zip(sizes[:-1], sizes[1:])):
        lin = nn.Linear(a, b)
        nn.init.xavier_uniform_(lin.weight)
        nn.init.zeros_(lin.bias)
        layers.append(lin)
        if i < len(sizes) - 2:
            layers.append(hidden)
    if out is not None:
        layers.append(out)
    return nn.Sequential(*layers)


class AuthorsGoalGan:
    """The teacher of the module's docstring, with sample() and update(goal, competence)."""

    def __init__(self, low, high, seed: int, n_rollouts: int = 2, update_size: int = 100, p_old: float = 0.2, noise_level: float = 0.05, lb: float = 0.25, ub: float = 0.75, iters: int = 250, target: float = 1.0, pretrain: bool = True) -> None:
        torch.manual_seed(seed)
        self.rng = np.random.default_rng(seed)
        self.low, self.high = np.asarray(low, dtype=float), np.asarray(high, dtype=float)
        self.centre, self.width = (self.low + self.high) / 2, self.high - self.low
        d = len(self.low)
        self.d = d
        self.gen = _mlp([d, 256, 256, d], nn.ReLU(), nn.Tanh())
        self.dis = _mlp([d, 128, 128, 1], nn.LeakyReLU(0.1), None)
        self.opt_g = torch.optim.RMSprop(self.gen.parameters(), lr=1e-3)
        self.opt_d = torch.optim.RMSprop(self.dis.parameters(), lr=1e-3)
        self.n_rollouts, self.update_size, self.p_old, self.lb, self.ub, self.iters, self.target = n_rollouts, update_size, p_old, lb, ub, iters, target
        self.noise = noise_level * self.width
        self.queue: deque[np.ndarray] = deque()
        self.pending: dict[bytes, list[list[bool]]] = {}
        self.goals: list[np.ndarray] = []
        self.labels: list[float] = []
        self.old: list[np.ndarray] = []
        self.min_gap = 0.01 * float(np.linalg.norm(self.width))
        if pretrain:
            pre = self.rng.uniform(self.low, self.high, size=(1000, d))
            self._train(pre, np.ones(1000), 500)

    def _generate(self, n: int) -> np.ndarray:
        with torch.no_grad():
            out = self.gen(torch.randn(n, self.d)).numpy().astype(float)
        return self.centre + out * self.width  # the authors' scaling: tanh's [-1, 1] onto twice the box

    def _train(self, goals: np.ndarray, labels: np.ndarray, iters: int) -> None:
        x = torch.tensor((goals - self.centre) / self.width, dtype=torch.float32)
        y = torch.tensor(labels, dtype=torch.float32)[:, None]
        n, start = len(x), 0
        for _ in range(iters):
            if n <= 64:
                bx, by = x, y
            else:
                idx = (start + torch.arange(64)) % n
                bx, by, start = x[idx], y[idx], (start + 64) % n
            z = torch.randn(64, self.d)
            with torch.no_grad():
                fake = self.gen(z)
            d_in = torch.cat([bx, fake])
            d_target = torch.cat([2 * by - 1, -torch.ones(64, 1)])
            self.opt_d.zero_grad()
            ((self.dis(d_in) - d_target) ** 2).mean().backward()
            self.opt_d.step()
            self.opt_g.zero_grad()
            ((self.dis(self.gen(z)) - self.target) ** 2).mean().backward()
            self.opt_g.step()

    def sample(self) -> np.ndarray:
        if self.queue:
            return self.queue.popleft()
        if self.rng.random() > self.p_old or not self.old:
            g = np.clip(self._generate(1)[0] + self.rng.standard_normal(self.d) * self.noise, self.low, self.high).astype(np.float32)
            self.pending.setdefault(g.tobytes(), []).append([])
            for _ in range(self.n_rollouts - 1):
                self.queue.append(g.copy())
            return g
        g = self.old[self.rng.integers(len(self.old))] + self.rng.standard_normal(self.d) * self.noise
        return np.clip(g, self.low, self.high).astype(np.float32)

    def update(self, goal: np.ndarray, competence: float) -> None:
        key = np.asarray(goal, dtype=np.float32).tobytes()
        if key not in self.pending:
            return  # a replayed old goal: not labelled, as in the authors' code
        runs = self.pending[key]
        runs[0].append(competence >= 0.5)
        if len(runs[0]) >= self.n_rollouts:
            rate = float(np.mean(runs.pop(0)))
            if not runs:
                del self.pending[key]
            g = np.frombuffer(key, dtype=np.float32).astype(float)
            self.goals.append(g)
            self.labels.append(float(self.lb <= rate <= self.ub))
            if rate > self.ub and (not self.old or np.min(np.linalg.norm(np.array(self.old) - g, axis=1)) > self.min_gap):
                self.old.append(g)
        if len(self.goals) >= self.update_size:
            if any(self.labels):
                self._train(np.array(self.goals), np.array(self.labels), self.iters)
            self.goals, self.labels = [], []


#: One change at a time from the authors' algorithm, toward saggriac's.
ABLATIONS = {"authors": {}, "target c=0": {"target": 0.0}, "no output noise": {"noise_level": 0.0}, "no pretraining": {"pretrain": False}}


def run(name: str, n_goals: int, seed: int, windows: int) -> dict[str, np.ndarray]:
    if name not in ABLATIONS:
        return claims.run(name, n_goals, seed, windows)
    learner = claims.MazeLearner(seed)
    teacher = AuthorsGoalGan([-1.0, -1.0], [1.0, 1.0], seed, **ABLATIONS[name])
    goid = np.zeros(n_goals, dtype=bool)
    coverage = [learner.coverage()]
    edges = np.linspace(0, n_goals, windows + 1).round().astype(int)
    for k in range(n_goals):
        g = teacher.sample().astype(float)
        goid[k] = claims.R_MIN <= learner.p(g) <= claims.R_MAX
        teacher.update(g, learner.attempt(g))
        if k + 1 in edges[1:]:
            coverage.append(learner.coverage())
    return {"goid": np.array([goid[a:b].mean() for a, b in zip(edges[:-1], edges[1:])]), "coverage": np.array(coverage)}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--seeds", type=int, default=5)
    p.add_argument("--goals", type=int, default=6000)
    p.add_argument("--windows", type=int, default=6)
    p.add_argument("--ablations", action="store_true", help="the authors' algorithm with one change at a time instead of beside saggriac's")
    a = p.parse_args()
    torch.set_num_threads(1)
    names = tuple(ABLATIONS) if a.ablations else ("authors", "goal_gan", "uniform")
    claims.summarise(claims.run_all(names, run, a.seeds, a.goals, a.windows))


if __name__ == "__main__":
    main()
