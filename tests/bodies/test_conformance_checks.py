"""What a run and the conformance checks refuse of the parts a user brings: placements beyond the
joint limits (refused, as GoalArmEnv and GymBody refuse them, not clipped), a body deaf to step(),
and a teacher of task indices given to a run (newcomer-audit-5 findings 9 and 10)."""

import math
import os

import numpy as np
import pytest

import saggriac as sg
from saggriac.bodies import PlanarArm, SpatialArm
from saggriac.errors import ConformanceError, InputError, ParameterError
from saggriac.testing import check_environment

CFG = sg.Config.from_preset("exp1", n_steps=300, n_test_goals=10, n_test_configs=10, n_evals=2)


@pytest.mark.parametrize("body", [PlanarArm, SpatialArm])
def test_a_placement_beyond_the_joint_limits_is_refused_naming_the_value_and_the_limit(body):
    arm = body()
    before = arm.theta.copy()
    with pytest.raises(InputError, match=r"reset\(options=\{'theta': \.\.\.\}\) must lie within the joint limits \[-1\.5708, 1\.5708\]; joint 0 is 10 \(15 joint\(s\) beyond\)"):
        arm.reset(options={"theta": [10] * 15})
    theta = [0.0] * 15
    theta[3] = -1.6
    with pytest.raises(InputError, match=r"joint 3 is -1\.6 \(1 joint\(s\) beyond\)"):
        arm.reset(options={"theta": theta})
    np.testing.assert_array_equal(arm.theta, before)  # refused before the state changes


@pytest.mark.parametrize("body", [PlanarArm, SpatialArm])
def test_a_placement_at_the_limits_is_taken_and_a_float32_rounding_is_clipped(body):
    arm = body(n_joints=3, joint_limit=1.0)
    np.testing.assert_array_equal(arm.reset(options={"theta": [1.0, -1.0, 0.5]})[0], [1.0, -1.0, 0.5])
    np.testing.assert_array_equal(arm.reset(options={"theta": np.float32([1.0, -1.0, 0.5]) * np.float32(1.0000001)})[0][:2], [1.0, -1.0])


def test_a_mujoco_arm_refuses_a_placement_beyond_its_range_too():
    if os.environ.get("SAGGRIAC_REQUIRE_EXTRAS") != "1":
        pytest.importorskip("mujoco", reason='the MuJoCo extra is not installed (pip install "saggriac[mujoco]")')
    from saggriac.bodies.mujoco_arm import pusher_arm

    arm = pusher_arm()
    with pytest.raises(InputError, match=r"MujocoArm.reset\(options=\{'theta': \.\.\.\}\) must lie within the joint limits \[-1, 1\]; joint 6 is 2 "):
        arm.reset(options={"theta": [0.0] * 6 + [2.0]})


class Frozen(PlanarArm):
    """Placed by reset, deaf to step (the audit's SC-stepfrozen)."""

    def step(self, dtheta):
        return self.theta.copy(), self.forward(self.theta)


def test_a_body_that_ignores_step_is_refused_by_run_and_by_check_environment():
    with pytest.raises(ConformanceError, match=r"environment.step\(dtheta\) must move the joints.*the body seems to ignore step\(\)"):
        sg.run(CFG, 0, environment=Frozen(), threads=1)
    with pytest.raises(ConformanceError, match=r"environment.step\(dtheta\) must move the joints"):
        check_environment(Frozen())


def test_an_episodic_run_never_steps_the_body_so_a_frozen_one_is_taken():
    sg.run(CFG.replace(paradigm="episodic"), 0, environment=Frozen(), threads=1)


class Stiff(PlanarArm):
    """Moves only while every joint is well inside its limits: the check steps from a placement
    a quarter of the range away from them, so such a body passes."""

    def step(self, dtheta):
        if np.any(np.abs(self.theta) > 0.9 * self.joint_limit):
            return self.theta.copy(), self.forward(self.theta)
        return super().step(dtheta)


@pytest.mark.parametrize(
    "body, cfg",
    [
        (PlanarArm(), CFG),
        (SpatialArm(), CFG.replace(body="spatial_arm", goal_low=(-50.0,) * 3, goal_high=(50.0,) * 3)),
        (PlanarArm(n_joints=2, joint_limit=math.pi), CFG.replace(n_joints=2, joint_limit=math.pi)),
        (Stiff(), CFG),
    ],
    ids=["planar", "spatial", "planar-2-joints-pi", "stiff"],
)
def test_the_python_arms_still_pass_and_still_run(body, cfg):
    check_environment(body)
    sg.run(cfg, 0, environment=body, threads=1)


def test_the_step_check_changes_no_result():
    # The check moves the body before the run resets it with the run's seed: the run of the
    # Python arm is still the built-in arm's, bit for bit.
    a = sg.run(CFG, 3, threads=1)
    b = sg.run(CFG, 3, environment=PlanarArm(), threads=1)
    np.testing.assert_array_equal(a.reach_error, b.reach_error)


@pytest.mark.parametrize("teacher, name", [(sg.PlrSelector(4), "plr"), (sg.DiscreteLpSelector(3), "discrete_lp")], ids=["plr", "discrete_lp"])
def test_a_run_refuses_a_teacher_of_task_indices_as_config_does(teacher, name):
    box = r"a teacher of goals in a box \(a run's goals are points of the goal space\)"
    with pytest.raises(ParameterError, match=box):
        CFG.replace(teacher=name)
    with pytest.raises(ParameterError, match=rf"The 'goal_selector' parameter of a run must be {box}\. Got {type(teacher).__name__}") as run_says:
        sg.run(CFG, 0, goal_selector=teacher, threads=1)
    assert "goal_low" not in str(run_says.value)  # no advice to make the goal space a range of indices


def test_an_episodic_run_with_refinement_places_the_python_arm_within_its_limits():
    cfg = sg.Config.from_preset("exp1", n_steps=3000, paradigm="episodic", episodic_refine=True)
    np.testing.assert_array_equal(sg.run(cfg, 0, threads=1).reach_error, sg.run(cfg, 0, environment=PlanarArm(), threads=1).reach_error)
