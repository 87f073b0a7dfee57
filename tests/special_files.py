"""Files a user may have where saggriac is told to write (a FIFO, a socket, a file of theirs, a
link, a dangling link), and a snapshot that shows whether any of them changed."""

import os
import socket
import stat
from pathlib import Path


def special_files(tmp_path: Path) -> dict[str, Path]:
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


def snapshot(p: Path):
    st = os.lstat(p)
    data = p.read_bytes() if stat.S_ISREG(st.st_mode) else None
    link = os.readlink(p) if stat.S_ISLNK(st.st_mode) else None
    return (stat.S_IFMT(st.st_mode), st.st_ino, data, link)
