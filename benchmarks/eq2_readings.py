"""Eq. 2's two readings for young regions, side by side on seeds 0-14 (a comparison; it picks nothing).

    python benchmarks/eq2_readings.py --repro /work/runs/repro --out /work/runs/eq2 \
        --presets exp2 exp1 explauto arm3d pusher [--seeds 15] [--workers 2] [--md FILE] \
        [--conditions sagg_riac actuator_riac]

A region holding fewer than zeta measurements gets, since saggriac 0.3, the difference of its
two half-sums divided by the fixed zeta (``interest_divisor="zeta"``, the default, the paper's
printed denominator); up to 0.2 it was divided by the region's own count w
(``interest_divisor="window"``). Only the conditions that keep a region tree use eq. 2:
SAGG-RIAC (the goal-space tree) and ACTUATOR-RIAC (its R-IAC tree).

For each preset this script runs those two conditions with ``interest_divisor="window"`` on the
seeds 0..N-1 at full scale, as a saggriac Study in OUT/PRESET (the preset's own step count and
n_evals, i.e. the same evaluation schedule as ``saggriac reproduce``; a folder that already holds
finished runs is resumed, not recomputed). It then pairs each run by seed with the run of the same
condition in the reproduction folder REPRO/reproduce-PRESET (made by ``bench_reproduce.py`` with
the new default) and compares, new reading minus old (saggriac.analysis.statistics.paired):

- the final reaching error and the final prediction error (both conditions);
- goals per run and the share of the second-half goals (started at step >= n_steps / 2) that lie
  in the reachable area (SAGG-RIAC only);
- in SAGG-RIAC's final tree, the part of mode 1's weights (eq. 3, |I - min I| over the leaves)
  that falls on young leaves (fewer than zeta measurements), where the two readings differ. The reachable area is the one of
  ``benchmarks/goal_placement.py`` (``zones``): |g| <= arm length for the planar and spatial arms,
  which is also ``benchmarks/sensitivity.py``'s definition, and the sampled reachable set for a
  chain (pusher).

--conditions limits the runs and the rows to some of the two conditions (default both): e.g. after
a change that ACTUATOR-RIAC does not read (eps_max, a parameter of SAGG's low level only), its
old-reading runs of an earlier OUT folder still hold and need no rerun.

Holm's correction is taken over the rows of each preset. The table is printed, and written as
markdown to --md (default OUT/eq2_readings.md) and as CSV beside it.
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
from saggriac.analysis.statistics import holm, paired

sys.path.insert(0, str(Path(__file__).resolve().parent))
from goal_placement import zones  # noqa: E402  (the reachable area, as goal_placement.py defines it)

CONDITIONS = ("sagg_riac", "actuator_riac")
NAMES = {"sagg_riac": "SAGG-RIAC", "actuator_riac": "ACTUATOR-RIAC"}
METRICS = (
    ("reach_error", "final reaching error", CONDITIONS),
    ("pred_error", "final prediction error", CONDITIONS),
    ("goals", "goals per run", ("sagg_riac",)),
    ("share_2nd_half", "2nd-half reachable share", ("sagg_riac",)),
    ("young_mass", "eq.-3 mass on young leaves", ("sagg_riac",)),
)


def old_study(preset: str, seeds: int, conditions: tuple[str, ...] = CONDITIONS) -> sg.Study:
    return sg.Study(sg.Config.from_preset(preset, interest_divisor="window"), conditions, tuple(range(seeds)))


def read_run(run_dir: Path) -> dict[str, float]:
    manifest = json.loads((run_dir / "run.json").read_text())
    cfg = sg.Config.from_saved(manifest["config"])
    last = pd.read_parquet(run_dir / "metrics.parquet").iloc[-1]
    row = {"reach_error": float(last["reach_error"]), "pred_error": float(last["pred_error"]), "divisor": cfg.interest_divisor, "commit": manifest.get("git_commit")}
    goals_file = run_dir / "goals.parquet"
    if cfg.condition.startswith("sagg") and goals_file.exists():
        goals = pd.read_parquet(goals_file)
        late = goals[goals["step_start"] >= cfg.n_steps / 2]
        row["goals"] = float(len(goals))
        row["share_2nd_half"] = float(zones(late, cfg)["reachable"].mean()) if len(late) else np.nan
    regions_file = run_dir / "regions.parquet"
    if cfg.condition == "sagg_riac" and regions_file.exists():
        # Mode 1's weights in the final tree (eq. 3: |I - min I| over the leaves), and the part of
        # them held by young leaves (fewer than zeta measurements), where the two readings differ.
        leaves = pd.read_parquet(regions_file)
        leaves = leaves[leaves["is_leaf"]]
        weight = (leaves["interest"] - leaves["interest"].min()).abs()
        young = leaves["n_measurements"] < cfg.zeta
        row["young_mass"] = float(weight[young].sum() / weight.sum()) if weight.sum() > 0 else np.nan
    return row


def read_folder(folder: Path, condition: str, seeds: int) -> pd.DataFrame:
    rows = {}
    for seed in range(seeds):
        run_dir = folder / "runs" / condition / f"seed{seed}"
        if (run_dir / "run.json").exists():
            rows[seed] = read_run(run_dir)
    return pd.DataFrame.from_dict(rows, orient="index").sort_index()


def check_same_but_divisor(old_folder: Path, new_folder: Path) -> None:
    """The two studies must differ in interest_divisor only (same preset, steps, evaluations)."""
    old = sg.Study.load(old_folder).base.to_dict()
    new = sg.Study.load(new_folder).base.to_dict()
    diff = sorted(k for k in set(old) | set(new) if old.get(k) != new.get(k))
    if diff != ["interest_divisor"] or old["interest_divisor"] != "window" or new["interest_divisor"] != "zeta":
        raise SystemExit(f"{old_folder} and {new_folder} should differ in interest_divisor only ('window' against 'zeta'); they differ in {diff}")


def compare(preset: str, old_folder: Path, new_folder: Path, seeds: int, conditions: tuple[str, ...] = CONDITIONS) -> pd.DataFrame:
    check_same_but_divisor(old_folder, new_folder)
    rows = []
    for cond in conditions:
        old, new = read_folder(old_folder, cond, seeds), read_folder(new_folder, cond, seeds)
        both = old.index.intersection(new.index)
        for metric, label, conds in METRICS:
            if cond not in conds or metric not in old or metric not in new:
                continue
            a, b = new.loc[both, metric].to_numpy(float), old.loc[both, metric].to_numpy(float)
            r = paired(a, b)
            rows.append(
                {
                    "preset": preset,
                    "condition": NAMES[cond],
                    "metric": label,
                    "seeds": len(both),
                    "old (w) mean": b.mean(),
                    "old (w) sd": b.std(ddof=1),
                    "new (zeta) mean": a.mean(),
                    "new (zeta) sd": a.std(ddof=1),
                    "new - old": r["mean_diff"],
                    "ci_low": r["ci_low"],
                    "ci_high": r["ci_high"],
                    "p": r["p_value"],
                }
            )
    frame = pd.DataFrame(rows)
    frame["p Holm"] = holm(frame["p"].to_numpy())
    return frame


DECIMALS = {"final reaching error": 2, "final prediction error": 2, "goals per run": 1, "2nd-half reachable share": 3, "eq.-3 mass on young leaves": 3}


def _num(x: float, d: int) -> str:
    return "-" if not np.isfinite(x) else f"{x:.{d}f}"


def _signed(x: float, d: int) -> str:
    return "-" if not np.isfinite(x) else f"{x:+.{d}f}"


def _p(x: float) -> str:
    return "-" if not np.isfinite(x) else f"{x:.2g}"


def markdown(table: pd.DataFrame, command: str) -> str:
    out = [
        "| preset | condition | metric | old reading (/w) | new reading (/zeta) | new - old [95 % CI] | p | p Holm |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for _, r in table.iterrows():
        d = DECIMALS[r["metric"]]
        if r["metric"].endswith("error") and max(abs(r["old (w) mean"]), abs(r["new (zeta) mean"])) < 1:
            d = 3  # explauto's errors are about 0.2
        out.append(
            f"| {r['preset']} | {r['condition']} | {r['metric']} | {_num(r['old (w) mean'], d)} ± {_num(r['old (w) sd'], d)} | "
            f"{_num(r['new (zeta) mean'], d)} ± {_num(r['new (zeta) sd'], d)} | {_signed(r['new - old'], d)} [{_signed(r['ci_low'], d)}, {_signed(r['ci_high'], d)}] | "
            f"{_p(r['p'])} | {_p(r['p Holm'])} |"
        )
    out += ["", f"*Mean ± sd over seeds, paired by seed (saggriac.analysis.statistics.paired); Holm over the rows of each preset. `{command}`*", ""]
    return "\n".join(out)


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--presets", nargs="+", default=["exp2", "exp1"])
    p.add_argument("--repro", required=True, help="folder holding reproduce-PRESET study folders (bench_reproduce.py --out)")
    p.add_argument("--out", required=True, help="the old reading's study folders go to OUT/PRESET")
    p.add_argument("--seeds", type=int, default=15)
    p.add_argument("--workers", type=int, default=None)
    p.add_argument("--md", default=None, help="markdown table (default OUT/eq2_readings.md)")
    p.add_argument("--conditions", nargs="+", choices=CONDITIONS, default=list(CONDITIONS), help="which of the two to run and compare (default both)")
    a = p.parse_args()
    out = Path(a.out)
    tables = []
    for preset in a.presets:
        new_folder = Path(a.repro) / f"reproduce-{preset}"
        if not (new_folder / "study.json").exists():
            print(f"{preset}: no reproduction folder {new_folder}; skipped", file=sys.stderr)
            continue
        t0 = time.perf_counter()
        conditions = tuple(c for c in CONDITIONS if c in a.conditions)
        res = sg.run_study(old_study(preset, a.seeds, conditions), out / preset, n_workers=a.workers, progress=False)
        print(f"{preset}: old reading, {res.n_computed} runs computed, {res.n_skipped} reused, {time.perf_counter() - t0:.1f} s wall", flush=True)
        tables.append(compare(preset, out / preset, new_folder, a.seeds, conditions))
    if not tables:
        return 1
    table = pd.concat(tables, ignore_index=True)
    command = "python benchmarks/eq2_readings.py " + " ".join(sys.argv[1:])
    md = markdown(table, command)
    print(md)
    md_path = Path(a.md) if a.md else out / "eq2_readings.md"
    md_path.write_text(md)
    table.to_csv(md_path.with_suffix(".csv"), index=False)
    return 0


if __name__ == "__main__":
    sys.exit(main())
