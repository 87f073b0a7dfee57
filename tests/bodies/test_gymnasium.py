"""The Gymnasium extra: registered goal environments, any Env as a body, selectors as teachers.

Skipped when Gymnasium is not installed, unless SAGGRIAC_REQUIRE_EXTRAS=1 (CI sets it): then a
missing extra fails."""

import math
import os

import numpy as np
import pytest

if os.environ.get("SAGGRIAC_REQUIRE_EXTRAS") != "1":
    pytest.importorskip("gymnasium", reason='the Gymnasium extra is not installed (pip install "saggriac[gymnasium]")')

import gymnasium
from gymnasium.utils.env_checker import check_env

import saggriac as sg
import saggriac.adapters.gym as sgym
from saggriac.testing import check_environment


@pytest.mark.parametrize("env_id", list(sgym.ENVIRONMENTS))
def test_registered_environments_pass_gymnasiums_checker(env_id):
    env = gymnasium.make(env_id)
    check_env(gymnasium.make(env_id, render_mode="rgb_array").unwrapped)
    obs, info = env.reset(seed=0)
    assert set(obs) == {"observation", "achieved_goal", "desired_goal"}
    assert env.observation_space.contains(obs)
    assert env.spec.max_episode_steps == sgym.MAX_EPISODE_STEPS


def test_module_prefixed_make_imports_the_registration_itself():
    env = gymnasium.make("saggriac.adapters.gym:saggriac/PlanarArmExp2-v0")
    assert env.unwrapped.goal_space.low.tolist() == [0.0, -150.0]


def test_an_episode_moves_the_arm_as_a_run_does_and_truncates():
    env = gymnasium.make("saggriac/PlanarArm-v0", action_scale="joint")
    obs, _ = env.reset(seed=1)
    arm = sg.bodies.environments.PlanarArm()
    arm.reset()
    rng = np.random.default_rng(0)
    for t in range(sgym.MAX_EPISODE_STEPS):
        a = rng.uniform(-0.08, 0.08, 15)  # beyond the bound: scaled down as in a run
        obs, reward, terminated, truncated, info = env.step(a)
        theta, x = arm.step(a)
        assert np.array_equal(obs["observation"], theta) and np.array_equal(obs["achieved_goal"], x)
        assert reward == (0.0 if info["is_success"] else -1.0)
        assert not terminated and truncated == (t == sgym.MAX_EPISODE_STEPS - 1)


def test_goals_come_from_options_then_next_goal_then_the_seeded_box():
    env = gymnasium.make("saggriac/PlanarArmExp1-v0").unwrapped
    a, _ = env.reset(seed=5)
    b, _ = env.reset(seed=5)
    assert np.array_equal(a["desired_goal"], b["desired_goal"])
    assert env.goal_space.contains(a["desired_goal"])
    obs, _ = env.reset(options={"goal": [10.0, 20.0], "theta": [0.1] * 15})
    assert obs["desired_goal"].tolist() == [10.0, 20.0] and np.allclose(obs["observation"], 0.1)
    env.next_goal = np.array([3.0, 4.0])
    assert env.reset()[0]["desired_goal"].tolist() == [3.0, 4.0]
    assert env.next_goal is None and env.reset()[0]["desired_goal"].tolist() != [3.0, 4.0]


def test_compute_reward_relabels_batches():
    env = gymnasium.make("saggriac/PlanarArm-v0", reward_type="dense").unwrapped
    achieved = np.array([[1.0, 2.0], [0.0, 0.0]])
    desired = np.array([[1.0, 2.0], [3.0, 4.0]])
    assert env.compute_reward(achieved, desired, None).tolist() == [0.0, -5.0]
    sparse = gymnasium.make("saggriac/PlanarArm-v0", distance_threshold=1.0).unwrapped
    assert sparse.compute_reward(achieved, desired + [[0.5, 0.0], [0.0, 0.0]], None).tolist() == [0.0, -1.0]


