"""The statistics table against known values and scipy."""

import numpy as np
import pandas as pd
import pytest
from scipy import stats as sps

from saggriac import statistics


def tidy(groups, metric="reach_error", step=100):
    rows = [dict(condition=c, seed=i, step=step, metric=metric, value=v) for c, vs in groups.items() for i, v in enumerate(vs)]
    return pd.DataFrame(rows)


def test_anova_on_a_hand_computed_example():
    # Three groups of three: means 2, 5, 8; SS_between = 3*(9+0+9) = 54, SS_within = 6,
    # F = (54/2) / (6/6) = 27 with (2, 6) degrees of freedom; eta^2 = 54/60 = 0.9.
    g = {"a": [1.0, 2.0, 3.0], "b": [4.0, 5.0, 6.0], "c": [7.0, 8.0, 9.0]}
    t = statistics.compare(tidy(g), steps=[100], metrics=["reach_error"])
    row = t[t["test"] == "anova"].iloc[0]
    assert row["statistic"] == pytest.approx(27.0)
    assert row["df"] == "2, 6"
    assert row["p_value"] == pytest.approx(sps.f.sf(27.0, 2, 6))
    assert row["effect"] == pytest.approx(0.9)


def test_pairwise_welch_and_effect_size_match_scipy():
    rng = np.random.default_rng(0)
    g = {"sagg_riac": rng.normal(1.0, 0.3, 15), "sagg_random": rng.normal(1.4, 0.6, 15)}
    t = statistics.compare(tidy(g), steps=[100], metrics=["reach_error"])
    w = t[t["test"] == "welch"].iloc[0]
    ref = sps.ttest_ind(g["sagg_riac"], g["sagg_random"], equal_var=False)
    assert (w["a"], w["b"]) == ("sagg_riac", "sagg_random")
    assert w["statistic"] == pytest.approx(ref.statistic) and w["p_value"] == pytest.approx(ref.pvalue)
    # Hedges' g by its textbook formula.
    a, b = g["sagg_riac"], g["sagg_random"]
    sp = np.sqrt((14 * a.var(ddof=1) + 14 * b.var(ddof=1)) / 28)
    assert w["effect"] == pytest.approx((a.mean() - b.mean()) / sp * (1 - 3 / (4 * 30 - 9)))
    md = statistics.to_markdown(t)
    assert md.count("\n") == 2 + len(t)
    assert "| reach_error | 100 | welch | sagg_riac | sagg_random |" in md


def test_checkpoints_end_at_the_last_step():
    frame = pd.concat([tidy({"a": [1.0, 2.0], "b": [3.0, 4.0]}, step=s) for s in range(0, 1001, 50)])
    cps = statistics.checkpoints(frame, n=4)
    assert cps[-1] == 1000 and len(cps) == 4 and cps == sorted(cps)
