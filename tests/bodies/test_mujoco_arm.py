"""The MuJoCo extra: a serial arm of a MuJoCo model as a saggriac body.

Skipped when MuJoCo is not installed, unless SAGGRIAC_REQUIRE_EXTRAS=1 (CI sets it)."""

import os

import numpy as np
import pytest

if os.environ.get("SAGGRIAC_REQUIRE_EXTRAS") != "1":
    pytest.importorskip("mujoco", reason='the MuJoCo extra is not installed (pip install "saggriac[mujoco]")')

import mujoco

import saggriac as sg
from saggriac.bodies.mujoco_arm import PUSHER_JOINTS, MujocoArm, pusher_arm, pusher_model_path
from saggriac.testing import check_environment


def test_the_pusher_arm_is_a_conforming_body():
    arm = pusher_arm()
    check_environment(arm)
    assert arm.joint_space.shape == (7,) and arm.joint_names == PUSHER_JOINTS


def test_the_repr_says_which_joints_move_which_end_effector():
    assert repr(pusher_arm()) == f"MujocoArm(joints={list(PUSHER_JOINTS)!r}, end_effector='tips_arm' (body), max_joint_step=0.02, model with 11 joints)"


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


# A model with what the Pusher lacks: tilted frames, off-centre hinges, two chosen joints in one
# body, a joint left out (at a qpos0 that is not 0), fixed bodies between joints, a site as the
# end effector and a joint whose qpos0 (ref) is not 0.
TWISTED = """
<mujoco>
  <worldbody>
    <body name="base" pos="0.1 0.2 0.3" quat="0.9 0.1 0.2 0.3">
      <geom size="0.02"/>
      <joint name="j0" type="hinge" axis="0 0 1" range="-1 1" pos="0.05 0 0"/>
      <body name="b1" pos="0.3 0 0" euler="0.3 0.2 0.1">
        <geom size="0.02"/>
        <joint name="j1" type="hinge" axis="0 1 1" range="-2 0.5"/>
        <joint name="left_out" type="hinge" axis="0 0 1" range="-1 1" ref="0.4"/>
        <joint name="j2" type="hinge" axis="1 0 0" range="-0.5 1.5" pos="0 0.02 0"/>
        <body name="fixed" pos="0 0 0.2" euler="0.5 0 -0.3">
          <body name="b3" pos="0.2 0 0">
            <geom size="0.02"/>
            <joint name="j3" type="hinge" axis="0 1 0" range="-1 1.2" ref="0.3" pos="0.01 0 0.01"/>
            <site name="tip" pos="0.1 0.05 -0.02"/>
          </body>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


def twisted_arm():
    return MujocoArm(mujoco.MjModel.from_xml_string(TWISTED), ("j0", "j1", "j2", "j3"), "tip")


@pytest.mark.parametrize("make", [pusher_arm, twisted_arm])
def test_the_native_chain_moves_as_mujoco_computes(make):
    arm = make()
    chain = arm.chain()
    rng = np.random.default_rng(1)
    thetas = rng.uniform(-1, 1, (300, len(arm.theta)))
    native = sg._core.chain_forward(list(chain), thetas)
    assert np.abs(native - np.array([arm.forward(t) for t in thetas])).max() < 1e-12
    # Scaled, and with the first joint's body moved to the origin.
    base = arm.forward(np.zeros(len(arm.theta))) - sg._core.chain_forward(list(chain), np.zeros((1, len(arm.theta))))[0]
    moved = sg._core.chain_forward(list(arm.chain(scale=100.0, at_origin=True)), thetas)
    offset = arm.model.body_pos[arm.model.jnt_bodyid[mujoco.mj_name2id(arm.model, mujoco.mjtObj.mjOBJ_JOINT, arm.joint_names[0])]]
    assert np.abs(base).max() < 1e-12
    assert np.abs(moved - 100.0 * (native - offset)).max() < 1e-9


def test_the_pusher_preset_is_the_model_scaled_to_reach_50():
    from saggriac.bodies import PUSHER_CHAIN
    from saggriac.bodies.mujoco_arm import pusher_chain

    assert np.allclose(PUSHER_CHAIN, pusher_chain(), rtol=0, atol=1e-12)
    cfg = sg.Config.from_preset("pusher")
    assert cfg.joints == 7 and abs(cfg.reach - 50.0) < 1e-12


def test_a_native_run_and_a_run_through_mujoco_see_the_same_test_set():
    arm = twisted_arm()
    cfg = sg.Config(body="chain", chain=arm.chain(), joint_limit=1.0, max_joint_step=0.02, goal_low=(-1.0, -1.0, -1.0), goal_high=(1.0, 1.0, 1.0), n_steps=300, n_evals=1, v=0.01, n_test_goals=10, n_test_configs=10)
    native = sg.run(cfg, seed=4)
    through = sg.run(cfg, seed=4, environment=arm)
    # The same goals and configurations; positions measured by MuJoCo in one, natively in the other.
    assert np.isclose(native.metrics["pred_error"].iloc[0], through.metrics["pred_error"].iloc[0], rtol=1e-9)
    assert np.isclose(native.metrics["reach_error"].iloc[0], through.metrics["reach_error"].iloc[0], rtol=1e-9)


@pytest.mark.parametrize(
    "call, param",
    [
        (lambda a: a.chain(scale=0.0), "scale"),
        (lambda a: a.chain(at_origin="yes"), "at_origin"),
        (lambda a: MujocoArm(a.model, ("j1", "j0"), "tip").chain(), "joints"),
        (lambda a: MujocoArm(a.model, ("j0", "j3"), "b1").chain(), "end_effector"),  # refused when the arm is made, before chain()
    ],
)
def test_chain_refusals_are_named(call, param):
    with pytest.raises(sg.ParameterError) as e:
        call(twisted_arm())
    assert e.value.param == param


def _asset(name):
    import gymnasium

    return os.path.join(os.path.dirname(gymnasium.__file__), "envs", "mujoco", "assets", name)


def test_an_unlimited_hinge_takes_a_stated_range():
    with pytest.raises(sg.ParameterError, match="no range in the model"):
        MujocoArm(_asset("reacher.xml"), ["joint0", "joint1"], "fingertip")
    arm = MujocoArm(_asset("reacher.xml"), ["joint0", "joint1"], "fingertip", ranges={"joint0": (-3.0, 3.0)})
    assert arm.low.tolist()[0] == -3.0 and arm.high.tolist()[0] == 3.0
    check_environment(arm)
    # theta = +-1 is the stated range's end.
    _, x = arm.reset(options={"theta": [1.0, 0.0]})
    np.testing.assert_allclose(arm.joint_angles([1.0, 0.0])[0], 3.0)
    for bad in ({"joint9": (0, 1)}, {"joint0": (1.0, -1.0)}, {"joint0": (0, float("inf"))}, {"joint0": "wide"}, [("joint0", (0, 1))]):
        with pytest.raises(sg.ParameterError, match="ranges"):
            MujocoArm(_asset("reacher.xml"), ["joint0", "joint1"], "fingertip", ranges=bad)


@pytest.mark.parametrize("model, joints, ee", [("half_cheetah.xml", ["bthigh", "fthigh"], "bfoot"), ("ant.xml", ["hip_1", "ankle_1"], "front_left_leg")])
def test_an_end_effector_that_a_chosen_joint_does_not_move_is_refused(model, joints, ee):
    with pytest.raises(sg.ParameterError, match="does not move when the joints"):
        MujocoArm(_asset(model), joints, ee)