@pytest.mark.parametrize(
    "kwargs,param",
    [({"body": "arm"}, "body"), ({"n_joints": 0}, "n_joints"), ({"max_joint_step": -1}, "max_joint_step"), ({"goal_low": [0.0]}, "goal_low"), ({"reward_type": "shaped"}, "reward_type"), ({"distance_threshold": float("nan")}, "distance_threshold"), ({"render_mode": "ascii"}, "render_mode")],
)
def test_bad_parameters_are_named(kwargs, param):
    with pytest.raises(sg.ParameterError) as e:
        sgym.GoalArmEnv(**kwargs)
    assert e.value.param == param and param in str(e.value)


def test_bad_options_and_actions_are_refused_clearly():
    env = sgym.GoalArmEnv()
    with pytest.raises(sg.InputError, match="goall"):
        env.reset(options={"goall": [1.0, 2.0]})
    with pytest.raises(sg.InputError, match="options\\['goal'\\]"):
        env.reset(options={"goal": [1.0, float("nan")]})
    env.reset()
    with pytest.raises(sg.InputError, match="15 finite joint changes"):
        env.step(np.zeros(3))


def _arm_body(env_id="saggriac/PlanarArm-v0"):
    # GymBody's env.step route needs actions that are joint changes; the arm's reach is the
    # built-in arm's (50), declared as a user who knows it would.
    env = gymnasium.make(env_id, action_scale="joint").unwrapped
    return sgym.GymBody(env, theta=lambda e, o: o["observation"], position=lambda e, o: o["achieved_goal"], joint_limit=math.pi / 2, max_joint_step=0.05, reach=50.0)


def test_a_gym_body_says_what_it_wraps():
    assert repr(_arm_body()) == "GymBody(saggriac/PlanarArm-v0, joints=15, task_dim=2, joint_limit=1.5708, max_joint_step=0.05, moves by env.step, reach=50)"


def test_a_gymnasium_arm_as_a_body_learns_exactly_as_the_built_in_arm():
    body = _arm_body()
    check_environment(body)
    cfg = sg.Config.from_preset("exp1", n_steps=1500, n_evals=2, n_test_goals=10, n_test_configs=10, test_configs="uniform")
    through_gym = sg.run(cfg, seed=3, environment=_arm_body())
    built_in = sg.run(cfg, seed=3)
    assert through_gym.metrics.equals(built_in.metrics)
    assert through_gym.goals.equals(built_in.goals)


def _acrobot_body(limit=math.pi / 2):
    """Gymnasium's Acrobot (two links of length 1) moved kinematically: the joint angles are the
    first two entries of its state, the tip follows from the link lengths."""
    env = gymnasium.make("Acrobot-v1").unwrapped

    def tip(e, obs):
        t1, t2 = e.state[0], e.state[1]
        return [math.sin(t1) + math.sin(t1 + t2), -math.cos(t1) - math.cos(t1 + t2)]

    def set_joints(e, theta):
        e.state = np.array([theta[0], theta[1], 0.0, 0.0])
        return e._get_ob()

    return sgym.GymBody(env, theta=lambda e, obs: e.state[:2], position=tip, set_joints=set_joints, joint_limit=limit, max_joint_step=0.05)


def test_the_run_takes_the_joint_limit_from_the_body(tmp_path):
    """Given once, to GymBody: before, a Config left at exp1's pi/2 was refused for a body in
    [-pi, pi] ("must match the environment's joint_space")."""
    cfg = sg.Config.from_preset("exp1", n_joints=2, goal_low=(-2.0, -2.0), goal_high=(2.0, 2.0), n_steps=300, n_evals=2, n_test_goals=10, n_test_configs=10)
    res = sg.run(cfg, seed=0, environment=_acrobot_body(limit=math.pi), out_dir=tmp_path / "run")
    assert res.config.joint_limit == math.pi == sg.RunResult.load(tmp_path / "run").config.joint_limit
    learner = sg.Learner(cfg, seed=0, environment=_acrobot_body(limit=math.pi))
    assert learner.config.joint_limit == math.pi
    learner.run()
    assert learner.result().metrics.equals(res.metrics)


