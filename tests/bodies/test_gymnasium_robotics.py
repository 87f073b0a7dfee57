"""saggriac's teachers on Gymnasium-Robotics' own goal environments (issue 25): a goal that is
not applied is refused, the environment's own success flags are not read as the teacher's, and a
teacher that does not fit the environment is an error before training. Skipped when
Gymnasium-Robotics is not installed (the test extra brings it), unless SAGGRIAC_REQUIRE_EXTRAS=1
(CI sets it)."""

import os

import numpy as np
import pytest

if os.environ.get("SAGGRIAC_REQUIRE_EXTRAS") != "1":
    pytest.importorskip("gymnasium_robotics", reason='Gymnasium-Robotics is not installed (pip install ".[test]")')

import gymnasium  # noqa: E402
import gymnasium_robotics  # noqa: E402

import saggriac as sg  # noqa: E402
from saggriac.errors import ConformanceError, ParameterError  # noqa: E402
from saggriac.adapters.gym import GoalArmEnv, GoalSlot, SelectorGoals, VectorSelectorGoals  # noqa: E402

gymnasium.register_envs(gymnasium_robotics)
MAZE = "PointMaze_UMaze-v3"


def teacher(dim=2, seed=0):
    return sg.RandomSelector([-1.0] * dim, [1.0] * dim, seed=seed)


def test_pointmaze_ignores_options_goal_and_the_wrapper_says_so():
    w = SelectorGoals(gymnasium.make(MAZE), teacher())
    with pytest.raises(ConformanceError, match="goal_cell"):
        w.reset(seed=0)


def test_pointmaze_through_a_vector_env_and_goalslot_is_refused_too():
    envs = gymnasium.vector.SyncVectorEnv([lambda: GoalSlot(gymnasium.make(MAZE))] * 2)
    w = VectorSelectorGoals(envs, teacher())
    with pytest.raises(ConformanceError, match="does not take goals that way"):
        w.reset(seed=0)


def test_observation_route_pursues_the_teachers_goal_and_flags_its_success():
    w = SelectorGoals(gymnasium.make(MAZE), teacher(), goal_via="observation", success=0.45)
    obs, info = w.reset(seed=0)
    goal = obs["desired_goal"].copy()
    assert "success_env_goal" in info and info["is_success"] == info["success"] == bool(np.linalg.norm(obs["achieved_goal"] - goal) <= 0.45)
    told = 0
    for _ in range(400):
        obs, reward, terminated, truncated, info = w.step(w.action_space.sample())
        np.testing.assert_array_equal(obs["desired_goal"], goal)
        assert "success_env_goal" in info
        # The teacher's goal's flag (SB3's success rate reads is_success), by PointMaze's own rule.
        assert info["is_success"] == info["success"] == bool(np.linalg.norm(obs["achieved_goal"] - goal) <= 0.45)
        assert reward == w.unwrapped.compute_reward(obs["achieved_goal"], goal, info)
        if terminated or truncated:
            told += 1
            assert "competence" in info
            break
    assert told == 1
    assert w.selector.history()["told_goal"].tolist() == [goal.tolist()]


def test_observation_route_without_a_success_rule_is_named_not_silent():
    """PointMaze reports success for its own goal and has no distance_threshold: the wrapper cannot
    tell the teacher's goal's success, and says which parameter decides it."""
    w = SelectorGoals(gymnasium.make(MAZE), teacher(), goal_via="observation")
    with pytest.raises(ConformanceError, match="success=the distance"):
        w.reset(seed=0)
    w = SelectorGoals(gymnasium.make(MAZE), teacher(), goal_via="observation", success=False)
    _, info = w.reset(seed=0)
    assert "is_success" not in info and "success" not in info and "success_env_goal" in info
    w = SelectorGoals(gymnasium.make(MAZE), teacher(), goal_via="observation", success=lambda a, d: True)
    assert w.reset(seed=0)[1]["is_success"] is True
    for bad in (0, -1.0, float("nan"), "0.45", True):
        with pytest.raises(ParameterError, match="'success' parameter of SelectorGoals"):
            SelectorGoals(gymnasium.make(MAZE), teacher(), goal_via="observation", success=bad)


def test_observation_route_reads_a_distance_threshold_where_the_env_has_one():
    env = GoalArmEnv(distance_threshold=2.0)
    w = SelectorGoals(env, sg.RandomSelector([49.0, -1.0], [50.0, 1.0], seed=0), goal_via="observation")
    obs, info = w.reset(seed=0)
    d = float(np.linalg.norm(obs["achieved_goal"] - obs["desired_goal"]))
    assert info["is_success"] == (d <= 2.0) and "is_success_env_goal" in info


def test_a_teacher_of_another_dimension_is_refused_before_training():
    with pytest.raises(ParameterError, match="3 dimension"):
        SelectorGoals(gymnasium.make(MAZE), teacher(dim=3), goal_via="observation")
    envs = gymnasium.vector.SyncVectorEnv([lambda: GoalSlot(GoalArmEnv())] * 2)
    with pytest.raises(ParameterError, match="desired_goal has shape"):
        VectorSelectorGoals(envs, teacher(dim=3))


def test_a_teacher_box_beyond_the_environments_goal_box_is_refused():
    env = GoalArmEnv(goal_low=(0.0, -50.0), goal_high=(50.0, 50.0))
    with pytest.raises(ParameterError, match="leaves the environment's desired_goal bounds"):
        SelectorGoals(env, sg.RandomSelector([0.0, -50.0], [60.0, 50.0]))


def test_a_teacher_without_a_box_giving_a_wrong_goal_is_named():
    class Loose:
        def sample(self):
            return np.zeros(3)

        def update(self, goal, competence):
            pass

    w = SelectorGoals(GoalArmEnv(), Loose())
    with pytest.raises(ConformanceError, match="sample\\(\\) gave"):
        w.reset(seed=0)


def test_goalslot_observation_route_takes_the_next_goal_and_names_its_parameters():
    slot = GoalSlot(gymnasium.make(MAZE), goal_via="observation", success=0.45)
    own = slot.reset(seed=0)[0]["desired_goal"]  # no next goal: the environment's own
    np.testing.assert_array_equal(own, slot.unwrapped.goal)
    slot.set_next_goal(np.array([0.5, -0.5]))
    obs, info = slot.reset(seed=0)
    np.testing.assert_array_equal(obs["desired_goal"], [0.5, -0.5])
    assert info["distance"] == pytest.approx(np.linalg.norm(obs["achieved_goal"] - [0.5, -0.5]))
    obs, reward, *_ = slot.step(np.zeros(2))
    assert reward == slot.unwrapped.compute_reward(obs["achieved_goal"], np.array([0.5, -0.5]), {})
    with pytest.raises(ParameterError, match="'goal_via' parameter of GoalSlot"):
        GoalSlot(gymnasium.make(MAZE), goal_via="obs")
    with pytest.raises(ParameterError, match="'success' parameter of GoalSlot"):
        GoalSlot(gymnasium.make(MAZE), goal_via="observation", success=-1.0)
    slot = GoalSlot(gymnasium.make(MAZE), goal_via="observation")
    slot.set_next_goal(np.array([0.5, -0.5]))
    with pytest.raises(ConformanceError, match="success=the distance"):
        slot.reset(seed=0)
