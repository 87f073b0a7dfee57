"""Disks fill, work survives: the free-space check counts the checkpoints, and a checkpoint
that cannot be written warns while the run finishes. From the third newcomer audit (issue 27)."""

from __future__ import annotations

import numpy as np
import pytest

import saggriac
from saggriac import Config
from saggriac.errors import StorageError


def test_the_free_space_check_counts_the_checkpoints(tmp_path, monkeypatch):
    from saggriac.runs import resources, storage

    cfg = Config.from_preset("exp2", n_evals=1)
    need = 2 * resources.checkpoint_bytes(cfg)
    assert need > 50e6  # exp2's state grows past 20 MB (audit: 22 MB at 81k steps)
    free = storage.MIN_FREE_BYTES + need // 2
    monkeypatch.setattr(storage.shutil, "disk_usage", lambda p: type("U", (), {"free": free})())
    with pytest.raises(StorageError, match="MB free"):
        saggriac.run(cfg, 0, out_dir=tmp_path / "r", checkpoint_every=50_000)
    # Without checkpoints the same disk is enough to start.
    storage.check_output_dir(tmp_path / "r", False, saggriac.runs.runner._min_free(cfg, None))


def test_a_failed_checkpoint_write_warns_and_the_run_finishes(tmp_path, monkeypatch):
    from saggriac.runs import checkpoint

    real = checkpoint.write_checkpoint
    calls = []

    def flaky(*a, **k):
        calls.append(1)
        if len(calls) == 2:
            raise StorageError("No space left on device (simulated)")
        real(*a, **k)

    monkeypatch.setattr(checkpoint, "write_checkpoint", flaky)
    # Checkpoints are written at evaluations, between goal attempts: many evaluations, many chances
    # (threads=1: with evaluations on other threads a loaded machine can coalesce the stops).
    cfg = Config.from_preset("exp1", n_steps=6000, n_evals=24, n_test_goals=5, n_test_configs=5)
    with pytest.warns(checkpoint.CheckpointWarning, match=r"last good checkpoint \(step \d+\) is kept"):
        res = saggriac.run(cfg, 0, out_dir=tmp_path / "r", checkpoint_every=250, threads=1)
    plain = saggriac.run(cfg, 0)
    assert res.path is not None and len(calls) >= 3  # and later checkpoints were written again
    np.testing.assert_array_equal(res.metrics["reach_error"], plain.metrics["reach_error"])
