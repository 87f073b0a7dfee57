"""SPDL and Goal GAN behind the ask/tell API: seeded, in the box, restored exactly, bad input
refused with the project's messages, choosing a run's goals, and end to end through SB3 and
Syllabus on a tiny budget."""

import copy
import pickle

import numpy as np
import pytest

import saggriac as sg

LOW, HIGH = [0.0, -2.0], [1.0, 2.0]
MAKE = {
    "spdl": lambda s=3: sg.SpdlSelector(LOW, HIGH, seed=s, update_every=20, warmup=20, delta=0.3),
    "goal_gan": lambda s=3: sg.GoalGanSelector(LOW, HIGH, seed=s, update_size=10, gan_iterations=20, hidden=8),
}


def competence(g, k):
    """Success in [0, 1]: likely near the low corner, every other try elsewhere."""
    return float(np.hypot(g[0], (g[1] + 2) / 4) < 0.5 or k % 2 == 0)


def drive(t, n, start=0):
    for k in range(start, start + n):
        g = t.sample()
        assert np.all(g >= LOW) and np.all(g <= HIGH)
        t.update(g, competence(g, k))


@pytest.mark.parametrize("name", list(MAKE))
@pytest.mark.parametrize("how", ["pickle", "deepcopy", "file"])
def test_restored_teacher_continues_with_the_same_goals(name, how, tmp_path):
    t = MAKE[name]()
    drive(t, 150)
    u = {"pickle": lambda: pickle.loads(pickle.dumps(t)), "deepcopy": lambda: copy.deepcopy(t), "file": lambda: sg.load_selector(t.save(tmp_path / "t.bin"))}[how]()
    assert type(u) is type(t) and u.seed == t.seed
    for k in range(150, 300):
        g, h = t.sample(), u.sample()
        assert np.array_equal(g, h)
        t.update(g, competence(g, k))
        u.update(h, competence(h, k))
    assert np.array_equal(t.sample_batch(7), u.sample_batch(7))


@pytest.mark.parametrize("name", list(MAKE))
def test_seeded_and_checked_by_the_conformance_helper(name):
    a, b, c = MAKE[name](1), MAKE[name](1), MAKE[name](2)
    drive(a, 60), drive(b, 60), drive(c, 60)
    assert np.array_equal(a.history()["asked_goal"], b.history()["asked_goal"])
    assert not np.array_equal(a.history()["asked_goal"], c.history()["asked_goal"])
    sg.testing.check_goal_selector(MAKE[name]())


@pytest.mark.parametrize(
    "make, message",
    [
        (lambda: sg.SpdlSelector([0.0], [1.0], epsilon=0.0), r"^The 'epsilon' parameter of SpdlSelector must be a finite float > 0. Got 0 instead.$"),
        (lambda: sg.SpdlSelector([0.0], [1.0], init_mean=1.5), r"^The 'init_mean' parameter of SpdlSelector must be a float in \[0, 1\]"),
        (lambda: sg.SpdlSelector([0.0], [1.0], update_every=1.0), r"^The 'update_every' parameter of SpdlSelector must be an int"),
        (lambda: sg.GoalGanSelector([0.0], [1.0], r_min=0.9, r_max=0.1), r"^The 'r_max' parameter of GoalGanSelector must be a float >= r_min \(r_min = 0.9\). Got 0.1 instead.$"),
        (lambda: sg.GoalGanSelector([0.0], [1.0], hidden=0), r"^The 'hidden' parameter of GoalGanSelector must be an int in \[1, 1024\]. Got 0 instead.$"),
        (lambda: sg.GoalGanSelector([0.0], [1.0], p_old=True), r"^The 'p_old' parameter of GoalGanSelector must be a float in \[0, 1\]. Got True instead.$"),
    ],
)
def test_bad_parameters_are_refused_by_name(make, message):
    with pytest.raises(sg.ParameterError, match=message):
        make()


@pytest.mark.parametrize("name", list(MAKE))
def test_bad_goals_and_competences_are_refused(name):
    t = MAKE[name]()
    with pytest.raises(sg.InputError):
        t.update([0.5], 1.0)
    with pytest.raises(sg.InputError):
        t.update([0.5, 0.0], float("nan"))
    assert len(t.history()["told_competence"]) == 0


