"""SAGG-RIAC's mode 3 readings on the bench (issue 48, item 4): the paper's ("lowest_competence")
against "interest_worst" (a region by interest, a goal about its worst goal). The protocol, the
rules and the results: docs/sagg_riac_mode3.md.

    python benchmarks/sagg_riac_mode3.py tune       # tuning seeds 100-114, the toy tasks
    python benchmarks/sagg_riac_mode3.py choose     # the registered rule -> choice.json
    python benchmarks/sagg_riac_mode3.py report     # report seeds 900-919, every quick task
    python benchmarks/sagg_riac_mode3.py analyse    # the tables of the doc, from the rows
    python benchmarks/sagg_riac_mode3.py arm        # the paper's exp1 / exp2, seeds 920-929
    python benchmarks/sagg_riac_mode3.py arm-analyse

Every run is one row of a CSV in --out (default docs/figures/sagg_riac_mode3), appended as soon
as it is done: a phase killed and run again computes only the runs it has no row for. A run is
the bench's own (``saggriac.bench.runner.run_one``: the seed's children, the quick tier's
budget), so rows of the paper's reading on seeds 0-4 equal the bench's shipped ones. One
process, one run at a time.
"""

from __future__ import annotations

import argparse
import csv
import json
import subprocess
import sys
from pathlib import Path

import numpy as np

from saggriac import _core
from saggriac.bench.runner import Job, run_one
from saggriac.bench.tasks import TASKS, in_tier
from saggriac.bench.teachers import TeacherSpec

OUT = Path("docs/figures/sagg_riac_mode3")
TUNING_SEEDS = tuple(range(100, 115))
REPORT_SEEDS = tuple(range(900, 920))
TOY_TASKS = ("2d", "2d+3", "5d")
TIER = "quick"

IW = (("mode3", "interest_worst"),)
#: The tuning's conditions (docs/sagg_riac_mode3.md, "Tuning rule"): the candidates are the
#: interest_worst rows; "paper" and "no_mode3" are context, never chosen.
SIGMAS = (0.01, 0.02, 0.05, 0.1, 0.2)
TUNING = {
    "paper": (),
    "no_mode3": (("p_interest", 0.8), ("p_lowest", 0.0)),
    **{f"interest_worst_{s:g}": IW + (("mode3_sigma", s),) for s in SIGMAS},
}
#: Ties: candidates within this of the best mean final are tied, and the tie goes to the sigma
#: nearest RIAC's published 0.1.
TIE = 0.005
FIELDS = ("phase", "condition", "task", "seed", "final", "area", "seconds", "version", "commit")


def git_commit() -> str:
    try:
        return subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return ""


def rows(path: Path) -> list[dict]:
    if not path.exists():
        return []
    with path.open() as f:
        return list(csv.DictReader(f))


def run_all(path: Path, phase: str, conditions: dict[str, tuple], tasks: tuple[str, ...], seeds: tuple[int, ...]) -> None:
    """Every (condition, task, seed) without a row in ``path``, one at a time, each row appended
    when done."""
    done = {(r["condition"], r["task"], int(r["seed"])) for r in rows(path)}
    new = not path.exists()
    path.parent.mkdir(parents=True, exist_ok=True)
    commit = git_commit()
    with path.open("a", newline="") as f:
        w = csv.DictWriter(f, FIELDS)
        if new:
            w.writeheader()
        for task in tasks:
            for seed in seeds:
                for name, params in conditions.items():
                    if (name, task, seed) in done:
                        continue
                    out = run_one(Job(task, TIER, TeacherSpec("sagg_riac", tuple(sorted(params))), seed))["row"]
                    w.writerow(dict(phase=phase, condition=name, task=task, seed=seed, final=repr(out["final"]), area=repr(out["area"]), seconds=f"{out['seconds']:.3f}", version=_core.__version__, commit=commit))
                    f.flush()
                    print(f"{phase} {name:22s} {task:12s} seed {seed}: final {out['final']:.3f} area {out['area']:.3f} ({out['seconds']:.1f} s)", flush=True)


def table(path: Path) -> dict[tuple[str, str], dict[int, tuple[float, float]]]:
    """(condition, task) -> seed -> (final, area)."""
    t: dict[tuple[str, str], dict[int, tuple[float, float]]] = {}
    for r in rows(path):
        t.setdefault((r["condition"], r["task"]), {})[int(r["seed"])] = (float(r["final"]), float(r["area"]))
    return t