def test_one_of_gymnasiums_own_environments_as_a_body():
    body = _acrobot_body()
    check_environment(body)
    theta, x = body.reset(options={"theta": [0.3, -0.2]})
    assert np.allclose(theta, [0.3, -0.2]) and np.allclose(x, [math.sin(0.3) + math.sin(0.1), -math.cos(0.3) - math.cos(0.1)])
    theta2, _ = body.step([1.0, 0.5])  # scaled to the largest step, direction kept
    assert np.allclose(theta2 - theta, [0.05, 0.025])
    cfg = sg.Config.from_preset("exp1", n_joints=2, arm_length=2.0, goal_low=(-2.0, -2.0), goal_high=(2.0, 2.0), n_steps=2000, n_evals=2, n_test_goals=10, n_test_configs=10)
    res = sg.run(cfg, seed=0, environment=_acrobot_body())
    assert res.reach_error[-1] < res.reach_error[0]


def test_gym_body_refuses_bad_readers():
    env = gymnasium.make("saggriac/PlanarArm-v0").unwrapped
    with pytest.raises(sg.ParameterError, match="joint_limit"):
        sgym.GymBody(env, theta=lambda e, o: o["observation"], position=lambda e, o: o["achieved_goal"], joint_limit=0, max_joint_step=0.05)
    with pytest.raises(sg.InputError, match="position\\(\\)"):
        sgym.GymBody(env, theta=lambda e, o: o["observation"], position=lambda e, o: np.zeros(5), joint_limit=1.0, max_joint_step=0.05)


def _play(env, n_steps, rng, vector=False):
    infos = []
    for _ in range(n_steps):
        shape = env.action_space.shape
        _, _, _, _, info = env.step(rng.uniform(-0.05, 0.05, shape))
        infos.append(info)
    return infos


@pytest.mark.parametrize("goal_via", ["options", "observation"])
def test_a_selector_chooses_each_episodes_goal_and_is_told_its_competence(goal_via):
    base = gymnasium.make("saggriac/PlanarArmExp2-v0", max_episode_steps=30)
    sel = sg.SaggRiacSelector([0.0, -150.0], [150.0, 150.0], seed=4)
    env = sgym.SelectorGoals(base, sel, goal_via=goal_via)
    rng = np.random.default_rng(1)
    told = []
    for episode in range(5):
        obs, _ = env.reset(seed=episode)
        asked = sel.history()["asked_goal"][-1]
        assert np.array_equal(obs["desired_goal"], asked)
        start = obs["achieved_goal"].copy()
        for t in range(30):
            obs, reward, term, trunc, info = env.step(rng.uniform(-0.05, 0.05, 15))
            assert reward == float(base.unwrapped.compute_reward(obs["achieved_goal"], asked, info))
        assert trunc and "competence" in info
        assert info["competence"] == sg.competence(asked, obs["achieved_goal"], start)
        told.append(info["competence"])
    h = sel.history()
    assert h["told_competence"].tolist() == told and len(h["told_goal"]) == 5


@pytest.mark.parametrize("vector_cls", ["sync", "async"])
def test_vector_environments_ask_and_tell_in_batches(vector_cls):
    n, steps = 3, 25
    # The module prefix imports saggriac.adapters.gym (the registration) in AsyncVectorEnv's processes too.
    make = lambda: gymnasium.make("saggriac.adapters.gym:saggriac/PlanarArmExp1-v0", max_episode_steps=steps)  # noqa: E731
    venv = gymnasium.vector.SyncVectorEnv([make] * n) if vector_cls == "sync" else gymnasium.vector.AsyncVectorEnv([make] * n, context="spawn")
    sel = sg.SaggRiacSelector([0.0, -50.0], [50.0, 50.0], seed=2)
    env = sgym.VectorSelectorGoals(venv, sel)
    try:
        obs, _ = env.reset(seed=7)
        assert np.array_equal(obs["desired_goal"], sel.history()["asked_goal"][:n])
        rng = np.random.default_rng(0)
        comps, goals_seen = [], [obs["desired_goal"].copy()]
        for t in range(2 * steps + 1):  # two episodes each, and the step that resets
            obs, _, term, trunc, info = env.step(rng.uniform(-0.05, 0.05, (n, 15)))
            comps.append(info["competence"])
            if t == steps:  # the reset step: the second episodes' goals
                goals_seen.append(obs["desired_goal"].copy())
        c = np.array(comps)
        assert np.isfinite(c).sum() == 2 * n
        h = sel.history()
        assert len(h["told_goal"]) == 2 * n and len(h["asked_goal"]) == 3 * n
        assert np.array_equal(goals_seen[1], h["asked_goal"][n : 2 * n])
        assert np.array_equal(np.sort(c[np.isfinite(c)]), np.sort(h["told_competence"]))
    finally:
        env.close()


