"""The episodic paradigm and the explauto preset."""

import numpy as np
import pandas as pd
import pytest

import saggriac
from saggriac.errors import ParameterError


def explauto(**kw):
    return saggriac.Config.from_preset("explauto", **{"n_steps": 4000, "n_evals": 4, **kw})


def test_explauto_preset_learns_to_reach():
    cfg = explauto()
    assert cfg.paradigm == "episodic" and cfg.n_joints == 15 and cfg.joint_limit == pytest.approx(np.pi)
    res = saggriac.run(cfg, seed=0)
    # One sample per movement; the reaching error on the disk of radius 50 falls far below the
    # error of the rest pose (about 57).
    assert list(res.metrics["n_samples"]) == list(res.steps)
    assert res.reach_error[0] > 40
    assert res.reach_error[-1] < 3.0
    g = res.goals
    assert len(g) == 4000
    assert g["goal_x"].between(-50, 50).all() and g["goal_y"].between(-50, 50).all()
    # Goal modes: initial draws, then the three SAGG-RIAC modes once the tree has split.
    assert set(g["mode"].unique()) == {0, 1, 2, 3}


@pytest.mark.parametrize("condition", ["sagg_random", "actuator_random", "actuator_riac"])
def test_other_conditions_run_episodically(condition):
    res = saggriac.run(explauto(condition=condition, n_steps=1500), seed=1)
    assert np.all(np.isfinite(res.reach_error))
    assert res.metrics["n_samples"].iloc[-1] == 1500


def test_refine_uses_the_local_model_and_is_deterministic():
    cfg = explauto(episodic_refine=True, episodic_k=20, n_steps=3000)
    a, b = saggriac.run(cfg, seed=2), saggriac.run(cfg, seed=2)
    pd.testing.assert_frame_equal(a.metrics, b.metrics, check_exact=True)
    plain = saggriac.run(cfg.replace(episodic_refine=False), seed=2)
    assert not np.array_equal(a.reach_error, plain.reach_error)
    assert a.reach_error[-1] < 3.0


def test_without_noise_sagg_gets_stuck_but_stays_finite():
    # No exploration noise: every movement repeats a stored configuration, so nothing new is
    # ever reached. The run must still be well defined.
    res = saggriac.run(explauto(episodic_noise=0.0, n_steps=500), seed=0)
    assert np.all(np.isfinite(res.reach_error))
    assert res.reach_error[-1] == pytest.approx(res.reach_error[1])


def test_bad_paradigm_values_are_named():
    with pytest.raises(ParameterError, match="paradigm"):
        explauto(paradigm="continuous")
    with pytest.raises(ParameterError, match="episodic_noise"):
        explauto(episodic_noise=-1.0)
