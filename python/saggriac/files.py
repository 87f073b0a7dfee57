"""Writing one file so that nothing a user has is lost: the one atomic single-file writer of
saggriac (teachers, figures, study files), and the checks it makes first; and the one lock
(a run's target, a study folder). Light: no pandas."""

from __future__ import annotations

import contextlib
import errno
import hashlib
import json
import os
import stat
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any, Callable

import numpy as np

from .errors import ParameterError, StorageError

try:
    import fcntl
except ImportError:  # pragma: no cover - Windows: no advisory locks
    fcntl = None  # type: ignore[assignment]


def as_path(value: Any, param: str, owner: str, kind: str = "folder") -> Path:
    """A path argument (of a ``kind``: "folder" or "file"), refused when empty (``Path('')``
    would silently mean the current folder)."""
    if isinstance(value, Path):
        text = str(value)
    elif isinstance(value, str):
        text = value
    else:
        raise ParameterError(f"The '{param}' parameter of {owner} must be a path (str or pathlib.Path). Got {value!r} instead.", param, repr(value))
    if not text.strip() or "\0" in text:
        raise ParameterError(f"The '{param}' parameter of {owner} must name a {kind}. Got {value!r} instead.", param, repr(value))
    return Path(value)


def check_flag(value: Any, param: str, owner: str) -> bool:
    """A yes/no argument: only True or False, numpy's included (``overwrite="no"`` and
    ``progress=0`` would be read by their truth, so they are refused)."""
    if not isinstance(value, (bool, np.bool_)):
        raise ParameterError(f"The '{param}' parameter of {owner} must be a bool (True or False). Got {value!r} instead.", param, repr(value))
    return bool(value)


def _kind_of(mode: int) -> str:
    for test, name in ((stat.S_ISDIR, "a folder"), (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"), (stat.S_ISFIFO, "a FIFO"), (stat.S_ISSOCK, "a socket")):
        if test(mode):
            return name
    return "not a regular file"


#: Bounds of the files saggriac reads, far above what it writes (a run.json or study.json of a
#: few kB to a few MB; a saved teacher takes about 70 bytes per goal told in 2 dimensions).
MAX_JSON_BYTES = 64_000_000
MAX_TEACHER_BYTES = 1_000_000_000


def read_bounded(path: str | os.PathLike[str], what: str, limit: int) -> bytes:
    """The bytes of the file ``path``: the one rule for every file saggriac reads. It must be a
    regular file (a link to one is followed) of at most ``limit`` bytes: a FIFO would block
    for a writer, a device never ends, a huge file would be read until memory runs out.

    The file is opened without blocking and looked at through the open descriptor, so what is
    checked is what is read. A missing file raises FileNotFoundError (callers word it); every
    other refusal is a StorageError naming the path, ``what`` it should be and the rule."""
    path = Path(path)
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0))
    except (FileNotFoundError, NotADirectoryError):
        raise
    except OSError as e:
        raise StorageError(f"Cannot read {what} {path}: {e.strerror or e}.") from None
    st = os.fstat(fd)
    if not stat.S_ISREG(st.st_mode) or st.st_size > limit:
        os.close(fd)
        if not stat.S_ISREG(st.st_mode):
            raise StorageError(f"{path} is {_kind_of(st.st_mode)}; saggriac reads {what} only from a regular file.")
        raise StorageError(f"{path} is {st.st_size:,} bytes; {what} is at most {limit:,} bytes, so it is not read.")
    with os.fdopen(fd, "rb") as f:
        try:
            data = f.read(limit + 1)
        except OSError as e:
            raise StorageError(f"Cannot read {what} {path}: {e.strerror or e}.") from None
    if len(data) > limit:
        raise StorageError(f"{path} grew beyond {limit:,} bytes while it was read; {what} is at most that.")
    return data


def write_file(path: Path, write: Callable[[Path], None], *, what: str, overwrite: bool = False, ours: Callable[[Path], bool] | None = None) -> Path:
    """Write one file through a temporary sibling renamed into place, so a half-written file
    never stands and a failure leaves nothing behind.

    Something already at ``path`` is replaced only with ``overwrite`` and only if it is a regular
    file (not a link, folder, device, FIFO or socket) that ``ours`` recognises as saggriac's;
    anything else is refused before a byte is written. ``what`` names the file in messages."""
    path = Path(path)
    try:
        st = os.lstat(path)
    except FileNotFoundError:
        st = None
    except OSError as e:
        raise StorageError(f"Cannot write {what} to {path}: {e.strerror or e}.") from None
    if st is not None:
        if stat.S_ISLNK(st.st_mode):
            raise StorageError(f"{path} is a symbolic link; saggriac writes {what} only to a new path or over a regular file it wrote itself.")
        if not stat.S_ISREG(st.st_mode):
            raise StorageError(f"{path} is {_kind_of(st.st_mode)}; saggriac writes {what} only to a new path or over a regular file it wrote itself.")
        if not overwrite:
            raise StorageError(f"{path} exists; pass overwrite=True to replace it.")
        if ours is not None and not ours(path):
            raise StorageError(f"{path} is not {what} saggriac wrote; it is left alone. Choose another path.")
    parent = path.parent if str(path.parent) else Path(".")
    if not parent.is_dir():
        raise StorageError(f"Cannot write {what} to {path}: {parent} is not a folder.")
    tmp = None
    try:
        fd, name = tempfile.mkstemp(dir=parent, prefix=f".{path.name}.", suffix=".tmp")
        os.close(fd)
        tmp = Path(name)
        # mkstemp makes 0600; the file is for whoever may read the folder.
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        write(tmp)
        fsync_path(tmp)
        os.replace(tmp, path)
    except BaseException as e:
        if tmp is not None:
            with contextlib.suppress(OSError):
                tmp.unlink()
        if isinstance(e, OSError) and not isinstance(e, StorageError):
            raise StorageError(f"Cannot write {what} to {path}: {e.strerror or e}.") from e
        raise
    return path


