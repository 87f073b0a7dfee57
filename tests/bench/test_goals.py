"""Each teacher's goals over time: a run keeps what its teacher asked (thinned), the bench writes
them as a table and one figure per task, and the shipped results carry the built-in teachers'
goals on each task's first seed."""

import numpy as np
import pandas as pd
import pytest

from saggriac.bench import TASKS, TeacherSpec, run_bench, run_one, shipped
from saggriac.bench.goal_log import KEPT, GoalLog
from saggriac.bench.goals import first_seed
from saggriac.bench.runner import Job

from .teachers_module import write


def test_the_log_keeps_at_most_kept_goals_evenly_with_first_and_last():
    log = GoalLog()
    for i in range(1000):
        log.add([i, -i])
    kept = log.thinned()
    assert len(kept) == KEPT and kept[0] == [1.0, 0.0, 0.0] and kept[-1] == [1000.0, 999.0, -999.0]
    calls = np.array([k[0] for k in kept])
    assert (np.diff(calls) > 0).all() and np.diff(calls).max() - np.diff(calls).min() <= 1
    assert all(k[1] == k[0] - 1 for k in kept)  # each goal sits at its own call
    short = GoalLog()
    for i in range(3):
        short.add(7)  # a task's index
    assert short.thinned() == [[1.0, 7.0], [2.0, 7.0], [3.0, 7.0]]


def test_a_run_records_the_goals_its_teacher_asked():
    record = run_one(Job("2d", "quick", TeacherSpec("random"), 0))
    asked = np.array(record["asked"])
    budget = TASKS["2d"].budgets["quick"]
    assert asked.shape == (KEPT, 3) and asked[0, 0] == 1 and asked[-1, 0] == budget
    task = TASKS["2d"](0)
    assert ((asked[:, 1:] >= task.low) & (asked[:, 1:] <= task.high)).all()
    # Uniform goals cover the box: every quarter holds some.
    quarter = (asked[:, 1:] > (task.low + task.high) / 2).astype(int) @ [1, 2]
    assert set(quarter) == {0, 1, 2, 3}


def test_the_bench_writes_the_goals_and_a_figure_per_task(tmp_path):
    (tmp_path / "user").mkdir()
    module = write(tmp_path / "user")
    res = run_bench([f"{module}:Centre"], out=tmp_path / "out", tasks=["2d", "niches-cells"], seeds=2, workers=1, progress=False, expert=False)
    goals = pd.read_parquet(tmp_path / "out" / "goals.parquet")
    centre = goals[goals.teacher == f"{module}:Centre"]
    # The centre teacher asked the centre every time, on both seeds, and nothing else.
    assert set(centre.seed) == {0, 1} and set(centre.task) == {"2d"}
    wide = centre.pivot_table(index=["seed", "call"], columns="dim", values="value")
    assert len(wide) == 2 * KEPT and np.allclose(wide.to_numpy(), (TASKS["2d"](0).low + TASKS["2d"](0).high) / 2)
    png = tmp_path / "out" / "goals" / "2d.png"
    assert png.is_file() and png.stat().st_size > 5_000
    assert res.written["goals_png"] == tmp_path / "out" / "goals"
    # The built-in teachers' goals come from the shipped results (first seed) when they ship,
    # and then the task list, where the user's box teacher does not run, has its figure too.
    if not shipped.load_goals("quick").empty:
        shown = first_seed(goals)
        assert {"random", "sagg_riac"} <= set(shown[shown.task == "2d"].teacher) and set(shown.seed) == {0}
        assert {"plr", "tscl"} <= set(shown[shown.task == "niches-cells"].teacher)
        assert (tmp_path / "out" / "goals" / "niches-cells.png").is_file()


SHIP_GOALS = shipped.load_goals("quick")


@pytest.mark.skipif(SHIP_GOALS.empty, reason="no goals ship with this tier's results")
def test_the_shipped_goals_are_each_teachers_first_seed_and_equal_a_rerun():
    runs = shipped.load("quick")[0]
    assert set(SHIP_GOALS.seed) == {0}
    assert set(map(tuple, SHIP_GOALS[["task", "teacher"]].drop_duplicates().to_numpy())) == set(map(tuple, runs[["task", "teacher"]].drop_duplicates().to_numpy()))
    for teacher in ("sagg_riac", "alp_gmm"):
        got = np.array(run_one(Job("2d-reach", "quick", TeacherSpec(teacher), 0))["asked"])
        ship = SHIP_GOALS[(SHIP_GOALS.task == "2d-reach") & (SHIP_GOALS.teacher == teacher)].pivot(index="call", columns="dim", values="value").sort_index()
        # The first two dimensions ship (the figures show no other).
        assert list(ship.columns) == [0, 1] and np.array_equal(got[:, 0], ship.index.to_numpy(float)) and np.array_equal(got[:, 1:3], ship.to_numpy()), teacher
