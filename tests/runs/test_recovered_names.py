"""A study's run that is saved elsewhere says which condition it belongs to, not only its seed:
``seed1.recovered-TIME`` in the current folder could be any condition's. From the fifth
newcomer audit (issue 44)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

import saggriac
from saggriac import Config
from saggriac.errors import StorageError
from saggriac.runs import runner


def small():
    return Config.from_preset("exp1", n_steps=300, n_evals=1, n_test_goals=3, n_test_configs=3)


def saved_to(e) -> Path:
    return Path(str(e.value).split("saved to ")[1].split(" instead")[0])


@pytest.mark.parametrize("grid, group", [({}, "sagg_random"), ({"v": [0.5]}, "sagg_random__v=0.5")])
def test_a_recovered_study_run_names_its_condition(tmp_path, unwritable_study_runs, grid, group):
    from saggriac import study

    task = study.Study(small(), "sagg_random", (1,), grid=grid).tasks()[0]
    with pytest.raises(StorageError, match="saved to") as e:
        study.run_task(task, tmp_path / "st")
    place = saved_to(e)
    assert place.parent == tmp_path / "st" / "runs" / group
    assert place.name.startswith(f"{group}-seed1.recovered-"), place
    got = saggriac.RunResult.load(place)
    assert (got.seed, got.config.condition) == (1, "sagg_random")


def test_away_from_the_study_the_name_still_says_the_condition(tmp_path, monkeypatch, unwritable_study_runs):
    from saggriac import study

    monkeypatch.chdir(tmp_path)
    task = study.Study(small(), "sagg_riac", (1,)).tasks()[0]
    # The study's condition folder is a file: nothing can be saved beside the run.
    (tmp_path / "st" / "runs").mkdir(parents=True)
    (tmp_path / "st" / "runs" / "sagg_riac").write_text("in the way")
    with pytest.raises(StorageError, match="saved to") as e:
        study.run_task(task, tmp_path / "st")
    assert saved_to(e).parent == tmp_path and saved_to(e).name.startswith("sagg_riac-seed1.recovered-")


def test_a_run_of_its_own_keeps_its_name(tmp_path):
    res = saggriac.run(small(), 0)
    message = runner.recover(res, tmp_path / "r", "Could not write the run (simulated).")
    assert [p for p in os.listdir(tmp_path) if p.startswith("r.recovered-")], message
