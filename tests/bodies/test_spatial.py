"""Task spaces other than the plane: the built-in arm in space (3-D), a Python body with a 1-D
task space, and the errors when the goal space and the body disagree."""

import math

import numpy as np
import pandas as pd
import pytest

import saggriac
from saggriac.analysis import plots
from saggriac.bodies.environments import Box, PlanarArm, SpatialArm
from saggriac.errors import InputError, ParameterError
from saggriac.testing import check_environment


def arm3d(**kw):
    return saggriac.Config.from_preset("arm3d", **{"n_steps": 1500, "n_evals": 3, "n_test_goals": 10, "n_test_configs": 10, **kw})


def test_the_spatial_arm_learns_to_reach_in_3d(tmp_path):
    res = saggriac.run(arm3d(n_steps=5000, n_evals=2, n_test_goals=20), seed=0, out_dir=tmp_path / "r")
    # Reaching error over 20 test goals in the half ball: far better after 5000 micro-actions.
    assert res.reach_error[-1] < 0.6 * res.reach_error[0], res.reach_error
    assert {"goal_x", "goal_y", "goal_z", "end_z"} <= set(res.goals.columns)
    assert {"low_z", "high_z"} <= set(res.regions.columns)
    # Goals fill the 3-D goal box, and the arm really leaves the plane z = 0.
    assert res.goals["goal_z"].min() < -20 and res.goals["goal_z"].max() > 20
    assert (res.goals["end_z"].abs() > 5).any()
    # The figures of a 3-D run: goal histograms in two projections, the arm in 3-D.
    assert plots.plot_goal_histograms(tmp_path / "r", tmp_path / "goals.png").stat().st_size > 10_000
    assert plots.plot_arm(res.config, tmp_path / "arm.png").stat().st_size > 10_000


def test_the_python_spatial_arm_gives_the_builtin_trajectory():
    cfg = arm3d()
    builtin = saggriac.run(cfg, seed=4)
    python = saggriac.run(cfg, seed=4, environment=SpatialArm())
    pd.testing.assert_frame_equal(builtin.metrics, python.metrics, check_exact=True)
    pd.testing.assert_frame_equal(builtin.goals, python.goals, check_exact=True)
    pd.testing.assert_frame_equal(builtin.attempts, python.attempts, check_exact=True)


def test_episodic_paradigm_in_3d():
    cfg = arm3d(paradigm="episodic", n_steps=3000, joint_limit=math.pi, goal_low=(-50.0, -50.0, -50.0))
    builtin = saggriac.run(cfg, seed=1)
    python = saggriac.run(cfg, seed=1, environment=SpatialArm(joint_limit=math.pi))
    pd.testing.assert_frame_equal(builtin.metrics, python.metrics, check_exact=True)
    assert builtin.reach_error[-1] < 0.5 * builtin.reach_error[0], builtin.reach_error


@pytest.mark.parametrize("env", [SpatialArm(), SpatialArm(n_joints=4, joint_limit=math.pi, link_lengths=[4, 3, 2, 1])])
def test_spatial_arm_conforms(env):
    check_environment(env)


def test_the_goal_space_must_have_the_body_dimension():
    with pytest.raises(ParameterError, match=r"'goal_low' parameter of Config must be a list of 3 floats \(the spatial arm's task space is 3-D\)"):
        saggriac.run(arm3d(goal_low=(0.0, -50.0), goal_high=(50.0, 50.0)), seed=0)
    with pytest.raises(ParameterError, match=r"'goal_low' parameter of Config must be a list of 2 floats \(the planar arm's task space is 2-D\)"):
        saggriac.run(arm3d(body="planar_arm"), seed=0)
    with pytest.raises(ParameterError, match="'goal_low' parameter of Config must be a list of 1 to 3 floats"):
        arm3d(goal_low=(0.0,) * 4, goal_high=(1.0,) * 4)
    with pytest.raises(ParameterError, match="'body' parameter of Config must be one of 'planar_arm', 'spatial_arm'"):
        arm3d(body="hexapod")
    # A Python body declares its task space: it must match the goal space.
    small2d = saggriac.Config.from_preset("exp1", n_steps=500, n_evals=1, n_test_goals=5, n_test_configs=5)
    with pytest.raises(ParameterError, match=r"'goal_low' parameter of Config must have one bound per dimension of the environment's task_space \(3\)"):
        saggriac.run(small2d, seed=0, environment=SpatialArm())


class Undeclared(SpatialArm):
    """A 3-D body that does not say so (no task_space)."""

    def __getattribute__(self, name):
        if name == "task_space":
            raise AttributeError(name)
        return super().__getattribute__(name)


def test_an_undeclared_task_space_is_checked_on_the_first_position():
    small2d = saggriac.Config.from_preset("exp1", n_steps=500, n_evals=1, n_test_goals=5, n_test_configs=5)
    with pytest.raises(InputError, match=r"x returned by environment.reset\(\) must have shape \(2,\); got shape \(3,\). \(the goal space goal_low/goal_high is 2-D\)"):
        saggriac.run(small2d, seed=0, environment=Undeclared())


class Rail(PlanarArm):
    """A body with a 1-D task space: only the x coordinate of the planar arm's hand counts."""

    def __init__(self, **kw):
        super().__init__(**kw)
        reach = sum(self.lengths)
        self.task_space = Box(-reach, reach, (1,))

    def forward(self, theta):
        return super().forward(theta)[:1]


def test_a_one_dimensional_task_space(tmp_path):
    env = Rail(n_joints=5, arm_length=10.0)
    check_environment(env)
    cfg = saggriac.Config.from_preset("exp1", n_joints=5, arm_length=10.0, goal_low=(-10.0,), goal_high=(10.0,), n_steps=3000, n_evals=2, n_test_goals=20, n_test_configs=10)
    res = saggriac.run(cfg, seed=0, environment=env, out_dir=tmp_path / "run")
    assert "goal_x" in res.goals.columns and "goal_y" not in res.goals.columns
    assert np.all(np.isfinite(res.reach_error)) and res.reach_error[-1] < 0.5 * res.reach_error[0], res.reach_error
    # Its goal histograms are plain 1-D histograms.
    from saggriac.analysis import plots

    out = plots.plot_goal_histograms(tmp_path / "run", tmp_path / "goals.png")
    assert out.stat().st_size > 10_000
