"""Three readings of the paper measured for issue 35 (item 4), by the rules that
docs/parameters.md states (committed before these runs).

    python benchmarks/reading_checks.py window  --out DIR [--workers 2]
    python benchmarks/reading_checks.py trigger --out DIR [--workers 2]
    python benchmarks/reading_checks.py trigger_more --out DIR [--workers 2]
    python benchmarks/reading_checks.py q20     --out DIR --repro REPRO [--workers 2]
    python benchmarks/reading_checks.py report  --out DIR [--repro REPRO] [--csv FILE]

- ``window``: eq. 2's full window, ``interest_divisor="printed"`` (the printed index ranges:
  zeta + 1 values, the middle one cancelling) against ``"zeta"`` (the last zeta values), exp2,
  SAGG-RIAC, tuning seeds 100-129, evaluated at the end only (DIR/exp2-zeta, DIR/exp2-printed).
- ``trigger``: ``exploration_trigger="desired"`` against the default ``"executed"``, the same runs
  on tuning seeds 100-114 (DIR/exp2-desired, paired with DIR/exp2-zeta); ``trigger_more`` adds
  seeds 115-129 (DIR/exp2-desired-more), after the registered comparison, to check its size.
- ``q20``: Fig. 3's setting, exp2 with q = 20, SAGG-RIAC and SAGG-Random on the report seeds
  15-29 (DIR/exp2-q20), paired with the q = 100 runs of the replication (REPRO/reproduce-exp2,
  made by ``bench_reproduce.py --first-seed 15``).
- ``report``: the paired tables of all three (variant minus reference, by seed), the trigger's
  disagreement counts of the default runs, and with --csv one row per run.

Each study resumes: finished runs in its folder are kept. Evaluation never changes learning, so
runs evaluated at the end only end where the reproduction's 20-evaluation runs end.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

import saggriac as sg
from saggriac.analysis.statistics import paired

sys.path.insert(0, str(Path(__file__).resolve().parent))
from eq2_readings import read_run  # noqa: E402  (final errors, goals, second-half reachable share)
from goal_placement import zones  # noqa: E402  (the reachable area)

TUNING_30 = tuple(range(100, 130))
TUNING_15 = tuple(range(100, 115))
REPORT_2 = tuple(range(15, 30))


def studies(which: str) -> dict[str, sg.Study]:
    """The study folders (name -> Study) that `which` runs."""
    base = dict(n_evals=1)
    if which == "window":
        return {
            "exp2-zeta": sg.Study(sg.Config.from_preset("exp2", interest_divisor="zeta", **base), ("sagg_riac",), TUNING_30),
            "exp2-printed": sg.Study(sg.Config.from_preset("exp2", interest_divisor="printed", **base), ("sagg_riac",), TUNING_30),
        }
    if which == "trigger":
        return {"exp2-desired": sg.Study(sg.Config.from_preset("exp2", exploration_trigger="desired", **base), ("sagg_riac",), TUNING_15)}
    if which == "trigger_more":
        # Added after the registered 15 seeds: the other 15 tuning seeds, to check the size of the
        # effect on the share (it decides nothing; docs/parameters.md says so).
        return {"exp2-desired-more": sg.Study(sg.Config.from_preset("exp2", exploration_trigger="desired", **base), ("sagg_riac",), TUNING_30[15:])}
    if which == "q20":
        return {"exp2-q20": sg.Study(sg.Config.from_preset("exp2", q=20, **base), ("sagg_riac", "sagg_random"), REPORT_2)}
    raise SystemExit(f"unknown study {which!r}")


def read(folder: Path, condition: str) -> pd.DataFrame:
    """One row per finished run of a condition: the measures of eq2_readings.read_run and the
    exploration trigger's counts (run.json profile)."""
    rows = {}
    for run_dir in sorted((folder / "runs" / condition).glob("seed*")):
        if not (run_dir / "run.json").exists():
            continue
        row = read_run(run_dir)
        prof = json.loads((run_dir / "run.json").read_text())["profile"]
        reaching = prof.get("reaching_steps", 0)
        if "trigger_gap_sum" in prof and reaching:
            row["reaching_steps"] = reaching
            row["explorations"] = prof["explorations"]
            row["only_executed"] = prof["trigger_only_executed"] / reaching
            row["only_desired"] = prof["trigger_only_desired"] / reaching
            row["disagree"] = (prof["trigger_only_executed"] + prof["trigger_only_desired"]) / reaching
            row["mean_gap"] = prof["trigger_gap_sum"] / reaching
        rows[int(run_dir.name[4:])] = row
    return pd.DataFrame.from_dict(rows, orient="index").sort_index()


