"""The guide's table of verdicts (docs/choosing_a_teacher.md), recomputed from committed tables.

    python benchmarks/guide.py            # rewrite the table in the guide
    python benchmarks/guide.py --check    # exit 1 if the guide's table is not what the tables give

Every cell is one teacher against the random teacher on one (task, learner, reward), paired by
seed: the mean gain with its 95 % interval and the verdict, read from a committed table of runs:

- the hypercube toys (docs/figures/teachers/toy_tasks_runs.csv, 10 seeds): the area under the
  score curve, paired t-test, Holm over every teacher and space of the toys; helps / hurts when
  the Holm-adjusted p < 0.05, by the sign of the gain;
- the registered progress-niche study (docs/figures/teachers/niches/comparisons.csv, 20 seeds):
  its pairs with random on the area, Holm within the study's family (every pair of its
  teachers, per space), the same rule;
- the bench's shipped quick results (python/saggriac/bench/results, 5 seeds) for every task but
  the four hypercubes above (the toys have twice the seeds): the area, as the bench's
  leaderboard computes it (Holm over the whole board), the same rule;
- the registered deep-RL studies (docs/figures/rl_curriculum/comparisons.csv and the evidence
  studies' comparisons.csv under docs/figures/evidence/, once every report run of a task is
  in): their primary family against random, as each study's decision rule gave it (its own
  measure, interval and Holm family).

Written between the guide's markers ``<!-- verdicts -->`` and ``<!-- /verdicts -->``; tests run
``--check`` on the committed data, so the guide and the tables cannot drift apart.
"""

from __future__ import annotations

import argparse
import json
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from saggriac.analysis.statistics import holm, paired
from saggriac.bench import TASKS, shipped
from saggriac.bench.report import leaderboard

REPO = Path(__file__).resolve().parents[1]
GUIDE = REPO / "docs" / "choosing_a_teacher.md"
START, END = "<!-- verdicts -->", "<!-- /verdicts -->"
ALPHA = 0.05
# Display names, in the order of the rows.
NAMES = {"oracle": "oracle (the task's own)", "sagg_riac": "SAGG-RIAC", "riac": "RIAC", "alp_gmm": "ALP-GMM", "covar_gmm": "Covar-GMM",
         "adr": "ADR", "adr_corner": "ADR from the solvable corner", "adr@high": "ADR, expert knowledge high", "spdl": "SPDL",
         "spdl_corner": "SPDL from the solvable corner", "spdl@high": "SPDL, expert knowledge high", "goal_gan": "Goal GAN",
         "goal_gan@high": "Goal GAN, expert knowledge high", "adr@low": "ADR, expert knowledge low", "spdl@low": "SPDL, expert knowledge low",
         "goal_gan@low": "Goal GAN, expert knowledge low", "discrete_lp": "discrete LP", "plr": "PLR", "plr_average": "PLR, ties averaged",
         "saggriac.bench.value_loss:PlrValueLoss": "PLR, value loss (its paper's score)", "tscl": "TSCL"}
TOY_SPACES = ("2d", "5d", "2d+3", "2d-reach")
MARK = {"helps": "↑", "hurts": "↓", "no difference shown": "·"}


@dataclass(frozen=True)
class Evidence:
    """One column of the table: a task, a learner and a reward, with the measure of its gain."""

    key: str
    task: str
    learner: str
    measure: str
    source: str


def verdict(gain: float, p_holm: float) -> str:
    if np.isnan(p_holm) or p_holm >= ALPHA:
        return "no difference shown"
    return "helps" if gain > 0 else "hurts"


def toy_rows() -> tuple[list[Evidence], pd.DataFrame]:
    runs = pd.read_csv(REPO / "docs" / "figures" / "teachers" / "toy_tasks_runs.csv")
    rows = []
    for space in TOY_SPACES:
        sub = runs[runs.space == space]
        ref = sub[sub.teacher == "random"].set_index("seed").auc
        for teacher, r in sub.groupby("teacher"):
            if teacher == "random":
                continue
            r = r.set_index("seed").auc
            seeds = r.index.intersection(ref.index)
            d = paired(r.loc[seeds].to_numpy(), ref.loc[seeds].to_numpy())
            rows.append(dict(key=f"toy:{space}", teacher=teacher, n=len(seeds), gain=d["mean_diff"], ci_low=d["ci_low"], ci_high=d["ci_high"], p_value=d["p_value"]))
    table = pd.DataFrame(rows)
    table["p_holm"] = holm(table.p_value.to_numpy(float))
    cols = [Evidence(f"toy:{s}", f"hypercube `{s}`", "cells mastered by practice", "area", "docs/figures/teachers/toy_tasks_runs.csv") for s in TOY_SPACES]
    return cols, table