def test_spdl_moves_from_its_initial_to_its_target_distribution_as_competence_allows():
    t = sg.SpdlSelector([0.0, 0.0], [1.0, 1.0], seed=0, init_mean=0.1, init_std=0.05, update_every=50, warmup=50)
    kl = [float(t.regions()["interest"][0])]
    for k in range(4000):
        g = t.sample()
        t.update(g, float(np.hypot(*g) < 0.3 + k / 4000))  # the solvable disc grows with practice
        if (k + 1) % 500 == 0:
            kl.append(float(t.regions()["interest"][0]))
    assert kl[-1] < 0.05 * kl[0] and all(b <= a + 1e-9 for a, b in zip(kl, kl[1:])), kl
    r = t.regions()
    np.testing.assert_allclose((r["low"] + r["high"])[0] / 2, [0.5, 0.5], atol=0.05)  # the target's mean
    np.testing.assert_allclose((r["high"] - r["low"])[0] / 2, [0.25, 0.25], atol=0.05)  # and sd
    # Competence below delta everywhere: the distribution stays where it started.
    s = sg.SpdlSelector([0.0, 0.0], [1.0, 1.0], seed=0, init_mean=0.1, init_std=0.05, update_every=50, warmup=50)
    before = s.regions()
    drive_flat = [s.update(s.sample(), 0.2) for _ in range(1000)]
    assert len(drive_flat) == 1000 and np.array_equal(s.regions()["low"], before["low"])


@pytest.mark.parametrize("name", list(MAKE))
def test_a_run_takes_its_goals_from_the_teacher(name):
    # A run's competences are <= 0 (0: reached), hence the threshold and delta.
    params = {"delta": -0.5, "update_every": 10, "warmup": 10} if name == "spdl" else {"success_threshold": -0.1, "update_size": 5, "gan_iterations": 5}
    cfg = sg.Config.from_preset("exp1", teacher=name, teacher_params=params, n_steps=3000, n_evals=1)
    res = sg.run(cfg, seed=3)
    cls = type(MAKE[name]())
    own = sg.run(cfg.replace(teacher="own", teacher_params={}), seed=3, goal_selector=cls(cfg.goal_low, cfg.goal_high, seed=sg.seeding.selector_seed(3), **params))
    goals = ["goal_x", "goal_y"]
    assert len(res.goals) > 20
    assert np.array_equal(res.goals[goals].to_numpy(), own.goals[goals].to_numpy())


@pytest.mark.parametrize("name", list(MAKE))
def test_through_syllabus(name):
    pytest.importorskip("syllabus")
    import gymnasium
    from syllabus.task_space import BoxTaskSpace

    from saggriac.adapters.syllabus import SelectorCurriculum

    space = BoxTaskSpace(gymnasium.spaces.Box(np.float32(LOW), np.float32(HIGH), dtype=np.float32))
    cur, bare = SelectorCurriculum(space, MAKE[name](5)), MAKE[name](5)
    for k in range(80):
        task = cur.sample(1)[0]
        assert space.gym_space.contains(np.asarray(task, np.float32))
        g = bare.sample()
        np.testing.assert_array_equal(np.float32(task), np.float32(g))
        c = competence(g, k)
        cur.update_on_episode(-1.0, 4, task, c)
        bare.update(np.asarray(task, np.float64), c)  # what the curriculum tells: the float32 task
    assert len(cur.selector.history()["told_competence"]) == 80
    np.testing.assert_array_equal(pickle.loads(pickle.dumps(cur)).selector.sample(), cur.selector.sample())


@pytest.mark.parametrize("name", list(MAKE))
def test_through_sb3(name):
    pytest.importorskip("stable_baselines3")
    import gymnasium
    from stable_baselines3 import PPO
    from stable_baselines3.common.env_util import make_vec_env

    from saggriac.adapters.sb3 import TeacherCallback

    make = {"spdl": lambda: sg.SpdlSelector([0.0, -50.0], [50.0, 50.0], seed=0, update_every=5, warmup=5, delta=-1.0), "goal_gan": lambda: sg.GoalGanSelector([0.0, -50.0], [50.0, 50.0], seed=0, update_size=3, gan_iterations=5, hidden=8, success_threshold=-0.5)}
    teacher = make[name]()
    venv = make_vec_env(lambda: gymnasium.make("saggriac.adapters.gym:saggriac/PlanarArm-v0", max_episode_steps=20), n_envs=2, seed=0)
    cb = TeacherCallback(teacher, competence="distance")
    PPO("MultiInputPolicy", venv, n_steps=64, batch_size=64, n_epochs=1, seed=0, device="cpu").learn(total_timesteps=640, callback=cb)
    venv.close()
    told = teacher.history()["told_goal"]
    assert len(told) == len(cb.history) == 30
    np.testing.assert_array_equal(told, np.array([g for g, _ in cb.history]))
    assert np.all(told >= [0.0, -50.0]) and np.all(told <= [50.0, 50.0])
