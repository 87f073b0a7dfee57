"""The paper's claims for experiments 1 and 2, as effect sizes, on two independent sets of seeds.

    python benchmarks/replication.py --sets 0-14=REPRO_A 15-29=REPRO_B [--write-runs DIR] [--md FILE] [--csv FILE]
    python benchmarks/replication.py --from-tables docs/figures/replication [--check] [--md FILE] [--csv FILE]

Each REPRO folder holds reproduce-exp1 and reproduce-exp2 study folders written by
``benchmarks/bench_reproduce.py`` (``--first-seed 15`` for the second set). --write-runs writes
one row per run of each (experiment, set) to DIR/EXP_runs_LABEL.csv: the final errors, goals,
reachable shares, time budget and the learning curves (reach_error@STEP etc., every evaluation),
read from the run folders. --from-tables reads those committed rows instead of the run folders,
and everything below is computed from them by the same code either way.

For each claim of the paper, and each set of seeds, the script gives the paired difference by
seed (mean, 95 % CI, t-test p, Cohen's d_z; saggriac.analysis.statistics.paired) and whether it
holds on that set by the rule fixed here before the second set was looked at:

- a claim that one condition is below another (SAGG below ACTUATOR, SAGG-RIAC below
  SAGG-Random, more SAGG-RIAC goals in reach) holds on a set when the difference has the paper's
  sign with p < 0.05 (the CI excludes 0);
- "most of SAGG-RIAC's goals in reach" (Fig. 3) holds when the 95 % CI of its mean second-half
  reachable share lies above 0.5;
- "ACTUATOR-RIAC is no better than ACTUATOR-Random" holds when ACTUATOR-RIAC is not
  significantly lower (not p < 0.05 with a negative difference);
- "SAGG-RIAC below SAGG-Random from 20,000 steps on" holds when the mean over seeds is lower at
  every evaluation from 20,000 steps on (a description of the curves, as in the paper's Fig. 5).

A claim replicates when it holds on the second set. The p-values are uncorrected, one per named
comparison; Holm's correction over the claims of each experiment and set is given beside them.

Printed: the tables of docs/reproduction.md's replication section, row for row (finals and
ANOVA, claims, the SAGG pair along the run, Fig. 3's shares and time budget; the q = 20 table's
rows with --readings, docs/figures/readings/runs.csv), then claims.md's tables. --check (with --from-tables)
also recomputes each set's statistics and time budget as ``saggriac reproduce`` writes them
(``statistics.compare``, the mean of run.json's time budgets) and compares them, and the claims
table, with the committed files (DIR/EXP_stats_15-29.csv and docs/figures/EXP/stats.csv for
0-14, the same for time_budget, DIR/claims.csv); it exits 1 on a difference.
"""

from __future__ import annotations

import argparse
import io
import json
import math
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import scipy.stats as sps

from saggriac import Config
from saggriac.analysis.statistics import compare, holm, paired
from saggriac.config import CONDITIONS
from saggriac.study.reproduce import BUDGET_COLUMNS

sys.path.insert(0, str(Path(__file__).resolve().parent))
from eq2_readings import read_run  # noqa: E402  (final errors, goals, second-half reachable share)
from goal_placement import zones  # noqa: E402  (the reachable area)

NAMES = {"sagg_riac": "SAGG-RIAC", "sagg_random": "SAGG-Random", "actuator_random": "ACTUATOR-Random", "actuator_riac": "ACTUATOR-RIAC"}
SAGG, ACT = ("sagg_riac", "sagg_random"), ("actuator_random", "actuator_riac")
METRICS = ("reach_error", "pred_error", "dx_error")
EXPERIMENTS = ("exp2", "exp1")
ROOT = Path(__file__).resolve().parents[1]


# -- one row per run ------------------------------------------------------------------------


