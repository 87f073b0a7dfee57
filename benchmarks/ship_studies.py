"""The bench's built-in rows of the deep-RL tasks, standard and full tiers: the registered studies' committed runs.

    python benchmarks/ship_studies.py            # write them into python/saggriac/bench/results/{standard,full}_*
    python benchmarks/ship_studies.py --check    # exit 1 if the shipped rows are not what the studies give

A task a registered study ran takes that study's report seeds (``BenchTask.study_seeds``): all of
them in the full tier, the first ten in the standard tier. A bench run of (task, teacher, seed) at
the study's budget is the study's run of it (the same code and seeds: the deep-RL study's
``rl_curriculum.py`` and the evidence studies' ``evidence.py`` play the bench's tasks). So the
study's committed rows are the shipped rows of every tier whose budget for the task is the
study's (the full tier always; the standard tier where its budget is the same, as for SAC), and
``saggriac bench`` places a user's teacher among them without rerunning tens of CPU hours;
``tests/bench/test_shipped.py`` reruns one through the bench and gets the study's numbers.

Sources: ``docs/figures/rl_curriculum/curves.csv`` (PPO, rl-arm-dense and rl-arm-sparse; the
bench's score is minus the final distance at each scoring after step 0) and every
``docs/figures/evidence/*/runs.csv`` and ``curves.csv`` (the bench's own rows). Only built-in
teachers ship (the oracle and a study's extra teachers do not), only the tier's seeds of the task at
the tier's budget, and no goals (the studies did not keep them; the goals figures show the
teachers run then). Rows of other tasks already shipped in a tier are kept.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import pandas as pd

from saggriac import _core
from saggriac.bench import TASKS, shipped
from saggriac.bench.goals import COLUMNS as GOAL_COLUMNS
from saggriac.bench.suite import builtin_specs
from saggriac.bench.tasks import tier_seeds

REPO = Path(__file__).resolve().parents[1]
FIGURES = REPO / "docs" / "figures"
SHIPPED_TIERS = ("standard", "full")
COMMAND = "python benchmarks/ship_studies.py"


STUDY_TASKS = frozenset(n for n, cls in TASKS.items() if cls.study_seeds)


def _keep(task: str, teacher: str, seed: int, budget: int, tier: str, builtins: frozenset[str]) -> bool:
    """Whether a study's run is a bench run of one of the ``builtins`` teachers in ``tier``."""
    return task in STUDY_TASKS and seed in tier_seeds(task, tier) and budget == TASKS[task].budgets[tier] and teacher in builtins


def _builtins() -> frozenset[str]:
    return frozenset(s.label for s in builtin_specs(True))


def from_rl_curriculum(tier: str, folder: Path = FIGURES / "rl_curriculum") -> tuple[pd.DataFrame, pd.DataFrame]:
    """The PPO study's runs as the bench's rows: its curves give each scoring's final distance."""
    curves = pd.read_csv(folder / "curves.csv", dtype={"commit": str})
    seconds = pd.read_csv(folder / "runs.csv", dtype={"commit": str}).set_index(["reward", "teacher", "seed"]).seconds
    curves = curves.assign(task="rl-arm-" + curves["reward"])
    names = _builtins()
    keep = np.array([_keep(t, te, int(s), int(b), tier, names) for t, te, s, b in zip(curves.task, curves.teacher, curves.seed, curves.budget)], dtype=bool)
    curves = curves[keep & (curves.step > 0).to_numpy()]
    bench_curves = pd.DataFrame(dict(task=curves.task, teacher=curves.teacher, seed=curves.seed.astype(int), step=curves.step.astype(int), score=-curves.distance.astype(float)))
    rows = []
    for (task, teacher, seed), c in bench_curves.groupby(["task", "teacher", "seed"], sort=True):
        c = c.sort_values("step")
        rows.append(dict(task=task, teacher=teacher, seed=int(seed), goals=int(c.step.iloc[-1]), area=float(np.mean(c.score)), final=float(c.score.iloc[-1]),
                         seconds=float(seconds[(task.removeprefix("rl-arm-"), teacher, seed)]), teacher_seconds=float("nan")))
    return pd.DataFrame(rows), bench_curves