def choose(out: Path) -> dict:
    """The registered rule on the tuning rows: the interest_worst sigma of highest mean final over
    2d, 2d+3 and 5d (each task's mean over seeds 100-114, then the mean of the three); candidates
    within TIE of the best are tied, and the tie goes to the sigma nearest 0.1."""
    t = table(out / "tuning_runs.csv")
    score = {}
    for name in TUNING:
        per_task = []
        for task in TOY_TASKS:
            runs = t.get((name, task), {})
            if set(runs) != set(TUNING_SEEDS):
                raise SystemExit(f"tuning incomplete: {name} on {task} has {len(runs)} of {len(TUNING_SEEDS)} seeds")
            per_task.append(float(np.mean([runs[s][0] for s in TUNING_SEEDS])))
        score[name] = dict(zip(TOY_TASKS, per_task), mean=float(np.mean(per_task)))
    candidates = {s: score[f"interest_worst_{s:g}"]["mean"] for s in SIGMAS}
    best = max(candidates.values())
    tied = [s for s, v in candidates.items() if v >= best - TIE]
    chosen = min(tied, key=lambda s: (abs(np.log(s / 0.1)), -s))
    choice = dict(rule="highest mean final over 2d, 2d+3, 5d on seeds 100-114; ties within 0.005 to the sigma nearest 0.1", scores=score, tied=tied, mode3="interest_worst", mode3_sigma=chosen)
    (out / "choice.json").write_text(json.dumps(choice, indent=1) + "\n")
    for name, s in score.items():
        print(f"{name:22s} " + " ".join(f"{k} {v:.3f}" for k, v in s.items()))
    print(f"chosen: mode3_sigma = {chosen:g} (tied: {tied})")
    return choice


def report_conditions(out: Path) -> dict[str, tuple]:
    choice = json.loads((out / "choice.json").read_text())
    return {"paper": (), "interest_worst": IW + (("mode3_sigma", choice["mode3_sigma"]),), "no_mode3": TUNING["no_mode3"]}


def box_tasks() -> tuple[str, ...]:
    """The quick tier's tasks SAGG-RIAC runs on (every box task)."""
    return tuple(n for n, c in TASKS.items() if in_tier(n, TIER) and c.space == "box" and not c.requires)


def paired(d: np.ndarray, rng: np.random.Generator) -> tuple[float, float, float, float]:
    """Mean, bootstrap 95 % interval (10,000 resamples) and the exact two-sided sign-flip p of the
    paired differences ``d``."""
    n = len(d)
    boots = d[rng.integers(0, n, (10_000, n))].mean(axis=1)
    lo, hi = np.percentile(boots, [2.5, 97.5])
    flips = 1 - 2 * ((np.arange(2**n)[:, None] >> np.arange(n)) & 1)
    null = np.abs((flips * d).mean(axis=1))
    p = float(np.mean(null >= abs(d.mean()) - 1e-12))
    return float(d.mean()), float(lo), float(hi), p


def holm(p: list[float]) -> list[float]:
    order = np.argsort(p)
    adj, running = [0.0] * len(p), 0.0
    for rank, i in enumerate(order):
        running = max(running, min(1.0, (len(p) - rank) * p[i]))
        adj[i] = running
    return adj


def analyse(out: Path) -> None:
    """The registered comparison (interest_worst against the paper's reading), then the secondary
    one (interest_worst against no_mode3), each Holm-adjusted over the tasks."""
    text = ""
    for base, other, name in (("paper", "interest_worst", "report_results.md"), ("no_mode3", "interest_worst", "report_secondary.md")):
        text += compare(out, base, other, name)
    print(text)


def compare(out: Path, base: str, other: str, name: str) -> str:
    t = table(out / "report_runs.csv")
    rng = np.random.default_rng(np.random.SeedSequence(48))
    lines, res = [], []
    for task in box_tasks():
        a, b = t.get((base, task), {}), t.get((other, task), {})
        seeds = sorted(set(a) & set(b) & set(REPORT_SEEDS))
        if len(seeds) < len(REPORT_SEEDS):
            print(f"{task}: {len(seeds)} of {len(REPORT_SEEDS)} paired seeds (interim)")
        if not seeds:
            continue
        fa, fb = np.array([a[s][0] for s in seeds]), np.array([b[s][0] for s in seeds])
        aa, ab = np.array([a[s][1] for s in seeds]), np.array([b[s][1] for s in seeds])
        res.append((task, len(seeds), fa.mean(), fb.mean(), paired(fb - fa, rng), aa.mean(), ab.mean(), paired(ab - aa, rng)))
    adj = holm([r[4][3] for r in res])
    lines.append(f"| task | seeds | {base} final | {other} final | difference [95 % CI] | p (Holm) | verdict | {base} area | {other} area | area difference [95 % CI] |")
    lines.append("|---|---|---|---|---|---|---|---|---|---|")
    for (task, n, fa, fb, (m, lo, hi, _), aa, ab, (am, alo, ahi, _)), p in zip(res, adj):
        verdict = ("better" if m > 0 else "worse") if p < 0.05 else "no difference shown"
        lines.append(f"| {task} | {n} | {fa:.3f} | {fb:.3f} | {m:+.3f} [{lo:+.3f}, {hi:+.3f}] | {p:.2g} | {verdict} | {aa:.3f} | {ab:.3f} | {am:+.3f} [{alo:+.3f}, {ahi:+.3f}] |")
    text = "\n".join(lines) + "\n"
    (out / name).write_text(text)
    return text


