"""The built-in teachers' results that ship with the package: they say which saggriac and which
seeds made them, and a rerun on the same version gives the same numbers."""

import pandas as pd
import pytest

from saggriac import _core
from saggriac.bench import TASKS, TIERS, TeacherSpec, run_one, shipped
from saggriac.bench.runner import Job
from saggriac.bench.suite import compare_with_shipped
from saggriac.teachers import available

SHIP = shipped.load("quick")


def test_the_quick_results_ship_with_version_seeds_and_command():
    assert SHIP is not None, "python/saggriac/bench/results/quick_* are missing"
    runs, curves, meta = SHIP
    assert meta["seeds"] == list(range(TIERS["quick"])) and meta["tier"] == "quick" and meta["command"].startswith("saggriac bench --tier quick --rerun")
    assert set(meta["teachers"]) == set(runs.teacher) and set(runs.seed) == set(meta["seeds"])
    assert len(curves) >= len(runs) and {"task", "teacher", "seed", "step", "score"} <= set(curves.columns)


@pytest.mark.skipif(SHIP is None or SHIP[2]["version"] != _core.__version__, reason="the shipped results were made by another version")
@pytest.mark.parametrize("task", ["2d-reach", "niches-cells"])
def test_the_shipped_results_equal_a_rerun_on_this_version(task):
    runs = SHIP[0]
    seed = 1
    names = [n for n in available() if TeacherSpec(n).takes(TASKS[task].space) and n in set(runs.teacher)]
    assert len(names) >= 3
    for name in names:
        row = run_one(Job(task, "quick", TeacherSpec(name), seed))["row"]
        ship = runs[(runs.task == task) & (runs.teacher == name) & (runs.seed == seed)].iloc[0]
        assert (row["area"], row["final"]) == (ship.area, ship.final), name


STANDARD = shipped.load("standard")


def test_the_standard_results_ship_for_the_tasks_without_deep_rl():
    """The standard tier ships the tasks without deep RL (its deep-RL runs are hours of CPU a
    teacher): every such task, every seed of the tier, the built-in teachers that take it, and
    the command that made them naming those tasks."""
    assert STANDARD is not None, "python/saggriac/bench/results/standard_* are missing"
    runs, curves, meta = STANDARD
    plain = sorted(n for n, c in TASKS.items() if c.budgets["standard"] is not None and not n.startswith("rl-"))
    assert sorted(set(runs.task)) == sorted(meta["tasks"]) == plain
    assert meta["seeds"] == list(range(TIERS["standard"])) == sorted(set(runs.seed)) and meta["tier"] == "standard"
    assert meta["command"].startswith("saggriac bench --tier standard --rerun --write-shipped")
    assert set(meta["command"].split("--tasks ")[1].split()[0].split(",")) == set(plain)
    for task in plain:
        sub = runs[runs.task == task]
        takers = {n for n in available() if TeacherSpec(n).takes(TASKS[task].space)}
        assert takers <= set(sub.teacher), task
        assert (sub.groupby("teacher").seed.nunique() == TIERS["standard"]).all(), task
    assert len(curves) >= len(runs)


@pytest.mark.skipif(STANDARD is None or STANDARD[2]["version"] != _core.__version__, reason="the shipped results were made by another version")
@pytest.mark.parametrize("task, names", [("2d-reach", None), ("arm-episodic", ["random", "sagg_riac"])])
def test_the_shipped_standard_results_equal_a_rerun_on_this_version(task, names):
    runs = STANDARD[0]
    seed = 7  # a seed only the standard tier has
    names = names or [n for n in available() if TeacherSpec(n).takes(TASKS[task].space) and n in set(runs.teacher)]
    for name in names:
        row = run_one(Job(task, "standard", TeacherSpec(name), seed))["row"]
        ship = runs[(runs.task == task) & (runs.teacher == name) & (runs.seed == seed)].iloc[0]
        assert (row["area"], row["final"]) == (ship.area, ship.final), name


def test_a_rerun_says_whether_it_differs_and_which_versions_made_what():
    ship = pd.DataFrame([dict(task="2d", teacher="riac", seed=0, goals=10, area=0.5, final=0.9)])
    same = compare_with_shipped(ship.copy(), ship, {"version": "0.0.1"})
    assert same == ["Rerun: the 1 runs shipped for these teachers, tasks and seeds were recomputed and are the same numbers."]
    moved = ship.assign(area=0.25)
    (note,) = compare_with_shipped(moved, ship, {"version": "0.0.1"})
    assert note.startswith("Rerun: 1 of 1 shipped runs differ (riac; largest area change 0.25)") and f"made by saggriac 0.0.1, these by saggriac {_core.__version__}" in note


def test_the_guides_bench_numbers_are_the_shipped_results():
    """docs/choosing_a_teacher.md quotes the bench's shipped quick results for TSCL: each number
    as the leaderboard of the shipped runs gives it, so the two cannot drift apart."""
    from pathlib import Path

    from saggriac.bench.report import leaderboard

    # Compared with the lines' wrapping taken out.
    guide = " ".join((Path(__file__).resolve().parents[2] / "docs" / "choosing_a_teacher.md").read_text().split())
    board = leaderboard(SHIP[0]).set_index(["task", "teacher"])
    area = lambda task, teacher: board.loc[(task, teacher), "area"]  # noqa: E731
    sd = lambda task, teacher: board.loc[(task, teacher), "area_sd"]  # noqa: E731
    quoted = [
        f"`2d-cells` area {area('2d-cells', 'tscl'):.3f} ± {sd('2d-cells', 'tscl'):.3f} against PLR's {area('2d-cells', 'plr'):.3f} and random's {area('2d-cells', 'random'):.3f}",
        f"`niches-cells` area {area('niches-cells', 'tscl'):.3f} ± {sd('niches-cells', 'tscl'):.3f} against random's {area('niches-cells', 'random'):.3f} and discrete LP's {area('niches-cells', 'discrete_lp'):.3f}",
    ]
    missing = [q for q in quoted if q not in guide]
    assert not missing, missing
