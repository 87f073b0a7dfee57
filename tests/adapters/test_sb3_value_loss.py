"""PLR's published scores in SB3's loop: TeacherCallback(competence="positive_value_loss" or
"value_l1") tells PlrSelector(score="told") each episode's mean clipped GAE, or mean |GAE|, read
from the rollout buffer of a real PPO. Checked against the buffer itself: its episode starts
split each sub-environment's steps into pieces, and its observations say which level each piece
pursued. Skipped when SB3 is not installed, unless SAGGRIAC_REQUIRE_EXTRAS=1 (CI sets it)."""

import os

import numpy as np
import pytest

if os.environ.get("SAGGRIAC_REQUIRE_EXTRAS") != "1":
    pytest.importorskip("stable_baselines3", reason='the SB3 extra is not installed (pip install "saggriac[sb3]")')

import gymnasium
from stable_baselines3 import DQN, PPO
from stable_baselines3.common.callbacks import BaseCallback, CallbackList
from stable_baselines3.common.vec_env import DummyVecEnv

import saggriac as sg
from saggriac.adapters.gym import GoalSlot
from saggriac.adapters.sb3 import TeacherCallback

LEVELS = 4
LENGTH = 5  # steps per episode


class Levels(gymnasium.Env):
    """Level k pays k/3 at every step where the action is 1: each level has its own value, which
    a young value function gets wrong by different amounts. The desired goal is the level."""

    def __init__(self) -> None:
        box = gymnasium.spaces.Box(0.0, LEVELS - 1.0, (1,), np.float64)
        self.observation_space = gymnasium.spaces.Dict({"observation": gymnasium.spaces.Box(0.0, 1.0, (1,), np.float64), "achieved_goal": box, "desired_goal": box})
        self.action_space = gymnasium.spaces.Discrete(2)
        self.level, self.t = 0.0, 0

    def _obs(self) -> dict:
        return {"observation": np.array([self.t / LENGTH]), "achieved_goal": np.zeros(1), "desired_goal": np.array([self.level])}

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self.level = float((options or {}).get("goal", [0.0])[0])
        self.t = 0
        return self._obs(), {}

    def step(self, action):
        self.t += 1
        reward = self.level / 3 * float(action)
        return self._obs(), reward, False, self.t >= LENGTH, {"is_success": False}


class Buffer(BaseCallback):
    """A copy of the rollout buffer at each rollout's end (after TeacherCallback's tells)."""

    def __init__(self) -> None:
        super().__init__()
        self.rollouts: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []

    def _on_step(self) -> bool:
        return True

    def _on_rollout_end(self) -> None:
        b = self.model.rollout_buffer
        self.rollouts.append((b.advantages.copy(), b.episode_starts.copy(), b.observations["desired_goal"][..., 0].copy()))


