"""Every teacher on hypercube-unlocking toy tasks, written from the toy space of Portelas, Colas,
Hofmann & Oudeyer (ALP-GMM, CoRL 2019): a score curve per teacher, side by side.

    python benchmarks/toy_tasks.py --out toy/ [--seeds 10] [--spaces 2d 5d 2d+3]

The task space is [0, 1]^d. Its first r dimensions (the relevant ones) are cut into ``bins`` cells
each; the other d - r are irrelevant (they change nothing). A cell is unlocked if it is the cell
at the origin or if a neighbouring cell (one bin away along one relevant dimension) is mastered.
Trying a goal in an unlocked cell practises it: after ``need`` practices the cell is mastered.
The competence told is the cell's progress k / need (k practices so far, 1 once mastered), and 0
in a locked cell. The score is the share of mastered cells. A teacher does well if it finds the
frontier of unlocked cells and keeps its goals there.

Spaces (``--spaces``): ``2d`` (r = 2, 10 bins, 100 cells), ``5d`` (r = 5, 3 bins, 243 cells) and
``2d+3`` (the 2-D task with 3 irrelevant dimensions). Teachers by name (``TEACHERS``; another
teacher joins with one entry): the box teachers with their papers' defaults, ``adr`` from the
box's centre (its default) and ``adr_corner`` from the origin cell's corner (``initial=0``, the
expert knowledge ADR relies on), and the task-list teachers (``discrete_lp``, ``plr``), which are
given the cells as a task list (an advantage: the box teachers must find the cells).

Seed s gives the teacher's generator; the task itself has no randomness. Writes ``runs.csv``,
``curves.csv`` (the score every ``--every`` goals), ``results.md`` and ``toy_tasks.png`` to --out.
"""

from __future__ import annotations

import argparse
import itertools
import multiprocessing as mp
import time
from pathlib import Path
from typing import Callable

import numpy as np
import pandas as pd

import saggriac as sg


