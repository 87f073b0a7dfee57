"""saggriac.sb3: one teacher in the main process for Stable-Baselines3's vector environments,
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
import saggriac.gym as sgym
from saggriac.sb3 import TeacherCallback

ENV = "saggriac.gym:saggriac/PlanarArm-v0"  # the module prefix registers the ids in spawned workers too


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


def test_a_goal_env_that_ignores_next_goal_is_refused():
    class Deaf(gymnasium.Wrapper):
        def set_next_goal(self, goal):  # takes the goal and forgets it
            pass

    teacher = sg.RandomSelector([0.0, -50.0], [50.0, 50.0], seed=0)
    venv = make_vec_env(lambda: Deaf(gymnasium.make(ENV, max_episode_steps=5)), n_envs=1, seed=0)
    model = PPO("MultiInputPolicy", venv, n_steps=16, batch_size=16, n_epochs=1, seed=0, device="cpu")
    with pytest.raises(sg.errors.ConformanceError, match="does not take goals that way"):
        model.learn(total_timesteps=32, callback=TeacherCallback(teacher))


def test_a_teacher_inside_the_workers_is_refused_with_the_callbacks_name(tmp_path):
    """The worker refuses its copy of the teacher; SB3 then loses the worker, and the worker's
    message (on stderr) names the way to do it."""
    import subprocess
    import sys

    script = tmp_path / "copied.py"
    script.write_text(
        f"""
import gymnasium, saggriac as sg, saggriac.gym as sgym
from stable_baselines3.common.vec_env import SubprocVecEnv
teacher = sg.SaggRiacSelector([0.0, -50.0], [50.0, 50.0], seed=0)
def make():
    return sgym.SelectorGoals(gymnasium.make({ENV!r}, max_episode_steps=5), teacher)
if __name__ == "__main__":
    SubprocVecEnv([make, make], start_method="spawn").reset()
"""
    )
    r = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=300)
    assert r.returncode != 0
    assert "ConformanceError" in r.stderr and "saggriac.sb3.TeacherCallback" in r.stderr, r.stderr[-2000:]
