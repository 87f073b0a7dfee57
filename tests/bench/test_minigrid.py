"""The rl-minigrid task (the minigrid extra): the level the teacher chose is the level played, or
the run stops; held-back levels are never trained on; the oracle's easy-to-hard order; PLR's
value-loss teacher told its score; the score against a known case."""

import os

import numpy as np
import pytest

from saggriac.bench import TASKS, TeacherSpec, run_one
from saggriac.bench.command import listing
from saggriac.bench.runner import Job
from saggriac.bench.teachers import Guarded, TeacherError, parse_teacher
from saggriac.errors import ConformanceError, ParameterError

if os.environ.get("SAGGRIAC_REQUIRE_EXTRAS") != "1":
    pytest.importorskip("minigrid", reason='the minigrid extra is not installed (pip install "saggriac[minigrid]")')
    pytest.importorskip("stable_baselines3", reason='the minigrid extra is not installed (pip install "saggriac[minigrid]")')

from saggriac.bench import minigrid as M  # noqa: E402


@pytest.fixture(scope="module")
def task():
    return M.RlMiniGrid(0)


def test_the_task_is_on_the_bench_list_as_a_task_list():
    row = next(line for line in listing().splitlines() if line.strip().startswith("rl-minigrid"))
    assert "tasks" in row and "160,000 environment steps" in row
    assert TASKS["rl-minigrid"].space == "tasks" and TASKS["rl-minigrid"].budgets["quick"] is None


def _layouts(levels):
    return [M._layout(M._grade_env(g), s) for g, s in levels]


def test_held_back_levels_are_other_mazes_and_cannot_be_asked_for_training(task):
    train, held = task.train_levels, task.held_levels
    assert task.n_tasks == len(train) == len(held) == len(M.GRADES) * M.PER_GRADE
    # No held-back maze (grid, start and heading) is any training level's, and no two repeat.
    assert len(set(_layouts(train)) | set(_layouts(held))) == 2 * len(train)
    env = M.make_level_env(train)
    for bad in (len(train), -1, 2.5, [0, 1]):
        env.set_next_goal(np.atleast_1d(bad))
        with pytest.raises(ParameterError, match=r"'goal' of the MiniGrid level list must be one level index, an int in \[0, 48\)"):
            env.reset()


def test_the_environment_plays_the_level_it_is_given_and_says_which(task):
    env = M.make_level_env(task.train_levels)
    for i in (0, 17, 47):
        env.set_next_goal(np.array([float(i)]))
        obs, info = env.reset()
        grade, layout = task.train_levels[i]
        mg = M._grade_env(grade)
        ref, _ = mg.reset(seed=layout)
        assert info["level"] == i and obs["desired_goal"].tolist() == [float(i)]
        np.testing.assert_array_equal(obs["image"], M.encode(ref["image"]))
        assert tuple(map(int, env.env.agent_pos)) == tuple(map(int, mg.agent_pos)) and env.env.agent_dir == mg.agent_dir


def _short(monkeypatch, steps):
    monkeypatch.setitem(TASKS["rl-minigrid"].budgets, "standard", steps)


@pytest.mark.slow
def test_every_episode_plays_the_level_its_teacher_chose(monkeypatch):
    """Through TeacherCallback: the levels whose episodes ended (as the environments report them)
    are the levels the teacher was told about, plus each environment's first episode, which plays
    the environment's own level 0 and is not told."""
    from collections import Counter

    task = M.RlMiniGrid(3)
    asked, told, ended = [], [], []
    rng = np.random.default_rng(1)

    def ask():
        asked.append(int(rng.integers(1, task.n_tasks)))  # never level 0
        return asked[-1]

    real = task.record
    monkeypatch.setattr(task, "record", lambda level, success: (ended.append(level), real(level, success)))
    task.play(ask, lambda goal, c: told.append(goal), 4_000)
    assert len(told) > 8 and set(told) <= set(asked)
    assert Counter(ended) == Counter(told) + Counter({0: M.N_ENVS})


@pytest.mark.slow
def test_a_level_not_applied_stops_the_run(monkeypatch):
    real = M.make_level_env

    def deaf(levels):
        env = real(levels)
        env.set_next_goal = lambda goal: None  # takes no level: every episode plays level 0
        return env

    monkeypatch.setattr(M, "make_level_env", deaf)
    with pytest.raises(ConformanceError, match=r"asked the environment for the goal \[5\.0\].*desired_goal is \[0\.0\]"):
        M.RlMiniGrid(1).play(lambda: 5, lambda goal, c: None, 2_000)