class HypercubeUnlock:
    """The toy task: cells of the relevant dimensions, unlocked by mastering a neighbour."""

    def __init__(self, relevant: int, bins: int, irrelevant: int = 0, need: int = 20) -> None:
        self.relevant, self.bins, self.need = relevant, bins, need
        self.dim = relevant + irrelevant
        self.low, self.high = np.zeros(self.dim), np.ones(self.dim)
        self.n_cells = bins**relevant
        self.practice = np.zeros(self.n_cells, dtype=np.int64)
        self.unlocked = np.zeros(self.n_cells, dtype=bool)
        self.unlocked[0] = True
        self._strides = bins ** np.arange(relevant)

    def cell(self, goal: np.ndarray) -> int:
        idx = np.minimum((np.asarray(goal[: self.relevant]) * self.bins).astype(np.int64), self.bins - 1)
        return int(idx @ self._strides)

    def centre(self, cell: int) -> np.ndarray:
        idx = (cell // self._strides) % self.bins
        return np.concatenate([(idx + 0.5) / self.bins, np.full(self.dim - self.relevant, 0.5)])

    def attempt_cell(self, c: int) -> float:
        if not self.unlocked[c]:
            return 0.0
        if self.practice[c] < self.need:
            self.practice[c] += 1
            if self.practice[c] == self.need:
                idx = (c // self._strides) % self.bins
                for j in range(self.relevant):
                    for step in (-1, 1):
                        if 0 <= idx[j] + step < self.bins:
                            self.unlocked[c + step * self._strides[j]] = True
        return self.practice[c] / self.need

    def attempt(self, goal: np.ndarray) -> float:
        return self.attempt_cell(self.cell(goal))

    def score(self) -> float:
        return float(np.mean(self.practice >= self.need))


SPACES = {"2d": dict(relevant=2, bins=10, irrelevant=0), "5d": dict(relevant=5, bins=3, irrelevant=0), "2d+3": dict(relevant=2, bins=10, irrelevant=3)}
BUDGET = {"2d": 10_000, "5d": 15_000, "2d+3": 10_000}

# name -> (factory(task, seed), whether its goals are cell indices)
TEACHERS: dict[str, tuple[Callable[[HypercubeUnlock, int], object], bool]] = {
    "sagg_riac": (lambda e, s: sg.SaggRiacSelector(e.low, e.high, seed=s), False),
    "riac": (lambda e, s: sg.RiacSelector(e.low, e.high, seed=s), False),
    "alp_gmm": (lambda e, s: sg.AlpGmmSelector(e.low, e.high, seed=s), False),
    "covar_gmm": (lambda e, s: sg.CovarGmmSelector(e.low, e.high, seed=s), False),
    "adr": (lambda e, s: sg.AdrSelector(e.low, e.high, seed=s), False),
    "adr_corner": (lambda e, s: sg.AdrSelector(e.low, e.high, seed=s, initial=0.0), False),
    "spdl": (lambda e, s: sg.SpdlSelector(e.low, e.high, seed=s), False),
    "spdl_corner": (lambda e, s: sg.SpdlSelector(e.low, e.high, seed=s, init_mean=0.05), False),
    "goal_gan": (lambda e, s: sg.GoalGanSelector(e.low, e.high, seed=s), False),
    "random": (lambda e, s: sg.RandomSelector(e.low, e.high, seed=s), False),
    "discrete_lp": (lambda e, s: sg.DiscreteLpSelector(e.n_cells, seed=s), True),
    "plr": (lambda e, s: sg.PlrSelector(e.n_cells, seed=s), True),
}
NAMES = {"sagg_riac": "SAGG-RIAC", "riac": "RIAC", "alp_gmm": "ALP-GMM", "covar_gmm": "Covar-GMM", "adr": "ADR", "adr_corner": "ADR (from the origin)", "spdl": "SPDL", "spdl_corner": "SPDL (from the origin)", "goal_gan": "Goal GAN", "random": "random", "discrete_lp": "discrete LP (cells given)", "plr": "PLR (cells given)"}


def one_run(job: tuple[str, str, int, int]) -> tuple[dict, list[dict]]:
    name, space, seed, every = job
    env = HypercubeUnlock(**SPACES[space])
    make, cells = TEACHERS[name]
    teacher = make(env, seed)
    curve, start = [], time.perf_counter()
    for t in range(1, BUDGET[space] + 1):
        if cells:
            c = teacher.sample_task()
            teacher.update(c, env.attempt_cell(c))
        else:
            g = teacher.sample()
            teacher.update(g, env.attempt(g))
        if t % every == 0:
            curve.append(dict(teacher=name, space=space, seed=seed, goals=t, score=env.score()))
    run = dict(teacher=name, space=space, seed=seed, final=env.score(), auc=float(np.mean([r["score"] for r in curve])), seconds=time.perf_counter() - start)
    return run, curve


def report(runs: pd.DataFrame, curves: pd.DataFrame, out: Path, names: list[str]) -> None:
    lines = ["# Hypercube-unlocking toy tasks: results", "", f"{runs.seed.nunique()} seeds per teacher and space; mean ± sd over seeds. "
             "Final: share of cells mastered after the budget; area: mean of the score curve (speed).", ""]
    spaces = [s for s in SPACES if s in set(runs.space)]
    lines.append("| teacher | " + " | ".join(f"{s} final | {s} area" for s in spaces) + " |")
    lines.append("|---|" + "---|---|" * len(spaces))
    for n in names:
        cells = []
        for s in spaces:
            r = runs[(runs.teacher == n) & (runs.space == s)]
            cells += [f"{r.final.mean():.3f} ± {r.final.std():.3f}", f"{r.auc.mean():.3f} ± {r.auc.std():.3f}"]
        lines.append(f"| {NAMES.get(n, n)} | " + " | ".join(cells) + " |")
    lines += ["", "Budgets: " + ", ".join(f"{s}: {BUDGET[s]:,} goals" for s in spaces) + "."]
    (out / "results.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(spaces), figsize=(5 * len(spaces), 4), squeeze=False)
    for ax, s in zip(axes[0], spaces):
        for n in names:
            c = curves[(curves.teacher == n) & (curves.space == s)].groupby("goals").score
            mu, sd = c.mean(), c.std()
            ls = ":" if TEACHERS[n][1] else ("--" if n.startswith("adr") else "-")
            ax.plot(mu.index, mu.values, ls=ls, label=NAMES.get(n, n))
            ax.fill_between(mu.index, (mu - sd).values, (mu + sd).values, alpha=0.12)
        ax.set_title(f"{s} ({SPACES[s]['bins'] ** SPACES[s]['relevant']} cells)")
        ax.set_xlabel("goals")
        ax.set_ylabel("share of cells mastered")
        ax.set_ylim(0, 1.02)
    axes[0][-1].legend(fontsize=7, loc="lower right")
    fig.tight_layout()
    fig.savefig(out / "toy_tasks.png", dpi=110)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", type=Path, required=True)
    p.add_argument("--seeds", type=int, default=10)
    p.add_argument("--spaces", nargs="+", default=list(SPACES), choices=list(SPACES))
    p.add_argument("--teachers", nargs="+", default=list(TEACHERS), choices=list(TEACHERS))
    p.add_argument("--every", type=int, default=500)
    p.add_argument("--workers", type=int, default=2)
    a = p.parse_args()
    a.out.mkdir(parents=True, exist_ok=True)
    jobs = list(itertools.product(a.teachers, a.spaces, range(a.seeds), [a.every]))
    # The slowest (mixture teachers in 5-D) first, so the pool ends together.
    jobs.sort(key=lambda j: (j[0] not in ("alp_gmm", "covar_gmm"), j[1] != "5d"))
    start = time.perf_counter()
    runs, curves = [], []
    with mp.get_context("spawn").Pool(a.workers) as pool:
        for i, (r, c) in enumerate(pool.imap_unordered(one_run, jobs), 1):
            runs.append(r)
            curves += c
            print(f"\r{i}/{len(jobs)} runs, {time.perf_counter() - start:.0f} s", end="", flush=True)
    print()
    runs_df, curves_df = pd.DataFrame(runs).sort_values(["space", "teacher", "seed"]), pd.DataFrame(curves)
    runs_df.to_csv(a.out / "runs.csv", index=False)
    curves_df.to_csv(a.out / "curves.csv", index=False)
    report(runs_df, curves_df, a.out, a.teachers)
    print(f"{len(jobs)} runs in {time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
