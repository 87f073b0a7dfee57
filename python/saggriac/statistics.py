"""Statistics over a study: one-way ANOVA across conditions and pairwise Welch t-tests, with
effect sizes, at the end of the runs and at checkpoints. The tests themselves come from scipy;
this module picks the data and lays out the table."""

from __future__ import annotations

import itertools
from typing import Sequence

import numpy as np
import pandas as pd
from scipy import stats as sps

METRICS = ("reach_error", "pred_error")


def _groups(frame: pd.DataFrame, metric: str, step: int) -> dict[str, np.ndarray]:
    sel = frame[(frame["metric"] == metric) & (frame["step"] == step)]
    return {c: g["value"].to_numpy(dtype=float) for c, g in sel.groupby("condition", sort=False)}


def eta_squared(groups: Sequence[np.ndarray]) -> float:
    """Share of the total variance explained by the grouping (effect size of the ANOVA)."""
    allv = np.concatenate(groups)
    grand = allv.mean()
    ss_between = sum(len(g) * (g.mean() - grand) ** 2 for g in groups)
    ss_total = ((allv - grand) ** 2).sum()
    return float(ss_between / ss_total) if ss_total > 0 else float("nan")


def hedges_g(a: np.ndarray, b: np.ndarray) -> float:
    """Standardised mean difference (a - b) with the small-sample correction."""
    na, nb = len(a), len(b)
    if na < 2 or nb < 2:
        return float("nan")
    pooled = np.sqrt(((na - 1) * a.var(ddof=1) + (nb - 1) * b.var(ddof=1)) / (na + nb - 2))
    if pooled == 0:
        return float("nan")
    d = (a.mean() - b.mean()) / pooled
    return float(d * (1 - 3 / (4 * (na + nb) - 9)))


def checkpoints(frame: pd.DataFrame, n: int = 4) -> list[int]:
    """The last step and n - 1 evenly spaced earlier steps present in every run."""
    steps = np.sort(frame["step"].unique())
    if len(steps) == 0:
        return []
    idx = np.unique(np.linspace(0, len(steps) - 1, n + 1).round().astype(int))[1:]
    return [int(steps[i]) for i in idx]


def compare(frame: pd.DataFrame, steps: Sequence[int] | None = None, metrics: Sequence[str] = METRICS) -> pd.DataFrame:
    """One row per (metric, step, test): the ANOVA over all conditions, then every pair.

    Columns: metric, step, test ('anova' or 'welch'), a, b (the pair; 'all' for the ANOVA),
    mean_a, mean_b, statistic (F or t), df, p_value, effect (eta^2 or Hedges' g), effect_name, n.
    """
    steps = checkpoints(frame) if steps is None else list(steps)
    rows = []
    for metric in metrics:
        for step in steps:
            groups = _groups(frame, metric, step)
            names = list(groups)
            vals = [groups[c] for c in names]
            n = sum(len(v) for v in vals)
            if len(names) >= 2 and all(len(v) >= 2 for v in vals):
                f, p = sps.f_oneway(*vals)
                rows.append(dict(metric=metric, step=step, test="anova", a="all", b="all", mean_a=np.nan, mean_b=np.nan,
                                 statistic=float(f), df=f"{len(names) - 1}, {n - len(names)}", p_value=float(p),
                                 effect=eta_squared(vals), effect_name="eta^2", n=n))
            for a, b in itertools.combinations(names, 2):
                ga, gb = groups[a], groups[b]
                if len(ga) < 2 or len(gb) < 2:
                    continue
                t = sps.ttest_ind(ga, gb, equal_var=False)
                rows.append(dict(metric=metric, step=step, test="welch", a=a, b=b, mean_a=float(ga.mean()), mean_b=float(gb.mean()),
                                 statistic=float(t.statistic), df=f"{float(t.df):.1f}", p_value=float(t.pvalue),
                                 effect=hedges_g(ga, gb), effect_name="hedges_g", n=len(ga) + len(gb)))
    return pd.DataFrame(rows)


def to_markdown(table: pd.DataFrame) -> str:
    """The comparison table as Markdown (no extra dependency)."""
    cols = ["metric", "step", "test", "a", "b", "mean_a", "mean_b", "statistic", "df", "p_value", "effect", "effect_name", "n"]
    out = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for _, r in table.iterrows():
        cells = []
        for c in cols:
            v = r[c]
            if isinstance(v, float):
                cells.append("" if np.isnan(v) else (f"{v:.3g}" if c == "p_value" else f"{v:.3f}"))
            else:
                cells.append(str(v))
        out.append("| " + " | ".join(cells) + " |")
    return "\n".join(out) + "\n"
