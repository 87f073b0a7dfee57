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
start method, and so is a second copy of a teacher in one process; ``allow_copy=True`` on the
wrapper says that the copies are meant to be independent.

The claims live in a private folder, ``$TMPDIR/saggriac-teachers-UID`` (mode 0700). It is a
security boundary: a folder that is a link, belongs to another user or is open to others is not
used, lock files are opened without following links, and only a file this process created is
ever written. Where the claim cannot be taken safely (no such folder can be made, a read-only or
full temporary directory, something else at a lock's place), the wrapper still works but warns
with :class:`OwnershipWarning`, saying why and what goes unchecked.

Copies are also told apart by how they were made (:mod:`.copies`). A teacher sent to another process through
multiprocessing (a pool's task, a queue, a process's arguments) carries who sent it and how many
copies that process had sent; one handed to a worker when it started (captured by an environment
factory of a SubprocVecEnv or an AsyncVectorEnv, pickled at spawn or inherited through fork) is
known as such. A goal wrapper refuses such a start-up copy, and any wrapper refuses a second copy
sent from one process, whether or not the copies overlap in time. A worker that refuses tells
the process that started it, by a signal, so the user sees the refusal where they built the
vector environment instead of a reset connection or a hang.

Teachers without an identity (a user's own class) are not tracked.
"""

from __future__ import annotations

import errno
import fcntl
import itertools
import multiprocessing
import os
import stat
import threading
import time
import uuid
import warnings
import weakref
from dataclasses import dataclass
from typing import Any, Callable

from ..errors import ConformanceError
from ..files import Busy, CannotLock, flock_at
from . import copies
from .copies import FIX
from .private_folder import Unchecked, alive, claims_dir, folder, open_claims_dir, remove, same_file


class OwnershipWarning(UserWarning):
    """A wrapper could not check that its teacher is used by one process only."""


@dataclass
class _Claim:
    pid: int
    fd: int | None  # None: the check could not be made here (warned once)
    teacher: Callable[[], Any]  # a weak reference to the object that holds the claim
    token: int


#: identity -> this process's claim
_claims: dict[str, _Claim] = {}
_lock = threading.RLock()
_tokens = itertools.count()
_HOLDER_BYTES = 64  # "pid ppid worker": the most a holder's note is read
_SWEEP_MAX = 256  # stale lock files removed at most per claim
_SETTLE_SECONDS = 1.0  # how long a lock held with no live holder's note is looked at again


def new_identity() -> str:
    return uuid.uuid4().hex


def _after_fork_in_child() -> None:
    global _lock
    _lock = threading.RLock()  # another thread of the parent may have held it at the fork
    _drop_inherited_claims()
    copies.after_fork_in_child()


def _drop_inherited_claims() -> None:
    # A forked child shares its parent's open files, and with them the parent's locks: it must
    # not count them as its own (the parent still holds them), so it closes its copies.
    for held in _claims.values():
        if held.fd is not None:
            try:
                os.close(held.fd)
            except OSError:
                pass
    _claims.clear()


os.register_at_fork(before=copies.before_fork, after_in_child=_after_fork_in_child)




def _is_worker() -> bool:
    """Whether this process was started by multiprocessing (a pool's or a vector env's worker)."""
    return multiprocessing.parent_process() is not None


def _read_holder(dfd: int, name: str) -> tuple[int, int, int] | None:
    """The pid, parent pid and worker flag written by the holder of a lock file, or None."""
    try:
        fd = os.open(name, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK | os.O_CLOEXEC, dir_fd=dfd)
    except OSError:
        return None
    try:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            return None
        parts = os.read(fd, _HOLDER_BYTES).split()
        return (int(parts[0]), int(parts[1]), int(parts[2])) if len(parts) == 3 else None
    except (OSError, ValueError):
        return None
    finally:
        os.close(fd)


def _checked(dfd: int, name: str, fd: int) -> None:
    """Refuse, as not saggriac's, a lock file that is not a regular file of this user's with one name."""
    st = os.fstat(fd)
    if not stat.S_ISREG(st.st_mode) or st.st_uid != os.getuid() or st.st_nlink != 1:
        os.close(fd)
        what = "not a regular file" if not stat.S_ISREG(st.st_mode) else "not yours" if st.st_uid != os.getuid() else "a file with another name too (a hard link)"
        raise Unchecked(f"{claims_dir() / name} is {what}, not a lock file saggriac made; remove it")


def _take(dfd: int, identity: str) -> int | tuple[int, int, int]:
    """Take the lock of ``identity``: its descriptor, or the holder's note (pid, ppid, worker
    flag; pid 0 when unknown) if another process holds it."""
    name = f"{identity}.lock"
    deadline = time.monotonic() + _SETTLE_SECONDS
    while True:
        try:
            fd, made = flock_at(dfd, name)
        except Busy:
            holder = _read_holder(dfd, name)
            if holder is not None and alive(holder[0]):
                return holder
            # No live holder has written its note: another process is between its flock and its
            # note, or clearing a stale file. Look again before calling the teacher taken.
            if time.monotonic() < deadline:
                time.sleep(0.01)
                continue
            return (0, 0, 0)
        except CannotLock as e:
            raise Unchecked(f"the temporary directory's file system cannot lock files ({e.error.strerror})") from None
        except OSError as e:
            where = claims_dir() / name
            if e.errno in (errno.ELOOP, errno.EISDIR):
                kind = "a symbolic link" if e.errno == errno.ELOOP else "a folder"
                raise Unchecked(f"{where} is {kind}, not a lock file saggriac made; remove it") from None
            raise Unchecked(f"the lock file {where} cannot be made ({e.strerror}); free space in the temporary directory, or point TMPDIR at a writable folder") from None
        _checked(dfd, name, fd)
        if not made:
            # A lock file left by a process that ended: ours must be a file made here, so that
            # nothing but saggriac's own file is ever written. Remove it and make a new one.
            os.unlink(name, dir_fd=dfd)
            os.close(fd)
            continue
        try:
            os.write(fd, f"{os.getpid()} {os.getppid()} {int(_is_worker())}\n".encode())
        except OSError:
            pass  # a full disk: the lock holds all the same, the holder is then "unknown"
        return fd


def _sweep(dfd: int) -> None:
    # Lock files of processes that ended (killed, os._exit) pile up: remove those nobody holds.
    try:
        names = [n for n in itertools.islice(os.listdir(dfd), 4 * _SWEEP_MAX) if n.endswith(".lock")][:_SWEEP_MAX]
    except OSError:
        return
    for name in names:
        try:
            fd = os.open(name, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK | os.O_CLOEXEC, dir_fd=dfd)
        except OSError:
            continue
        try:
            st = os.fstat(fd)
            if stat.S_ISREG(st.st_mode) and st.st_uid == os.getuid() and st.st_nlink == 1:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
                if same_file(dfd, name, fd):
                    os.unlink(name, dir_fd=dfd)
        except OSError:
            pass
        finally:
            os.close(fd)



def _who(holder: tuple[int, int, int]) -> str:
    pid, ppid, worker = holder
    if pid == 0:
        return "another process (its pid is unknown)"
    if pid == os.getppid():
        return f"the process that started this one (pid {pid}) and handed it a copy"
    if ppid == os.getpid():
        return f"a worker this process started (pid {pid}) with a copy of it"
    if worker and ppid == os.getppid():
        return f"a sibling worker (pid {pid}) started from the same parent with a copy of it"
    if worker or _is_worker():
        return f"another process (pid {pid}) that received a copy of it"
    return f"another process (pid {pid}), no worker of this one: two jobs each loaded the same saved teacher (pickle keeps a teacher's identity)"


def _refusal(owner: str, teacher: Any, holder: tuple[int, int, int] | None) -> ConformanceError:
    where = "another copy of the same teacher in this process" if holder is None else _who(holder)
    return ConformanceError(
        f"{owner} (pid {os.getpid()}) was given a teacher, {teacher!r}, that a saggriac wrapper already uses through {where}. "
        f"Each copy would learn from its own episodes only, and the other would be told nothing. {FIX}"
    )


def _unchecked_warning(owner: str, teacher: Any, why: str) -> None:
    warnings.warn(
        f"{owner} cannot check that {teacher!r} is used by this process only: {why}. Unchecked, a copy of this teacher in another process "
        "(a worker of a SubprocVecEnv, an AsyncVectorEnv or a pool capturing it) would learn alone while this one is told nothing.",
        OwnershipWarning,
        stacklevel=4,
    )



def claim(teacher: Any, owner: str, allow_copy: bool = False) -> None:
    """Claim ``teacher`` for this process; raise ConformanceError if it is a copy sent to this
    worker, or another process or another copy in this process holds it; warn with
    OwnershipWarning if it cannot be checked. A worker's refusal is also told to its parent."""
    identity = getattr(teacher, "_identity", None)
    if allow_copy or not isinstance(identity, str):
        return
    try:
        copy_of = copies.copy_of(teacher)
        refusal = copies.copy_refusal(owner, teacher, copy_of) if copy_of else None
        if refusal is not None:
            raise refusal
        _claim(teacher, owner, identity)
    except ConformanceError as e:
        copies.tell_parent(str(e))
        raise


def _claim(teacher: Any, owner: str, identity: str) -> None:
    # Nothing that may run a user's code or the garbage collector's finalizers (a teacher's
    # repr, a warning) runs under the lock; the lock is reentrant all the same, since a
    # finalizer (release) may run in this thread wherever memory is allocated.
    pid = os.getpid()
    why: str | None = None
    with _lock:
        held = _claims.get(identity)
        if held is not None and held.pid == pid:
            holder = held.teacher()
            if holder is teacher:
                return
            if holder is not None:
                got: Any = None  # another live copy here
            else:
                release(identity, held.token)  # the copy that held it is gone: free it first
                held = None
        if held is None:
            try:
                dfd = open_claims_dir()
                try:
                    _sweep(dfd)
                    got = _take(dfd, identity)
                finally:
                    os.close(dfd)
            except Unchecked as e:
                why, got = str(e), None
            if not isinstance(got, tuple):
                token = next(_tokens)
                _claims[identity] = _Claim(pid, got, weakref.ref(teacher), token)
    if held is not None:
        raise _refusal(owner, teacher, None)
    if isinstance(got, tuple):
        raise _refusal(owner, teacher, got)
    weakref.finalize(teacher, release, identity, token)
    if why is not None:
        _unchecked_warning(owner, teacher, why)


def release(identity: str, token: int | None = None) -> None:
    """Give up this process's claim (when the teacher that holds it is gone)."""
    with _lock:
        held = _claims.get(identity)
        if held is None or held.pid != os.getpid() or (token is not None and held.token != token):
            return
        del _claims[identity]
        if held.fd is None:
            return
        with folder() as dfd:
            if dfd is not None and same_file(dfd, f"{identity}.lock", held.fd):
                remove(dfd, f"{identity}.lock")
        os.close(held.fd)


def holds(teacher: Any) -> bool:
    """Whether this process holds ``teacher``'s claim (that is, ``teacher`` itself holds it)."""
    held = _claims.get(getattr(teacher, "_identity", None) or "")
    return held is not None and held.pid == os.getpid() and held.teacher() is teacher and held.fd is not None
