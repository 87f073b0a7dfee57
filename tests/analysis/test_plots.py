"""Figures replace only figures saggriac wrote. From the third newcomer audit (issue 27)."""

from __future__ import annotations

import os

import pytest

from saggriac import Config
from saggriac.errors import StorageError
from tests.special_files import snapshot


def test_figures_replace_only_saggriac_figures(tmp_path):
    from saggriac.analysis import plots

    cfg = Config.from_preset("exp1")
    mine = tmp_path / "photo.png"
    mine.write_bytes(b"\x89PNG\r\n\x1a\n" + b"\0" * 64)  # someone's PNG
    before = snapshot(mine)
    with pytest.raises(StorageError, match="not a figure saggriac wrote"):
        plots.plot_arm(cfg, mine)
    assert snapshot(mine) == before
    fig = plots.plot_arm(cfg, tmp_path / "arm.png")
    plots.plot_arm(cfg, fig)  # its own figure is replaced
    fifo = tmp_path / "fifo.png"
    os.mkfifo(fifo)
    with pytest.raises(StorageError, match="FIFO"):
        plots.plot_arm(cfg, fifo)