def test_wrappers_refuse_what_they_cannot_use():
    with pytest.raises(sg.ConformanceError, match="achieved_goal"):
        sgym.SelectorGoals(gymnasium.make("Acrobot-v1"), sg.RandomSelector([0.0], [1.0]))
    with pytest.raises(sg.ParameterError, match="goal_via"):
        sgym.SelectorGoals(gymnasium.make("saggriac/PlanarArm-v0"), sg.RandomSelector([-50.0, -50.0], [50.0, 50.0]), goal_via="info")
    with pytest.raises(sg.ParameterError, match="kind"):
        sgym.SelectorGoals(gymnasium.make("saggriac/PlanarArm-v0"), sg.RandomSelector([-50.0, -50.0], [50.0, 50.0]), competence="squared")
    same_step = gymnasium.vector.SyncVectorEnv([lambda: gymnasium.make("saggriac/PlanarArm-v0")], autoreset_mode=gymnasium.vector.AutoresetMode.SAME_STEP)
    with pytest.raises(sg.ParameterError, match="NEXT_STEP"):
        sgym.VectorSelectorGoals(same_step, sg.RandomSelector([-50.0, -50.0], [50.0, 50.0]))


def test_competence_is_eq7_as_in_a_run():
    assert sg.competence([10.0, 0.0], [8.0, 0.0], [0.0, 0.0]) == pytest.approx(-0.2, abs=1e-15)
    assert sg.competence([10.0, 0.0], [10.0, 0.3], [0.0, 0.0]) == 0.0  # within eps_c
    assert sg.competence([10.0, 0.0], [40.0, 0.0], [0.0, 0.0]) == -1.0  # clipped to min_c
    assert sg.competence([1.0], [1.5], [1.0]) == -1.0  # started on the goal, left it
    batch = sg.competence([[10.0, 0.0], [0.0, 10.0]], [[8.0, 0.0], [0.0, 5.0]], [[0.0, 0.0], [0.0, 0.0]])
    assert batch.tolist() == pytest.approx([-0.2, -0.5])
    assert sg.competence([10.0, 0.0], [5.0, 0.0], [9.0, 0.0], kind="absolute", reach=50.0) == pytest.approx(-0.1)
    with pytest.raises(sg.ParameterError, match="reach"):
        sg.competence([1.0], [0.0], [0.0], kind="absolute")
    with pytest.raises(sg.ParameterError, match="eps_c"):
        sg.competence([1.0], [0.0], [0.0], eps_c=-2.0)
    with pytest.raises(sg.InputError, match="shape"):
        sg.competence([[1.0, 2.0]], [[1.0, 2.0], [0.0, 0.0]], [[0.0, 0.0]])


def test_the_curriculum_example_runs():
    import subprocess
    import sys
    from pathlib import Path

    script = Path(__file__).resolve().parents[2] / "examples" / "gymnasium_curriculum.py"
    out = subprocess.run([sys.executable, str(script), "--envs", "4", "--episodes", "8"], capture_output=True, text=True, check=True).stdout
    lines = [ln for ln in out.splitlines() if "mean test error" in ln]
    assert [ln.split(":")[0].strip() for ln in lines] == ["sagg_riac", "random"]
    assert all(0 <= float(ln.split("error")[1].split()[0]) < 150 for ln in lines)


