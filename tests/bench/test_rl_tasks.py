"""The bench's deep-RL tasks (the sb3 extra): the first registered study's task, run through the
same code as its script, left out of the quick tier and out of a bench without the extra."""

import os

import numpy as np
import pytest

from saggriac.bench import TASKS, TeacherSpec, run_bench, run_one
from saggriac.bench.runner import Job
from saggriac.bench.tasks import in_tier
from saggriac.errors import ParameterError
from tests import benchmark_scripts

RL = [n for n in TASKS if n.startswith("rl-")]


def test_deep_rl_is_not_in_the_quick_tier_and_is_refused_there(tmp_path):
    assert RL and not any(in_tier(n, "quick") for n in RL) and all(in_tier(n, "standard") and in_tier(n, "full") for n in RL)
    with pytest.raises(ParameterError, match="'rl-arm-dense' is not in the tier 'quick'"):
        run_bench(["random"], out=tmp_path / "b", tier="quick", tasks=["rl-arm-dense"], progress=False)


def test_without_the_extra_the_tasks_are_left_out_and_named(tmp_path, monkeypatch):
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "stable_baselines3" else real(name, *a))
    with pytest.raises(ParameterError, match=r"'rl-arm-sparse' needs the sb3 extra: pip install \"saggriac\[sb3\]\""):
        run_bench(["random"], out=tmp_path / "b", tier="standard", tasks=["rl-arm-sparse"], progress=False)
    from saggriac.bench.command import listing

    assert "not installed: rl-arm-dense needs the sb3 extra" in listing()


@pytest.mark.parametrize("reward", ["dense", "sparse"])
def test_the_random_teacher_gives_the_studys_own_random_run(reward, monkeypatch):
    """rl-arm-REWARD with the built-in random teacher asks the goals the study's script asks
    with its random teacher (the same seeds' derivation and code): the same distances."""
    if os.environ.get("SAGGRIAC_REQUIRE_EXTRAS") != "1":
        pytest.importorskip("stable_baselines3", reason='the SB3 extra is not installed (pip install "saggriac[sb3]")')
    name = f"rl-arm-{reward}"
    monkeypatch.setitem(TASKS[name].budgets, "standard", 1_200)
    row = run_one(Job(name, "standard", TeacherSpec("random"), 7))
    study = benchmark_scripts.load("rl_curriculum")
    rows = study.one_run((reward, "random", 7, 1_200, 120, study.THRESHOLDS[reward], "test"))
    assert [s for _, s in row["curve"]] == [-r["distance"] for r in rows[1:]]
    assert [t for t, _ in row["curve"]] == list(range(120, 1_201, 120))


def _sb3():
    if os.environ.get("SAGGRIAC_REQUIRE_EXTRAS") != "1":
        pytest.importorskip("stable_baselines3", reason='the SB3 extra is not installed (pip install "saggriac[sb3]")')


