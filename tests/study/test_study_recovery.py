"""A study's run that cannot be written is saved elsewhere, and the error says where. From the third newcomer audit (issue 27)."""

from __future__ import annotations

from pathlib import Path

import pytest

import saggriac
from saggriac import Config
from saggriac.errors import StorageError


def test_a_study_run_that_cannot_be_written_says_where_it_went(tmp_path, unwritable_study_runs):
    from saggriac import study as study_mod

    cfg = Config.from_preset("exp1", n_steps=300, n_evals=1, n_test_goals=3, n_test_configs=3)
    task = study_mod.Study(cfg, "sagg_riac", (0,)).tasks()[0]
    with pytest.raises(StorageError, match="saved to (.*recovered-[^ ]*)") as e:
        study_mod.run_task(task, tmp_path / "st")
    place = Path(str(e.value).split("saved to ")[1].split(" instead")[0])
    assert saggriac.RunResult.load(place).seed == 0