@pytest.mark.parametrize("env_id, shape", [("saggriac/PlanarArmExp2-v0", (480, 480, 3)), ("saggriac/SpatialArm-v0", (480, 960, 3))])
def test_rgb_array_renders_the_arm_and_the_goal(env_id, shape):
    env = gymnasium.make(env_id, render_mode="rgb_array")
    env.reset(seed=0)
    first = env.render()
    assert first.shape == shape and first.dtype == np.uint8
    assert len(np.unique(first.reshape(-1, 3), axis=0)) > 10  # more than a blank canvas
    for _ in range(30):
        env.step(env.action_space.high)
    assert not np.array_equal(first, env.render())  # the arm moved in the picture
    env.close()


def test_human_render_mode_runs_headless(monkeypatch):
    monkeypatch.setenv("MPLBACKEND", "Agg")
    env = gymnasium.make("saggriac/PlanarArm-v0", render_mode="human")
    env.reset(seed=0)
    assert env.step(env.action_space.sample())[0] is not None
    env.close()


def test_compute_terminated_and_truncated_as_goal_environments_have_them():
    env = gymnasium.make("saggriac/PlanarArm-v0").unwrapped
    obs, _ = env.reset(seed=0, options={"goal": [50.0, 0.0]})
    assert env.compute_terminated(obs["achieved_goal"], obs["desired_goal"], {}) is False
    assert env.compute_truncated(obs["achieved_goal"], obs["desired_goal"], {}) is False
    batch = np.zeros((4, 2))
    assert env.compute_terminated(batch, batch, [{}] * 4).tolist() == [False] * 4
    assert env.compute_truncated(batch, batch, [{}] * 4).shape == (4,)


class _ReadsGoalCell(gymnasium.Wrapper):
    """A goal environment that takes its goal elsewhere (as PointMaze reads options['goal_cell']):
    options['goal'] and next_goal are ignored."""

    def reset(self, *, seed=None, options=None):
        options = {k: v for k, v in (options or {}).items() if k != "goal"}
        self.env.unwrapped.next_goal = None
        return self.env.reset(seed=seed, options=options)


def test_a_goal_not_applied_is_an_error_not_a_silent_curriculum():
    env = _ReadsGoalCell(gymnasium.make("saggriac/PlanarArm-v0"))
    teacher = sg.SaggRiacSelector([0.0, -50.0], [50.0, 50.0], seed=0)
    with pytest.raises(sg.errors.ConformanceError, match="does not take goals that way"):
        sgym.SelectorGoals(env, teacher).reset(seed=0)
    assert len(teacher.history()["told_competence"]) == 0
    venv = gymnasium.vector.SyncVectorEnv([lambda: _ReadsGoalCell(gymnasium.make("saggriac/PlanarArm-v0")) for _ in range(2)])
    with pytest.raises(sg.errors.ConformanceError, match="sub-environment 0"):
        sgym.VectorSelectorGoals(venv, teacher).reset(seed=0)


def test_goal_via_observation_recomputes_the_end_test_for_the_teachers_goal():
    base = gymnasium.make("saggriac/PlanarArm-v0").unwrapped
    base.compute_terminated = lambda a, d, info: bool(np.linalg.norm(np.asarray(a) - np.asarray(d)) < 1.0)
    # The teacher's goal is where the arm rests: the first step ends the episode for that goal.
    teacher = sg.RandomSelector([49.9, -0.05], [50.0, 0.05], seed=0)
    env = sgym.SelectorGoals(base, teacher, goal_via="observation")
    env.reset(seed=0)
    assert env.step(np.zeros(15))[2] is True


