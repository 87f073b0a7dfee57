"""TeacherCallback(save_with=CheckpointCallback): the teacher is saved exactly when the model is,
across learn() calls that reuse the checkpoint callback and whatever the order of the two
callbacks, tested with SB3 itself (PPO). Skipped when SB3 is not installed, unless
SAGGRIAC_REQUIRE_EXTRAS=1 (CI sets it)."""

import os
import re

import pytest

if os.environ.get("SAGGRIAC_REQUIRE_EXTRAS") != "1":
    pytest.importorskip("stable_baselines3", reason='the SB3 extra is not installed (pip install "saggriac[sb3]")')

from stable_baselines3 import PPO
from stable_baselines3.common.callbacks import BaseCallback, CheckpointCallback
from stable_baselines3.common.env_util import make_vec_env

import saggriac as sg
from saggriac.adapters.sb3 import TeacherCallback, teacher_path

ENV = "saggriac.adapters.gym:saggriac/PlanarArmExp1-v0"


class _Told(BaseCallback):
    """How many episodes the teacher had been told at each step (placed after the teacher's
    callback, so that it sees the step's tells)."""

    def __init__(self, teacher, seen):
        super().__init__()
        self.teacher, self.seen = teacher, seen

    def _on_step(self):
        self.seen[self.num_timesteps] = len(self.teacher.history()["told_goal"])
        return True


def _minus_distance(info):
    return -info["distance"]


def _steps(folder, pattern):
    return sorted(int(m.group(1)) for f in os.listdir(folder) if (m := re.fullmatch(pattern, f)))


@pytest.mark.parametrize("teacher_first", [False, True], ids=["checkpoint-first", "teacher-first"])
def test_every_model_checkpoint_has_its_teacher_across_two_learn_calls(tmp_path, teacher_first):
    # ecosystem-review-5 N4: the checkpoint callback's count runs on across learn() calls, a
    # new TeacherCallback's starts at 0; the teacher used to follow its own count.
    venv = make_vec_env(ENV, n_envs=2, seed=0, env_kwargs=dict(max_episode_steps=10))
    teacher = sg.SaggRiacSelector([0.0, -50.0], [50.0, 50.0], seed=0)
    ckpt = CheckpointCallback(save_freq=7, save_path=str(tmp_path / "ckpt"), name_prefix="rl_model")
    model = PPO("MultiInputPolicy", venv, n_steps=16, batch_size=32, n_epochs=1, seed=0, device="cpu")
    told: dict[int, int] = {}
    for first in (True, False):
        cb = TeacherCallback(teacher, competence=_minus_distance, save_with=ckpt)
        pair = [cb, ckpt] if teacher_first else [ckpt, cb]
        model.learn(96, reset_num_timesteps=first, callback=[*pair, _Told(teacher, told)])
        del cb  # lets the next callback claim the teacher
    venv.close()
    folder = tmp_path / "ckpt"
    models = _steps(folder, r"rl_model_(\d+)_steps\.zip")
    teachers = _steps(folder, r"rl_model_teacher_(\d+)_steps\.saggriac")
    # save_freq 7 calls of 2 environments: a model every 14 steps over 2 x 96 steps.
    assert models == list(range(14, 193, 14))
    assert teachers == models
    assert not [f for f in os.listdir(folder) if f.startswith(".")]  # no save made ahead is left
    for steps in models:
        saved = sg.load_selector(teacher_path(folder / f"rl_model_{steps}_steps.zip"))
        assert len(saved.history()["told_goal"]) == told[steps], steps  # the teacher of that very step


def test_a_checkpoint_callback_left_out_of_a_learn_call_saves_no_teacher_there(tmp_path):
    venv = make_vec_env(ENV, n_envs=2, seed=0, env_kwargs=dict(max_episode_steps=10))
    teacher = sg.RandomSelector([0.0, -50.0], [50.0, 50.0], seed=0)
    ckpt = CheckpointCallback(save_freq=8, save_path=str(tmp_path / "ckpt"), name_prefix="rl_model")
    model = PPO("MultiInputPolicy", venv, n_steps=16, batch_size=32, n_epochs=1, seed=0, device="cpu")
    model.learn(64, callback=[ckpt, TeacherCallback(teacher, competence=_minus_distance, save_with=ckpt)])
    # The second call forgets the checkpoint callback: no model is saved, so no teacher either.
    model.learn(64, reset_num_timesteps=False, callback=TeacherCallback(teacher, competence=_minus_distance, save_with=ckpt))
    venv.close()
    folder = tmp_path / "ckpt"
    assert _steps(folder, r"rl_model_(\d+)_steps\.zip") == [16, 32, 48, 64]
    assert _steps(folder, r"rl_model_teacher_(\d+)_steps\.saggriac") == [16, 32, 48, 64]
    assert not [f for f in os.listdir(folder) if f.startswith(".")]
