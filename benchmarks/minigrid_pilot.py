"""The pilot of the MiniGrid task-list study (docs/evidence/minigrid.md): the bench task
rl-minigrid's play() with the random teacher and the oracle on the tuning seeds, then the
registered rule that fixes the budget and the number of report seeds.

    python benchmarks/minigrid_pilot.py            # the runs; resumes (a finished run is skipped)
    python benchmarks/minigrid_pilot.py --decide   # the rule, from the committed CSVs alone

One process, one torch thread. Each finished run appends its scorings to
docs/figures/evidence/minigrid/pilot/curves.csv and its row to runs.csv at once.
"""

from __future__ import annotations

import argparse
import json
import math
import subprocess
import time
from pathlib import Path

import numpy as np
import pandas as pd

REPO = Path(__file__).resolve().parents[1]
OUT = REPO / "docs" / "figures" / "evidence" / "minigrid" / "pilot"
PROTOCOL = REPO / "docs" / "figures" / "evidence" / "minigrid" / "protocol.json"
# Fixed by the registration (docs/evidence/minigrid.md), before any run.
SEEDS = (108, 109)
TEACHERS = ("random", "oracle")
PILOT_STEPS = 160_000
SCORINGS = 10
CANDIDATES = tuple(range(80_000, PILOT_STEPS + 1, 16_000))
STUDY_TEACHERS = 6
FAMILY = STUDY_TEACHERS - 1
ALPHA = 0.05
MEANINGFUL = 0.05
CPU_ALLOWED = 8 * 3600
MARGIN = 0.9  # a tenth kept for teachers costlier than random
MIN_SEEDS, MAX_SEEDS = 12, 100
FLOOR, CEILING = 0.05, 0.90


def commit() -> str:
    return subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=REPO, capture_output=True, text=True).stdout.strip()


def one_run(teacher: str, seed: int) -> tuple[list[dict], dict]:
    """One pilot run as the bench runs it: the task built from the run's seed, the random
    teacher guarded as the bench guards it (teacher's seed from the task's child_seeds), the
    oracle asking the task's oracle()."""
    from saggriac.bench.minigrid import RlMiniGrid
    from saggriac.bench.teachers import Guarded, TeacherSpec, alarm_handler

    teacher_seed, task_seed = RlMiniGrid.child_seeds(seed)
    task = RlMiniGrid(task_seed)
    cpu, wall = time.process_time(), time.perf_counter()
    if teacher == "oracle":
        curve = task.play(task.oracle, lambda goal, c: None, PILOT_STEPS)
    else:
        with alarm_handler():
            guard = Guarded(TeacherSpec(teacher), task, teacher_seed, run_seed=seed)
            curve = task.play(guard.ask, guard.tell, PILOT_STEPS)
    cpu, wall = time.process_time() - cpu, time.perf_counter() - wall
    rows = [dict(teacher=teacher, seed=seed, step=int(t), score=float(s)) for t, s in curve]
    run = dict(teacher=teacher, seed=seed, steps=PILOT_STEPS, final=rows[-1]["score"], area=float(np.mean([r["score"] for r in rows])), cpu_s=round(cpu, 1), wall_s=round(wall, 1), oracle_grade=task.grade if teacher == "oracle" else "", commit=commit())
    return rows, run


def append(path: Path, rows: list[dict]) -> None:
    frame = pd.DataFrame(rows)
    frame.to_csv(path, mode="a", header=not path.exists(), index=False)


def run_all() -> None:
    import torch

    torch.set_num_threads(1)
    OUT.mkdir(parents=True, exist_ok=True)
    done = set()
    if (OUT / "runs.csv").exists():
        done = {(r.teacher, int(r.seed)) for r in pd.read_csv(OUT / "runs.csv").itertuples()}
    for seed in SEEDS:
        for teacher in TEACHERS:
            if (teacher, seed) in done:
                continue
            rows, run = one_run(teacher, seed)
            append(OUT / "curves.csv", rows)
            append(OUT / "runs.csv", [run])
            print(json.dumps(run), flush=True)


def power(n: int, d: float, alpha: float) -> float:
    """Power of a two-sided paired t-test with n pairs at effect d_z (noncentral t)."""
    from scipy import stats

    df, nc = n - 1, d * math.sqrt(n)
    crit = stats.t.ppf(1 - alpha / 2, df)
    return float(stats.nct.sf(crit, df, nc) + np.nan_to_num(stats.nct.cdf(-crit, df, nc)))


