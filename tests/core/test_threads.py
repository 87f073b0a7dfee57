"""Evaluations on other threads: the same results as in the learner's thread, and clear errors."""

from __future__ import annotations

import pytest

import saggriac
from saggriac.cli import main
from saggriac.errors import ParameterError

TABLES = ("metrics", "goals", "attempts", "regions")


@pytest.mark.parametrize("condition", ["sagg_riac", "actuator_random"])
def test_threads_do_not_change_any_table(condition: str) -> None:
    cfg = saggriac.Config.from_preset("exp1", condition=condition, n_steps=4000, n_evals=8, n_test_goals=20, n_test_configs=20)
    one = saggriac.run(cfg, seed=3, threads=1)
    for threads in (2, 4):
        many = saggriac.run(cfg, seed=3, threads=threads)
        for t in TABLES:
            assert getattr(one, t).equals(getattr(many, t)), f"{t} differs on {threads} threads"
        assert one.manifest["profile"]["test_steps"] == many.manifest["profile"]["test_steps"]


@pytest.mark.parametrize("bad", [0, -1, 1.5, True, "2", 10**6])
def test_bad_thread_counts_are_refused_with_the_rule(bad: object) -> None:
    with pytest.raises(ParameterError, match=r"The 'threads' parameter of run must be an int in \[1, 1024\] or None"):
        saggriac.run(saggriac.Config(n_steps=10), threads=bad)


def test_cli_takes_threads(tmp_path, capsys) -> None:
    out = tmp_path / "r"
    assert main(["run", "--steps", "300", "--set", "n_evals=2", "--threads", "2", "--out", str(out), "--no-progress"]) == 0
    assert (out / "run.json").exists()
    assert main(["run", "--steps", "300", "--threads", "0", "--out", str(tmp_path / "s"), "--no-progress"]) != 0
    assert "'threads' parameter" in capsys.readouterr().err
    assert not (tmp_path / "s").exists()
