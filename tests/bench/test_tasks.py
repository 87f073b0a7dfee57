"""Every task's score against a case whose answer is known: a perfect teacher (one that sees the
learner's state, ``task.oracle()``) and a constant one (the box's centre)."""

import math

import numpy as np
import pytest

import saggriac as sg
from saggriac.bench import TASKS, TeacherSpec, run_one
from saggriac.bench.runner import Job, child_seeds
from saggriac.bench.arm import ArmTask
from saggriac.bench.challenges import Abilities, Forgetting, Rugged
from saggriac.bench.tasks import Hypercube, Niches

TOY = [n for n, c in TASKS.items() if issubclass(c, (Hypercube, Niches))]
#: The hypercubes where a perfect teacher masters one cell every `need` goals.
CHAIN = [n for n in TOY if issubclass(TASKS[n], Hypercube) and not issubclass(TASKS[n], (Forgetting, Rugged))]


def _play(task, ask, budget):
    return task.play(ask, lambda goal, c: None, budget)


@pytest.mark.parametrize("name", CHAIN)
def test_hypercube_perfect_teacher_masters_a_cell_every_need_goals(name):
    cls = TASKS[name]
    task = cls(0)
    budget = cls.budgets["quick"]
    curve = _play(task, task.oracle, budget)
    n = int(task.possible.sum())
    # One cell mastered every `need` goals, in an order that always keeps a frontier open.
    assert curve == [(t, min(t // cls.need, n) / n) for t, _ in curve]
    assert curve[-1][1] == 1.0 and len(curve) == cls.points


@pytest.mark.parametrize("name", TOY)
def test_a_teacher_that_always_asks_the_centre_learns_nothing(name):
    cls = TASKS[name]
    task = cls(0)
    middle = np.full(len(task.low), 0.5)
    if cls.space == "box":
        goal = (task.low + task.high) / 2
    else:  # the cell holding the box's centre
        goal = task.cell(middle) if issubclass(cls, Hypercube) else task.env.cell(middle)
    curve = _play(task, lambda: goal, 2000)
    # The centre is a locked cell of the hypercubes, an impossible cell of the niches and a
    # trivial goal of trivial-90; in the rugged grid it is one open cell, mastered once.
    expect = 1 / task.n_cells if cls is Rugged else 0.0
    assert [s for _, s in curve][-1] == expect and max(s for _, s in curve) == expect


@pytest.mark.parametrize("name", [n for n in TOY if issubclass(TASKS[n], Niches) and not issubclass(TASKS[n], Abilities)])
def test_niches_perfect_teacher_follows_the_chain_in_closed_form(name):
    cls = TASKS[name]
    task = cls(0)
    curve = _play(task, task.oracle, cls.budgets["quick"])
    lr, unlock = task.env.learning_rate, task.env.unlock_at
    per_niche = math.ceil(math.log(1 - unlock) / math.log(1 - lr))  # practices until the next one opens (46)
    n = len(task.env.skill)
    t, s = curve[0]
    full, part = divmod(t, per_niche)
    expect = (full * (1 - (1 - lr) ** per_niche) + (1 - (1 - lr) ** part)) / n
    assert t == 250 and full < n and s == pytest.approx(expect, rel=1e-12)
    # Once the chain is open it keeps the least skilled niche practised: about 1000 tries each.
    assert curve[-1][1] == pytest.approx(1 - (1 - lr) ** (cls.budgets["quick"] // n), abs=1e-6)


def test_forgetting_perfect_teacher_keeps_everything_and_others_forget():
    cls = TASKS["forgetting"]
    task = cls(0)
    curve = _play(task, task.oracle, cls.budgets["quick"])
    # Until the first cell can be forgotten it is the plain chain; at the end all is held.
    assert curve[0] == (500, 25 / 100) and curve[-1][1] == 1.0
    task = cls(0)
    for c in [0] * 20 + [1] * (cls.forget_after + 1):
        task.attempt_cell(c)
    assert task.practice[0] == task.need // 2 and task.unlocked[1] and not task.mastered()[0]


def test_rugged_perfect_teacher_takes_the_easiest_cells_first():
    cls = TASKS["rugged"]
    task = cls(3)
    needs = np.sort(task.needs)
    curve = _play(task, task.oracle, cls.budgets["quick"])
    assert [s for _, s in curve] == [np.searchsorted(np.cumsum(needs), t, side="right") / task.n_cells for t, _ in curve]
    assert set(np.unique(needs)) == {5, 10, 20, 40, 80}


def test_abilities_students_differ_by_seed_and_a_perfect_teacher_teaches_each():
    rates = [TASKS["abilities"](s).learning_rate for s in range(10)]
    assert min(rates) >= 0.005 and max(rates) <= 0.08 and max(rates) / min(rates) > 4
    for seed in (0, 1):
        task = TASKS["abilities"](seed)
        curve = _play(task, task.oracle, 8000)
        assert curve[-1][1] > 1 - (1 - task.learning_rate) ** 900


@pytest.mark.parametrize("name", [n for n, c in TASKS.items() if issubclass(c, ArmTask)])
def test_the_arm_with_random_goals_is_the_runs_own_sagg_random(name):
    """Every arm task with the built-in random teacher asks exactly the goals of saggriac.run's
    condition sagg_random on the task's preset (the teacher is seeded as the run's high level):
    the same scores."""
    task = TASKS[name]
    row = run_one(Job(name, "quick", TeacherSpec("random"), 4))
    cfg = sg.Config.from_preset(task.preset, n_steps=task.budgets["quick"], n_evals=task.evals, condition="sagg_random", **task.settings)
    m = sg.run(cfg, seed=4, threads=1).metrics
    assert [s for _, s in row["curve"]] == list(-m.reach_error.to_numpy()[1:])
    assert row["row"]["final"] == -m.reach_error.iloc[-1] < 0


def test_seeds_are_children_of_the_runs_root_seed():
    a, b = child_seeds(7)
    assert a != b and 0 <= a < 2**63 and 0 <= b < 2**63 and child_seeds(7) == (a, b) and child_seeds(8) != (a, b)


def test_the_same_job_gives_the_same_bits():
    job = Job("niches-4", "quick", TeacherSpec("sagg_riac"), 2)
    one, two = run_one(job), run_one(job)
    for timed in ("seconds", "teacher_seconds"):
        one["row"].pop(timed), two["row"].pop(timed)
    assert one == two


def test_a_run_times_its_teacher_apart_from_the_task():
    """The row's teacher_seconds is the time inside the teacher's sample and update: part of the
    run's, and on the board as microseconds per goal beside the run's total."""
    from saggriac.bench.report import leaderboard

    rows = [run_one(Job("2d", "quick", TeacherSpec(t), 0))["row"] for t in ("random", "covar_gmm")]
    assert all(0 < r["teacher_seconds"] < r["seconds"] for r in rows)
    board = leaderboard(__import__("pandas").DataFrame(rows)).set_index("teacher")
    assert (board.teacher_us_per_goal > 0).all() and (board.teacher_us_per_goal < board.us_per_goal).all()