ARM_SEEDS = tuple(range(920, 930))
ARM_PRESETS = ("exp1", "exp2")
ARM_FIELDS = ("preset", "condition", "seed", "reach_error", "pred_error", "seconds", "version", "commit")


def arm_runs(out: Path) -> None:
    """The paper's experiments (their presets and budgets, condition sagg_riac) with each mode 3
    reading: the final evaluation's reaching error, one row per run."""
    import time

    import saggriac as sg

    path = out / "arm_runs.csv"
    done = {(r["preset"], r["condition"], int(r["seed"])) for r in rows(path)}
    new = not path.exists()
    sigma = json.loads((out / "choice.json").read_text())["mode3_sigma"]
    readings = {"paper": {}, "interest_worst": {"mode3": "interest_worst", "mode3_sigma": sigma}}
    commit = git_commit()
    with path.open("a", newline="") as f:
        w = csv.DictWriter(f, ARM_FIELDS)
        if new:
            w.writeheader()
        for preset in ARM_PRESETS:
            for seed in ARM_SEEDS:
                for name, kw in readings.items():
                    if (preset, name, seed) in done:
                        continue
                    start = time.perf_counter()
                    last = sg.run(sg.Config.from_preset(preset, **kw), seed=seed).metrics.iloc[-1]
                    row = dict(preset=preset, condition=name, seed=seed, reach_error=repr(float(last["reach_error"])), pred_error=repr(float(last["pred_error"])), seconds=f"{time.perf_counter() - start:.1f}", version=_core.__version__, commit=commit)
                    w.writerow(row)
                    f.flush()
                    print(f"arm {preset} {name:16s} seed {seed}: reach_error {float(last['reach_error']):.3f}", flush=True)


def arm_analyse(out: Path) -> None:
    """interest_worst minus paper in final reaching error (lower is better), paired by seed; Holm
    over the two presets."""
    t: dict[tuple[str, str], dict[int, float]] = {}
    for r in rows(out / "arm_runs.csv"):
        t.setdefault((r["preset"], r["condition"]), {})[int(r["seed"])] = float(r["reach_error"])
    rng = np.random.default_rng(np.random.SeedSequence(920))
    res = []
    for preset in ARM_PRESETS:
        a, b = t.get((preset, "paper"), {}), t.get((preset, "interest_worst"), {})
        seeds = sorted(set(a) & set(b))
        if not seeds:
            continue
        d = np.array([b[s] - a[s] for s in seeds])
        res.append((preset, len(seeds), np.mean([a[s] for s in seeds]), np.mean([b[s] for s in seeds]), paired(d, rng)))
    adj = holm([r[4][3] for r in res])
    lines = ["| preset | seeds | paper reach error | interest_worst reach error | difference [95 % CI] | p (Holm) | verdict |", "|---|---|---|---|---|---|---|"]
    for (preset, n, ea, eb, (m, lo, hi, _)), p in zip(res, adj):
        verdict = ("better" if m < 0 else "worse") if p < 0.05 else "no difference shown"
        lines.append(f"| {preset} | {n} | {ea:.3f} | {eb:.3f} | {m:+.3f} [{lo:+.3f}, {hi:+.3f}] | {p:.2g} | {verdict} |")
    text = "\n".join(lines) + "\n"
    (out / "arm_results.md").write_text(text)
    print(text)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("phase", choices=["tune", "choose", "report", "analyse", "arm", "arm-analyse"])
    ap.add_argument("--out", default=str(OUT))
    args = ap.parse_args()
    out = Path(args.out)
    if args.phase == "tune":
        run_all(out / "tuning_runs.csv", "tune", TUNING, TOY_TASKS, TUNING_SEEDS)
    elif args.phase == "choose":
        choose(out)
    elif args.phase == "report":
        run_all(out / "report_runs.csv", "report", report_conditions(out), box_tasks(), REPORT_SEEDS)
    elif args.phase == "analyse":
        analyse(out)
    elif args.phase == "arm":
        arm_runs(out)
    else:
        arm_analyse(out)


if __name__ == "__main__":
    sys.exit(main())
