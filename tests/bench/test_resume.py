"""A bench stopped part way (runs lost, a file cut short, or the process killed) and run again
computes only what is missing and ends with the same numbers."""

import os
import signal
import subprocess
import sys
import time

import pandas as pd
import pytest

from saggriac.bench import run_bench

from .teachers_module import write

NUMBERS = ["task", "teacher", "seeds", "area", "final", "diff_area", "ci_low", "ci_high", "p_holm", "diff_final", "rank"]


@pytest.fixture
def module(tmp_path):
    (tmp_path / "user").mkdir()
    return write(tmp_path / "user")


def test_lost_and_damaged_runs_are_recomputed_to_the_same_numbers(module, tmp_path):
    kw = dict(out=tmp_path / "out", tasks=["2d", "niches-4"], seeds=3, workers=1, progress=False, expert=False)
    first = run_bench([f"{module}:Uniform"], **kw)
    files = sorted((tmp_path / "out" / "runs").rglob("seed*.json"))
    assert len(files) == 6
    files[0].unlink()
    files[1].unlink()
    files[2].write_text(files[2].read_text()[:50])  # a run file cut short
    again = run_bench([f"{module}:Uniform"], **kw)
    assert (again.computed, again.kept) == (3, 3)
    pd.testing.assert_frame_equal(first.board[NUMBERS], again.board[NUMBERS])
    key = ["task", "teacher", "seed"]
    a, b = first.runs.sort_values(key).reset_index(drop=True), again.runs.sort_values(key).reset_index(drop=True)
    pd.testing.assert_frame_equal(a[[*key, "area", "final"]], b[[*key, "area", "final"]])


def test_a_killed_bench_resumes_to_the_same_numbers(module, tmp_path):
    cmd = [sys.executable, "-m", "saggriac.cli", "bench", "--teacher", f"{module}:Slow", "--tasks", "rugged", "--seeds", "5", "--workers", "2", "--no-progress", "--no-expert"]
    killed = subprocess.Popen([*cmd, "--out", "killed"], cwd=tmp_path, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    runs = tmp_path / "killed" / "runs"
    deadline = time.monotonic() + 90
    while time.monotonic() < deadline and not list(runs.rglob("seed*.json")):
        time.sleep(0.05)
    os.killpg(killed.pid, signal.SIGKILL)
    killed.wait(timeout=30)
    left = len(list(runs.rglob("seed*.json")))
    assert 1 <= left < 5, left
    done = subprocess.run([*cmd, "--out", "killed"], cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert f"{5 - left} runs computed" in done.stdout and f"{left} kept" in done.stdout
    whole = subprocess.run([*cmd, "--out", "whole"], cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert whole.returncode == 0, whole.stderr
    a, b = pd.read_csv(tmp_path / "killed" / "leaderboard.csv"), pd.read_csv(tmp_path / "whole" / "leaderboard.csv")
    pd.testing.assert_frame_equal(a[NUMBERS], b[NUMBERS])
