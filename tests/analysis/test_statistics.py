"""The statistics table against known values and scipy."""

import numpy as np
import pandas as pd
import pytest
from scipy import stats as sps

from saggriac.analysis import statistics


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


def test_pairs_are_compared_seed_by_seed_like_scipy():
    rng = np.random.default_rng(0)
    # A seed effect shared by both conditions (the same test sets), which pairing removes.
    seed_effect = rng.normal(0.0, 2.0, 15)
    g = {"sagg_riac": seed_effect + rng.normal(1.0, 0.3, 15), "sagg_random": seed_effect + rng.normal(1.4, 0.3, 15)}
    frame = tidy(g).sample(frac=1.0, random_state=1)  # row order must not matter
    t = statistics.compare(frame, steps=[100], metrics=["reach_error"])
    w = t[t["test"] == "paired_t"].iloc[0]
    a, b = g["sagg_riac"], g["sagg_random"]
    ref = sps.ttest_rel(a, b)
    assert (w["a"], w["b"], w["n"]) == ("sagg_riac", "sagg_random", 15)
    assert w["statistic"] == pytest.approx(ref.statistic) and w["p_value"] == pytest.approx(ref.pvalue)
    d = a - b
    half = sps.t.ppf(0.975, 14) * d.std(ddof=1) / np.sqrt(15)
    assert (w["mean_diff"], w["ci_low"], w["ci_high"]) == pytest.approx((d.mean(), d.mean() - half, d.mean() + half))
    assert w["effect"] == pytest.approx(d.mean() / d.std(ddof=1)) and w["effect_name"] == "cohen_dz"
    # Unpaired, the seed effect would hide the difference.
    assert w["p_value"] < 1e-4 < sps.ttest_ind(a, b, equal_var=False).pvalue
    md = statistics.to_markdown(t)
    assert md.count("\n") == 2 + len(t)
    assert "| reach_error | 100 | paired_t | sagg_riac | sagg_random |" in md


def test_only_seeds_present_in_both_conditions_are_paired():
    frame = tidy({"a": [1.0, 2.0, 3.0, 4.0], "b": [2.0, 2.5, 4.5]})
    w = statistics.compare(frame, steps=[100], metrics=["reach_error"]).query("test == 'paired_t'").iloc[0]
    assert w["n"] == 3 and w["mean_diff"] == pytest.approx(np.mean([-1.0, -0.5, -1.5]))


def test_holm_correction():
    p = [0.01, 0.04, 0.03, np.nan, 0.005]
    # Sorted: 0.005*4, 0.01*3, 0.03*2, 0.04*1, each at least the previous.
    assert statistics.holm(p)[[4, 0, 2, 1]] == pytest.approx([0.02, 0.03, 0.06, 0.06])
    assert np.isnan(statistics.holm(p)[3])
    rng = np.random.default_rng(3)
    frame = pd.concat([tidy({c: rng.normal(0, 1, 6) for c in "abc"}, step=s) for s in (10, 20)])
    t = statistics.compare(frame, steps=[10, 20], metrics=["reach_error"])
    pairs = t[t["test"] == "paired_t"]
    assert len(pairs) == 6 and (pairs["p_holm"] >= pairs["p_value"]).all()
    assert pairs["p_holm"].to_numpy() == pytest.approx(statistics.holm(pairs["p_value"].to_numpy()))


def test_checkpoints_end_at_the_last_step():
    frame = pd.concat([tidy({"a": [1.0, 2.0], "b": [3.0, 4.0]}, step=s) for s in range(0, 1001, 50)])
    cps = statistics.checkpoints(frame, n=4)
    assert cps[-1] == 1000 and len(cps) == 4 and cps == sorted(cps)