def expected_tells(rollouts, clip: bool) -> list[tuple[float, float]]:
    """(level, score) per episode piece, from the buffers alone, in the order of the tells
    (rollout by rollout, sub-environment by sub-environment, in time): each sub-environment's
    steps cut where an episode starts and where a rollout ends, its first episode (the
    environment's own goal, before the teacher's) left out."""
    steps = len(rollouts[0][0])
    advantages, starts, levels = (np.concatenate([r[i] for r in rollouts]).astype(np.float64) for i in range(3))
    total, n_envs = advantages.shape
    pieces = []
    for env in range(n_envs):
        episode_starts = [t for t in range(1, total) if starts[t, env]]
        cuts = sorted(set(episode_starts) | set(range(steps, total + 1, steps)))
        begin = 0
        for end in cuts:
            assert np.all(levels[begin:end, env] == levels[begin, env]), "a piece pursues one level"
            if begin >= episode_starts[0]:
                piece = advantages[begin:end, env]
                score = float(np.mean(np.maximum(piece, 0.0) if clip else np.abs(piece)))
                pieces.append((begin // steps, env, begin, float(levels[begin, env]), score))
            begin = end
    return [(level, score) for *_, level, score in sorted(pieces)]


def train(competence: str, seed: int = 0):
    teacher = sg.PlrSelector(LEVELS, seed=seed, score="told")
    venv = DummyVecEnv([lambda: GoalSlot(Levels())] * 2)
    cb, buf = TeacherCallback(teacher, competence=competence), Buffer()
    model = PPO("MultiInputPolicy", venv, n_steps=32, batch_size=32, n_epochs=1, seed=seed, device="cpu")
    model.learn(total_timesteps=128, callback=CallbackList([cb, buf]))
    return teacher, cb, buf


@pytest.mark.parametrize("competence", ["positive_value_loss", "value_l1"])
def test_plr_is_told_each_episodes_value_loss_from_ppos_rollout_buffer(competence):
    teacher, cb, buf = train(competence)
    want = expected_tells(buf.rollouts, clip=competence == "positive_value_loss")
    got = [(float(g[0]), s) for g, s in cb.history]
    # 2 rollouts of 32 steps per sub-environment, episodes of 5: 12 episode starts and the end of
    # the first rollout cut the 64 steps into 14 pieces (an episode running when a rollout ends
    # is told on its steps so far, as the authors' code does), less the first episode of each of
    # the 2 sub-environments.
    assert len(buf.rollouts) == 2 and len(got) == len(want) == 2 * (14 - 1)
    np.testing.assert_allclose(np.array(got), np.array(want), rtol=1e-12, atol=0)
    told = teacher.history()
    np.testing.assert_array_equal(told["told_competence"], [s for _, s in got])
    # The teacher's score of each level is the last one told for it.
    last = {level: s for level, s in got}
    assert set(last) == set(range(LEVELS))
    np.testing.assert_allclose(teacher._inner.task_probabilities().sum(), 1.0)
    if competence == "positive_value_loss":
        assert all(s >= 0 for _, s in got) and any(s > 0 for _, s in got)


def test_the_value_losses_differ_by_level_and_the_scores_are_the_published_ones():
    _, cb_pos, buf = train("positive_value_loss")
    _, cb_l1, _ = train("value_l1")
    # Same seed, same training: the two scores of one piece, |GAE| at least clipped GAE.
    assert [tuple(g) for g, _ in cb_pos.history] == [tuple(g) for g, _ in cb_l1.history]
    assert all(l1 >= pos - 1e-15 for (_, pos), (_, l1) in zip(cb_pos.history, cb_l1.history))
    assert len({round(s, 9) for _, s in cb_l1.history}) > 10


def test_a_value_loss_needs_plr_with_told_scores_and_an_on_policy_model():
    with pytest.raises(sg.ParameterError, match="PlrSelector with score='progress' would read it as a competence") as e:
        TeacherCallback(sg.PlrSelector(4), competence="positive_value_loss")
    assert e.value.param == "competence"
    with pytest.raises(sg.ParameterError, match="DiscreteLpSelector would read it as a competence"):
        TeacherCallback(sg.DiscreteLpSelector(4), competence="value_l1")
    with pytest.raises(sg.ParameterError, match="'value_l2'"):
        TeacherCallback(sg.PlrSelector(4, score="told"), competence="value_l2")
    venv = DummyVecEnv([lambda: GoalSlot(Levels())])
    model = DQN("MultiInputPolicy", venv, learning_starts=0, buffer_size=100, seed=0, device="cpu")
    with pytest.raises(sg.ConformanceError, match="DQN has none"):
        model.learn(total_timesteps=4, callback=TeacherCallback(sg.PlrSelector(LEVELS, score="told"), competence="value_l1"))


def test_competences_still_reach_plr_without_a_value_function():
    """A learner without a value function tells competences, as before: PLR's own score."""
    teacher = sg.PlrSelector(LEVELS, seed=0)
    venv = DummyVecEnv([lambda: GoalSlot(Levels())] * 2)
    cb = TeacherCallback(teacher, competence=lambda info: 0.5)
    PPO("MultiInputPolicy", venv, n_steps=32, batch_size=32, n_epochs=1, seed=0, device="cpu").learn(total_timesteps=64, callback=cb)
    assert len(cb.history) == 2 * (64 // 2 // LENGTH) - 2 and all(c == 0.5 for _, c in cb.history)


def test_a_restored_plr_keeps_its_told_scores_and_is_accepted(tmp_path):
    """The check reads the teacher's own parameters (get_params, from the core), so a teacher
    restored from a file, built without __init__, is judged as the one saved."""
    path = sg.PlrSelector(LEVELS, seed=0, score="told", ties="average").save(tmp_path / "plr.saggriac")
    restored = sg.load_selector(path)
    assert restored.get_params() == {"n_tasks": LEVELS, "temperature": 0.1, "staleness_coef": 0.1, "replay_schedule": "proportionate", "replay_prob": 0.5, "score": "told", "ties": "average"}
    TeacherCallback(restored, competence="value_l1")
    with pytest.raises(sg.ParameterError, match="score='progress'"):
        TeacherCallback(sg.load_selector(sg.PlrSelector(LEVELS).save(tmp_path / "progress.saggriac")), competence="value_l1")
