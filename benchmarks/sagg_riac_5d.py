"""What holds SAGG-RIAC back in 5d (issue 48, item 4): one factor at a time on the bench's `5d`
task (5 relevant dimensions, 3 bins, 243 cells, 15,000 goals), tuning seeds 100-114 only.

    python benchmarks/sagg_riac_5d.py            # the runs, resumable
    python benchmarks/sagg_riac_5d.py --analyse  # the table of docs/sagg_riac_mode3.md

Each run is the bench's run of SaggRiacSelector on `5d` (the seed's two children, the task's
competence told as c - 1), made here by hand so that it can also count where the goals went
(a locked cell, the frontier of unlocked cells not yet mastered, a mastered cell) and how many
leaves the tree ends with. Its final score equals the bench's for the same parameters and seed
(checked against the tuning rows where both exist). One row per run in
docs/figures/sagg_riac_mode3/diagnose_5d.csv.
"""

from __future__ import annotations

import argparse
import csv
import json
import time
from pathlib import Path

import numpy as np

import saggriac as sg
from saggriac.bench.runner import child_seeds
from saggriac.bench.tasks import TASKS

OUT = Path("docs/figures/sagg_riac_mode3")
SEEDS = tuple(range(100, 115))
FIELDS = ("condition", "seed", "final", "area", "leaves", "locked", "frontier", "mastered", "seconds")


def conditions(out: Path) -> dict[str, dict]:
    """The chosen reading (choice.json) as the base, each factor moved alone; the paper's reading
    with the same moves of g_max for comparison."""
    choice = json.loads((out / "choice.json").read_text())
    iw = {"mode3": "interest_worst", "mode3_sigma": choice["mode3_sigma"]}
    c = {"paper": {}, "interest_worst": iw}
    for g in (25, 100, 200, 400):
        c[f"interest_worst g_max={g}"] = {**iw, "g_max": g}
    for g in (100, 400):
        c[f"paper g_max={g}"] = {"g_max": g}
    for z in (10, 40, 80):
        c[f"interest_worst zeta={z}"] = {**iw, "zeta": z}
    c["interest_worst min_child=20"] = {**iw, "min_child": 20}
    c["interest_worst p_global=0.1"] = {**iw, "p_interest": 0.8, "p_global": 0.1}
    return c


def run(params: dict, seed: int) -> dict:
    cls = TASKS["5d"]
    teacher_seed, task_seed = child_seeds(seed)
    task = cls(task_seed)
    sel = sg.SaggRiacSelector(task.low, task.high, seed=teacher_seed, **params)
    budget = cls.budgets["quick"]
    every = max(1, budget // task.points)
    where = np.zeros(3)
    scores = []
    start = time.perf_counter()
    for t in range(1, budget + 1):
        goal = np.asarray(sel.sample(), float)
        c = task.cell(goal)
        where[0 if not task.unlocked[c] else 2 if task.practice[c] >= task.need else 1] += 1
        sel.update(goal, -1.0 + task.attempt(goal))
        if t % every == 0 or t == budget:
            scores.append(task.score())
    leaves = len(sel.leaves()["interest"])
    return dict(final=scores[-1], area=float(np.mean(scores)), leaves=leaves, locked=where[0] / budget, frontier=where[1] / budget, mastered=where[2] / budget, seconds=time.perf_counter() - start)


def runs(out: Path) -> None:
    path = out / "diagnose_5d.csv"
    done = set()
    if path.exists():
        with path.open() as f:
            done = {(r["condition"], int(r["seed"])) for r in csv.DictReader(f)}
    new = not path.exists()
    with path.open("a", newline="") as f:
        w = csv.DictWriter(f, FIELDS)
        if new:
            w.writeheader()
        for seed in SEEDS:
            for name, params in conditions(out).items():
                if (name, seed) in done:
                    continue
                r = run(params, seed)
                w.writerow({"condition": name, "seed": seed, **{k: repr(float(v)) if k != "leaves" else v for k, v in r.items()}})
                f.flush()
                print(f"{name:32s} seed {seed}: final {r['final']:.3f} leaves {r['leaves']} frontier {r['frontier']:.3f} locked {r['locked']:.3f}", flush=True)


def analyse(out: Path) -> None:
    with (out / "diagnose_5d.csv").open() as f:
        rows = list(csv.DictReader(f))
    tuning = {}
    with (out / "tuning_runs.csv").open() as f:
        for r in csv.DictReader(f):
            if r["task"] == "5d":
                tuning[(r["condition"], int(r["seed"]))] = float(r["final"])
    choice = json.loads((out / "choice.json").read_text())
    same = {"paper": "paper", "interest_worst": f"interest_worst_{choice['mode3_sigma']:g}"}
    for r in rows:
        key = (same.get(r["condition"], ""), int(r["seed"]))
        if key in tuning and tuning[key] != float(r["final"]):
            raise SystemExit(f"{r['condition']} seed {r['seed']}: final {r['final']} here, {tuning[key]} in the bench's tuning run")
    # Exploratory (no registered rule): each condition minus the chosen reading, paired by seed,
    # with a bootstrap 95 % interval.
    base = {int(r["seed"]): float(r["final"]) for r in rows if r["condition"] == "interest_worst"}
    rng = np.random.default_rng(np.random.SeedSequence(5))
    print("| condition | seeds | final (sd) | minus interest_worst [95 % CI] | area | leaves | goals on the frontier | in locked cells | in mastered cells |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name in dict.fromkeys(r["condition"] for r in rows):
        sub = [r for r in rows if r["condition"] == name]
        v = {k: np.array([float(r[k]) for r in sub]) for k in FIELDS[2:]}
        d = np.array([float(r["final"]) - base[int(r["seed"])] for r in sub])
        boots = d[rng.integers(0, len(d), (10_000, len(d)))].mean(axis=1)
        diff = "-" if name == "interest_worst" else f"{d.mean():+.3f} [{np.percentile(boots, 2.5):+.3f}, {np.percentile(boots, 97.5):+.3f}]"
        print(f"| {name} | {len(sub)} | {v['final'].mean():.3f} ({v['final'].std(ddof=1):.3f}) | {diff} | {v['area'].mean():.3f} | {v['leaves'].mean():.0f} | {v['frontier'].mean():.1%} | {v['locked'].mean():.1%} | {v['mastered'].mean():.1%} |")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=str(OUT))
    ap.add_argument("--analyse", action="store_true")
    args = ap.parse_args()
    (analyse if args.analyse else runs)(Path(args.out))


if __name__ == "__main__":
    main()
