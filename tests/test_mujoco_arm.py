"""The MuJoCo extra: a serial arm of a MuJoCo model as a saggriac body.

Skipped when MuJoCo is not installed, unless SAGGRIAC_REQUIRE_EXTRAS=1 (CI sets it)."""

import os

import numpy as np
import pytest

if os.environ.get("SAGGRIAC_REQUIRE_EXTRAS") != "1":
    pytest.importorskip("mujoco", reason='the MuJoCo extra is not installed (pip install "saggriac[mujoco]")')

import mujoco

import saggriac as sg
from saggriac.mujoco_arm import PUSHER_JOINTS, MujocoArm, pusher_arm, pusher_model_path
from saggriac.testing import check_environment


def test_the_pusher_arm_is_a_conforming_body():
    arm = pusher_arm()
    check_environment(arm)
    assert arm.joint_space.shape == (7,) and arm.joint_names == PUSHER_JOINTS


def test_joints_and_limits_come_from_the_model_and_mujoco_computes_the_tip():
    arm = pusher_arm()
    model = mujoco.MjModel.from_xml_path(pusher_model_path())
    data = mujoco.MjData(model)
    rng = np.random.default_rng(0)
    for _ in range(20):
        theta = rng.uniform(-1, 1, 7)
        _, x = arm.reset(options={"theta": theta})
        q = np.empty(7)
        for i, name in enumerate(PUSHER_JOINTS):
            lo, hi = model.joint(name).range
            q[i] = lo + (theta[i] + 1) / 2 * (hi - lo)
            data.qpos[model.joint(name).qposadr[0]] = q[i]
        mujoco.mj_kinematics(model, data)
        assert np.allclose(x, data.body("tips_arm").xpos, atol=1e-12)
    # theta = -1 and 1 are the model's limits
    lo = np.array([model.joint(n).range[0] for n in PUSHER_JOINTS])
    assert np.allclose(arm.joint_angles(-np.ones(7)), lo)


def test_steps_are_bounded_in_range_units_and_deterministic():
    a, b = pusher_arm(max_joint_step=0.02), pusher_arm(max_joint_step=0.02)
    a.reset()
    b.reset()
    rng = np.random.default_rng(1)
    for _ in range(50):
        d = rng.uniform(-0.1, 0.1, 7)
        ta, xa = a.step(d)
        tb, xb = b.step(d)
        assert np.array_equal(ta, tb) and np.array_equal(xa, xb)
    t0, _ = a.reset()
    t1, _ = a.step(np.array([0.1, 0, 0, 0, 0, 0, 0.05]))
    assert np.allclose(t1 - t0, [0.02, 0, 0, 0, 0, 0, 0.01])


def test_a_short_run_learns_on_the_pusher_arm():
    cfg = sg.Config.from_preset("arm3d", n_joints=7, joint_limit=1.0, max_joint_step=0.02, arm_length=1.0, goal_low=(-1.0, -2.0, -1.0), goal_high=(1.5, 1.0, 1.0), n_steps=1500, n_evals=2, n_test_goals=8, n_test_configs=8)
    res = sg.run(cfg, seed=0, environment=pusher_arm())
    assert res.reach_error[-1] < res.reach_error[0]


@pytest.mark.parametrize(
    "kwargs,param",
    [({"joints": ("elbow",)}, "joints"), ({"joints": ("obj_slidey",)}, "joints"), ({"end_effector": "hand"}, "end_effector"), ({"max_joint_step": 2.0}, "max_joint_step"), ({"joints": ()}, "joints")],
)
def test_bad_parameters_are_named(kwargs, param):
    args = dict(model=pusher_model_path(), joints=PUSHER_JOINTS, end_effector="tips_arm") | kwargs
    with pytest.raises(sg.ParameterError) as e:
        MujocoArm(**args)
    assert e.value.param == param