def niches_rows() -> tuple[list[Evidence], pd.DataFrame]:
    """The registered niche study's pairs with random (the area, its own Holm family per space and
    measure), read from its comparisons; the extra rows are left out."""
    comp = pd.read_csv(REPO / "docs" / "figures" / "teachers" / "niches" / "comparisons.csv")
    comp = comp[(comp.family == "registered") & (comp.metric == "auc") & ((comp.a == "random") | (comp.b == "random"))]
    rows = []
    for r in comp.itertuples():
        flip = r.a == "random"  # the difference as teacher minus random
        rows.append(dict(key=f"niches:{r.distractors}", teacher=r.b if flip else r.a, n=r.n, gain=-r.mean_diff if flip else r.mean_diff,
                         ci_low=-r.ci_high if flip else r.ci_low, ci_high=-r.ci_low if flip else r.ci_high, p_holm=r.p_holm))
    spaces = sorted(set(comp.distractors))
    cols = [Evidence(f"niches:{d}", f"progress niches, {d} distractors", "niches opened by practice, noisy and impossible cells", "area", "docs/figures/teachers/niches/comparisons.csv") for d in spaces]
    return cols, pd.DataFrame(rows)


def bench_rows() -> tuple[list[Evidence], pd.DataFrame]:
    ship = shipped.load("quick")
    if ship is None:
        return [], pd.DataFrame()
    board = leaderboard(ship[0])
    tasks = [t for t in TASKS if t in set(board.task) and t not in TOY_SPACES]
    board = board[board.task.isin(tasks) & (board.teacher != "random")]
    table = pd.DataFrame(dict(key="bench:" + board.task, teacher=board.teacher, n=board.seeds, gain=board.diff_area, ci_low=board.ci_low, ci_high=board.ci_high, p_holm=board.p_holm))
    cols = [Evidence(f"bench:{t}", f"bench `{t}`", TASKS[t].learner, "area", "python/saggriac/bench/results/quick_runs.parquet") for t in tasks]
    return cols, table


def study_rows(path: Path, label: str, learner: str, note: str = "") -> tuple[list[Evidence], pd.DataFrame]:
    """A registered study's primary comparisons against random, one column per reward (or task);
    ``note`` follows each column's name (a replication's)."""
    comp = pd.read_csv(path)
    comp = comp[(comp.family == "primary") & (comp.b == "random")]
    by = "reward" if "reward" in comp else "task"
    table = pd.DataFrame(dict(key=f"{label}:" + comp[by].astype(str) + note, teacher=comp.a, n=comp.n, gain=comp.gain, ci_low=comp.ci_low, ci_high=comp.ci_high, p_holm=comp.p_holm, verdict=comp.verdict))
    rel = path.relative_to(REPO).as_posix()
    cols = [Evidence(f"{label}:{v}{note}", f"{label}, {v}{note}", learner, str(comp[comp[by] == v].metric.iloc[0]).replace("_", " "), rel) for v in dict.fromkeys(comp[by].astype(str))]
    return cols, table


def shown(path: Path) -> str:
    """A table's path as the guide names it: from the repository's root."""
    return path.relative_to(REPO).as_posix() if path.is_relative_to(REPO) else str(path)


def seed_count(text: str) -> int:
    """How many seeds a protocol's "a-b,c" names."""
    return sum(int(b or a) - int(a) + 1 for a, _, b in (part.partition("-") for part in str(text).split(",")))


def evidence_rows(folder: Path = REPO / "docs" / "figures" / "evidence") -> tuple[list[Evidence], pd.DataFrame]:
    """Every registered study of benchmarks/evidence.py whose report is complete: per task, its
    teachers against the baseline, as the study's own rule decided (its comparisons.csv). A study
    still running has no column yet: its numbers decide nothing until every run is in."""
    cols, parts = [], []
    for protocol in sorted(folder.glob("*/protocol.json")):
        comp_path = protocol.parent / "comparisons.csv"
        if not comp_path.exists() or not comp_path.read_text().strip():
            continue  # not yet analysed, or no complete seed
        p = json.loads(protocol.read_text())
        comp = pd.read_csv(comp_path)
        comp = comp[comp.family == "against the baseline"]
        for task in p["tasks"]:
            mine = comp[comp.task == task]
            if mine.empty or int(mine.seeds.iloc[0]) < seed_count(p["report"][task]):
                continue
            key = f"{p['study']}:{task}"
            cls = TASKS.get(task)
            cols.append(Evidence(key, f"{p['study']} study, `{task}`", cls.learner if cls else task, str(p["rule"]["primary"]), shown(comp_path)))
            parts.append(pd.DataFrame(dict(key=key, teacher=mine.a, n=mine.seeds, gain=mine.gain, ci_low=mine.ci_low, ci_high=mine.ci_high, p_holm=mine.p_holm, verdict=mine.verdict)))
    return cols, (pd.concat(parts, ignore_index=True) if parts else pd.DataFrame())


