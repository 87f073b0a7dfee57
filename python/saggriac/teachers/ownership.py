"""One teacher, one process: how saggriac's wrappers find a teacher split across processes.

A teacher handed to worker processes is copied into each of them (pickled under spawn and
forkserver, duplicated with the whole memory under fork). Every copy then learns from its own
worker only, and the original is told nothing: a failure no output shows. So each teacher
carries an identity (kept by pickle, new for ``copy.copy``/``copy.deepcopy`` and
:func:`load_selector`), and a wrapper that uses a teacher (``SelectorGoals``,
``VectorSelectorGoals``, ``TeacherCallback``) claims that identity for its process first. The
claim is an exclusive ``flock`` on a file named by the identity: the kernel drops it when the
process ends, so a teacher pickled to disk and restored after its first process ended is free
again, and a teacher that lives in exactly one worker (one per worker of a pool) is allowed.
A second process claiming the same identity while the first holds it is refused, whatever the
start method; ``allow_copy=True`` on the wrapper says that the copies are meant to be
independent.

Teachers without an identity (a user's own class) are not tracked.
"""

from __future__ import annotations

import errno
import fcntl
import os
import tempfile
import threading
import uuid
import weakref
from pathlib import Path
from typing import Any

from ..errors import ConformanceError

#: identity -> (pid that claimed it, open file holding the lock)
_claims: dict[str, tuple[int, int]] = {}
_lock = threading.Lock()


def new_identity() -> str:
    return uuid.uuid4().hex


def _drop_inherited_claims() -> None:
    # A forked child shares its parent's open files, and with them the parent's locks: it must
    # not count them as its own (the parent still holds them), so it closes its copies.
    for _, fd in _claims.values():
        try:
            os.close(fd)
        except OSError:
            pass
    _claims.clear()


os.register_at_fork(after_in_child=_drop_inherited_claims)


def _claims_dir() -> Path:
    d = Path(tempfile.gettempdir()) / f"saggriac-teachers-{os.getuid()}"
    d.mkdir(mode=0o700, exist_ok=True)
    return d


def _holder(path: Path) -> str:
    try:
        return path.read_text().strip() or "unknown"
    except OSError:
        return "unknown"


def _refusal(owner: str, teacher: Any, holder: str) -> ConformanceError:
    return ConformanceError(
        f"{owner} (pid {os.getpid()}) was given a teacher, {teacher!r}, that a saggriac wrapper in another process (pid {holder}) already uses: "
        "it was copied into worker processes (a SubprocVecEnv, an AsyncVectorEnv or a process pool capturing it), so each copy would learn "
        "from its own worker only and the original would be told nothing. To keep one teacher for all workers, keep it in the main process: "
        "saggriac.adapters.sb3.TeacherCallback(teacher) for Stable-Baselines3, or saggriac.adapters.gym.VectorSelectorGoals around a Gymnasium vector "
        "environment. If each process is meant to have its own independent teacher, build it there, give each its own copy "
        "(copy.deepcopy(teacher) in the parent), or pass allow_copy=True."
    )


def claim(teacher: Any, owner: str, allow_copy: bool = False) -> None:
    """Claim ``teacher`` for this process, or raise ConformanceError if another process holds it."""
    identity = getattr(teacher, "_identity", None)
    if allow_copy or not isinstance(identity, str):
        return
    pid = os.getpid()
    with _lock:
        held = _claims.get(identity)
        if held is not None and held[0] == pid:
            return
        try:
            directory = _claims_dir()
        except OSError:
            return  # no writable temporary folder: nothing to lock with
        path = directory / f"{identity}.lock"
        while True:
            fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o600)
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError as e:
                os.close(fd)
                if e.errno in (errno.EWOULDBLOCK, errno.EAGAIN, errno.EACCES):
                    raise _refusal(owner, teacher, _holder(path)) from None
                raise
            # The file may have been unlinked by a releasing process between open and flock.
            try:
                same = os.fstat(fd).st_ino == os.stat(path).st_ino
            except FileNotFoundError:
                same = False
            if same:
                break
            os.close(fd)
        os.ftruncate(fd, 0)
        os.write(fd, str(pid).encode())
        _claims[identity] = (pid, fd)
    weakref.finalize(teacher, release, identity)


def release(identity: str) -> None:
    """Give up this process's claim (when its teacher is gone)."""
    with _lock:
        held = _claims.pop(identity, None)
        if held is None or held[0] != os.getpid():
            return
        try:
            (_claims_dir() / f"{identity}.lock").unlink()
        except OSError:
            pass
        os.close(held[1])


def holds(teacher: Any) -> bool:
    """Whether this process holds ``teacher``'s claim."""
    held = _claims.get(getattr(teacher, "_identity", None) or "")
    return held is not None and held[0] == os.getpid()
