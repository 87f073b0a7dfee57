"""Eq. 2's denominator for young regions (issue 24): zeta as printed, or the region's own window."""

import numpy as np
import pytest

import saggriac
from saggriac import Config
from saggriac.errors import ParameterError


def root_interest(values, **kw):
    sel = saggriac.SaggRiacSelector([0.0], [1.0], seed=0, g_max=50, zeta=20, **kw)
    for i, c in enumerate(values):
        sel.update([0.1 + 0.01 * i], c)
    return float(sel.regions()["interest"][0])


def test_young_region_divides_by_zeta_as_printed():
    young = [-1, -1, -1, 0, 0, 0]
    assert root_interest(young) == pytest.approx(0.15, abs=1e-15)
    assert root_interest(young, interest_divisor="zeta") == pytest.approx(0.15, abs=1e-15)
    assert root_interest(young, interest_divisor="window") == pytest.approx(0.5, abs=1e-15)
    assert root_interest([-1.0] * 6) == 0.0
    # A full window: both readings divide by zeta.
    full = list(np.linspace(-1, 0, 30))
    assert root_interest(full) == root_interest(full, interest_divisor="window")


@pytest.mark.parametrize("bad", ["w", "ZETA", "", 20, None, True])
def test_bad_divisor_is_named(bad):
    with pytest.raises(ParameterError, match="interest_divisor") as e:
        saggriac.SaggRiacSelector([0.0], [1.0], interest_divisor=bad)
    assert e.value.param == "interest_divisor"
    with pytest.raises(ParameterError, match="interest_divisor"):
        Config(interest_divisor=bad)


def test_runs_saved_before_the_key_read_back_as_window():
    d = Config.from_preset("exp2").to_dict()
    del d["interest_divisor"]
    assert Config.from_saved(d).interest_divisor == "window"
    assert Config.from_preset("exp2").interest_divisor == "zeta"


def test_printed_index_ranges_read_zeta_plus_one_values():
    """'printed': eq. 2's sums over j = |R| - zeta .. |R| - zeta/2 and |R| - zeta/2 .. |R| hold
    zeta + 1 values, the shared middle one cancelling (issue 35)."""
    # 21 values: the oldest -1, then 20 zeros. The last 20 show no progress; the printed
    # ranges reach the -1: |-1 - 0| / 20.
    values = [-1.0] + [0.0] * 20
    assert root_interest(values) == 0.0
    assert root_interest(values, interest_divisor="printed") == pytest.approx(0.05, abs=1e-15)
    # Random windows: |sum(w[:10]) - sum(w[11:])| / 20 over the last 21, middle dropped.
    rng = np.random.default_rng(5)
    for n in (21, 22, 37, 49):
        v = list(-rng.random(n))
        w = np.array(v[-21:])
        assert root_interest(v, interest_divisor="printed") == pytest.approx(abs(w[:10].sum() - w[11:].sum()) / 20, abs=1e-12)
        assert root_interest(v, interest_divisor="zeta") == pytest.approx(abs(w[1:11].sum() - w[11:].sum()) / 20, abs=1e-12)
    # Up to zeta values, 'printed' reads like 'zeta', young regions included.
    for n in range(0, 21):
        v = list(-rng.random(n))
        assert root_interest(v, interest_divisor="printed") == root_interest(v)


@pytest.mark.parametrize("divisor", ["zeta", "window", "printed"])
def test_the_run_and_the_selector_read_eq2_alike(divisor):
    """A run's built-in high level and a SaggRiacSelector given the same seed and reading choose
    the same goals."""
    cfg = Config.from_preset("exp2", n_steps=6000, n_evals=1, n_test_goals=5, n_test_configs=5, interest_divisor=divisor, zeta=10, g_max=20)
    built_in = saggriac.run(cfg, seed=3)
    seed = saggriac.seeding.selector_seed(3)
    sel = saggriac.SaggRiacSelector(cfg.goal_low, cfg.goal_high, seed=seed, g_max=20, zeta=10, interest_divisor=divisor)
    user = saggriac.run(cfg, seed=3, goal_selector=sel)
    cols = ["goal_x", "goal_y", "competence"]
    np.testing.assert_array_equal(built_in.goals[cols].to_numpy(), user.goals[cols].to_numpy())


def test_a_run_follows_its_reading():
    """The key reaches the run's region tree: the two readings part after the first splits, and
    each run's tree holds the interests its reading gives."""
    cfg = Config.from_preset("exp1", n_steps=20000, n_evals=1, n_test_goals=5, n_test_configs=5)
    a = saggriac.run(cfg, seed=101)
    b = saggriac.run(cfg.replace(interest_divisor="window"), seed=101)
    c = saggriac.run(cfg.replace(interest_divisor="printed"), seed=101)
    for other in (b, c):
        n = min(len(a.goals), len(other.goals))
        assert not np.array_equal(a.goals["goal_x"].to_numpy()[:n], other.goals["goal_x"].to_numpy()[:n])
    for res, divisor in ((a, "zeta"), (b, "window"), (c, "printed")):
        att = res.attempts
        sel = saggriac.SaggRiacSelector(cfg.goal_low, cfg.goal_high, interest_divisor=divisor)
        sel.update_batch(np.clip(att[["target_x", "target_y"]].to_numpy(), cfg.goal_low, cfg.goal_high), att["competence"].to_numpy())
        np.testing.assert_array_equal(np.sort(sel.leaves()["interest"]), np.sort(res.regions.query("is_leaf")["interest"].to_numpy()))
