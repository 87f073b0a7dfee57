"""The paper's claims for experiments 1 and 2, as effect sizes, on two independent sets of seeds.

    python benchmarks/replication.py --sets 0-14=REPRO_A 15-29=REPRO_B [--md FILE] [--csv FILE]

Each REPRO folder holds reproduce-exp1 and reproduce-exp2 study folders written by
``benchmarks/bench_reproduce.py`` (``--first-seed 15`` for the second set). For each claim of the
paper, and each set of seeds, the script gives the paired difference by seed (mean, 95 % CI,
t-test p, Cohen's d_z; saggriac.analysis.statistics.paired) and whether it holds on that set by
the rule fixed here before the second set was looked at:

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
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import scipy.stats as sps

from saggriac.analysis.statistics import holm, paired

sys.path.insert(0, str(Path(__file__).resolve().parent))
from eq2_readings import read_run  # noqa: E402  (final errors, goals, second-half reachable share)

NAMES = {"sagg_riac": "SAGG-RIAC", "sagg_random": "SAGG-Random", "actuator_random": "ACTUATOR-Random", "actuator_riac": "ACTUATOR-RIAC"}
SAGG, ACT = ("sagg_riac", "sagg_random"), ("actuator_random", "actuator_riac")


def runs(study: Path, condition: str) -> dict[int, Path]:
    return {int(d.name[4:]): d for d in sorted((study / "runs" / condition).glob("seed*")) if (d / "run.json").exists()}


def per_run(study: Path, condition: str) -> pd.DataFrame:
    rows = {}
    for seed, d in runs(study, condition).items():
        row = read_run(d)
        m = pd.read_parquet(d / "metrics.parquet")
        row.update({f"reach@{int(s)}": float(v) for s, v in zip(m["step"], m["reach_error"])})
        rows[seed] = row
    return pd.DataFrame.from_dict(rows, orient="index").sort_index()


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


def table(sets: dict[str, Path]) -> pd.DataFrame:
    rows = []
    for exp in ("exp2", "exp1"):
        for label, folder in sets.items():
            study = folder / f"reproduce-{exp}"
            if not study.exists():
                continue
            data = {c: per_run(study, c) for c in NAMES}
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


def finals(sets: dict[str, Path]) -> str:
    """Final reaching and prediction error and goals, mean ± sd over each set's seeds."""
    out = ["| experiment | seeds | condition | reaching error | prediction error | goals |", "|---|---|---|---|---|---|"]
    for exp in ("exp2", "exp1"):
        for label, folder in sets.items():
            study = folder / f"reproduce-{exp}"
            if not study.exists():
                continue
            for c, name in NAMES.items():
                d = per_run(study, c)
                if d.empty:
                    continue
                goals = f"{d['goals'].mean():.0f}" if "goals" in d else "-"
                out.append(f"| {exp} | {label} | {name} | {d['reach_error'].mean():.2f} ± {d['reach_error'].std(ddof=1):.2f} | {d['pred_error'].mean():.2f} ± {d['pred_error'].std(ddof=1):.2f} | {goals} |")
    return "\n".join(out) + "\n"


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--sets", nargs="+", required=True, metavar="LABEL=FOLDER", help="sets of seeds in order, the replication last")
    p.add_argument("--md", default=None)
    p.add_argument("--csv", default=None)
    a = p.parse_args()
    sets = {s.split("=", 1)[0]: Path(s.split("=", 1)[1]) for s in a.sets}
    t = table(sets)
    md = markdown(t) + "\n" + finals(sets)
    print(md)
    if a.md:
        Path(a.md).write_text(md + "\n")
    if a.csv:
        t.to_csv(a.csv, index=False)
    return 0


if __name__ == "__main__":
    sys.exit(main())
