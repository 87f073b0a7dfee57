"""Scale that follows the body (issue 25): v, eps_max and eval_tolerance relative to the reach
unless given, a user's body measured when it declares no reach, its test goals where it is."""

import dataclasses

import numpy as np
import pytest

import saggriac as sg
from saggriac import _core
from saggriac.config import LENGTH_DIVISORS, PRESETS, Config
from saggriac.bodies.environments import PlanarArm
from saggriac.errors import ConformanceError
from saggriac.bodies.scale import diameter, measure


@pytest.mark.parametrize("preset", sorted(PRESETS))
def test_paper_presets_keep_their_lengths_exactly(preset):
    cfg = Config.from_preset(preset)
    d = cfg.core_dict()
    assert (d["v"], d["eps_max"], d["eval_tolerance"]) == (0.5, 0.1, 0.01)


def test_given_lengths_are_used_as_given():
    cfg = Config(arm_length=2.0, goal_low=(0.0, -2.0), goal_high=(2.0, 2.0), v=0.3)
    assert cfg.lengths() == {"v": 0.3, "eps_max": 2.0 / 500, "eval_tolerance": 2.0 / 5000}
    assert set(LENGTH_DIVISORS) == {"v", "eps_max", "eval_tolerance"}


def test_a_small_arm_learns_as_the_paper_arm_does_in_units_of_its_reach():
    """The same run on a 50-unit and a 1-unit arm (goal box scaled too) gives the same reaching
    errors relative to the reach; with the old absolute lengths (v = 0.5 on a 1-unit arm) it
    does not."""
    def errors(length, **lengths):
        cfg = Config(arm_length=length, goal_low=(0.0, -length), goal_high=(length, length), n_steps=3000, n_evals=3, **lengths)
        return sg.run(cfg, seed=4).metrics["reach_error"].to_numpy() / length

    paper = errors(50.0)
    np.testing.assert_allclose(errors(1.0), paper, rtol=1e-6)
    assert not np.allclose(errors(1.0, v=0.5, eps_max=0.1, eval_tolerance=0.01), paper, rtol=1e-3)


class OffsetArm:
    """A 3-joint arm of reach 2 whose base sits at (100, 100); it declares no reach."""

    def __init__(self):
        self.arm = PlanarArm(n_joints=3, arm_length=2.0, max_joint_step=0.05)
        self.joint_space = self.arm.joint_space

    def reset(self, *, seed=None, options=None):
        t, x = self.arm.reset(seed=seed, options=options)
        return t, x + 100.0

    def step(self, dtheta):
        t, x = self.arm.step(dtheta)
        return t, x + 100.0


def test_a_body_away_from_the_origin_is_measured_and_tested_where_it_is():
    cfg = Config(n_joints=3, goal_low=(98.0, 97.0), goal_high=(103.0, 103.0), n_steps=2000, n_evals=2)
    r = sg.run(cfg, seed=0, environment=OffsetArm())
    scale = r.manifest["scale"]
    assert scale["source"] == "measured"
    assert 0.97 * 2.0 <= scale["reach"] <= 2.0
    assert scale["v"] == scale["reach"] / 100 and scale["eval_tolerance"] == scale["reach"] / 5000
    assert r.manifest["test_set"]["unreached_goals"] == 0
    goals = np.asarray(_test_goals(cfg, OffsetArm()))
    assert np.all(np.linalg.norm(goals - 100.0, axis=1) <= 2.0 + 1e-9)
    assert np.all((goals >= cfg.goal_low) & (goals <= cfg.goal_high))
    # Learning happens: the reaching error falls.
    e = r.metrics["reach_error"].to_numpy()
    assert e[-1] < 0.6 * e[0]


def _test_goals(cfg, env):
    from saggriac.bodies.scale import body_scale
    from saggriac.seeding import derive_seeds
    from saggriac.testing import joint_space_of

    body = body_scale(env, *joint_space_of(env), 2)
    learner = _core.Learner(cfg.core_dict(reach=body.reach), *derive_seeds(0), environment=env, test_cloud=(body.configs.tolist(), body.positions.tolist()))
    return learner.test_set()["goals"]


def test_saggriacs_python_arm_declares_its_reach_and_runs_as_the_builtin_arm():
    cfg = Config(n_steps=1500, n_evals=2, n_test_goals=20, n_test_configs=20)
    python = sg.run(cfg, seed=2, environment=PlanarArm())
    builtin = sg.run(cfg, seed=2)
    assert python.manifest["scale"] == {**builtin.manifest["scale"], "source": "declared"}
    np.testing.assert_array_equal(python.metrics["reach_error"], builtin.metrics["reach_error"])


@pytest.mark.parametrize("reach", [0, -1.0, float("nan"), "2", True])
def test_a_bad_declared_reach_is_refused(reach):
    env = OffsetArm()
    env.reach = reach
    with pytest.raises(ConformanceError, match=r"environment.reach must be a float in \[1e-12, 1e\+12\]"):
        sg.run(Config(n_joints=3, goal_low=(98.0, 97.0), goal_high=(103.0, 103.0), n_steps=10), environment=env)


def test_a_body_that_never_moves_is_refused_with_the_reason():
    class Stuck(OffsetArm):
        def reset(self, *, seed=None, options=None):
            t, _ = self.arm.reset(seed=seed, options=options)
            return t, np.array([1.0, 1.0])

    with pytest.raises(ConformanceError):
        measure(Stuck(), -np.ones(3), np.ones(3), 2)


@pytest.mark.parametrize("m", [1, 2, 3])
def test_diameter_matches_brute_force(m):
    rng = np.random.default_rng(m)
    for _ in range(5):
        pts = rng.normal(size=(400, m)) * rng.uniform(0.1, 10, m)
        brute = np.sqrt(((pts[:, None] - pts[None]) ** 2).sum(-1).max())
        got = diameter(pts)
        assert got <= brute + 1e-12
        assert got >= 0.995 * brute


def test_a_test_cloud_that_does_not_fit_is_refused():
    cfg = Config(n_joints=3, goal_low=(98.0, 97.0), goal_high=(103.0, 103.0))
    with pytest.raises(ValueError, match="test_cloud"):
        _core.Learner(cfg.core_dict(reach=2.0), 1, 2, environment=OffsetArm(), test_cloud=([[0.0, 0.0, 0.0]], [[float("nan"), 1.0]]))
    assert dataclasses.replace(cfg).v is None
