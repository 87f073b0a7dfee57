"""Every teacher on hypercube-unlocking toy tasks, written from the toy space of Portelas, Colas,
Hofmann & Oudeyer (ALP-GMM, CoRL 2019): a score curve per teacher, side by side.

    python benchmarks/toy_tasks.py --out docs/figures/teachers --workers 1

The task space is [0, 1]^d. Its first r dimensions (the relevant ones) are cut into ``bins`` cells
each; the other d - r are irrelevant (they change nothing). A cell is unlocked if it is the cell
at the origin or if a neighbouring cell (one bin away along one relevant dimension) is mastered.
Trying a goal in an unlocked cell practises it: after ``need`` practices the cell is mastered.
The competence told is the cell's progress k / need (k practices so far, 1 once mastered), and 0
in a locked cell. The score is the share of the cells that can be mastered that are. A teacher
does well if it finds the frontier of unlocked cells and keeps its goals there.

Spaces (``--spaces``): ``2d`` (r = 2, 10 bins, 100 cells), ``5d`` (r = 5, 3 bins, 243 cells),
``2d+3`` (the 2-D task with 3 irrelevant dimensions) and ``2d-reach`` (the 2-D task where only
the 21 cells with bin indices i + j <= 5 can ever be unlocked: 79 % of the box is impossible and
always gives 0, like the goals out of an arm's reach). Teachers by name (``TEACHERS``; another
teacher joins with one entry): the box teachers with their papers' defaults, ``adr`` and
``spdl`` from their defaults (the box's centre) and ``adr_corner`` / ``spdl_corner`` from the
origin cell's corner (the expert knowledge they rely on), and the task-list teachers
(``discrete_lp``, ``plr``), which are given every cell as a task list, the impossible ones too
(an advantage: the box teachers must find the cells).

Each run is the bench's task played by its own loop (``saggriac.bench.tasks.BenchTask.play``),
watched for where each goal lands. Seed s gives the teacher's generator; the task itself has no randomness. Writes to --out:
``toy_tasks_runs.csv`` (one row per run: final score, area, where the goals went, leaves, time),
``toy_tasks_curves.csv`` (the score every ``--every`` goals), ``toy_tasks_modes.csv`` (where the
goals of each of a teacher's modes went), the summary table ``toy_tasks_results.md`` and
``toy_tasks_results.csv``, and the figure ``toy_tasks.png``. ``--report-only`` rebuilds the last
three from the runs and curves already in --out, without running anything.
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
from saggriac.bench.tasks import Hypercube, HypercubeCells


class HypercubeUnlock(Hypercube):
    """The bench's hypercube-unlocking task (saggriac.bench.tasks.Hypercube) with its sizes
    given, and where a try lands; the task has no randomness, so its seed is 0."""

    def __init__(self, relevant: int, bins: int, irrelevant: int = 0, need: int = 20, reach: int | None = None) -> None:
        self.relevant, self.bins, self.irrelevant, self.need, self.reach = relevant, bins, irrelevant, need, reach
        super().__init__(seed=0)

    def where(self, c: int) -> str:
        """Where a try of cell c lands now: impossible, locked, frontier or mastered."""
        if not self.possible[c]:
            return "impossible"
        if not self.unlocked[c]:
            return "locked"
        return "mastered" if self.practice[c] >= self.need else "frontier"


class HypercubeUnlockCells(HypercubeCells, HypercubeUnlock):
    """The same task given as its list of cells (goals are cell indices), for task-list teachers."""


SPACES = {"2d": dict(relevant=2, bins=10, irrelevant=0), "5d": dict(relevant=5, bins=3, irrelevant=0), "2d+3": dict(relevant=2, bins=10, irrelevant=3), "2d-reach": dict(relevant=2, bins=10, irrelevant=0, reach=5)}
BUDGET = {"2d": 10_000, "5d": 15_000, "2d+3": 10_000, "2d-reach": 10_000}
PLACES = ("impossible", "locked", "frontier", "mastered")

# name -> (factory(task, seed), whether its goals are cell indices): every registered teacher with
# its papers' defaults (a task-list teacher is given every cell as a task), and ADR and SPDL
# started from the origin cell's corner, the expert knowledge they rely on.
def _registered(cls):
    cells = "tasks" in cls.spaces
    return (lambda e, s: cls(e.n_cells, seed=s)) if cells else (lambda e, s: cls(e.low, e.high, seed=s)), cells


TEACHERS: dict[str, tuple[Callable[[HypercubeUnlock, int], object], bool]] = {kind: _registered(cls) for kind, cls in sg.teachers.available().items()}
TEACHERS["adr_corner"] = (lambda e, s: sg.AdrSelector(e.low, e.high, seed=s, initial=0.0), False)
TEACHERS["spdl_corner"] = (lambda e, s: sg.SpdlSelector(e.low, e.high, seed=s, init_mean=0.05), False)
TEACHERS["plr_average"] = (lambda e, s: sg.PlrSelector(e.n_cells, seed=s, ties="average"), True)
NAMES = {"sagg_riac": "SAGG-RIAC", "riac": "RIAC", "alp_gmm": "ALP-GMM", "covar_gmm": "Covar-GMM", "adr": "ADR", "adr_corner": "ADR (from the origin)", "spdl": "SPDL", "spdl_corner": "SPDL (from the origin)", "goal_gan": "Goal GAN", "random": "random", "discrete_lp": "discrete LP (cells given)", "plr": "PLR (cells given)", "plr_average": "PLR, ties at their mean rank (cells given)"}
NAMES.update({k: k for k in TEACHERS if k not in NAMES})  # a teacher without a display name here


def one_run(job: tuple[str, str, int, int]) -> tuple[dict, list[dict], list[dict]]:
    """One teacher on one space, played by the bench task's own loop (``BenchTask.play``: ask a
    goal, attempt it, tell the competence, score every ``every`` goals), watched on the way: where
    each goal landed, and under which of the teacher's modes. The teacher's seed is the run's seed
    itself (the task has no randomness), as when the committed runs were made."""
    name, space, seed, every = job
    make, cells = TEACHERS[name]
    env = (HypercubeUnlockCells if cells else HypercubeUnlock)(**SPACES[space])
    n = BUDGET[space]
    if every < 1 or n % every:
        raise ValueError(f"--every must divide the budget of every space; got {every} for {space} ({n:,} goals)")
    env.points = n // every
    teacher = make(env, seed)
    placed = {p: 0 for p in PLACES}
    by_mode: dict[str, dict[str, int]] = {}
    asked: list[str] = []

    def ask():
        goal = teacher.sample_task() if cells else teacher.sample()
        asked.append(env.where(goal if cells else env.cell(goal)))  # before the try changes the cell
        return goal

    def tell(goal, competence: float) -> None:
        teacher.update(goal, competence)
        place = asked.pop()
        placed[place] += 1
        mode = getattr(teacher, "last_mode", None)
        if mode is not None:
            by_mode.setdefault(mode, {p: 0 for p in PLACES})[place] += 1

    start = time.perf_counter()
    curve = [dict(teacher=name, space=space, seed=seed, goals=t, score=score) for t, score in env.play(ask, tell, n)]
    seconds = time.perf_counter() - start
    # Leaves only for the tree teachers: the others' n_regions means something else.
    leaves = teacher.n_regions if name in ("sagg_riac", "riac") else np.nan
    run = dict(teacher=name, space=space, seed=seed, final=env.score(), auc=float(np.mean([r["score"] for r in curve])), **{p: placed[p] / n for p in PLACES}, leaves=leaves, seconds=seconds)
    modes = [dict(teacher=name, space=space, seed=seed, mode=m, goals=sum(k.values()), **k) for m, k in by_mode.items()]
    return run, curve, modes


def _ci(a: pd.Series, b: pd.Series) -> tuple[float, float, float]:
    """Difference of means a - b with Welch's 95 % interval (the seeds are not paired: the
    task has no randomness, the seed only drives each teacher's own generator)."""
    from scipy import stats

    d = a.mean() - b.mean()
    va, vb = a.var() / len(a), b.var() / len(b)
    se = np.sqrt(va + vb)
    if se == 0:
        return d, d, d
    df = (va + vb) ** 2 / (va**2 / (len(a) - 1) + vb**2 / (len(b) - 1))
    h = stats.t.ppf(0.975, df) * se
    return d, d - h, d + h


