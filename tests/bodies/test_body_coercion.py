"""Round 3 of 'nothing silently wrong' for bodies (issue 33, item 7): Gymnasium actions and a
Python environment's values must be numbers, a Python environment must keep its joints within
its joint_space, and a placement beyond the limits is refused rather than clipped without a word."""

import math

import gymnasium
import numpy as np
import pytest

import saggriac
import saggriac.adapters.gym as sgym
from saggriac.bodies.environments import PlanarArm
from saggriac.errors import InputError


def small(**kw):
    return saggriac.Config.from_preset("exp1", **{"n_steps": 1500, "n_evals": 3, "n_test_goals": 10, "n_test_configs": 10, **kw})


@pytest.mark.parametrize("make", [lambda: sgym.GoalArmEnv(), lambda: gymnasium.make("saggriac/PlanarArm-v0")])
@pytest.mark.parametrize("action", [["0.01"] * 15, [True] * 15, np.array(["0"] * 15), [None] * 15])
def test_gymnasium_step_refuses_text_and_bools(make, action):
    env = make()
    env.reset(seed=0)
    before = env.unwrapped._theta.copy()
    with pytest.raises(InputError, match="strings and bools are refused"):
        env.step(action)
    np.testing.assert_array_equal(env.unwrapped._theta, before)


@pytest.mark.parametrize("action", [[0.01] * 15, np.full(15, 0.01, dtype=np.float32), [np.float64(0.01)] * 15, [0] * 15, np.zeros(15, dtype=np.int64)])
def test_gymnasium_step_takes_numbers_of_every_kind_alike(action):
    a, b = sgym.GoalArmEnv(), sgym.GoalArmEnv()
    a.reset(seed=0)
    b.reset(seed=0)
    oa = a.step(np.asarray(action, dtype=np.float64))[0]
    ob = b.step(action)[0]
    np.testing.assert_array_equal(oa["observation"], ob["observation"])


def test_gymnasium_reset_theta_beyond_the_limits_is_refused():
    env = sgym.GoalArmEnv()
    with pytest.raises(InputError, match=r"joint limits \[-1.5708, 1.5708\]; joint 0 is 10"):
        env.reset(seed=0, options={"theta": [10.0] * 15})
    with pytest.raises(InputError, match="strings and bools"):
        env.reset(seed=0, options={"theta": ["0"] * 15})
    # At the limit (and within float32 rounding of it) is taken.
    obs, _ = env.reset(seed=0, options={"theta": [np.float32(math.pi / 2)] * 15})
    assert np.all(np.abs(obs["observation"]) <= math.pi / 2)


def test_gym_body_reset_theta_beyond_the_limits_is_refused():
    env = gymnasium.make("saggriac/PlanarArm-v0")
    body = sgym.GymBody(env, theta=lambda e, o: o["observation"], position=lambda e, o: o["achieved_goal"], joint_limit=math.pi / 2, max_joint_step=0.05, reach=50.0)
    with pytest.raises(InputError, match=r"GymBody.reset.*joint limits.*joint 3 is -4"):
        body.reset(options={"theta": [0.0] * 3 + [-4.0] + [0.0] * 11})
    theta, _ = body.reset(options={"theta": [0.5] * 15})
    np.testing.assert_allclose(theta, 0.5)


@pytest.mark.parametrize("shapes", [((5, 2), (4, 2)), ((5, 2), (5, 3)), ((3,), (2,)), ((2, 5, 2), (2, 5, 2))])
def test_compute_reward_names_both_shapes(shapes):
    env = sgym.GoalArmEnv()
    a, g = np.zeros(shapes[0]), np.ones(shapes[1])
    with pytest.raises(InputError, match=rf"achieved_goal of shape \({shapes[0][0]},.*desired_goal of shape \({shapes[1][0]},"):
        env.compute_reward(a, g, {})


def test_compute_reward_takes_points_and_batches():
    env = sgym.GoalArmEnv(reward_type="dense")
    assert env.compute_reward([3.0, 4.0], [0.0, 0.0], {}) == pytest.approx(-5.0)
    np.testing.assert_allclose(env.compute_reward(np.zeros((4, 2)), np.full((4, 2), 3.0), {}), -np.full(4, math.hypot(3, 3)))
    np.testing.assert_allclose(env.compute_reward(np.zeros((4, 2)), [3.0, 4.0], [{}] * 4), -np.full(4, 5.0))


class Returns(PlanarArm):
    """A Python arm that, from its step number ``at`` on, returns ``what`` in place of theta or x."""

    def __init__(self, at, what, **kw):
        super().__init__(**kw)
        self.at, self.what, self.n = at, what, 0

    def step(self, dtheta):
        self.n += 1
        theta, x = super().step(dtheta)
        if self.n >= self.at:
            if self.what == "strings":
                x = [str(v) for v in x]
            elif self.what == "bools":
                theta = [True] * len(theta)
            elif self.what == "beyond":
                theta = theta.copy()
                theta[2] = self.joint_limit + 10.0
        return theta, x


@pytest.mark.parametrize(
    "what, message",
    [
        ("strings", r"x returned by environment.step\(\) must be an array of 2 numbers .*strings and bools are refused.*time step \d+"),
        ("bools", r"theta returned by environment.step\(\) must be an array of 15 numbers .*time step \d+"),
        ("beyond", r"theta returned by environment.step\(\) must stay within the joint limits \[-1.5708, 1.5708\].*joint 2 is 11.57.*time step \d+"),
    ],
)
def test_a_python_environment_returning_nonsense_is_refused_at_that_step(tmp_path, what, message):
    with pytest.raises(InputError, match=message) as e:
        saggriac.run(small(), seed=0, environment=Returns(300, what), out_dir=tmp_path / "run")
    assert not (tmp_path / "run").exists()
    step = int(e.value.args[0].split("time step ")[1].split(";")[0])
    assert 290 <= step <= 310


def test_a_python_arm_at_its_limits_runs_as_the_builtin_arm():
    cfg = small(n_steps=600, joint_limit=0.3)
    python = saggriac.run(cfg, seed=1, environment=PlanarArm(joint_limit=0.3))
    builtin = saggriac.run(cfg, seed=1)
    np.testing.assert_array_equal(python.metrics["reach_error"], builtin.metrics["reach_error"])