def _trained_sac(steps=800):
    """SAC trained by the arm's own train() on the dense reward with a random teacher; the model
    and the TeacherCallback as they are at the end."""
    from saggriac.bench import rl
    from saggriac.teachers import RandomSelector

    seen = {}

    def score(step, model, callback):
        seen.update(model=model, callback=callback)

    rl.train("dense", rl.THRESHOLDS["dense"], RandomSelector([-2, -2], [2, 2], seed=3), 7, steps, steps // 2, score, learner="sac")
    return seen["model"], seen["callback"]


def test_sac_trains_on_the_teachers_goals_and_a_goal_not_applied_is_refused():
    """Every episode in SAC's replay buffer but each environment's first pursued a goal the
    teacher gave, and every told episode is there; a buffer where an episode's goal is not the
    teacher's, or changes mid-episode, or HER's buffer, is refused with the reason."""
    _sb3()
    from stable_baselines3.common.buffers import DictReplayBuffer

    from saggriac.bench.rl import EPISODE_STEPS, N_ENVS, check_replay_goals
    from saggriac.errors import ConformanceError

    model, callback = _trained_sac()
    assert type(model).__name__ == "SAC" and type(model.replay_buffer) is DictReplayBuffer
    # 800 steps = 200 per environment = 4 episodes each; the first of each is the environment's own.
    assert len(callback.history) == N_ENVS * (800 // N_ENVS // EPISODE_STEPS - 1)
    assert check_replay_goals(model, callback) >= len(callback.history)

    goals = model.replay_buffer.observations["desired_goal"]
    kept = goals.copy()
    goals[EPISODE_STEPS : 2 * EPISODE_STEPS, 0] = [1.5, -1.5]  # env 0's second episode pursued another goal
    with pytest.raises(ConformanceError, match="stored with a goal the teacher did not give: 1"):
        check_replay_goals(model, callback)
    goals[:] = kept
    goals[EPISODE_STEPS + 10, 1] = [0.1, 0.1]  # a goal changed within an episode
    with pytest.raises(ConformanceError, match="goal changes within it"):
        check_replay_goals(model, callback)
    goals[:] = kept
    callback.history.append((np.array([1.9, 1.9]), 0.0))  # told of an episode never trained on
    with pytest.raises(ConformanceError, match="told but never stored: 1"):
        check_replay_goals(model, callback)


def test_sac_with_her_is_refused():
    _sb3()
    from stable_baselines3 import SAC, HerReplayBuffer
    from stable_baselines3.common.vec_env import DummyVecEnv

    from saggriac.bench import rl
    from saggriac.errors import ConformanceError

    env = DummyVecEnv([lambda: rl.make_env("sparse", 0.3)] * 2)
    model = SAC("MultiInputPolicy", env, replay_buffer_class=HerReplayBuffer, device="cpu", seed=0, learning_starts=10_000)
    with pytest.raises(ConformanceError, match="HerReplayBuffer, which may replace them"):
        rl.check_replay_goals(model, object())


def test_the_learner_is_checked():
    from saggriac.bench import rl

    with pytest.raises(ParameterError, match="'learner' parameter of train must be one of 'ppo', 'sac'. Got 'td3'"):
        rl.train("dense", 0.2, object(), 0, 8, 4, lambda *a: None, learner="td3")


def test_a_sac_task_runs_on_the_bench_with_its_measures(monkeypatch):
    """rl-arm-sac-dense through the bench's runner: SAC learns (its final distance is below the
    untrained policy's), its curve has the task's 10 points, and its own measures agree with the
    score."""
    _sb3()
    from saggriac.bench.runner import play_run
    from saggriac.bench.teachers import Guarded

    task, guard, curve, _ = play_run("rl-arm-sac-dense", 7, 2_000, lambda t, s: Guarded(TeacherSpec("random"), t, s))
    assert [t for t, _ in curve] == list(range(200, 2_001, 200))
    own = task.own_measures()
    assert len(own) == 10 and [-m["distance"] for m in own] == [s for _, s in curve]
    assert own[-1]["distance"] < own[0]["start_distance"] - 0.05
    assert 0 < own[-1]["reachable_share"] < 0.5  # random asks goals anywhere in the box, a fifth in reach


@pytest.mark.parametrize("reward", ["dense", "sparse"])
def test_the_oracle_of_the_arm_gives_the_studys_oracle_run(reward):
    """The teacher named "oracle" on rl-arm-REWARD (the task's oracle_teacher, through the
    bench's guard) asks the goals of the first study's oracle: the same distances."""
    _sb3()
    from saggriac.bench.runner import play_run
    from saggriac.bench.teachers import GuardedOracle

    task, guard, curve, _ = play_run(f"rl-arm-{reward}", 7, 1_200, lambda t, s: GuardedOracle(t, s, run_seed=7), points=10)
    study = benchmark_scripts.load("rl_curriculum")
    rows = study.one_run((reward, "oracle", 7, 1_200, 120, study.THRESHOLDS[reward], "test"))
    assert [s for _, s in curve] == [-r["distance"] for r in rows[1:]]
    np.testing.assert_array_equal([m["reachable_share"] for m in task.own_measures()], [r["reachable_share"] for r in rows[1:]])  # NaN before any episode is told
    assert guard.spec.label == "oracle"


def test_the_free_joint_arm_gives_the_free_joint_studys_run():
    """rl-arm-free-sparse is the sparse arm with free joints: its random run is the one the
    free-joint check's script makes (rl_curriculum.py with the protocol's joints="free"), with
    the spread of the final tips among its measures."""
    _sb3()
    from saggriac.bench.runner import play_run
    from saggriac.bench.teachers import Guarded

    task, guard, curve, _ = play_run("rl-arm-free-sparse", 7, 1_200, lambda t, s: Guarded(TeacherSpec("random"), t, s, run_seed=7), points=10)
    study = benchmark_scripts.load("rl_curriculum")
    rows = study.one_run(("sparse", "random", 7, 1_200, 120, study.THRESHOLDS["sparse"], "test", "free"))
    assert [s for _, s in curve] == [-r["distance"] for r in rows[1:]]
    assert [m["tip_spread"] for m in task.own_measures()] == [r["tip_spread"] for r in rows[1:]]
    limited = study.one_run(("sparse", "random", 7, 1_200, 120, study.THRESHOLDS["sparse"], "test"))
    assert [r["distance"] for r in limited] != [r["distance"] for r in rows] and "tip_spread" not in limited[0]
