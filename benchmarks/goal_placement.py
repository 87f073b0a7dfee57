"""Where each condition puts its goals, and why SAGG-RIAC's interest goes there.

    python benchmarks/goal_placement.py STUDY_FOLDER [STUDY_FOLDER ...]

For a study made by `saggriac reproduce` (or any study of the built-in planar arms), prints two
tables and writes them as CSV beside the study (``goal_placement.csv``, ``leaf_interest.csv``):

1. Per condition, the share of goals (by count, mean over seeds) in zones of the goal space (2-D
   or 3-D): the reachable disk or ball (|g| <= arm length L; for a chain, its sampled reachable
   set, saggriac.bodies.reachable), the area near the base (|g| < 0.3 L), the band just outside the rim
   (unreachable, |g| <= 1.1 L), and near the rest position (|g - rest| < 0.2 L); over the
   whole run, its second half and each quarter (by the step a goal started at).
2. For SAGG-RIAC, the leaves of the final region tree grouped by their mean competence: how many
   leaves, their mean interest (eq. 2), and their share of the summed interest, i.e. of what mode 1
   (eq. 3) hands out. A leaf whose competence has saturated near 0 has no competence progress and
   so no interest, however much is left to learn inside it for a uniform test.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pandas as pd

import saggriac as sg
from saggriac.analysis.splits import reachable_shares
from saggriac.analysis.statistics import paired
from saggriac.bodies.reachable import ReachableSet


def _against_zero(d: np.ndarray) -> str:
    """Mean of per-seed differences, its 95 % CI and p (saggriac.analysis.statistics.paired against 0)."""
    r = paired(d, np.zeros_like(d))
    return f"{r['mean_diff']:+.3f} [{r['ci_low']:+.3f}, {r['ci_high']:+.3f}], p = {r['p_value']:.2g} (n = {len(d)})"


def zones(goals: pd.DataFrame, cfg: sg.Config) -> dict[str, np.ndarray]:
    cols = [c for c in ("goal_x", "goal_y", "goal_z") if c in goals.columns]
    g = goals[cols].to_numpy(float)
    reach = cfg.reach
    r = np.sqrt((g**2).sum(axis=1))
    if cfg.chain is not None:
        # A chain reaches an irregular set around its first joint (the origin); rest is mid-range.
        inside = ReachableSet(cfg).contains(g)
        rest = sg._core.chain_forward(list(cfg.chain), np.zeros((1, cfg.joints)))[0][: len(cols)]
    else:
        inside = r <= reach
        rest = np.zeros(len(cols))
        rest[0] = reach  # the straight arm along x
    return {
        "reachable": inside,
        "near_base": r < 0.3 * reach,
        "rim_band": ~inside & (r <= 1.1 * reach),
        "near_rest": np.sqrt(((g - rest) ** 2).sum(axis=1)) < 0.2 * reach,
    }


def placement(folder: Path) -> pd.DataFrame:
    rows = []
    for task in sg.Study.load(folder).tasks():
        run = folder / task.path
        if task.condition not in ("sagg_riac", "sagg_random") or not (run / "run.json").exists():
            continue
        cfg = sg.Config.from_saved(json.loads((run / "run.json").read_text())["config"])
        goals = pd.read_parquet(run / "goals.parquet")
        late = goals[goals["step_start"] >= cfg.n_steps / 2]
        quarter = np.minimum((4 * goals["step_start"].to_numpy() // max(cfg.n_steps, 1)), 3)
        parts = [("whole run", goals), ("second half", late)] + [(f"quarter {q + 1}", goals[quarter == q]) for q in range(4)]
        for part, sel in parts:
            z = zones(sel, cfg)
            rows.append({"condition": task.condition, "seed": task.seed, "part": part, "goals": len(sel), **{k: float(v.mean()) for k, v in z.items()}})
    frame = pd.DataFrame(rows)
    whole = frame[frame["part"] == "whole run"].pivot(index="seed", columns="condition", values="reachable")
    if {"sagg_riac", "sagg_random"} <= set(whole.columns):
        d = (whole["sagg_riac"] - whole["sagg_random"]).dropna().to_numpy()
        if len(d) > 1:
            print(f"{folder}: share of goals in the reachable area, SAGG-RIAC - SAGG-Random, paired by seed: {_against_zero(d)}")
    return frame.groupby(["part", "condition"], sort=False).mean(numeric_only=True).drop(columns="seed").reset_index()


BINS = [(-np.inf, -0.5, "C <= -0.5"), (-0.5, -0.05, "-0.5 < C <= -0.05"), (-0.05, np.inf, "C > -0.05 (saturated)")]


def leaf_interest(folder: Path) -> pd.DataFrame:
    rows = []
    for task in sg.Study.load(folder).tasks():
        run = folder / task.path
        if task.condition != "sagg_riac" or not (run / "regions.parquet").exists():
            continue
        cfg = sg.Config.from_saved(json.loads((run / "run.json").read_text())["config"])
        r = pd.read_parquet(run / "regions.parquet")
        leaves = r[r["is_leaf"] & (r["n_measurements"] > 0)]
        total = leaves["interest"].sum()
        dims = [c[len("low_") :] for c in leaves.columns if c.startswith("low_")]
        inside = reachable_shares(leaves[[f"low_{d}" for d in dims]].to_numpy(float), leaves[[f"high_{d}" for d in dims]].to_numpy(float), ReachableSet(cfg) if cfg.chain is not None else cfg.reach, grid=20)
        for lo, hi, label in BINS:
            sel = (leaves["mean_competence"] > lo) & (leaves["mean_competence"] <= hi)
            rows.append(
                {
                    "seed": task.seed,
                    "mean competence": label,
                    "leaves": int(sel.sum()),
                    "mean interest": float(leaves.loc[sel, "interest"].mean()) if sel.any() else np.nan,
                    "share of interest": float(leaves.loc[sel, "interest"].sum() / total) if total > 0 else np.nan,
                    "mean reachable share": float(inside[sel.to_numpy()].mean()) if sel.any() else np.nan,
                }
            )
    frame = pd.DataFrame(rows)
    if frame.empty:
        return frame
    return frame.groupby("mean competence", sort=False).mean(numeric_only=True).drop(columns="seed").reset_index()


def split_test(folder: Path) -> None:
    """Fig. 3's split statistic against its null model (``splits.csv`` of ``reproduce``): per seed,
    the mean over the quarters of the reachable share of the split regions, SAGG-RIAC's tree minus
    the tree SAGG-Random's measurements build, paired by seed."""
    path = folder / "splits.csv"
    if not path.exists():
        return
    s = pd.read_csv(path).groupby(["tree", "seed"])["reachable_share"].mean().unstack("tree").dropna()
    d = (s["sagg_riac"] - s["sagg_random_replayed"]).to_numpy()
    if len(d) > 1:
        print(f"{folder}: reachable share of split regions, SAGG-RIAC - replayed SAGG-Random, paired by seed: {_against_zero(d)}")


def main(argv: list[str]) -> int:
    if not argv:
        print(__doc__)
        return 2
    pd.set_option("display.width", 200)
    for arg in argv:
        folder = Path(arg)
        place, leaves = placement(folder), leaf_interest(folder)
        place.to_csv(folder / "goal_placement.csv", index=False)
        leaves.to_csv(folder / "leaf_interest.csv", index=False)
        print(f"{folder}: share of goals by zone (mean over seeds)\n{place.to_string(index=False, float_format='%.3f')}\n")
        print(f"{folder}: SAGG-RIAC's final leaves by mean competence (mean over seeds)\n{leaves.to_string(index=False, float_format='%.3f')}\n")
        split_test(folder)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
