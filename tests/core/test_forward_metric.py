"""The forward-model metric at each test goal's least-norm configuration (docs/reproduction.md, "What is measured")."""

import numpy as np
import pytest

import saggriac
from saggriac import Config
from saggriac.errors import ParameterError


@pytest.fixture(scope="module")
def run():
    return saggriac.run(Config.from_preset("exp1", condition="sagg_random", n_steps=6000, n_evals=3), seed=7)


def test_prediction_error_falls_below_its_no_learning_value(run):
    m, ts = run.metrics, run.manifest["test_set"]
    assert ts["configs"] == "ik_min_norm" and ts["n_configs"] == 100 and ts["unreached_goals"] == 0
    # Before learning the prediction is the origin: the step-0 value is the no-learning value.
    assert m["pred_error"].iloc[0] == pytest.approx(ts["pred_error_no_learning"])
    assert m["pred_error"].iloc[-1] < 0.6 * ts["pred_error_no_learning"]
    # No model yet: no motion predicted, relative error exactly 1.
    assert m["dx_error"].iloc[0] == 1.0 and np.isfinite(m["dx_error"]).all() and (m["dx_error"] > 0).all()
    # The least-norm configurations of the paper's arm are gentle bends, near the straight rest.
    assert 0.2 < ts["mean_config_norm"] < 1.5


def test_the_time_budget_adds_up(run):
    tb = run.manifest["time_budget"]
    kinds = tb["micro_actions"]
    assert sum(kinds.values()) == 6000 and kinds["babbling"] == 0
    assert tb["goals"] == len(run.goals) > 0
    assert 0 <= tb["share_on_reachable_goals"] <= 1 and tb["goals_reachable"] <= tb["goals"]
    assert sum(tb["share_by_mode"].values()) == pytest.approx(1.0)
    assert set(tb["share_by_mode"]) == {"random"}


def test_uniform_configurations_stay_available():
    r = saggriac.run(Config.from_preset("exp1", n_steps=1500, n_evals=2, test_configs="uniform"), seed=7)
    assert r.manifest["test_set"]["configs"] == "uniform" and "unreached_goals" not in r.manifest["test_set"]
    # Same learning, same reaching test; only the forward-model test moved.
    ik = saggriac.run(Config.from_preset("exp1", n_steps=1500, n_evals=2), seed=7)
    assert r.metrics["reach_error"].tolist() == ik.metrics["reach_error"].tolist()
    assert r.metrics["pred_error"].iloc[0] != ik.metrics["pred_error"].iloc[0]


def test_a_run_saved_before_the_option_reads_back_as_uniform():
    saved = Config.from_preset("exp1").to_dict()
    del saved["test_configs"]
    assert Config.from_saved(saved).test_configs == "uniform"
    assert Config.from_saved({**saved, "test_configs": "ik_min_norm"}).test_configs == "ik_min_norm"


def test_an_unknown_kind_is_refused_with_the_rule():
    with pytest.raises(ParameterError, match=r"'test_configs' parameter of Config must be one of 'ik_min_norm', 'uniform'. Got 'grid'"):
        Config(test_configs="grid")


def test_split_null_model_replays_trees_exactly():
    from saggriac.analysis.splits import replay_regions, split_shares

    cfg = Config.from_preset("exp2", n_steps=30000, n_evals=1)
    riac = saggriac.run(cfg, seed=103)
    # Replaying a run's own measurements rebuilds its tree: the replay is faithful.
    rep = replay_regions(riac.attempts, cfg)
    cols = ["low_x", "low_y", "high_x", "high_y", "parent", "created_at", "split_dim"]
    assert len(rep) == len(riac.regions) > 3
    assert np.array_equal(rep[cols].to_numpy(float), riac.regions[cols].to_numpy(float), equal_nan=True)
    shares = split_shares(riac.regions, cfg.reach)
    assert len(shares) == 4 and all(0.0 <= s <= 1.0 for s in shares if not np.isnan(s))
    # The whole goal box of exp2 is 8.7 % reachable (a half-disk of radius 50 in 150 x 300).
    from saggriac.analysis.splits import reachable_share

    assert reachable_share(np.array([0.0, -150.0]), np.array([150.0, 150.0]), 50.0, grid=300) == pytest.approx(np.pi * 50**2 / 2 / (150 * 300), abs=2e-3)
