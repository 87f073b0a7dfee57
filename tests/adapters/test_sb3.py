"""saggriac.adapters.sb3: one teacher in the main process for Stable-Baselines3's vector environments,
tested with SB3 itself (DummyVecEnv and SubprocVecEnv, PPO). Skipped when SB3 is not installed,
unless SAGGRIAC_REQUIRE_EXTRAS=1 (CI sets it)."""

import os
import warnings

import numpy as np
import pytest

if os.environ.get("SAGGRIAC_REQUIRE_EXTRAS") != "1":
    pytest.importorskip("stable_baselines3", reason='the SB3 extra is not installed (pip install "saggriac[sb3]")')

import gymnasium
from stable_baselines3 import PPO
from stable_baselines3.common.env_checker import check_env
from stable_baselines3.common.env_util import make_vec_env
from stable_baselines3.common.vec_env import DummyVecEnv, SubprocVecEnv

import saggriac as sg
import saggriac.adapters.gym as sgym
from saggriac.adapters.sb3 import TeacherCallback

ENV = "saggriac.adapters.gym:saggriac/PlanarArm-v0"  # the module prefix registers the ids in spawned workers too


@pytest.mark.parametrize("env_id", list(sgym.ENVIRONMENTS))
def test_sb3_check_env_passes_without_warnings(env_id):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_env(gymnasium.make(env_id).unwrapped)


def test_make_vec_env_works_with_sb3s_default_render_mode():
    venv = make_vec_env(ENV, n_envs=2, seed=0)  # SB3 asks for render_mode="rgb_array"
    assert venv.render_mode == "rgb_array"
    venv.reset()
    assert venv.render().ndim == 3
    venv.close()


@pytest.mark.parametrize("vec_cls", [DummyVecEnv, SubprocVecEnv])
def test_one_teacher_in_the_main_process_is_told_every_episode(vec_cls):
    teacher = sg.SaggRiacSelector([0.0, -50.0], [50.0, 50.0], seed=0, g_max=10)
    kw = {"start_method": "spawn"} if vec_cls is SubprocVecEnv else {}
    venv = make_vec_env(lambda: gymnasium.make(ENV, max_episode_steps=20), n_envs=2, seed=0, vec_env_cls=vec_cls, vec_env_kwargs=kw)
    cb = TeacherCallback(teacher, competence="distance")
    model = PPO("MultiInputPolicy", venv, n_steps=64, batch_size=64, n_epochs=1, seed=0, device="cpu")
    model.learn(total_timesteps=640, callback=cb)
    venv.close()
    # 640 steps / 20 per episode = 32 episodes; the first of each of the 2 workers is the env's own.
    told = teacher.history()["told_competence"]
    assert len(told) == len(cb.history) == 32 - 2
    goals = np.array([g for g, _ in cb.history])
    assert len(np.unique(goals, axis=0)) == len(goals)  # both workers pursued distinct teacher goals
    np.testing.assert_array_equal(teacher.history()["told_goal"], goals)
    assert all(c <= 0 for _, c in cb.history)


def test_adr_chooses_the_goals_of_sb3_training_and_its_ranges_follow_what_it_is_told():
    """ADR in the main process behind SB3's PPO: every finished episode is told, and the
    boundary goals' competences reach ADR's buffers (thresholds that any distance passes, so
    the ranges must grow)."""
    teacher = sg.AdrSelector([0.0, -50.0], [50.0, 50.0], seed=0, boundary_prob=1.0, buffer_size=2, t_low=-2e6, t_high=-1e6)
    venv = make_vec_env(lambda: gymnasium.make(ENV, max_episode_steps=20), n_envs=2, seed=0)
    cb = TeacherCallback(teacher, competence="distance")
    model = PPO("MultiInputPolicy", venv, n_steps=64, batch_size=64, n_epochs=1, seed=0, device="cpu")
    model.learn(total_timesteps=640, callback=cb)
    venv.close()
    h = teacher.history()
    assert len(h["told_competence"]) == len(cb.history) == 32 - 2
    np.testing.assert_array_equal(h["told_goal"], np.array([g for g, _ in cb.history]))
    lo, hi = teacher.bounds
    assert np.all(hi - lo > 0) and np.all(lo >= [0.0, -50.0]) and np.all(hi <= [50.0, 50.0])


def test_a_goal_env_that_ignores_next_goal_is_refused():
    class Deaf(gymnasium.Wrapper):
        def set_next_goal(self, goal):  # takes the goal and forgets it
            pass

    teacher = sg.RandomSelector([0.0, -50.0], [50.0, 50.0], seed=0)
    venv = make_vec_env(lambda: Deaf(gymnasium.make(ENV, max_episode_steps=5)), n_envs=1, seed=0)
    model = PPO("MultiInputPolicy", venv, n_steps=16, batch_size=16, n_epochs=1, seed=0, device="cpu")
    with pytest.raises(sg.errors.ConformanceError, match="does not take goals that way"):
        model.learn(total_timesteps=32, callback=TeacherCallback(teacher))