def test_the_oracle_goes_easy_to_hard_on_the_bar(task):
    t = M.RlMiniGrid(0)
    first = [t.oracle() for _ in range(10)]
    assert {t.grade_of[i] for i in first} == {0} and len(set(first)) == M.PER_GRADE
    grade0 = int(np.flatnonzero(t.grade_of == 0)[0])
    # Just under the bar over the window: it stays.
    n_ok = int(np.ceil(M.ORACLE_BAR * M.ORACLE_WINDOW)) - 1
    for k in range(M.ORACLE_WINDOW):
        t.record(grade0, k >= M.ORACLE_WINDOW - n_ok)
    assert t.grade_of[t.oracle()] == 0
    # Successes on another grade do not count for this one.
    for _ in range(M.ORACLE_WINDOW):
        t.record(int(np.flatnonzero(t.grade_of == 3)[0]), True)
    assert t.grade_of[t.oracle()] == 0
    t.record(grade0, True)  # now on the bar
    assert t.grade_of[t.oracle()] == 1


def test_plr_on_value_loss_is_told_its_score_only_where_a_task_has_it(task):
    spec = parse_teacher("saggriac.bench.value_loss:PlrValueLoss")
    guard = Guarded(spec, task, 7)
    assert guard.told == "positive_value_loss" and M.told_by(guard.tell) == "positive_value_loss"
    assert M.told_by(Guarded(TeacherSpec("plr"), task, 7).tell) == "competence"
    with pytest.raises(TeacherError, match=r"asks to be told 'positive_value_loss' \(its class's 'told'\), and the task tells only 'competence'"):
        Guarded(spec, TASKS["2d-cells"](0), 7)


@pytest.mark.slow
def test_plr_on_value_loss_gets_positive_value_losses(monkeypatch):
    _short(monkeypatch, 3_000)
    told = []
    real = Guarded.tell
    monkeypatch.setattr(Guarded, "tell", lambda self, goal, c: (told.append(c), real(self, goal, c)))
    row = run_one(Job("rl-minigrid", "standard", parse_teacher("saggriac.bench.value_loss:PlrValueLoss"), 5))
    # Each rollout's pieces of episode are told their mean GAE clipped at 0: not successes.
    assert told and min(told) >= 0.0 and any(0.0 < c and c not in (1.0,) for c in told)
    assert len(row["curve"]) == 10 and row["curve"][-1][0] >= 3_000


def test_the_score_draws_its_own_actions_and_leaves_torch_alone(task):
    import torch
    from stable_baselines3 import PPO
    from stable_baselines3.common.vec_env import DummyVecEnv

    env = DummyVecEnv([lambda: M.make_level_env(task.train_levels)])
    model = PPO("MultiInputPolicy", env, seed=0, device="cpu", policy_kwargs=dict(features_extractor_class=M.image_extractor()), n_steps=64, batch_size=64)
    state = torch.random.get_rng_state()
    some = task.held_levels[:6]
    first = M.evaluate(model, some)
    assert torch.equal(torch.random.get_rng_state(), state)
    assert M.evaluate(model, some) == first
    assert 0.0 <= first[0] <= 1.0 and 0.0 <= first[1] <= 1.0


def test_grades_at_bar_counts_the_grades_the_student_passes_whatever_the_teacher():
    t = M.RlMiniGrid(0)
    assert t.grades_at_bar() == 0
    for g in (0, 2):
        level = int(np.flatnonzero(t.grade_of == g)[0])
        for _ in range(M.ORACLE_WINDOW):
            t.record(level, True)
    assert t.grades_at_bar() == 2 and t.own_measures() == []


@pytest.mark.slow
@pytest.mark.parametrize("teacher", ["random", "oracle"])
def test_the_pilot_script_runs_what_the_evidence_runner_runs(teacher, monkeypatch):
    """benchmarks/minigrid_pilot.py made the pilot's rows; the study's report runs go through
    benchmarks/evidence.py. At a small budget both give the same score curve for a pilot seed."""
    from tests import benchmark_scripts

    pilot = benchmark_scripts.load("minigrid_pilot")
    evidence = benchmark_scripts.load("evidence")
    monkeypatch.setattr(pilot, "PILOT_STEPS", 1_600)
    rows, run = pilot.one_run(teacher, 108)
    curves, row = evidence.one_run(("rl-minigrid", teacher, 108, 1_600, 10, 30.0, "test", ()))
    assert [(r["step"], r["score"]) for r in rows] == [(c["step"], c["score"]) for c in curves]
    assert run["final"] == row["final"] and 0.0 <= row["final_solved"] <= 1.0


def test_the_bench_plans_plr_on_value_loss_only_where_it_can_be_told():
    from saggriac.bench.runner import plan

    teachers = [parse_teacher("saggriac.bench.value_loss:PlrValueLoss"), parse_teacher("plr")]
    jobs = plan(teachers, ["2d-cells", "niches-cells", "rl-minigrid"], "standard", [0], 30.0)
    assert sorted((j.teacher.label, j.task) for j in jobs) == sorted(
        [("saggriac.bench.value_loss:PlrValueLoss", "rl-minigrid"), ("plr", "2d-cells"), ("plr", "niches-cells"), ("plr", "rl-minigrid")]
    )