def run_row(run_dir: Path) -> dict:
    """Everything the page reads of one run: final errors, goals and reachable shares
    (eq2_readings.read_run, goal_placement.zones), the time budget of run.json, and the learning
    curves at every evaluation (columns METRIC@STEP)."""
    manifest = json.loads((run_dir / "run.json").read_text())
    cfg = manifest["config"]
    m = pd.read_parquet(run_dir / "metrics.parquet")
    if int(m["step"].iloc[-1]) != cfg["n_steps"]:
        raise SystemExit(f"{run_dir} did not finish: its last evaluation is at step {int(m['step'].iloc[-1])} of {cfg['n_steps']}")
    base = read_run(run_dir)
    row: dict = {"condition": cfg["condition"], "seed": int(manifest["seed"]), "n_steps": int(cfg["n_steps"])}
    row.update({k: float(m[k].iloc[-1]) for k in METRICS})
    tb = manifest.get("time_budget") or {}
    row["goals"] = float(tb.get("goals", 0))
    if "goals" in base and base["goals"] != row["goals"]:
        raise SystemExit(f"{run_dir}: goals.parquet holds {base['goals']:.0f} goals, its time budget {row['goals']:.0f}")
    for k in BUDGET_COLUMNS[1:]:
        row[k] = np.nan if tb.get(k) is None else float(tb[k])
    for k in ("global", "initial", "interest", "lowest_competence", "random"):
        row[f"share_mode_{k}"] = float(tb.get("share_by_mode", {}).get(k, np.nan))
    row["share_2nd_half"] = base.get("share_2nd_half", np.nan)
    row.update({f"share_q{i + 1}": np.nan for i in range(4)})
    row["share_whole"] = np.nan
    if cfg["condition"].startswith("sagg"):
        goals = pd.read_parquet(run_dir / "goals.parquet")
        reach = np.asarray(zones(goals, Config.from_saved(cfg))["reachable"], float)
        quarter = np.minimum(goals["step_start"].to_numpy() * 4 // cfg["n_steps"], 3)
        row.update({f"share_q{i + 1}": float(reach[quarter == i].mean()) for i in range(4)})
        row["share_whole"] = float(reach.mean())
    row["young_mass"] = base.get("young_mass", np.nan)
    row.update({"wall_seconds": float(manifest["wall_seconds"]), "version": manifest.get("version"), "git_commit": manifest.get("git_commit")})
    for k in METRICS:
        row.update({f"{k}@{int(s)}": float(v) for s, v in zip(m["step"], m[k])})
    return row


def runs_from_folder(study: Path) -> pd.DataFrame:
    """One row per finished run of a study folder, in the study's order (seed, then condition)."""
    rows = []
    for c in CONDITIONS:
        for d in sorted((study / "runs" / c).glob("seed*")):
            if (d / "run.json").exists():
                rows.append(run_row(d))
    if not rows:
        return pd.DataFrame()
    return order(pd.DataFrame(rows))


def order(runs: pd.DataFrame) -> pd.DataFrame:
    """Rows in the order ``saggriac reproduce`` reads a study (seed by seed, the paper's order of
    conditions within a seed): means and tests then add the same numbers in the same order."""
    rank = runs["condition"].map({c: i for i, c in enumerate(CONDITIONS)})
    return runs.assign(_r=rank).sort_values(["seed", "_r"], kind="stable").drop(columns="_r").reset_index(drop=True)


def read_csv(path) -> pd.DataFrame:
    """A committed table, each float read back to the bits that were written: pandas 3's default
    parser does; pandas 2's may differ in the last bit unless asked to round-trip (an option
    pandas 3 deprecates)."""
    return pd.read_csv(path, **({"float_precision": "round_trip"} if int(pd.__version__.split(".")[0]) < 3 else {}))


def read_runs(path: Path) -> pd.DataFrame:
    return order(read_csv(path))


def tidy(runs: pd.DataFrame) -> pd.DataFrame:
    """The runs as saggriac.study.load_study gives them: condition, seed, step, metric, value."""
    parts = []
    for _, r in runs.iterrows():
        for k in METRICS:
            cols = [c for c in runs.columns if c.startswith(f"{k}@") and pd.notna(r[c])]
            parts.append(pd.DataFrame({"condition": r["condition"], "seed": int(r["seed"]), "step": [int(c.split("@")[1]) for c in cols], "metric": k, "value": [float(r[c]) for c in cols]}))
    return pd.concat(parts, ignore_index=True)


def stats(runs: pd.DataFrame) -> pd.DataFrame:
    """stats.csv of the study these runs are (statistics.compare at its checkpoints)."""
    return compare(tidy(runs))


def time_budget(runs: pd.DataFrame) -> pd.DataFrame:
    """time_budget.csv of the study these runs are: the mean over its runs, per condition."""
    cols = [*BUDGET_COLUMNS, *(c for c in runs.columns if c.startswith("share_mode_"))]
    summary = runs[cols].groupby(runs["condition"], sort=False).mean()
    summary.insert(0, "runs", runs.groupby("condition", sort=False).size())
    return summary.reset_index()


def per_condition(runs: pd.DataFrame, condition: str) -> pd.DataFrame:
    """The runs of one condition indexed by seed, with reach@STEP for the curve claim."""
    d = runs[runs["condition"] == condition].set_index("seed").sort_index()
    return d.rename(columns={c: "reach@" + c.split("@")[1] for c in d.columns if c.startswith("reach_error@")})


# -- the registered claims --------------------------------------------------------------------


def claims(exp: str) -> list[tuple[str, str, str, str, str]]:
    """(claim, metric, a, b, kind): a - b; kind 'below' (a < b claimed), 'above' (a > b) or
    'not_better' (a not significantly below b)."""
    if exp == "exp1":
        out = [(f"{NAMES[s]} below {NAMES[a]}, reaching error", "reach_error", s, a, "below") for s in SAGG for a in ACT]
        out += [(f"{NAMES[s]} below {NAMES[a]}, prediction error", "pred_error", s, a, "below") for s in SAGG for a in ACT]
        out.append(("ACTUATOR-RIAC no better than ACTUATOR-Random, reaching error", "reach_error", "actuator_riac", "actuator_random", "not_better"))
        out.append(("ACTUATOR-RIAC no better than ACTUATOR-Random, prediction error", "pred_error", "actuator_riac", "actuator_random", "not_better"))
        return out
    out = [
        ("SAGG-RIAC below SAGG-Random, reaching error (paper p = 0.002)", "reach_error", "sagg_riac", "sagg_random", "below"),
        ("SAGG-RIAC below SAGG-Random, prediction error (paper p = 0.0065)", "pred_error", "sagg_riac", "sagg_random", "below"),
    ]
    out += [(f"{NAMES[s]} below {NAMES[a]}, reaching error (Fig. 5)", "reach_error", s, a, "below") for s in SAGG for a in ACT]
    out.append(("Fig. 3: SAGG-RIAC's goals more in reach than SAGG-Random's (2nd-half share)", "share_2nd_half", "sagg_riac", "sagg_random", "above"))
    return out


def table(sets: dict[str, dict[str, pd.DataFrame]]) -> pd.DataFrame:
    """The claims on each set: sets[label][exp] is the set's runs of that experiment."""
    rows = []
    for exp in EXPERIMENTS:
        for label, by_exp in sets.items():
            if exp not in by_exp:
                continue
            data = {c: per_condition(by_exp[exp], c) for c in NAMES}
            block = []
            for claim, metric, a, b, kind in claims(exp):
                A, B = data[a], data[b]
                both = A.index.intersection(B.index)
                if len(both) < 2:
                    continue
                x, y = A.loc[both, metric].to_numpy(float), B.loc[both, metric].to_numpy(float)
                r = paired(x, y)
                sig_below = r["p_value"] < 0.05 and r["mean_diff"] < 0
                holds = {"below": sig_below, "above": r["p_value"] < 0.05 and r["mean_diff"] > 0, "not_better": not sig_below}[kind]
                block.append({"experiment": exp, "seeds": label, "n": len(both), "claim": claim, "metric": metric, "a": a, "b": b, "mean_a": x.mean(), "mean_b": y.mean(), "mean_diff": r["mean_diff"], "ci_low": r["ci_low"], "ci_high": r["ci_high"], "p": r["p_value"], "d_z": r["effect"], "holds": holds})
            if exp == "exp2":
                steps = sorted(int(c[6:]) for c in data["sagg_riac"].columns if c.startswith("reach@") and int(c[6:]) >= 20000)
                both = data["sagg_riac"].index.intersection(data["sagg_random"].index)
                below = [data["sagg_riac"].loc[both, f"reach@{s}"].mean() < data["sagg_random"].loc[both, f"reach@{s}"].mean() for s in steps]
                block.append({"experiment": exp, "seeds": label, "n": len(both), "claim": f"SAGG-RIAC's mean reaching error below SAGG-Random's at every evaluation from 20,000 on ({sum(below)} of {len(below)})", "metric": "reach_error curve", "a": "sagg_riac", "b": "sagg_random", "holds": all(below)})
                share = data["sagg_riac"]["share_2nd_half"].to_numpy(float)
                half = float(sps.t.ppf(0.975, len(share) - 1)) * share.std(ddof=1) / np.sqrt(len(share))
                block.append({"experiment": exp, "seeds": label, "n": len(share), "claim": "Fig. 3: most of SAGG-RIAC's goals in reach (2nd-half share, mean [95 % CI], above 0.5)", "metric": "share_2nd_half", "a": "sagg_riac", "b": "", "mean_a": share.mean(), "ci_low": share.mean() - half, "ci_high": share.mean() + half, "holds": share.mean() - half > 0.5})
            frame = pd.DataFrame(block)
            frame["p_holm"] = holm(frame["p"].to_numpy(float)) if "p" in frame else np.nan
            rows.append(frame)
    return pd.concat(rows, ignore_index=True)


# -- claims.md (the record the rule's script has written since the replication) ---------------


def _f(x, d=2, signed=False):
    if x is None or (isinstance(x, float) and not np.isfinite(x)):
        return "-"
    return f"{x:+.{d}f}" if signed else f"{x:.{d}f}"


def _p(x):
    return "-" if x is None or not np.isfinite(x) else f"{x:.2g}"


def markdown(t: pd.DataFrame) -> str:
    out = []
    for exp in t["experiment"].unique():
        sets = list(t.loc[t["experiment"] == exp, "seeds"].unique())
        out += [f"**{exp}**", "", "| claim | " + " | ".join(f"seeds {s}: a - b [95 % CI], p (Holm), d_z, holds?" for s in sets) + " | replicates? |", "|---|" + "---|" * len(sets) + "---|"]
        part = t[t["experiment"] == exp]
        for claim in dict.fromkeys(c.split(" (")[0] if "at every evaluation" in c else c for c in part["claim"]):
            cells = []
            last = None
            for s in sets:
                r = part[(part["seeds"] == s) & (part["claim"].str.startswith(claim))]
                if r.empty:
                    cells.append("-")
                    continue
                r = r.iloc[0]
                last = r
                d = 3 if r["metric"] == "share_2nd_half" else 2
                if r["metric"] == "reach_error curve":
                    cells.append(r["claim"][r["claim"].rfind("(") :] + (", holds" if r["holds"] else ", does not hold"))
                elif not np.isfinite(r.get("mean_diff", np.nan)):
                    cells.append(f"{_f(r['mean_a'], 3)} [{_f(r['ci_low'], 3)}, {_f(r['ci_high'], 3)}], " + ("holds" if r["holds"] else "does not hold"))
                else:
                    cells.append(f"{_f(r['mean_diff'], d, True)} [{_f(r['ci_low'], d, True)}, {_f(r['ci_high'], d, True)}], p = {_p(r['p'])} ({_p(r['p_holm'])}), d_z = {_f(r['d_z'], 2, True)}, " + ("holds" if r["holds"] else "does not hold"))
            rep = "yes" if last is not None and bool(last["holds"]) else "no"
            out.append(f"| {claim} | " + " | ".join(cells) + f" | {rep} |")
        out.append("")
    return "\n".join(out)


def finals(sets: dict[str, dict[str, pd.DataFrame]]) -> str:
    """Final reaching and prediction error and goals, mean ± sd over each set's seeds."""
    out = ["| experiment | seeds | condition | reaching error | prediction error | goals |", "|---|---|---|---|---|---|"]
    for exp in EXPERIMENTS:
        for label, by_exp in sets.items():
            if exp not in by_exp:
                continue
            for c, name in NAMES.items():
                d = per_condition(by_exp[exp], c)
                if d.empty:
                    continue
                goals = f"{d['goals'].mean():.0f}" if c in SAGG else "-"
                out.append(f"| {exp} | {label} | {name} | {d['reach_error'].mean():.2f} ± {d['reach_error'].std(ddof=1):.2f} | {d['pred_error'].mean():.2f} ± {d['pred_error'].std(ddof=1):.2f} | {goals} |")
    return "\n".join(out) + "\n"


# -- the page's tables ------------------------------------------------------------------------


def p_text(p: float) -> str:
    """A p-value as the page writes it: two significant digits down to 0.001, one below
    (0.0009; 4e-5 under 1e-4); "-" if there is none."""
    if p is None or not np.isfinite(p):
        return "-"
    if p >= 0.001:
        d = 1 - math.floor(math.log10(p))
        s = f"{p:.{d}f}"
        return f"{p:.{d - 1}f}" if d > 1 and float(s) >= 10.0 ** (math.floor(math.log10(p)) + 1) else s
    if p >= 1e-4:
        return f"{p:.4f}"
    mant, exp = f"{p:.0e}".split("e")
    return f"{mant}e{int(exp)}"


def sig3(x: float) -> str:
    """Three significant digits, trailing zeros kept (5.30, 11.7, 160)."""
    return f"{x:.{max(0, 2 - math.floor(math.log10(abs(x))))}f}"


def diff_text(r, d: int = 2, p: bool = True, dz: bool = False, holm_p: float | None = None) -> str:
    s = f"{r['mean_diff']:+.{d}f} [{r['ci_low']:+.{d}f}, {r['ci_high']:+.{d}f}]"
    if p:
        s += f", p = {p_text(r['p_value'] if 'p_value' in r else r['p'])}"
    if holm_p is not None:
        s += f" (Holm {p_text(holm_p)})"
    if dz:
        s += f", d_z = {(r['effect'] if 'effect' in r else r['d_z']):+.2f}"
    return s


def sd_text(v: pd.Series, d: int) -> str:
    return f"{v.mean():.{d}f} ± {v.std(ddof=1):.{d}f}"


def finals_table(runs: pd.DataFrame, st: pd.DataFrame) -> list[str]:
    end = int(runs["n_steps"].max())
    out = ["| condition | reaching error | prediction error | goals |", "|---|---|---|---|"]
    for c, name in NAMES.items():
        d = per_condition(runs, c)
        goals = f"{d['goals'].mean():.0f}" if c in SAGG else "-"
        out.append(f"| {name} | {sd_text(d['reach_error'], 2)} | {sd_text(d['pred_error'], 2)} | {goals} |")
    cells = []
    for metric in ("reach_error", "pred_error"):
        a = st[(st["metric"] == metric) & (st["step"] == end) & (st["test"] == "anova")].iloc[0]
        cells.append(f"F({a['df']}) = {sig3(a['statistic'])}, p = {p_text(a['p_value'])}, eta^2 = {a['effect']:.2f}")
    out.append(f"| one-way ANOVA | {cells[0]} | {cells[1]} | |")
    return out


def claims_table(t: pd.DataFrame, exp: str, labels: list[str]) -> list[str]:
    part = t[t["experiment"] == exp]
    last = labels[-1]
    out = [f"| claim (a - b, paired by seed) | {' | '.join(f'seeds {s}' for s in labels)} | Holm p, seeds {last} | replicates? |", "|---|" + "---|" * (len(labels) + 2)]
    for claim in dict.fromkeys(c.split(" (")[0] if "at every evaluation" in c else c for c in part["claim"]):
        cells, r = [], None
        for s in labels:
            rs = part[(part["seeds"] == s) & (part["claim"].str.startswith(claim))]
            if rs.empty:
                cells.append("-")
                continue
            r = rs.iloc[0]
            if r["metric"] == "reach_error curve":
                cell = r["claim"][r["claim"].rfind("(") + 1 : -1] + " evaluations"
            elif not np.isfinite(r.get("mean_diff", np.nan)):
                cell = f"{r['mean_a']:.3f} [{r['ci_low']:.3f}, {r['ci_high']:.3f}]"
            else:
                cell = diff_text(r, 3 if r["metric"] == "share_2nd_half" else 2, dz=True)
            cells.append(cell + ("" if r["holds"] else " (does not hold)"))
        holm_p = p_text(r["p_holm"]) if r is not None and r["seeds"] == last else "-"
        rep = "**yes**" if r is not None and r["seeds"] == last and bool(r["holds"]) else "**no**"
        out.append(f"| {claim} | " + " | ".join(cells) + f" | {holm_p} | {rep} |")
    return out


def pair_table(stats_by_set: dict[str, pd.DataFrame], a: str, b: str) -> list[str]:
    """a - b at each checkpoint of the statistics, reaching and prediction error, each set."""
    labels = list(stats_by_set)
    out = [f"| {NAMES[a]} - {NAMES[b]} | step | {' | '.join(f'seeds {s}' for s in labels)} |", "|---|---|" + "---|" * len(labels)]
    for metric, name in (("reach_error", "reaching error"), ("pred_error", "prediction error")):
        steps = sorted(set(stats_by_set[labels[-1]].query("metric == @metric")["step"]))
        for step in steps:
            cells = []
            for s in labels:
                st = stats_by_set[s]
                r = st[(st["metric"] == metric) & (st["step"] == step) & (st["test"] == "paired_t") & (st["a"] == a) & (st["b"] == b)]
                cells.append(diff_text(r.iloc[0], holm_p=r.iloc[0]["p_holm"]) if len(r) else "-")
            out.append(f"| {name} | {step:,} | " + " | ".join(cells) + " |")
    return out


def quarters(d: pd.DataFrame) -> str:
    return " / ".join(f"{100 * d[f'share_q{i}'].mean():.1f}" for i in range(1, 5)) + " %"


def goals_table(runs_by_set: dict[str, pd.DataFrame]) -> list[str]:
    """Fig. 3's measures of exp2 on each set: where the SAGG conditions put their goals."""
    labels = list(runs_by_set)
    out = [f"| exp2, SAGG goals | {' | '.join(f'seeds {s}' for s in labels)} |", "|---|" + "---|" * len(labels)]
    rows: dict[str, list[str]] = {}
    for s in labels:
        r, g = per_condition(runs_by_set[s], "sagg_riac"), per_condition(runs_by_set[s], "sagg_random")
        both = r.index.intersection(g.index)
        cells = {
            "SAGG-RIAC, 2nd-half reachable share": sd_text(r["share_2nd_half"], 3),
            "SAGG-Random, 2nd-half reachable share": sd_text(g["share_2nd_half"], 3),
            "SAGG-RIAC minus SAGG-Random, 2nd-half share": diff_text(paired(r.loc[both, "share_2nd_half"], g.loc[both, "share_2nd_half"]), 3, dz=True),
            "SAGG-RIAC, share by quarter of the run": quarters(r),
            "SAGG-Random, share by quarter of the run": quarters(g),
            "goals per run, SAGG-RIAC / SAGG-Random": f"{r['goals'].mean():.0f} / {g['goals'].mean():.0f}",
            "share of micro-actions on reachable goals, SAGG-RIAC / SAGG-Random": f"{100 * r['share_on_reachable_goals'].mean():.1f} % / {100 * g['share_on_reachable_goals'].mean():.1f} %",
        }
        for k, v in cells.items():
            rows.setdefault(k, []).append(v)
    out += [f"| {k} | " + " | ".join(v) + " |" for k, v in rows.items()]
    return out


def q_table(runs: pd.DataFrame, readings: Path) -> list[str]:
    """The rows of the q = 20 table of docs/reproduction.md (Fig. 3's section) that committed
    tables give: the q = 100 runs are this set's; the q = 20 runs are readings/runs.csv's (its
    rows carry no shares by quarter, so that row gives the q = 100 side only)."""
    q20 = read_csv(readings)
    q20 = q20[q20["study"] == "exp2-q20"]
    got = {c: (q20[q20["condition"] == c].set_index("seed").sort_index(), per_condition(runs, c)) for c in SAGG}
    out = []

    def row(name: str, c: str, metric: str, d: int) -> str:
        v20, v100 = got[c][0][metric], got[c][1][metric]
        both = v20.index.intersection(v100.index)
        r = paired(v20.loc[both], v100.loc[both])
        head = f"{v100.mean():.0f} | {v20.mean():.0f}" if metric == "goals" else f"{sd_text(v100, d)} | {sd_text(v20, d)}"
        return f"| {name} | {head} | {diff_text(r, d, p=False)} | {p_text(r['p_value'])} |"

    def gap(v: dict[str, pd.Series], d: int, p: bool) -> str:
        both = v["sagg_riac"].index.intersection(v["sagg_random"].index)
        return diff_text(paired(v["sagg_riac"].loc[both], v["sagg_random"].loc[both]), d, p=p)

    out.append(row("SAGG-RIAC, 2nd-half reachable share", "sagg_riac", "share_2nd_half", 3))
    out.append(f"| SAGG-RIAC, share by quarter | {quarters(got['sagg_riac'][1])} |")
    out.append(row("SAGG-Random, 2nd-half reachable share", "sagg_random", "share_2nd_half", 3))
    v100 = {c: got[c][1]["share_2nd_half"] for c in SAGG}
    v20 = {c: got[c][0]["share_2nd_half"] for c in SAGG}
    out.append(f"| SAGG-RIAC minus SAGG-Random, 2nd-half share | {gap(v100, 3, False)} | {gap(v20, 3, True)} | | |")
    out.append(row("SAGG-RIAC goals per run", "sagg_riac", "goals", 0))
    out.append(row("SAGG-RIAC, final reaching error", "sagg_riac", "reach_error", 2))
    out.append(row("SAGG-Random, final reaching error", "sagg_random", "reach_error", 2))
    v100 = {c: got[c][1]["reach_error"] for c in SAGG}
    v20 = {c: got[c][0]["reach_error"] for c in SAGG}
    out.append(f"| SAGG-RIAC minus SAGG-Random, reaching error | {gap(v100, 2, False)} | {gap(v20, 2, True)} | | |")
    return out


def page(sets: dict[str, dict[str, pd.DataFrame]], t: pd.DataFrame, stats_of: dict[tuple[str, str], pd.DataFrame], readings: Path | None) -> str:
    labels = list(sets)
    last = labels[-1]
    out = []
    for exp in EXPERIMENTS:
        if exp not in sets[last]:
            continue
        ok = [s for s in labels if exp in sets[s]]
        out += [f"## {exp} on seeds {last}", "", *finals_table(sets[last][exp], stats_of[(exp, last)]), ""]
        out += [f"### {exp}: the claims", "", *claims_table(t, exp, ok), ""]
        out += [f"### {exp}: SAGG-RIAC against SAGG-Random along the run", "", *pair_table({s: stats_of[(exp, s)] for s in ok}, "sagg_riac", "sagg_random"), ""]
        if exp == "exp2":
            out += ["### exp2: where the SAGG conditions put their goals", "", *goals_table({s: sets[s][exp] for s in ok}), ""]
            if readings is not None and readings.exists():
                out += [f"### exp2: q = 100 (seeds {last}) against q = 20 ({readings.relative_to(ROOT) if readings.is_relative_to(ROOT) else readings})", "", *q_table(sets[last][exp], readings), ""]
    return "\n".join(out)


# -- checks against the committed files -------------------------------------------------------


def committed(label: str, exp: str, kind: str, tables: Path) -> Path:
    """The committed stats.csv or time_budget.csv of a set: the replication's beside the tables,
    seeds 0-14's in docs/figures/EXP (the page's first half)."""
    return tables / f"{exp}_{kind}_{label}.csv" if label != "0-14" else ROOT / "docs" / "figures" / exp / f"{kind}.csv"


def show(path: Path) -> str:
    return str(path.relative_to(ROOT)) if path.is_relative_to(ROOT) else str(path)


def check(sets: dict[str, dict[str, pd.DataFrame]], t: pd.DataFrame, stats_of: dict[tuple[str, str], pd.DataFrame], tables: Path) -> list[str]:
    """What differs between the recomputation and the committed files ([] if nothing)."""
    bad = []
    for label, by_exp in sets.items():
        for exp, runs in by_exp.items():
            for kind, mine in (("stats", stats_of[(exp, label)]), ("time_budget", time_budget(runs))):
                path = committed(label, exp, kind, tables)
                if not path.exists():
                    bad.append(f"{path} is missing")
                    continue
                text = mine.to_csv(index=False)
                if text == path.read_text():
                    print(f"{show(path)}: identical to the recomputation from the runs' rows")
                    continue
                old = read_csv(path)
                try:
                    pd.testing.assert_frame_equal(read_csv(io.StringIO(text)), old, rtol=1e-12, check_like=True)
                    print(f"{show(path)}: equal to the recomputation within 1e-12 (not byte for byte)")
                except AssertionError as e:
                    bad.append(f"{show(path)} differs from the recomputation: {str(e).splitlines()[0:4]}")
    path = tables / "claims.csv"
    if path.exists():
        old = read_csv(path)
        old = old[old["seeds"].astype(str).isin(list(sets))].reset_index(drop=True)  # the sets whose rows are here
        mine = read_csv(io.StringIO(t.to_csv(index=False)))
        try:
            pd.testing.assert_frame_equal(mine, old, rtol=1e-12)
            print(f"{show(path)}: equal to the recomputation")
        except AssertionError as e:
            bad.append(f"{show(path)} differs from the recomputation: {str(e).splitlines()[0:4]}")
    return bad


# -- command ----------------------------------------------------------------------------------


def from_tables(tables: Path) -> dict[str, dict[str, pd.DataFrame]]:
    """The committed rows: TABLES/EXP_runs_LABEL.csv, sets in the order of their first seed."""
    sets: dict[str, dict[str, pd.DataFrame]] = {}
    files = sorted(tables.glob("exp*_runs_*.csv"), key=lambda p: int(p.stem.split("_runs_")[1].split("-")[0]))
    for path in files:
        exp, label = path.stem.split("_runs_")
        sets.setdefault(label, {})[exp] = read_runs(path)
    if not sets:
        raise SystemExit(f"{tables} holds no EXP_runs_LABEL.csv")
    return sets


def report(sets: dict[str, dict[str, pd.DataFrame]], readings: Path | None) -> tuple[str, pd.DataFrame, dict]:
    for label, by_exp in sets.items():
        for exp, runs in by_exp.items():
            n = runs.groupby("condition").size().to_dict()
            print(f"{exp}, seeds {label}: {len(runs)} runs ({', '.join(f'{NAMES[c]} {n.get(c, 0)}' for c in NAMES)}), saggriac {', '.join(sorted(set(runs['version'].astype(str))))}")
    t = table(sets)
    stats_of = {(exp, label): stats(runs) for label, by_exp in sets.items() for exp, runs in by_exp.items()}
    text = page(sets, t, stats_of, readings) + "\n\n## claims.md\n\n" + markdown(t) + "\n" + finals(sets)
    return text, t, stats_of


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    src = p.add_mutually_exclusive_group(required=True)
    src.add_argument("--sets", nargs="+", metavar="LABEL=FOLDER", help="sets of seeds in order, the replication last")
    src.add_argument("--from-tables", metavar="DIR", help="read the committed rows DIR/EXP_runs_LABEL.csv instead of run folders")
    p.add_argument("--write-runs", metavar="DIR", default=None, help="with --sets: write each set's rows to DIR/EXP_runs_LABEL.csv")
    p.add_argument("--check", action="store_true", help="with --from-tables: compare the recomputation with the committed stats, time budgets and claims; exit 1 on a difference")
    p.add_argument("--md", default=None, help="write claims.md's tables here")
    p.add_argument("--csv", default=None, help="write the claims table here")
    p.add_argument("--out", default=None, help="write the printed text here")
    p.add_argument("--readings", default=str(ROOT / "docs" / "figures" / "readings" / "runs.csv"), help="the q = 20 runs' rows (default: docs/figures/readings/runs.csv)")
    a = p.parse_args()
    if a.sets:
        sets = {}
        for s in a.sets:
            label, folder = s.split("=", 1)
            sets[label] = {exp: r for exp in EXPERIMENTS if (Path(folder) / f"reproduce-{exp}").exists() and not (r := runs_from_folder(Path(folder) / f"reproduce-{exp}")).empty}
        if a.write_runs:
            Path(a.write_runs).mkdir(parents=True, exist_ok=True)
            for label, by_exp in sets.items():
                for exp, runs in by_exp.items():
                    path = Path(a.write_runs) / f"{exp}_runs_{label}.csv"
                    runs.to_csv(path, index=False)
                    print(f"{path}: {len(runs)} rows")
        tables = Path(a.write_runs) if a.write_runs else ROOT / "docs" / "figures" / "replication"
    else:
        tables = Path(a.from_tables)
        sets = from_tables(tables)
    text, t, stats_of = report(sets, Path(a.readings))
    print(text)
    if a.out:
        Path(a.out).write_text(text + "\n")
    if a.md:
        Path(a.md).write_text(markdown(t) + "\n" + finals(sets) + "\n")
    if a.csv:
        t.to_csv(a.csv, index=False)
    if a.check:
        bad = check(sets, t, stats_of, tables)
        for b in bad:
            print("DIFFERS:", b)
        return 1 if bad else 0
    return 0


if __name__ == "__main__":
    sys.exit(main())
