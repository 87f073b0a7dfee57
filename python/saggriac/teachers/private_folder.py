"""The private folder where teachers' claims and workers' refusals are kept: a security boundary.

``$TMPDIR/saggriac-teachers-UID`` is made with mode 0700 and used only while it is a folder (not a
link) of this user's that no one else can write to. Files in it are opened relative to the
folder's descriptor, without following links, and read only when they are regular files of this
user's, a bounded number of bytes at a time.
"""

from __future__ import annotations

import contextlib
import errno
import os
import stat
import tempfile
from collections.abc import Iterator
from pathlib import Path


def claims_dir() -> Path:
    """Where the claims live: a folder of this user's in the temporary directory."""
    return Path(tempfile.gettempdir()) / f"saggriac-teachers-{os.getuid()}"


class Unchecked(Exception):
    """The claim cannot be taken safely; the message says why and what the user can do."""


def open_claims_dir(make: bool = True) -> int:
    """A descriptor of the private claims folder, made if missing; Unchecked if it is unsafe."""
    d = claims_dir()
    if os.path.islink(d):
        raise Unchecked(f"{d} is a symbolic link, and saggriac uses only a private folder of its own there; remove it, or point TMPDIR elsewhere")
    try:
        if make:
            os.mkdir(d, 0o700)
    except FileExistsError:
        pass
    except OSError as e:
        raise Unchecked(f"its folder {d} cannot be made ({e.strerror}); point TMPDIR at a writable folder of yours") from None
    try:
        dfd = os.open(d, os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW | os.O_CLOEXEC)
    except OSError as e:
        kind = "a symbolic link" if e.errno == errno.ELOOP else "not a folder" if e.errno == errno.ENOTDIR else None
        why = f"{d} is {kind}" if kind else f"{d} cannot be opened ({e.strerror})"
        raise Unchecked(f"{why}, and saggriac uses only a private folder of its own there; remove it, or point TMPDIR elsewhere") from None
    st = os.fstat(dfd)
    if st.st_uid != os.getuid():
        os.close(dfd)
        raise Unchecked(f"{d} belongs to another user (uid {st.st_uid}), who could read and plant files in it; remove it, or point TMPDIR at a folder of yours")
    if st.st_mode & 0o077:
        os.close(dfd)
        raise Unchecked(f"{d} is open to other users (mode {stat.S_IMODE(st.st_mode):04o}; saggriac makes it 0700), who could plant files in it; remove it, or make it private with chmod 700")
    return dfd

def read_private(dfd: int, name: str, limit: int) -> bytes | None:
    try:
        fd = os.open(name, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK | os.O_CLOEXEC, dir_fd=dfd)
    except OSError:
        return None
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode) or st.st_uid != os.getuid():
            return None
        return os.read(fd, limit)
    except OSError:
        return None
    finally:
        os.close(fd)


def alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:
        return True  # alive, but another user's
    return pid > 0


def same_file(dfd: int, name: str, fd: int) -> bool:
    try:
        return os.fstat(fd).st_ino == os.stat(name, dir_fd=dfd, follow_symlinks=False).st_ino
    except OSError:
        return False


def names(dfd: int) -> list[str]:
    """The folder's file names (none where it cannot be listed)."""
    try:
        return sorted(os.listdir(dfd))
    except OSError:
        return []


@contextlib.contextmanager
def folder(make: bool = False) -> Iterator[int | None]:
    """The claims folder's descriptor for the block, or None where it is missing or unsafe (for
    what only tidies up or tells, which then does nothing)."""
    try:
        dfd = open_claims_dir(make)
    except (Unchecked, OSError):
        yield None
        return
    try:
        yield dfd
    finally:
        os.close(dfd)


def write_new(dfd: int, name: str, data: bytes) -> None:
    """Make the file ``name`` (it must not exist; never through a link) holding ``data``."""
    fd = os.open(name, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW | os.O_CLOEXEC, 0o600, dir_fd=dfd)
    try:
        os.write(fd, data)
    finally:
        os.close(fd)


def remove(dfd: int, name: str) -> None:
    """Remove ``name`` (a link itself, never what it names) if it is there."""
    with contextlib.suppress(OSError):
        os.unlink(name, dir_fd=dfd)