def gather() -> tuple[list[Evidence], pd.DataFrame]:
    parts = [toy_rows(), niches_rows(), bench_rows(), study_rows(REPO / "docs" / "figures" / "rl_curriculum" / "comparisons.csv", "goal arm", "PPO"),
             study_rows(REPO / "docs" / "figures" / "rl_curriculum" / "replication" / "comparisons.csv", "goal arm", "PPO", " (replication)"), evidence_rows()]
    cols = [c for p in parts for c in p[0]]
    table = pd.concat([p[1] for p in parts if not p[1].empty], ignore_index=True)
    if "verdict" not in table:
        table["verdict"] = np.nan
    own = table.verdict.isna()
    table.loc[own, "verdict"] = [verdict(g, p) for g, p in zip(table.gain[own], table.p_holm[own])]
    return cols, table


def _cell(r: pd.Series) -> str:
    return f"{r.gain:+.3f} [{r.ci_low:+.3f}, {r.ci_high:+.3f}] {MARK[r.verdict]}"


def label(c: Evidence) -> str:
    """A column's short name in the table's header."""
    kind, name = c.key.split(":", 1)
    if kind == "niches":
        return f"niches study, {name} distractors"
    if kind in ("toy", "bench") or "study" in c.task:
        return name
    return f"{kind}, {name}"


def render(cols: list[Evidence], table: pd.DataFrame) -> str:
    teachers = [t for t in NAMES if t in set(table.teacher)] + sorted(set(table.teacher) - set(NAMES))
    lines = [START, "", "*Generated by `python benchmarks/guide.py` from the committed tables named below; do not edit by hand.*", "",
             "Each teacher against the random teacher on the same seeds: ↑ helps, ↓ hurts (Holm-adjusted p < 0.05, by the gain's sign), · no difference shown, blank: not run there. "
             "The oracle is each task's own: on the goal arms and PointMaze goals uniform over what can be reached (focus alone), on MiniGrid a hand-written easy-to-hard order of the levels.", ""]
    header = "| teacher | " + " | ".join(label(c) for c in cols) + " |"
    lines += [header, "|---|" + "---|" * len(cols)]
    by = table.set_index(["teacher", "key"])
    for t in teachers:
        marks = [MARK[by.loc[(t, c.key), "verdict"]] if (t, c.key) in by.index else "" for c in cols]
        lines.append(f"| {NAMES.get(t, t)} | " + " | ".join(marks) + " |")
    lines += ["", "The gains, with their 95 % intervals (the measure's units; higher is better):", ""]
    for c in cols:
        sub = table[table.key == c.key].set_index("teacher")
        n = sorted(set(sub.n.astype(int)))
        lines += [f"- **{c.task}** ({c.learner}; {c.measure}; {'/'.join(map(str, n))} seeds; `{c.source}`): " + "; ".join(f"{NAMES.get(t, t)} {_cell(sub.loc[t])}" for t in teachers if t in sub.index)]
    lines += ["", END]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--check", action="store_true", help="exit 1 if the guide's table differs from the committed tables")
    args = ap.parse_args(argv)
    text = GUIDE.read_text()
    if START not in text or END not in text:
        print(f"{GUIDE} has no {START} ... {END} block", file=sys.stderr)
        return 1
    head, rest = text.split(START, 1)
    _, tail = rest.split(END, 1)
    new = head + render(*gather()) + tail
    if args.check:
        if new != text:
            print(f"{GUIDE}: the table of verdicts differs from the committed tables; run python benchmarks/guide.py", file=sys.stderr)
            return 1
        print("the guide's table of verdicts is what the committed tables give")
        return 0
    GUIDE.write_text(new)
    print(f"wrote the table of verdicts in {GUIDE}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
