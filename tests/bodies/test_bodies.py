"""Body variants: long arms with unequal links, motor and sensor noise, a body that changes."""

import numpy as np
import pandas as pd
import pytest

import saggriac
from saggriac.bodies.environments import PlanarArm
from saggriac.errors import ParameterError


def small(**kw):
    return saggriac.Config.from_preset("exp1", **{"n_steps": 3000, "n_evals": 6, "n_test_goals": 20, "n_test_configs": 20, **kw})


def test_hundred_unequal_links():
    lengths = np.linspace(2.0, 0.5, 100)
    cfg = small(link_lengths=tuple(lengths * 50 / lengths.sum()), n_steps=800, n_evals=2)
    res = saggriac.run(cfg, seed=0)
    assert np.all(np.isfinite(res.reach_error)) and res.metrics["n_samples"].iloc[-1] == 800


@pytest.mark.parametrize("noise", [dict(motor_noise=0.002), dict(sensor_noise=0.05)])
def test_noise_is_seeded_and_changes_the_run(noise):
    clean = saggriac.run(small(), seed=1)
    a, b = saggriac.run(small(**noise), seed=1), saggriac.run(small(**noise), seed=1)
    pd.testing.assert_frame_equal(a.metrics, b.metrics, check_exact=True)
    assert not np.array_equal(a.reach_error, clean.reach_error)
    assert np.all(np.isfinite(a.reach_error)) and a.reach_error[-1] < a.reach_error[0]


def test_a_link_that_changes_mid_run():
    base = small(n_steps=4000, eval_schedule=(0, 1000, 1999, 2000, 3000, 4000))
    same = saggriac.run(base, seed=2)
    changed = saggriac.run(base.replace(body_change_step=2000, body_change_link=14, body_change_length=12.0), seed=2)
    m0, m1 = same.metrics.set_index("step"), changed.metrics.set_index("step")
    # Identical until the change ...
    assert m0.loc[[0, 1000, 1999]].equals(m1.loc[[0, 1000, 1999]])
    # ... then the same memory is judged on a different body: the prediction truths moved.
    assert m0.loc[2000, "pred_error"] != m1.loc[2000, "pred_error"]
    assert not m0.loc[[3000, 4000]].equals(m1.loc[[3000, 4000]])


def test_body_variants_are_validated():
    with pytest.raises(ParameterError, match="body_change_link"):
        small(body_change_step=10, body_change_link=15, body_change_length=1.0)
    with pytest.raises(ParameterError, match="body_change_length"):
        small(body_change_step=10, body_change_link=3, body_change_length=-1.0)
    with pytest.raises(ParameterError, match="body_change_step"):
        small(body_change_step=10**6, body_change_link=3, body_change_length=1.0)
    with pytest.raises(ParameterError, match="motor_noise"):
        small(motor_noise=-0.1)
    with pytest.raises(ParameterError, match="motor_noise/sensor_noise"):
        saggriac.run(small(sensor_noise=0.1), seed=0, environment=PlanarArm())
    with pytest.raises(ParameterError, match="body_change_step"):
        saggriac.run(small(body_change_step=10, body_change_link=3, body_change_length=1.0), seed=0, environment=PlanarArm())