def seeds_needed(d: float, alpha: float) -> int:
    return next((n for n in range(3, 1000) if power(n, d, alpha) >= 0.8), 1000)


def decide() -> str:
    """The registered rule, from pilot/curves.csv and runs.csv."""
    curves, runs = pd.read_csv(OUT / "curves.csv"), pd.read_csv(OUT / "runs.csv")
    cpu_per_step = float((runs["cpu_s"] / runs["steps"]).mean())
    first = ALPHA / FAMILY
    lines = [f"pilot: {len(runs)} runs ({', '.join(f'{r.teacher} {r.seed}' for r in runs.itertuples())}), mean CPU {cpu_per_step * 1000:.3f} s per 1,000 steps", ""]
    lines += ["| B | random mean | oracle mean | pooled SD | d_z of 0.05 | seeds for 80 % (alpha 0.05/5) | seeds the CPU allows | fits |", "|---|---|---|---|---|---|---|---|"]
    table = []
    for b in CANDIDATES:
        # The score at B: the pilot's scoring at the first step >= B (scorings every 16,000 steps).
        at = curves[curves["step"] >= b].sort_values("step").groupby(["teacher", "seed"]).first().reset_index()
        sd = float(np.sqrt(at.groupby("teacher")["score"].var(ddof=1).mean()))
        d = MEANINGFUL / (math.sqrt(2) * sd) if sd > 0 else math.inf
        need = max(seeds_needed(d, first), 3)
        allowed = int(CPU_ALLOWED * MARGIN // (STUDY_TEACHERS * cpu_per_step * b))
        means = at.groupby("teacher")["score"].mean()
        table.append((b, need, allowed, means.get("random", math.nan), means.get("oracle", math.nan)))
        lines.append(f"| {b:,} | {means.get('random', math.nan):.3f} | {means.get('oracle', math.nan):.3f} | {sd:.4f} | {d:.2f} | {need} | {allowed} | {'yes' if need <= allowed else 'no'} |")
    fits = [t for t in table if t[1] <= t[2]]
    if fits:
        b, need, allowed, rnd, orc = fits[-1]
        n = min(allowed, max(need, MIN_SEEDS), MAX_SEEDS)
        how = f"the largest B where the seeds needed ({need}) fit in the CPU ({allowed})"
    else:
        b, need, allowed, rnd, orc = min(table, key=lambda t: t[1] / max(t[2], 1))
        n = min(allowed, MAX_SEEDS)
        how = f"no B fits; the B with the smallest ratio of seeds needed to seeds allowed ({need} / {allowed}), all the seeds the CPU allows"
    family_ok = FLOOR <= rnd <= CEILING
    lines += ["", f"budget B = {b:,} steps ({how}); report seeds: {n} (1300-{1300 + n - 1})"]
    lines.append(f"level family: random's mean held-back score at B is {rnd:.3f}: {'within' if family_ok else 'OUTSIDE'} [{FLOOR}, {CEILING}], so the six-grade ladder {'stays' if family_ok else 'is not used: the study stops here and is registered anew'}")
    lines.append(f"projected CPU of the report runs: {STUDY_TEACHERS} x {n} x {cpu_per_step * b:.0f} s = {STUDY_TEACHERS * n * cpu_per_step * b / 3600:.1f} h")
    sd_b = float(np.sqrt(curves[curves["step"] >= b].sort_values("step").groupby(["teacher", "seed"]).first().groupby("teacher")["score"].var(ddof=1).mean()))
    detect = next((d for d in np.arange(0.1, 5.0, 0.01) if power(n, d, first) >= 0.8), math.nan)
    lines.append(f"at {n} seeds, 80 % power at Holm's first step for d_z >= {detect:.2f}, a difference of {detect * math.sqrt(2) * sd_b:.3f} in held-back return (pilot SD {sd_b:.4f}, no pairing assumed)")
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--decide", action="store_true", help="apply the registered rule to the pilot's CSVs and write pilot/decision.md")
    args = parser.parse_args()
    if args.decide:
        text = decide()
        (OUT / "decision.md").write_text(text + "\n")
        print(text)
    else:
        run_all()


if __name__ == "__main__":
    main()
