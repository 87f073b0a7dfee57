"""The ask/tell goal selectors on their own (no arm)."""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import saggriac
from saggriac.errors import InputError, ParameterError

ROOT = Path(__file__).resolve().parents[2]


def toy_competence(goal, practised, rng):
    """Learnable only in the strip x < 0.3: skill grows with nearby practice."""
    if goal[0] >= 0.3:
        return float(np.clip(-0.9 + rng.normal(0.0, 0.02), -1.0, 0.0))
    near = sum(1 for p in practised if np.hypot(*(p - goal)) < 0.1)
    practised.append(goal)
    return -1.0 / (1.0 + 0.2 * near)


def share_in_strip(selector, n_goals, seed):
    rng = np.random.default_rng(seed)
    practised = []
    for _ in range(n_goals):
        g = selector.sample()
        selector.update(g, toy_competence(g, practised, rng))
    asked = selector.history()["asked_goal"]
    return float(np.mean(asked[n_goals // 2 :, 0] < 0.3))


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_sagg_riac_concentrates_on_the_learnable_region(seed):
    sagg = share_in_strip(saggriac.SaggRiacSelector([0, 0], [1, 1], seed=seed), 2000, seed)
    rand = share_in_strip(saggriac.RandomSelector([0, 0], [1, 1], seed=seed), 2000, seed)
    assert sagg > 0.55, sagg
    assert 0.25 < rand < 0.35, rand


def test_same_seed_same_goals_and_regions():
    def trace(seed):
        s = saggriac.SaggRiacSelector([-1, 0, 5], [1, 2, 6], seed=seed, g_max=20, zeta=6, min_child=3)
        goals = []
        for i in range(600):
            g = s.sample()
            goals.append(g)
            s.update(g, -abs(np.sin(3 * g[0] + i * 0.01)))
        return np.array(goals), s.regions()

    (a, ra), (b, rb), (c, _) = trace(4), trace(4), trace(5)
    assert np.array_equal(a, b)
    assert not np.array_equal(a, c)
    assert all(np.array_equal(ra[k], rb[k], equal_nan=True) for k in ra)
    assert ra["is_leaf"].sum() > 5  # 600 measurements with g_max = 20 must have split


def test_batches_equal_single_calls():
    one = saggriac.SaggRiacSelector([0, 0], [1, 1], seed=9, g_max=10, zeta=4, min_child=2)
    many = saggriac.SaggRiacSelector([0, 0], [1, 1], seed=9, g_max=10, zeta=4, min_child=2)
    for _ in range(20):
        goals = many.sample_batch(8)
        singles = np.array([one.sample() for _ in range(8)])
        assert np.array_equal(goals, singles)
        comp = -goals[:, 0] * goals[:, 1]
        regions = many.update_batch(goals, comp)
        assert list(regions) == [one.update(g, c) for g, c in zip(singles, comp)]
    assert np.array_equal(one.history()["told_competence"], many.history()["told_competence"])


def test_history_and_leaves_are_consistent():
    s = saggriac.SaggRiacSelector([0, 0], [1, 1], seed=1, g_max=10, zeta=4, min_child=2)
    for i in range(200):
        g = s.sample()
        s.update(g, -g[0])
    h = s.history()
    assert h["asked_goal"].shape == (200, 2) and h["told_goal"].shape == (200, 2)
    assert set(np.unique(h["asked_mode"])) <= set(saggriac.teachers.MODES)
    leaves = s.leaves()
    assert leaves["n_measurements"].sum() <= 200
    assert s.n_regions == len(leaves["interest"]) > 1
    # Every leaf box lies inside the root box and the leaves tile it (areas sum to 1).
    area = np.prod(leaves["high"] - leaves["low"], axis=1).sum()
    assert area == pytest.approx(1.0)


def test_bad_input_names_the_problem_and_changes_nothing():
    s = saggriac.SaggRiacSelector([0, 0], [1, 1], seed=0)
    with pytest.raises(InputError, match="2 coordinates|shape \\(2,\\)"):
        s.update([0.5], -0.1)
    with pytest.raises(InputError, match="coordinate 0 is 2"):
        s.update([2.0, 0.5], -0.1)
    with pytest.raises(InputError, match="finite"):
        s.update([0.5, 0.5], float("nan"))
    with pytest.raises(InputError, match="row 1"):
        s.update_batch([[0.1, 0.1], [0.2, np.inf]], [-0.1, -0.2])
    with pytest.raises(ParameterError, match="'n' parameter of SaggRiacSelector.sample_batch must be an int"):
        s.sample_batch(-1)
    assert len(s.history()["told_competence"]) == 0
    with pytest.raises(ParameterError, match="g_max"):
        saggriac.SaggRiacSelector([0, 0], [1, 1], g_max=1)
    with pytest.raises(ParameterError, match="p_lowest"):
        saggriac.SaggRiacSelector([0, 0], [1, 1], p_interest=0.9)
    with pytest.raises(ParameterError, match="low"):
        saggriac.RandomSelector([0, 1], [1, 1])


def test_curriculum_example_runs():
    out = subprocess.run([sys.executable, str(ROOT / "examples" / "curriculum.py"), "--goals", "1500"], capture_output=True, text=True, check=True).stdout
    sagg, rand = (float(x) for x in out.split("SAGG-RIAC ")[1].split(", random "))
    assert sagg > rand + 0.15, out