def test_a_pickled_teacher_is_refused_only_while_another_process_uses_it(tmp_path):
    """A copy of a teacher (pickle keeps its identity) used through a wrapper in a second process
    is refused while the first process uses it; once that process has let it go (or never
    wrapped it), the copy is the only one in use and runs."""
    import copy
    import pickle
    import subprocess
    import sys

    teacher = sg.SaggRiacSelector([0.0, -50.0], [50.0, 50.0], seed=0)
    f = tmp_path / "teacher.pkl"
    f.write_bytes(pickle.dumps(teacher))
    child = tmp_path / "child.py"
    child.write_text(f"""
import pickle, gymnasium, saggriac.adapters.gym as sgym
t = pickle.load(open({str(f)!r}, "rb"))
try:
    sgym.SelectorGoals(gymnasium.make("saggriac/PlanarArm-v0"), t).reset(seed=0)
    print("ran")
except Exception as e:
    print(type(e).__name__, e)
""")

    def in_child() -> str:
        out = subprocess.run([sys.executable, str(child)], capture_output=True, text=True, timeout=120)
        assert out.returncode == 0, out.stderr
        return out.stdout

    assert in_child().startswith("ran")  # nobody else uses it: a restored teacher
    env = sgym.SelectorGoals(gymnasium.make("saggriac/PlanarArm-v0"), teacher)
    said = in_child()
    assert said.startswith("ConformanceError") and "saggriac.adapters.sb3.TeacherCallback" in said and f"pid {os.getpid()}" in said
    # In this process, a pickled copy is a second copy of the teacher in use (before 0.6 it was
    # taken as the same, and the two learnt apart); copy.deepcopy makes another teacher.
    with pytest.raises(sg.ConformanceError, match="another copy of the same teacher in this process"):
        sgym.SelectorGoals(gymnasium.make("saggriac/PlanarArm-v0"), pickle.loads(pickle.dumps(teacher)))
    other = copy.deepcopy(teacher)
    assert other._identity != teacher._identity and pickle.loads(pickle.dumps(teacher))._identity == teacher._identity
    np.testing.assert_array_equal(other.sample(), copy.deepcopy(teacher).sample())  # the same state
    del env, teacher
    import gc

    gc.collect()
    assert in_child().startswith("ran")  # this process let it go


def test_free_joints_turn_for_ever_where_limited_ones_fold():
    """joints="free": an arm with no limit to fold onto. Driving every joint one way folds the
    limited arm onto its limits, the tip fixed (the deep-RL study's fold); the free arm keeps
    turning, its angles in [-pi, pi), its tip where its forward kinematics puts it."""
    import math

    from saggriac.bodies.environments import PlanarArm

    GoalArmEnv = sgym.GoalArmEnv
    kw = dict(n_joints=3, arm_length=1.0, max_joint_step=0.2, goal_low=(-2.0, -2.0), goal_high=(2.0, 2.0))
    limited, free = GoalArmEnv(joint_limit=math.pi, **kw), GoalArmEnv(joints="free", **kw)
    tips = {}
    for name, env in (("limited", limited), ("free", free)):
        env.reset(options={"goal": [0.5, 0.0]})
        seen = []
        for _ in range(100):
            obs, *_ = env.step(np.ones(3, np.float32))
            assert env.observation_space.contains(obs)
            seen.append(obs["achieved_goal"])
        tips[name] = np.array(seen)
    assert np.allclose(tips["limited"][-20:], [-1 / 3, 0.0])
    assert np.ptp(tips["free"][-20:], axis=0).min() > 0.5  # still sweeping
    theta = free.step(np.zeros(3, np.float32))[0]["observation"]
    assert np.all((-math.pi <= theta) & (theta < math.pi))
    assert np.allclose(free.step(np.zeros(3, np.float32))[0]["achieved_goal"], PlanarArm(n_joints=3, arm_length=1.0).forward(theta))
    # 100 steps of 0.2 rad: joint 0 has turned 20 rad, wrapped.
    assert math.isclose(theta[0], math.remainder(20.0, 2 * math.pi), abs_tol=1e-9)


def test_free_joints_refuse_a_joint_limit_and_unknown_modes():
    import math

    from saggriac.errors import ParameterError

    GoalArmEnv = sgym.GoalArmEnv
    with pytest.raises(ParameterError, match="'joint_limit' parameter of GoalArmEnv must be left unset with joints='free'"):
        GoalArmEnv(joints="free", joint_limit=math.pi)
    with pytest.raises(ParameterError, match="'joints' parameter of GoalArmEnv must be one of 'limited', 'free'. Got 'loose'"):
        GoalArmEnv(joints="loose")
