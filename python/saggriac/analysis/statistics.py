"""Statistics over a study, paired by seed (all conditions of a seed meet the same test sets):
at the end of the runs and at checkpoints, the one-way ANOVA the paper quotes and, for every pair
of conditions, a paired t-test on the per-seed differences with their mean, its 95 % confidence
interval and an effect size (Cohen's d_z); p-values are also given Holm-corrected over every
test of a metric (all pairs and checkpoints; the ANOVAs form their own family). The tests come
from scipy; this module picks the data and lays out the table."""

from __future__ import annotations

import itertools
from typing import Sequence

import numpy as np
import pandas as pd
from scipy import stats as sps

from ..config import CONDITIONS

METRICS = ("reach_error", "pred_error", "dx_error")
COLUMNS = ["metric", "step", "test", "a", "b", "mean_a", "mean_b", "mean_diff", "ci_low", "ci_high", "statistic", "df", "p_value", "p_holm", "effect", "effect_name", "n"]


def _groups(frame: pd.DataFrame, metric: str, step: int) -> dict[str, pd.Series]:
    """Per condition, the values at ``step`` indexed by seed."""
    sel = frame[(frame["metric"] == metric) & (frame["step"] == step)]
    return {c: g.set_index("seed")["value"].astype(float) for c, g in sel.groupby("condition", sort=False)}


def eta_squared(groups: Sequence[np.ndarray]) -> float:
    """Share of the total variance explained by the grouping (effect size of the ANOVA)."""
    allv = np.concatenate(groups)
    grand = allv.mean()
    ss_between = sum(len(g) * (g.mean() - grand) ** 2 for g in groups)
    ss_total = ((allv - grand) ** 2).sum()
    return float(ss_between / ss_total) if ss_total > 0 else float("nan")


def paired(a: np.ndarray, b: np.ndarray) -> dict[str, float]:
    """Paired comparison of a and b (same seeds, same order): the mean of a - b, its 95 %
    confidence interval (Student t), the paired t-test and Cohen's d_z = mean / sd of a - b."""
    d = np.asarray(a, float) - np.asarray(b, float)
    n = len(d)
    mean, sd = float(d.mean()), float(d.std(ddof=1))
    if sd == 0.0:
        # Identical differences: no spread to test against.
        return dict(mean_diff=mean, ci_low=mean, ci_high=mean, statistic=float("nan"), p_value=float("nan"), effect=float("nan"), df=n - 1)
    half = float(sps.t.ppf(0.975, n - 1)) * sd / np.sqrt(n)
    t = sps.ttest_rel(a, b)
    return dict(mean_diff=mean, ci_low=mean - half, ci_high=mean + half, statistic=float(t.statistic), p_value=float(t.pvalue), effect=mean / sd, df=n - 1)


def holm(p: Sequence[float]) -> np.ndarray:
    """Holm-Bonferroni adjusted p-values (NaN stays NaN and is not counted)."""
    p = np.asarray(p, float)
    out = np.full(len(p), np.nan)
    ok = np.flatnonzero(~np.isnan(p))
    order = ok[np.argsort(p[ok], kind="stable")]
    m = len(order)
    running = 0.0
    for rank, i in enumerate(order):
        running = max(running, min(1.0, (m - rank) * p[i]))
        out[i] = running
    return out


def checkpoints(frame: pd.DataFrame, n: int = 4) -> list[int]:
    """The last step and n - 1 evenly spaced earlier steps present in every run."""
    steps = np.sort(frame["step"].unique())
    if len(steps) == 0:
        return []
    idx = np.unique(np.linspace(0, len(steps) - 1, n + 1).round().astype(int))[1:]
    return [int(steps[i]) for i in idx]


def compare(frame: pd.DataFrame, steps: Sequence[int] | None = None, metrics: Sequence[str] = METRICS) -> pd.DataFrame:
    """One row per (metric, step, test): the ANOVA over all conditions, then every pair paired
    by seed (only seeds present in both). ``frame`` is tidy: condition, seed, step, metric, value.

    Columns: metric, step, test ('anova' or 'paired_t'), a, b (the pair; 'all' for the ANOVA),
    mean_a, mean_b, mean_diff (a - b) with ci_low, ci_high (95 %), statistic (F or t), df,
    p_value, p_holm, effect (eta^2 or Cohen's d_z), effect_name, n (runs, or pairs).
    """
    steps = checkpoints(frame) if steps is None else list(steps)
    nan = float("nan")
    rows = []
    for metric in metrics:
        for step in steps:
            groups = _groups(frame, metric, step)
            # The paper's order of conditions, then any others by name: pairs do not depend on
            # the order of the rows.
            names = [c for c in CONDITIONS if c in groups] + sorted(set(groups) - set(CONDITIONS))
            vals = [groups[c].to_numpy() for c in names]
            n = sum(len(v) for v in vals)
            if len(names) >= 2 and all(len(v) >= 2 for v in vals):
                f, p = sps.f_oneway(*vals)
                rows.append(dict(metric=metric, step=step, test="anova", a="all", b="all", mean_a=nan, mean_b=nan, mean_diff=nan, ci_low=nan, ci_high=nan,
                                 statistic=float(f), df=f"{len(names) - 1}, {n - len(names)}", p_value=float(p), effect=eta_squared(vals), effect_name="eta^2", n=n))
            for a, b in itertools.combinations(names, 2):
                both = groups[a].index.intersection(groups[b].index)
                if len(both) < 2:
                    continue
                ga, gb = groups[a].loc[both].to_numpy(), groups[b].loc[both].to_numpy()
                r = paired(ga, gb)
                rows.append(dict(metric=metric, step=step, test="paired_t", a=a, b=b, mean_a=float(ga.mean()), mean_b=float(gb.mean()), mean_diff=r["mean_diff"],
                                 ci_low=r["ci_low"], ci_high=r["ci_high"], statistic=r["statistic"], df=str(r["df"]), p_value=r["p_value"], effect=r["effect"],
                                 effect_name="cohen_dz", n=len(both)))
    table = pd.DataFrame(rows, columns=[c for c in COLUMNS if c != "p_holm"])
    table["p_holm"] = np.nan
    for (_, _), idx in table.groupby(["metric", "test"]).groups.items():
        table.loc[idx, "p_holm"] = holm(table.loc[idx, "p_value"].to_numpy())
    return table[COLUMNS]


def to_markdown(table: pd.DataFrame) -> str:
    """The comparison table as Markdown (no extra dependency)."""
    cols = COLUMNS
    out = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for _, r in table.iterrows():
        cells = []
        for c in cols:
            v = r[c]
            if isinstance(v, float):
                cells.append("" if np.isnan(v) else (f"{v:.3g}" if c in ("p_value", "p_holm") else f"{v:.3f}"))
            else:
                cells.append(str(v))
        out.append("| " + " | ".join(cells) + " |")
    return "\n".join(out) + "\n"
