"""A user's teacher, from a module outside the repository, placed on the leaderboard among the
built-in teachers; a teacher that always asks the box's centre ranks below random where focus
matters."""

import subprocess
import sys

import pandas as pd
import pytest

from saggriac.bench import REFERENCE, run_bench

from .teachers_module import write

FOCUS = ["2d", "2d-reach", "niches-0"]


@pytest.fixture
def module(tmp_path):
    (tmp_path / "user").mkdir()
    return write(tmp_path / "user")


def test_a_users_teacher_by_file_path_and_the_centre_teacher_are_placed(module, tmp_path):
    # expert=False: the built-in teachers given expert knowledge are left out (until the shipped
    # results hold them they would be computed here too; tests/bench/test_expert.py runs them).
    res = run_bench([f"{module}:Uniform", f"{module}:Centre"], out=tmp_path / "out", tasks=FOCUS, seeds=3, workers=1, progress=False, expert=False)
    board = res.board
    mine, centre = f"{module}:Uniform", f"{module}:Centre"
    for task in FOCUS:
        rows = board[board.task == task].set_index("teacher")
        assert {mine, centre, REFERENCE, "sagg_riac"} <= set(rows.index)
        assert rows.loc[mine, "seeds"] == 3 and rows.loc[mine, "rank"] >= 1 and not pd.isna(rows.loc[mine, "p_holm"])
        # Where focus matters, the centre (a locked or impossible cell) learns nothing.
        assert rows.loc[centre, "area"] == 0.0 < rows.loc[REFERENCE, "area"]
        assert rows.loc[centre, "rank"] > rows.loc[REFERENCE, "rank"] and rows.loc[centre, "diff_area"] < 0
    # Only the two user teachers were computed; the built-in ones came from the shipped results.
    assert res.computed == 2 * len(FOCUS) * 3 and res.from_shipped > 0
    assert set(res.runs[res.runs.source == "computed"].teacher) == {mine, centre}
    for name in ("runs.parquet", "curves.parquet", "leaderboard.csv", "leaderboard.md", "curves.png", "ranks.png"):
        assert (tmp_path / "out" / name).is_file()
    text = (tmp_path / "out" / "leaderboard.md").read_text()
    assert "## 2d-reach" in text and "Uniform" in text


def test_the_command_benches_a_module_of_the_current_folder_by_import_path(module, tmp_path):
    cmd = [sys.executable, "-m", "saggriac.cli", "bench", "--teacher", "myteachers:Uniform", "--teacher-param", "spread=0.5", "--tasks", "2d", "--seeds", "2", "--workers", "2", "--out", "out", "--no-progress", "--no-expert"]
    done = subprocess.run(cmd, cwd=module.parent, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    board = pd.read_csv(module.parent / "out" / "leaderboard.csv")
    row = board[board.teacher == "myteachers:Uniform[spread=0.5]"]
    assert len(row) == 1 and row.seeds.iloc[0] == 2
    assert "myteachers:Uniform[spread=0.5]: " in done.stdout and "s of CPU" in done.stdout
