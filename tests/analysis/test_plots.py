"""Figures replace only figures saggriac wrote. From the third newcomer audit (issue 27)."""

from __future__ import annotations

import os
import socket
import stat
from pathlib import Path

import pytest

from saggriac import Config
from saggriac.errors import StorageError


def _special_files(tmp_path: Path) -> dict[str, Path]:
    out = {}
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    out["fifo"] = fifo
    sock = tmp_path / "sock"
    s = socket.socket(socket.AF_UNIX)
    s.bind(str(sock))
    s.close()  # the socket file stays
    out["socket"] = sock
    foreign = tmp_path / "notes.txt"
    foreign.write_text("a user's notes")
    out["foreign"] = foreign
    target = tmp_path / "elsewhere.bin"
    target.write_text("a user's file the link points to")
    link = tmp_path / "link.bin"
    link.symlink_to(target)
    out["link"] = link
    out["dangling"] = tmp_path / "dangling.bin"
    out["dangling"].symlink_to(tmp_path / "nowhere" / "x")
    return out


def _snapshot(p: Path):
    st = os.lstat(p)
    data = p.read_bytes() if stat.S_ISREG(st.st_mode) else None
    link = os.readlink(p) if stat.S_ISLNK(st.st_mode) else None
    return (stat.S_IFMT(st.st_mode), st.st_ino, data, link)


def test_figures_replace_only_saggriac_figures(tmp_path):
    from saggriac.analysis import plots

    cfg = Config.from_preset("exp1")
    mine = tmp_path / "photo.png"
    mine.write_bytes(b"\x89PNG\r\n\x1a\n" + b"\0" * 64)  # someone's PNG
    before = _snapshot(mine)
    with pytest.raises(StorageError, match="not a figure saggriac wrote"):
        plots.plot_arm(cfg, mine)
    assert _snapshot(mine) == before
    fig = plots.plot_arm(cfg, tmp_path / "arm.png")
    plots.plot_arm(cfg, fig)  # its own figure is replaced
    fifo = tmp_path / "fifo.png"
    os.mkfifo(fifo)
    with pytest.raises(StorageError, match="FIFO"):
        plots.plot_arm(cfg, fifo)