def summary(runs: pd.DataFrame, names: list[str]) -> pd.DataFrame:
    rows = []
    for s in [s for s in SPACES if s in set(runs.space)]:
        for n in names:
            r = runs[(runs.teacher == n) & (runs.space == s)]
            rows.append(dict(space=s, teacher=n, seeds=len(r), final_mean=r.final.mean(), final_sd=r.final.std(), auc_mean=r.auc.mean(), auc_sd=r.auc.std(),
                             **{p: r[p].mean() for p in PLACES}, leaves=r.leaves.mean(), seconds=r.seconds.mean()))
    return pd.DataFrame(rows)


def report(runs: pd.DataFrame, curves: pd.DataFrame, out: Path, names: list[str]) -> None:
    table = summary(runs, names)
    table.to_csv(out / "toy_tasks_results.csv", index=False, float_format="%.4f")
    spaces = list(dict.fromkeys(table.space))
    lines = ["# Hypercube-unlocking toy tasks: results", "",
             f"{runs.seed.nunique()} seeds per teacher and space; mean ± sd over seeds. Final: share of the cells that can be mastered "
             "that are, after the budget; area: mean of the score curve (speed). Goals in: where the teacher's goals landed when tried "
             "(impossible: a cell that can never be unlocked; locked: not unlocked yet; frontier: unlocked, not mastered; mastered: "
             "already mastered). Leaves: the tree's leaves at the end (SAGG-RIAC, RIAC). s/run: seconds per run (teacher and task).", "",
             "Budgets: " + ", ".join(f"{s}: {BUDGET[s]:,} goals" for s in spaces) + ".", "",
             "| space | teacher | final | area | goals in impossible | locked | frontier | mastered | leaves | s/run |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for _, r in table.iterrows():
        leaves = "" if np.isnan(r.leaves) else f"{r.leaves:.0f}"
        lines.append(f"| {r.space} | {NAMES.get(r.teacher, r.teacher)} | {r.final_mean:.3f} ± {r.final_sd:.3f} | {r.auc_mean:.3f} ± {r.auc_sd:.3f} | "
                     f"{r.impossible:.0%} | {r.locked:.0%} | {r.frontier:.0%} | {r.mastered:.0%} | {leaves} | {r.seconds:.2f} |")
    if "sagg_riac" in names:
        lines += ["", "SAGG-RIAC's final score and area minus each other teacher's, with Welch's 95 % interval (descriptive; no decision rule was set for this benchmark):", "",
                  "| teacher | " + " | ".join(spaces) + " |", "|---|" + "---|" * len(spaces)]
        for n in names:
            if n == "sagg_riac":
                continue
            for metric, col in (("final", "final"), ("area", "auc")):
                cells = []
                for s in spaces:
                    d, lo, hi = _ci(runs[(runs.teacher == "sagg_riac") & (runs.space == s)][col], runs[(runs.teacher == n) & (runs.space == s)][col])
                    cells.append(f"{d:+.3f} [{lo:+.3f}, {hi:+.3f}]")
                lines.append(f"| {NAMES.get(n, n)} {metric} | " + " | ".join(cells) + " |")
    (out / "toy_tasks_results.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    colours = {n: plt.get_cmap("tab20")(i % 20) for i, n in enumerate(names)}
    fig, axes = plt.subplots(2, len(spaces), figsize=(4.6 * len(spaces), 9), squeeze=False)
    for ax, s in zip(axes[0], spaces):
        for n in names:
            c = curves[(curves.teacher == n) & (curves.space == s)].groupby("goals").score
            mu, sd = c.mean(), c.std()
            ls = ":" if TEACHERS[n][1] else ("--" if n.startswith(("adr", "spdl")) else "-")
            ax.plot(mu.index, mu.values, ls=ls, color=colours[n], label=NAMES.get(n, n))
            ax.fill_between(mu.index, (mu - sd).values, (mu + sd).values, color=colours[n], alpha=0.1)
        env = HypercubeUnlock(**SPACES[s])
        ax.set_title(f"{s} ({int(env.possible.sum())} cells can be mastered)", fontsize=10)
        ax.set_xlabel("goals")
        ax.set_ylim(0, 1.02)
    axes[0][0].set_ylabel("share of cells mastered (mean ± sd)")
    place_colours = {"impossible": "0.25", "locked": "0.6", "frontier": "tab:green", "mastered": "tab:blue"}
    for ax, s in zip(axes[1], spaces):
        t = table[table.space == s].set_index("teacher").loc[names]
        left = np.zeros(len(names))
        for p in PLACES:
            ax.barh(range(len(names)), t[p].values, left=left, color=place_colours[p], label=p)
            left += t[p].values
        ax.set_yticks(range(len(names)))
        ax.set_yticklabels([NAMES.get(n, n) for n in names] if s == spaces[0] else [], fontsize=7)
        ax.invert_yaxis()
        ax.set_xlim(0, 1)
        ax.set_xlabel("share of goals tried in ...")
    # Legends below the panels, where they hide no curve and no bar.
    fig.legend(*axes[0][0].get_legend_handles_labels(), loc="lower left", ncol=6, fontsize=8, frameon=False)
    fig.legend(*axes[1][0].get_legend_handles_labels(), loc="lower right", ncol=4, fontsize=8, frameon=False)
    fig.tight_layout(rect=(0, 0.06, 1, 1))
    fig.savefig(out / "toy_tasks.png", dpi=100)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", type=Path, required=True)
    p.add_argument("--seeds", type=int, default=10)
    p.add_argument("--spaces", nargs="+", default=list(SPACES), choices=list(SPACES))
    p.add_argument("--teachers", nargs="+", default=list(TEACHERS), choices=list(TEACHERS))
    p.add_argument("--every", type=int, default=500)
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--report-only", action="store_true", help="rebuild the table and the figure from the runs and curves already in --out")
    a = p.parse_args()
    if a.every < 1 or any(BUDGET[s] % a.every for s in a.spaces):
        p.error(f"--every must be >= 1 and divide every space's budget ({', '.join(f'{s}: {BUDGET[s]:,}' for s in a.spaces)}); got {a.every}")
    if a.report_only:
        runs_df = pd.read_csv(a.out / "toy_tasks_runs.csv")
        names = [n for n in TEACHERS if n in set(runs_df.teacher)]
        report(runs_df, pd.read_csv(a.out / "toy_tasks_curves.csv"), a.out, names)
        return
    a.out.mkdir(parents=True, exist_ok=True)
    jobs = list(itertools.product(a.teachers, a.spaces, range(a.seeds), [a.every]))
    # The slowest (mixture teachers in 5-D) first, so the pool ends together.
    jobs.sort(key=lambda j: (j[0] not in ("alp_gmm", "covar_gmm"), j[1] != "5d"))
    start = time.perf_counter()
    runs, curves, modes = [], [], []
    with mp.get_context("spawn").Pool(a.workers) as pool:
        for i, (r, c, m) in enumerate(pool.imap_unordered(one_run, jobs), 1):
            runs.append(r)
            curves += c
            modes += m
            print(f"\r{i}/{len(jobs)} runs, {time.perf_counter() - start:.0f} s", end="", flush=True)
    print()
    runs_df, curves_df = pd.DataFrame(runs).sort_values(["space", "teacher", "seed"]), pd.DataFrame(curves)
    runs_df.to_csv(a.out / "toy_tasks_runs.csv", index=False)  # full precision: the table recomputes to the byte
    curves_df.sort_values(["space", "teacher", "seed", "goals"]).to_csv(a.out / "toy_tasks_curves.csv", index=False, float_format="%.6g")
    pd.DataFrame(modes).sort_values(["space", "teacher", "seed", "mode"]).to_csv(a.out / "toy_tasks_modes.csv", index=False)
    report(runs_df, curves_df, a.out, a.teachers)
    print(f"{len(jobs)} runs in {time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