def starts_with(prefix: bytes) -> Callable[[Path], bool]:
    """``ours`` for :func:`write_file`: a file whose first bytes are ``prefix``."""

    def check(path: Path) -> bool:
        try:
            with open(path, "rb") as f:
                return f.read(len(prefix)) == prefix
        except OSError:
            return False

    return check


def fsync_path(path: Path) -> None:
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


class Busy(Exception):
    """Another process holds the lock."""


class CannotLock(Exception):
    """The file system cannot lock files (``flock`` failed otherwise than busy); ``error`` says why."""

    def __init__(self, error: OSError) -> None:
        super().__init__(str(error))
        self.error = error


def flock_at(dfd: int, name: str, mode: int = 0o600) -> tuple[int, bool]:
    """An exclusive ``flock`` on the file ``name`` of the folder ``dfd``, made if missing; the
    descriptor and whether this call made the file. Never follows a link (ELOOP), and never
    blocks on a FIFO. Raises :class:`Busy` if another process holds it, :class:`CannotLock` where
    the file system cannot lock, and the OSError of opening the file. The one locking loop of saggriac (run and study folders, teacher
    claims): the holder before us may remove the file after we opened it, so the lock is taken
    again on the file that lives at ``name`` once it is held."""
    flags = os.O_RDWR | os.O_NOFOLLOW | os.O_NONBLOCK | os.O_CLOEXEC
    while True:
        try:
            fd, made = os.open(name, flags | os.O_CREAT | os.O_EXCL, mode, dir_fd=dfd), True
        except FileExistsError:
            try:
                fd, made = os.open(name, flags, dir_fd=dfd), False
            except FileNotFoundError:
                continue  # removed meanwhile
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError as e:
            os.close(fd)
            if e.errno in (errno.EWOULDBLOCK, errno.EAGAIN, errno.EACCES):
                raise Busy from None
            raise CannotLock(e) from None
        try:
            same = os.fstat(fd).st_ino == os.stat(name, dir_fd=dfd, follow_symlinks=False).st_ino
        except FileNotFoundError:
            same = False
        if same:
            return fd, made
        os.close(fd)


@contextlib.contextmanager
def lock(path: Path, busy: str, *, remove: bool = False) -> Iterator[OSError | None]:
    """Hold an exclusive lock on the file ``path`` (made if missing) until the block ends. If
    another process holds it, raise ``StorageError(busy)`` at once; the kernel drops the lock
    when its process dies. An OSError opening the file (a link at its place among them) is left
    to the caller to word.

    Yields None, or the error of a file system that cannot lock (the block then runs unlocked;
    where the system has no advisory locks at all, it runs unlocked and None is yielded). With
    ``remove`` the file is removed on release."""
    if fcntl is None:  # pragma: no cover - Windows
        yield None
        return
    path = Path(path)
    dfd = os.open(path.parent, os.O_RDONLY | os.O_DIRECTORY | os.O_CLOEXEC)
    fd: int | None = None
    try:
        try:
            fd, _ = flock_at(dfd, path.name, 0o644)
            unlocked: OSError | None = None
        except Busy:
            raise StorageError(busy) from None
        except CannotLock as e:  # pragma: no cover - file systems without flock
            unlocked = e.error
        yield unlocked
    finally:
        if fd is not None:
            if remove:
                with contextlib.suppress(OSError):
                    os.unlink(path.name, dir_fd=dfd)
            os.close(fd)
        os.close(dfd)


# -- provenance: a checksum over a JSON record (run.json, checkpoint.json) -----------------------

#: The first version whose run.json and checkpoint.json carry a checksum.
SEALED_SINCE = (0, 3, 0)


def json_checksum(record: dict[str, Any]) -> str:
    """SHA-256 of the record without its "checksum" key, in a canonical encoding."""
    body = {k: v for k, v in record.items() if k != "checksum"}
    return hashlib.sha256(json.dumps(body, sort_keys=True, separators=(",", ":"), allow_nan=True).encode()).hexdigest()


def seal(record: dict[str, Any]) -> dict[str, Any]:
    """The record with its checksum, so that an edit of any value (a seed, a parameter, the list
    of tables) is detected when it is read back."""
    return {**record, "checksum": json_checksum(record)}


def _version(text: Any) -> tuple[int, ...] | None:
    try:
        return tuple(int(p) for p in str(text).split("+")[0].split("-")[0].split("."))
    except ValueError:
        return None


def check_seal(record: dict[str, Any], where: Path) -> None:
    """Refuse a record whose checksum does not match its content, or a record of a version that
    writes checksums without one (an edited key name, a hand-made file)."""
    if "checksum" in record:
        if record["checksum"] != json_checksum(record):
            raise StorageError(f"{where} was changed or damaged: its checksum does not match its content (an edited seed, parameter or table list is not trusted).")
        return
    version = _version(record.get("version"))
    if version is None or version >= SEALED_SINCE:
        raise StorageError(f"{where} was changed or damaged: saggriac {record.get('version')!s} writes a checksum into it and there is none.")
