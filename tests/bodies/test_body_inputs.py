"""Bodies check their inputs: Python arms refuse bad actions and parameters, the MuJoCo arm
refuses duplicate joints, a run refuses a body that ignores placement, a goal environment
refuses a goal outside its box. From the third newcomer audit (issue 27)."""

from __future__ import annotations

import numpy as np
import pytest

import saggriac
from saggriac import Config
from saggriac.errors import InputError, ParameterError


@pytest.mark.parametrize("make", [lambda: saggriac.bodies.environments.PlanarArm(), lambda: saggriac.bodies.environments.SpatialArm(n_joints=6), lambda: saggriac.bodies.environments.PlanarArm(link_lengths=[1.0, 2.0])])
@pytest.mark.parametrize("action", ["short", "long", "nan", "inf", "strings", "bools"])
def test_python_arms_refuse_bad_actions_and_keep_their_state(make, action):
    arm = make()
    n = len(arm.theta)
    arm.reset(options={"theta": np.full(n, 0.1)})
    before = (arm.theta.copy(), arm.forward(arm.theta))
    value = {"short": np.zeros(max(1, n - 1)), "long": np.zeros(n + 3), "nan": np.full(n, np.nan), "inf": np.full(n, np.inf), "strings": ["0.1"] * n, "bools": [True] * n}[action]
    with pytest.raises(InputError, match=f"{n} finite floats"):
        arm.step(value)
    with pytest.raises(InputError):
        arm.reset(options={"theta": value})
    np.testing.assert_array_equal(arm.theta, before[0])
    theta, x = arm.step(np.zeros(n))
    np.testing.assert_array_equal(x, before[1])


@pytest.mark.parametrize("kw", [dict(n_joints=0), dict(n_joints=2.5), dict(arm_length=-1.0), dict(arm_length=float("nan")), dict(link_lengths=[]), dict(link_lengths=[1.0, -1.0]), dict(joint_limit=0.0), dict(max_joint_step=float("inf"))])
def test_python_arms_check_their_parameters(kw):
    with pytest.raises(ParameterError):
        saggriac.bodies.environments.PlanarArm(**kw)


def test_mujoco_arm_refuses_duplicate_joints_and_bad_actions():
    mj = pytest.importorskip("saggriac.bodies.mujoco_arm")
    with pytest.raises(ParameterError, match="more than once"):
        mj.MujocoArm(mj.pusher_model_path(), [mj.PUSHER_JOINTS[0], mj.PUSHER_JOINTS[1], mj.PUSHER_JOINTS[0]], "tips_arm")
    arm = mj.pusher_arm()
    with pytest.raises(InputError, match="7 finite floats"):
        arm.step(np.zeros(3))
    assert arm.step(np.zeros(7))[0].shape == (7,)


class _IgnoresPlacement(saggriac.bodies.environments.PlanarArm):
    def reset(self, *, seed=None, options=None):
        return super().reset(seed=seed)


class _ClaimsPlacement(saggriac.bodies.environments.PlanarArm):
    def reset(self, *, seed=None, options=None):
        theta, x = super().reset(seed=seed)
        return (np.asarray(options["theta"], dtype=float) if options else theta), x


@pytest.mark.parametrize("env", [_IgnoresPlacement, _ClaimsPlacement])
def test_run_refuses_a_body_that_ignores_placement(env, tmp_path):
    cfg = Config.from_preset("exp1", n_steps=200, n_evals=1, n_test_goals=3, n_test_configs=3)
    with pytest.raises(saggriac.errors.ConformanceError, match="options=\\{'theta'"):
        saggriac.run(cfg, 0, environment=env(), out_dir=tmp_path / "r")
    assert not (tmp_path / "r").exists()


def test_goal_env_refuses_a_goal_outside_its_box():
    gym = pytest.importorskip("gymnasium")
    import saggriac.adapters.gym  # noqa: F401 (registers the environments)

    env = gym.make("saggriac/PlanarArmExp1-v0")
    with pytest.raises(InputError, match="outside the environment's goal box"):
        env.reset(options={"goal": [1e6, 1e6]})
    obs, _ = env.reset(options={"goal": [10.0, 10.0]})
    assert env.observation_space.contains(obs)