def test_vecnormalize_and_the_loggers_csv_carry_the_teachers_columns(tmp_path):
    """PPO on VecNormalize (SB3's advice for continuous control) with TeacherCallback: the goal
    check reads the observations VecNormalize received, not the normalised ones (before: a false
    ConformanceError naming set_attr), and SB3's CSV log gets the teacher's figures."""
    import pandas as pd
    from stable_baselines3.common.logger import configure
    from stable_baselines3.common.vec_env import VecNormalize

    teacher = sg.SaggRiacSelector([0.0, -50.0], [50.0, 50.0], seed=0, g_max=10)
    venv = VecNormalize(make_vec_env(lambda: gymnasium.make(ENV, max_episode_steps=20), n_envs=2, seed=0))
    model = PPO("MultiInputPolicy", venv, n_steps=64, batch_size=64, n_epochs=1, seed=0, device="cpu")
    model.set_logger(configure(str(tmp_path), ["csv"]))
    cb = TeacherCallback(teacher, competence="distance")
    model.learn(total_timesteps=640, callback=cb)
    model.logger.close()
    log = pd.read_csv(tmp_path / "progress.csv")
    for col in ("teacher/asked", "teacher/told", "teacher/competence", "teacher/regions", "teacher/uniform_share"):
        assert col in log.columns, sorted(log.columns)
    assert log["teacher/told"].iloc[-1] == len(cb.history) == 30
    assert log["teacher/asked"].iloc[-1] == 30 + 2 * 2  # each worker holds one goal queued and one pursued
    assert log["teacher/competence"].dropna().between(-1e9, 0).all() and log["teacher/regions"].iloc[-1] >= 1
    assert log["teacher/uniform_share"].dropna().between(0, 1).all()


def test_a_mistaken_goal_under_vecnormalize_names_the_route_used():
    from stable_baselines3.common.vec_env import VecNormalize

    class Deaf(gymnasium.Wrapper):
        def set_next_goal(self, goal):
            pass

    venv = VecNormalize(make_vec_env(lambda: Deaf(gymnasium.make(ENV, max_episode_steps=5)), n_envs=1, seed=0))
    model = PPO("MultiInputPolicy", venv, n_steps=16, batch_size=16, n_epochs=1, seed=0, device="cpu")
    with pytest.raises(sg.errors.ConformanceError, match=r"env_method\('set_next_goal', \.\.\.\) \(read before VecNormalize"):
        model.learn(total_timesteps=32, callback=TeacherCallback(sg.RandomSelector([0.0, -50.0], [50.0, 50.0], seed=0)))


def test_checkpoints_save_the_teacher_and_a_resumed_training_continues_it(tmp_path):
    from stable_baselines3.common.callbacks import CheckpointCallback

    from saggriac.adapters.sb3 import teacher_path

    def make():
        return make_vec_env(lambda: gymnasium.make(ENV, max_episode_steps=20), n_envs=2, seed=0)

    teacher = sg.SaggRiacSelector([0.0, -50.0], [50.0, 50.0], seed=0, g_max=10)
    ckpt = CheckpointCallback(save_freq=160, save_path=str(tmp_path), name_prefix="rl_model")
    model = PPO("MultiInputPolicy", make(), n_steps=64, batch_size=64, n_epochs=1, seed=0, device="cpu")
    model.learn(total_timesteps=640, callback=[ckpt, TeacherCallback(teacher, competence="distance", save_with=ckpt)])
    saved = sorted(tmp_path.glob("rl_model_teacher_*_steps.saggriac"))
    assert [p.name for p in saved] == [f"rl_model_teacher_{n}_steps.saggriac" for n in (320, 640)]
    assert teacher_path(tmp_path / "rl_model_320_steps.zip") == saved[0]
    # The last save is the teacher as the training left it: it asks exactly what the teacher asks next.
    last = sg.load_selector(saved[1])
    np.testing.assert_array_equal(last.history()["told_goal"], teacher.history()["told_goal"])
    np.testing.assert_array_equal(last.sample_batch(5), teacher.sample_batch(5))
    # Resume from the first checkpoint: the model and the teacher it had, the teacher's history goes on.
    mid = sg.load_selector(saved[0])
    told_before = len(mid.history()["told_goal"])
    assert 0 < told_before < len(teacher.history()["told_goal"])
    model = PPO.load(tmp_path / "rl_model_320_steps.zip", env=make(), device="cpu")
    cb = TeacherCallback(mid, competence="distance")
    model.learn(total_timesteps=320, callback=cb, reset_num_timesteps=False)
    assert len(mid.history()["told_goal"]) == told_before + len(cb.history) > told_before


def test_save_with_must_be_a_checkpoint_callback():
    with pytest.raises(sg.errors.ParameterError, match="'save_with' parameter of TeacherCallback"):
        TeacherCallback(sg.RandomSelector([0.0], [1.0]), save_with="ckpt/")
    with pytest.raises(sg.errors.ParameterError, match="'allow_copy' parameter of TeacherCallback"):
        TeacherCallback(sg.RandomSelector([0.0], [1.0]), allow_copy="yes")
