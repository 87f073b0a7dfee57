"""SAGG-RIAC's mode 3 readings (issue 48): the paper's, the default, and 'interest_worst', a region
drawn by interest and a goal about its worst goal."""

import numpy as np
import pytest

import saggriac
from saggriac import Config
from saggriac.errors import ParameterError

MODE3 = 3  # the mode number goals of mode 3 are logged with


def taught(seed=0, n=300, **kw):
    """A teacher on [0, 1]^2 told a learnable left half (rising competence) and a flat right
    half, with every goal from mode 3 once the tree has split; and the points it was told with
    their competences."""
    sel = saggriac.SaggRiacSelector([0.0, 0.0], [1.0, 1.0], seed=seed, g_max=20, zeta=10, min_child=3, p_interest=0.0, p_global=0.0, p_lowest=1.0, **kw)
    rng = np.random.default_rng(np.random.SeedSequence(seed))
    told = [([0.2, 0.3], -1.0)]
    for i in range(n):
        told.append(([rng.uniform(0, 0.5), rng.uniform(0, 1)], -0.99 + i / n))
        told.append(([rng.uniform(0.5, 1), rng.uniform(0, 1)], -0.9))
    for g, c in told:
        sel.update(g, c)
    return sel, told


def worst_points(sel, told):
    """Each leaf's box with the worst point told in it (the newest of equals)."""
    leaves = sel.leaves()
    out = []
    for lo, hi in zip(leaves["low"], leaves["high"]):
        inside = [(c, -i, g) for i, (g, c) in enumerate(told) if np.all(lo <= g) and np.all(np.asarray(g) < hi)]
        if inside:
            out.append((lo, hi, np.asarray(min(inside)[2])))
    return out


def test_the_default_is_the_papers_reading():
    assert Config().mode3 == "lowest_competence"
    (a, _), (b, _) = taught(), taught(mode3="lowest_competence")
    ga, gb = [a.sample() for _ in range(200)], [b.sample() for _ in range(200)]
    np.testing.assert_array_equal(ga, gb)
    # The region of lowest mean competence is the flat right half.
    assert all(g[0] >= 0.5 for g in ga)


def test_interest_worst_aims_near_the_worst_goal_of_an_interesting_region():
    sigma = 0.02
    sel, told = taught(mode3="interest_worst", mode3_sigma=sigma)
    goals = np.array([sel.sample() for _ in range(1000)])
    # Drawn by interest: mostly the learnable half (a leaf may straddle x = 0.5); the paper's
    # reading never goes there (test above).
    assert (goals[:, 0] < 0.5).mean() > 0.8
    # Each goal within 3 sd (in each dimension) of the worst point of a leaf holding it: 99.5 %
    # of an unclipped Gaussian's draws, and clipping to the leaf only brings them closer.
    boxes = worst_points(sel, told)
    near = [any(np.all(lo <= g) and np.all(g <= hi) and np.all(np.abs(g - w) < 3 * sigma) for lo, hi, w in boxes) for g in goals]
    assert np.mean(near) > 0.97, np.mean(near)
    # Uniform in the leaf (the paper's reading) is far less often that near.
    paper, _ = taught()
    uniform = np.array([paper.sample() for _ in range(1000)])
    boxes = worst_points(paper, told)
    near = [any(np.all(lo <= g) and np.all(g <= hi) and np.all(np.abs(g - w) < 3 * sigma) for lo, hi, w in boxes) for g in uniform]
    assert np.mean(near) < 0.5


@pytest.mark.parametrize("kw, param", [
    (dict(mode3="worst"), "mode3"),
    (dict(mode3=None), "mode3"),
    (dict(mode3="interest_worst", mode3_sigma=0.0), "mode3_sigma"),
    (dict(mode3="interest_worst", mode3_sigma=1.5), "mode3_sigma"),
    (dict(mode3="interest_worst", mode3_sigma=float("nan")), "mode3_sigma"),
    (dict(mode3_sigma=0.3), "mode3_sigma"),
])
def test_bad_values_are_named(kw, param):
    with pytest.raises(ParameterError, match=f"'{param}' parameter of SaggRiacSelector") as e:
        saggriac.SaggRiacSelector([0.0], [1.0], **kw)
    assert e.value.param == param
    with pytest.raises(ParameterError, match=f"'{param}' parameter of Config"):
        Config(**kw)


def test_sigma_alone_is_refused_with_the_rule():
    with pytest.raises(ParameterError, match=r"^The 'mode3_sigma' parameter of SaggRiacSelector must be left at its default .* with mode3 = 'lowest_competence' .*Got 0.3 instead.$"):
        saggriac.SaggRiacSelector([0.0], [1.0], mode3_sigma=0.3)


def test_save_and_load_carry_the_reading(tmp_path):
    sel, _ = taught(mode3="interest_worst", mode3_sigma=0.07)
    path = sel.save(tmp_path / "teacher.bin")
    back = saggriac.load_selector(path)
    params = back.get_params()
    assert params["mode3"] == "interest_worst" and params["mode3_sigma"] == 0.07
    np.testing.assert_array_equal([sel.sample() for _ in range(100)], [back.sample() for _ in range(100)])


def test_runs_saved_before_the_key_read_back_as_the_papers():
    d = Config.from_preset("exp2").to_dict()
    del d["mode3"], d["mode3_sigma"]
    assert Config.from_saved(d).mode3 == "lowest_competence"


def test_the_run_and_the_selector_read_mode3_alike():
    """The key reaches a run's own high level: a run and a SaggRiacSelector given the same seed
    and reading choose the same goals, and the reading changes them."""
    kw = dict(mode3="interest_worst", mode3_sigma=0.05)
    cfg = Config.from_preset("exp1", paradigm="episodic", n_steps=3000, n_evals=1, n_test_goals=5, n_test_configs=5, zeta=10, g_max=20, **kw)
    built_in = saggriac.run(cfg, seed=3)
    sel = saggriac.SaggRiacSelector(cfg.goal_low, cfg.goal_high, seed=saggriac.seeding.selector_seed(3), g_max=20, zeta=10, **kw)
    user = saggriac.run(cfg, seed=3, goal_selector=sel)
    cols = ["goal_x", "goal_y", "competence"]
    np.testing.assert_array_equal(built_in.goals[cols].to_numpy(), user.goals[cols].to_numpy())
    assert (built_in.goals["mode"].to_numpy() == MODE3).any()
    paper = saggriac.run(cfg.replace(mode3="lowest_competence", mode3_sigma=Config().mode3_sigma), seed=3)
    n = min(len(paper.goals), len(built_in.goals))
    assert not np.array_equal(paper.goals["goal_x"].to_numpy()[:n], built_in.goals["goal_x"].to_numpy()[:n])