def quarter_shares(folder: Path, condition: str, seeds: tuple[int, ...]) -> np.ndarray:
    """Mean over seeds of the reachable share of the goals started in each quarter of the run."""
    out = []
    for seed in seeds:
        run_dir = folder / "runs" / condition / f"seed{seed}"
        cfg = sg.Config.from_saved(json.loads((run_dir / "run.json").read_text())["config"])
        goals = pd.read_parquet(run_dir / "goals.parquet")
        quarter = np.minimum(goals["step_start"].to_numpy() * 4 // cfg.n_steps, 3)
        reach = np.asarray(zones(goals, cfg)["reachable"], float)
        out.append([reach[quarter == i].mean() for i in range(4)])
    return np.mean(out, axis=0)


METRICS = (("reach_error", "final reaching error", 2), ("share_2nd_half", "2nd-half reachable share", 3), ("pred_error", "final prediction error", 2), ("goals", "goals per run", 1))


def compare(label: str, variant: pd.DataFrame, reference: pd.DataFrame) -> list[dict]:
    both = variant.index.intersection(reference.index)
    rows = []
    for metric, name, d in METRICS:
        a, b = variant.loc[both, metric].to_numpy(float), reference.loc[both, metric].to_numpy(float)
        r = paired(a, b)
        rows.append({"comparison": label, "metric": name, "seeds": f"{both.min()}-{both.max()} ({len(both)})", "reference": f"{b.mean():.{d}f} ± {b.std(ddof=1):.{d}f}", "variant": f"{a.mean():.{d}f} ± {a.std(ddof=1):.{d}f}", "variant - reference [95 % CI]": f"{r['mean_diff']:+.{d}f} [{r['ci_low']:+.{d}f}, {r['ci_high']:+.{d}f}]", "p": f"{r['p_value']:.2g}", "d_z": f"{r['effect']:+.2f}"})
    return rows


def markdown(table: pd.DataFrame) -> str:
    lines = ["| " + " | ".join(table.columns) + " |", "|" + "---|" * len(table.columns)]
    lines += ["| " + " | ".join(str(v) for v in row) + " |" for row in table.itertuples(index=False)]
    return "\n".join(lines)


def report(out: Path, repro: Path | None, csv: Path | None) -> int:
    rows, per_run = [], []
    ref = read(out / "exp2-zeta", "sagg_riac") if (out / "exp2-zeta").exists() else pd.DataFrame()
    for folder, label in (("exp2-printed", "eq. 2 window: 'printed' - 'zeta' (SAGG-RIAC)"), ("exp2-desired", "trigger: 'desired' - 'executed' (SAGG-RIAC)"), ("exp2-desired-more", "trigger, seeds added after the rule: 'desired' - 'executed' (SAGG-RIAC)")):
        if (out / folder).exists() and not ref.empty:
            var = read(out / folder, "sagg_riac")
            rows += compare(label, var, ref)
            per_run.append(var.assign(study=folder, condition="sagg_riac"))
    if (out / "exp2-desired-more").exists() and not ref.empty:
        var = pd.concat([read(out / "exp2-desired", "sagg_riac"), read(out / "exp2-desired-more", "sagg_riac")])
        rows += compare("trigger, all 30 tuning seeds: 'desired' - 'executed' (SAGG-RIAC)", var, ref)
    if not ref.empty:
        per_run.append(ref.assign(study="exp2-zeta", condition="sagg_riac"))
    if repro is not None and (out / "exp2-q20").exists():
        for cond in ("sagg_riac", "sagg_random"):
            q20, q100 = read(out / "exp2-q20", cond), read(repro / "reproduce-exp2", cond)
            q100 = q100.loc[q100.index.intersection(list(REPORT_2))]
            rows += compare(f"Fig. 3's q: q = 20 - q = 100 ({cond})", q20, q100)
            per_run += [q20.assign(study="exp2-q20", condition=cond), q100.assign(study="replication exp2 (q = 100)", condition=cond)]
        print("reachable share of the goals started in each quarter of the run (mean over seeds 15-29)")
        for cond in ("sagg_riac", "sagg_random"):
            for name, folder in (("q = 20", out / "exp2-q20"), ("q = 100", repro / "reproduce-exp2")):
                print(f"  {cond:12s} {name:8s} " + " ".join(f"{v:.3f}" for v in quarter_shares(folder, cond, REPORT_2)))
        print()
        r20, s20 = read(out / "exp2-q20", "sagg_riac"), read(out / "exp2-q20", "sagg_random")
        rows += compare("at q = 20: SAGG-RIAC - SAGG-Random", r20, s20)
    table = pd.DataFrame(rows)
    print(markdown(table))
    if not ref.empty and "disagree" in ref:
        print("\nexploration trigger, default runs (exp2-zeta): share of reaching micro-actions, mean over seeds [min, max]")
        for col in ("only_executed", "only_desired", "disagree", "mean_gap"):
            v = ref[col]
            print(f"  {col:14s} {v.mean():.4f} [{v.min():.4f}, {v.max():.4f}]")
        print(f"  explorations per run {ref['explorations'].mean():.0f}, reaching micro-actions per run {ref['reaching_steps'].mean():.0f}")
    if csv is not None:
        pd.concat(per_run).rename_axis("seed").reset_index().to_csv(csv, index=False)
        print(f"\nper-run table: {csv}")
    return 0


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("what", choices=("window", "trigger", "trigger_more", "q20", "report"))
    p.add_argument("--out", required=True, help="folder of the study folders")
    p.add_argument("--repro", default=None, help="folder holding reproduce-exp2 of seeds 15-29 (for q20)")
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--csv", default=None, help="with report: write one row per run here")
    a = p.parse_args()
    out = Path(a.out)
    if a.what == "report":
        return report(out, Path(a.repro) if a.repro else None, Path(a.csv) if a.csv else None)
    for name, study in studies(a.what).items():
        t0 = time.perf_counter()
        res = sg.run_study(study, out / name, n_workers=a.workers, progress=False)
        print(f"{name}: {res.n_computed} runs computed, {res.n_skipped} reused, {time.perf_counter() - t0:.1f} s wall", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
