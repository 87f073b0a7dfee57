"""The PointMaze study's pilot (docs/evidence/pointmaze.md, "Pilot"): the random teacher and the
oracle on tuning seeds, on both candidate maps, each run through the task's own ``play`` as the
bench runs it, then the registered rules that fix the map, the budget and the report's size.

    python benchmarks/pointmaze_pilot.py            # runs what is missing (resumable)
    python benchmarks/pointmaze_pilot.py --rules    # the rules, from the committed rows alone

Rows go to docs/figures/evidence/pointmaze/pilot/{runs,curves}.csv as each run ends; a run whose
(task, teacher, seed) is in runs.csv is not run again. One process, one torch thread.
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO / "benchmarks"))
from rl_curriculum import commit, power  # noqa: E402  (the first study's commit stamp and power)

from saggriac.bench import TASKS, TeacherSpec  # noqa: E402
from saggriac.bench.teachers import Guarded  # noqa: E402

OUT = REPO / "docs" / "figures" / "evidence" / "pointmaze" / "pilot"
PROTOCOL = REPO / "docs" / "figures" / "evidence" / "pointmaze" / "protocol.json"
RUN_COLUMNS = ["task", "learner", "teacher", "seed", "budget", "final", "area", "final_distance", "goals_asked", "goals_reachable", "goals_reachable_last", "scoring_cpu_seconds", "seconds", "cpu_seconds", "commit"]


def one_run(task_name: str, teacher: str, seed: int, budget: int) -> tuple[dict, list[dict]]:
    """One run as the bench makes it: the task built from the run's seed, the teacher from its
    child (the oracle: the task's own oracle(), told nothing)."""
    cls = TASKS[task_name]
    teacher_seed, task_seed = cls.child_seeds(seed)
    task = cls(task_seed)
    if teacher == "oracle":
        ask, tell = task.oracle, (lambda goal, competence: None)
    else:
        guard = Guarded(TeacherSpec(teacher), task, teacher_seed, run_seed=seed)
        ask, tell = guard.ask, guard.tell
    wall, cpu = time.perf_counter(), time.process_time()
    curve = task.play(ask, tell, budget)
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    scores = [s for _, s in curve]
    row = dict(task=task_name, learner=cls.learner, teacher=teacher, seed=seed, budget=budget, final=scores[-1], area=float(np.mean(scores)), **task.run_measures(), seconds=wall, cpu_seconds=cpu, commit=commit())
    return row, [dict(task=task_name, teacher=teacher, seed=seed, step=t, score=s) for t, s in curve]


def append(path: Path, rows: list[dict], columns: list[str]) -> None:
    new = not path.exists()
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("a", newline="") as f:
        w = csv.DictWriter(f, fieldnames=columns, extrasaction="raise")
        if new:
            w.writeheader()
        w.writerows(rows)


def read(path: Path) -> list[dict]:
    if not path.exists():
        return []
    with path.open(newline="") as f:
        return list(csv.DictReader(f))


def run(pilot: dict, out: Path) -> None:
    done = {(r["task"], r["teacher"], int(r["seed"])) for r in read(out / "runs.csv")}
    jobs = [(task, teacher, seed) for seed in pilot["seeds"] for task in pilot["tasks"] for teacher in pilot["teachers"]]
    for k, (task, teacher, seed) in enumerate(jobs, 1):
        if (task, teacher, seed) in done:
            continue
        row, curve = one_run(task, teacher, seed, pilot["budget"])
        append(out / "curves.csv", curve, ["task", "teacher", "seed", "step", "score"])
        append(out / "runs.csv", [row], RUN_COLUMNS)
        print(f"[{k}/{len(jobs)}] {task} {teacher} seed {seed}: final success {row['final']:.3f}, {row['cpu_seconds']:.0f} CPU s", flush=True)


# ---------------------------------------------------------------- the registered rules


def browne_sd(values_by_teacher: list[list[float]], confidence: float) -> tuple[float, float, int]:
    """The pooled within-teacher sd, and its upper one-sided ``confidence`` limit (Browne 1995:
    size a study on the pilot's sd's upper 80 % limit, not on the sd itself), and its df."""
    from scipy import stats

    ss = sum(float(np.sum((np.asarray(v) - np.mean(v)) ** 2)) for v in values_by_teacher)
    df = sum(len(v) - 1 for v in values_by_teacher)
    sd = math.sqrt(ss / df)
    return sd, sd * math.sqrt(df / stats.chi2.ppf(1 - confidence, df)), df


def rules(out: Path, protocol: dict) -> str:
    """The pilot's rules (docs/evidence/pointmaze.md), applied to the pilot's rows."""
    p, r = protocol["pilot"], protocol["pilot_rules"]
    runs, curves = read(out / "runs.csv"), read(out / "curves.csv")
    family = len(protocol["teachers"]) - 1
    alpha = protocol["rule"]["alpha"] / family  # Holm's first step
    delta = protocol["rule"]["meaningful_effect"]
    lines = [f"Pilot: {len(runs)} runs, seeds {p['seeds']}, budget {p['budget']:,}; family of {family} comparisons, Holm's first step alpha = {alpha:.5f}; meaningful effect {delta} in final success.", ""]
    choice: dict[str, dict] = {}
    for task in p["tasks"]:
        mine = [x for x in runs if x["task"] == task]
        if len(mine) < len(p["seeds"]) * len(p["teachers"]):
            lines.append(f"{task}: {len(mine)} of {len(p['seeds']) * len(p['teachers'])} runs; incomplete.")
            continue
        cpu = float(np.mean([float(x["cpu_seconds"]) for x in mine]))
        scoring = float(np.mean([float(x["scoring_cpu_seconds"]) for x in mine]))
        random_final = float(np.mean([float(x["final"]) for x in mine if x["teacher"] == "random"]))
        lines.append(f"## {task}")
        lines.append(f"CPU s per run at {p['budget']:,}: {cpu:.1f} (of which scoring {scoring:.1f}); random's mean final success {random_final:.3f}; the oracle's {np.mean([float(x['final']) for x in mine if x['teacher'] == 'oracle']):.3f}.")
        lines += ["", "| B | sd (pooled) | sd, upper 80 % | d_z of the effect | seeds for 80 % power | seeds that fit | CPU h at that size |", "|---|---|---|---|---|---|---|"]
        best = None
        for b in range(p["budget"], r["min_budget"] - 1, -r["budget_step"]):
            at = [[float(c["score"]) for c in curves if c["task"] == task and c["teacher"] == t and int(c["step"]) == b] for t in p["teachers"]]
            sd, upper, df = browne_sd(at, r["sd_confidence"])
            upper = max(upper, r["sd_floor"])
            dz = delta / (math.sqrt(2) * upper)
            need = next((n for n in range(r["min_seeds"], r["max_seeds"] + 1) if power(n, dz, alpha) >= r["power"]), None)
            cost = scoring + (cpu - scoring) * b / p["budget"]
            fit = min(int(r["cpu_seconds"] // (len(protocol["teachers"]) * cost)), r["max_seeds"])
            size = need if need is not None and need <= fit else fit
            lines.append(f"| {b:,} | {sd:.3f} | {upper:.3f} | {dz:.2f} | {need if need is not None else '> ' + str(r['max_seeds'])} | {fit} | {len(protocol['teachers']) * size * cost / 3600:.2f} |")
            if best is None and need is not None and need <= fit:
                best = dict(budget=b, seeds=need, dz=dz, cost=cost, powered=True)
        if best is None:
            b = p["budget"]
            at = [[float(c["score"]) for c in curves if c["task"] == task and c["teacher"] == t and int(c["step"]) == b] for t in p["teachers"]]
            upper = max(browne_sd(at, r["sd_confidence"])[1], r["sd_floor"])
            fit = min(int(r["cpu_seconds"] // (len(protocol["teachers"]) * cpu)), r["max_seeds"])
            dz_80 = next(d for d in np.arange(0.05, 5.0, 0.01) if power(fit, d, alpha) >= r["power"])
            best = dict(budget=b, seeds=fit, dz=delta / (math.sqrt(2) * upper), cost=cpu, powered=False, detectable=float(dz_80 * math.sqrt(2) * upper))
        best["random_final"] = random_final
        choice[task] = best
        lines.append("")
        lines.append(f"Rules 2-3 on {task}: B = {best['budget']:,}, {best['seeds']} report seeds" + ("" if best["powered"] else f" (the most that fit; power 0.8 at Holm's first step only for a gain of {best['detectable']:.3f})") + f", {len(protocol['teachers']) * best['seeds'] * best['cost'] / 3600:.2f} CPU hours projected.")
        lines.append("")
    if len(choice) == len(p["tasks"]):
        medium = choice[r["preferred"]]
        pick = r["preferred"] if medium["random_final"] >= r["preferred_min_success"] and medium["powered"] else r["fallback"]
        why = f"random's mean final success on {r['preferred']} is {medium['random_final']:.3f} (rule: >= {r['preferred_min_success']}) and power 0.8 is {'within' if medium['powered'] else 'out of'} reach there"
        c = choice[pick]
        lines.append(f"Rule 1: {why}, so the study runs on {pick}: B = {c['budget']:,}, report seeds {r['first_report_seed']}-{r['first_report_seed'] + c['seeds'] - 1} ({c['seeds']}).")
        lines.append("")
        lines.append(json.dumps({"task": pick, "budget": c["budget"], "seeds": c["seeds"], "first_seed": r["first_report_seed"]}))
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rules", action="store_true", help="apply the registered rules to the rows already written")
    ap.add_argument("--out", type=Path, default=OUT)
    args = ap.parse_args(argv)
    protocol = json.loads(PROTOCOL.read_text())
    if args.rules:
        print(rules(args.out, protocol))
    else:
        run(protocol["pilot"], args.out)


if __name__ == "__main__":
    main()