def from_evidence(tier: str, folder: Path) -> tuple[pd.DataFrame, pd.DataFrame]:
    """An evidence study's runs (made by the bench's runner) as they are."""
    runs = pd.read_csv(folder / "runs.csv", dtype={"commit": str, "teacher": str, "task": str})
    curves = pd.read_csv(folder / "curves.csv", dtype={"commit": str, "teacher": str, "task": str})
    names = _builtins()
    runs = runs[[_keep(t, te, int(s), int(b), tier, names) for t, te, s, b in zip(runs.task, runs.teacher, runs.seed, runs.budget)]]
    bench_runs = pd.DataFrame(dict(task=runs.task, teacher=runs.teacher, seed=runs.seed.astype(int), goals=runs.budget.astype(int), area=runs.area.astype(float),
                                   final=runs.final.astype(float), seconds=runs.seconds.astype(float), teacher_seconds=runs.teacher_seconds.astype(float)))
    curves = curves.merge(bench_runs[["task", "teacher", "seed"]], on=["task", "teacher", "seed"])
    return bench_runs, curves[["task", "teacher", "seed", "step", "score"]].astype({"seed": int, "step": int, "score": float})


def gather(tier: str) -> tuple[pd.DataFrame, pd.DataFrame, list[str]]:
    """The studies' rows that are bench runs of ``tier``, and the tables they come from."""
    parts = [(from_rl_curriculum(tier), "docs/figures/rl_curriculum/curves.csv")]
    for runs in sorted((FIGURES / "evidence").glob("*/runs.csv")):
        parts.append((from_evidence(tier, runs.parent), runs.relative_to(REPO).as_posix()))
    sources = [source for (r, _), source in parts if len(r)]
    runs = pd.concat([r for (r, _), _ in parts], ignore_index=True)
    curves = pd.concat([c for (_, c), _ in parts], ignore_index=True)
    return runs.assign(version=_core.__version__), curves, sources


def merged(tier: str, folder: Path = shipped.RESULTS) -> tuple[pd.DataFrame, pd.DataFrame, pd.DataFrame, list[int], str]:
    """``tier``'s shipped tables with the studies' rows in place of what shipped for their tasks;
    the command says how the rest was made too."""
    runs, curves, sources = gather(tier)
    command = f"{COMMAND} (from {', '.join(sources)})"
    old = shipped.load(tier, folder)
    goals = pd.DataFrame(columns=GOAL_COLUMNS)
    if old is not None:
        kept = old[0][~old[0].task.isin(STUDY_TASKS)]
        runs = pd.concat([kept, runs], ignore_index=True)
        curves = pd.concat([old[1][~old[1].task.isin(STUDY_TASKS)], curves], ignore_index=True)
        goals = shipped.load_goals(tier, folder)
        goals = goals[~goals.task.isin(STUDY_TASKS)]
        theirs = str(old[2].get("command", "")).split(COMMAND)[0].rstrip(" ;&")
        if len(kept) and theirs:
            command = f"{theirs} && {command}"
    seeds = sorted(set(int(s) for s in runs.seed))
    return runs, curves, goals, seeds, command


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--check", action="store_true", help="exit 1 if a tier's shipped study rows differ from what the committed studies give")
    args = ap.parse_args(argv)
    key = ["task", "teacher", "seed"]
    for tier in SHIPPED_TIERS:
        runs, curves, goals, seeds, command = merged(tier)
        studied = runs[runs.task.isin(STUDY_TASKS)]
        if args.check:
            ship = shipped.load(tier)
            if ship is None:
                print(f"no {tier} tier ships; run python benchmarks/ship_studies.py", file=sys.stderr)
                return 1
            mine = runs.drop(columns=["version"]).sort_values(key).reset_index(drop=True)
            theirs = ship[0].drop(columns=["version"]).sort_values(key).reset_index(drop=True)
            mine_c = curves.sort_values([*key, "step"]).reset_index(drop=True)
            theirs_c = ship[1].sort_values([*key, "step"]).reset_index(drop=True)
            if list(theirs.columns) != list(mine.columns) or not mine.equals(theirs[mine.columns]) or not mine_c.equals(theirs_c[mine_c.columns]):
                print(f"the shipped {tier} tier is not what the committed studies give; run python benchmarks/ship_studies.py", file=sys.stderr)
                return 1
            print(f"the shipped {tier} tier holds the studies' {len(studied)} runs")
            continue
        for p in shipped.write(tier, runs, curves, goals, seeds, command):
            print(f"wrote {p.relative_to(REPO)}")
        print(f"{tier}: {len(studied)} study runs: " + (", ".join(f"{t} {n}" for t, n in studied.groupby("task").size().items()) or "none"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
