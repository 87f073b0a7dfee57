"""How a copy of a teacher came to be, and how a worker's refusal reaches the process that started it.

A teacher sent to another process through multiprocessing (a pool's task, a queue, a process's
arguments) carries who sent it and how many copies that process had sent; one handed to a worker
when it started (captured by an environment factory of a SubprocVecEnv or an AsyncVectorEnv,
pickled at spawn or inherited through fork) is known as such. A worker that refuses its teacher
writes why into the private folder and sends its parent a real-time signal; the parent, which
listens only if it started workers from its main thread and has no handler of its own for that
signal, raises the worker's ConformanceError where the user built the vector environment.
"""

from __future__ import annotations

import atexit
import multiprocessing
import os
import signal
import sys
import threading
import time
import uuid
import weakref
from typing import Any

from ..errors import ConformanceError, WorkerRefusalError
from .private_folder import folder, names, read_private, remove, write_new

_lock = threading.RLock()
#: how many copies of each identity this process has sent to other processes
_sent: dict[str, int] = {}
#: whether a teacher with an identity exists in this process (a fork then hands copies out)
_has_teachers = False
_SIGNAL = signal.SIGRTMIN + 5 if hasattr(signal, "SIGRTMIN") else None  # a refusal in a worker, told to its parent
_armed = False
_REFUSAL_BYTES = 16384
_QUIET_SECONDS = 10.0  # after raising a worker's refusal, the others' are not raised again for this long
_told_at = -_QUIET_SECONDS - 1.0
_forking = False  # inside a fork's hooks, where an exception raised is dropped
_deferred = False  # a refusal came while forking, to be raised after
#: How long a refusing worker waits for its parent to read the refusal before it exits.
_WAIT_FOR_PARENT = 10.0
_GOAL_WRAPPERS = ("SelectorGoals", "VectorSelectorGoals")
#: teacher -> (the pid of the process it came to be in, the copy it is or None); a fork copies
#: this table with the teachers, so a forked worker finds its teachers born elsewhere
_origins: weakref.WeakKeyDictionary[Any, tuple[int, tuple[int, int, bool] | None]] = weakref.WeakKeyDictionary()


def mark_new(teacher: Any) -> None:
    """Called when a teacher object comes to be in this process (built or unpickled)."""
    global _has_teachers
    with _lock:
        _origins[teacher] = (os.getpid(), None)
    _has_teachers = True


def _sending() -> bool:
    # multiprocessing pickles what it sends with reduction.dump (a process's arguments at spawn)
    # or ForkingPickler.dumps (pools, queues, pipes); pickle.dump to a file goes through neither.
    frame = sys._getframe(2)
    for _ in range(64):
        if frame is None:
            return False
        code = frame.f_code
        if code.co_name in ("dump", "dumps") and code.co_filename.endswith(os.path.join("multiprocessing", "reduction.py")):
            return True
        frame = frame.f_back
    return False


def on_pickle(teacher: Any) -> tuple[int, int, bool] | None:
    """What a pickled teacher carries when it is sent to another process: (this pid, the number of
    copies of it sent so far, whether it goes with a process being started)."""
    identity = getattr(teacher, "_identity", None)
    if not isinstance(identity, str) or not _sending():
        return None
    import multiprocessing.context

    starting = multiprocessing.context.get_spawning_popen() is not None
    if starting:
        _arm()
    with _lock:
        _sent[identity] = _sent.get(identity, 0) + 1
        return (os.getpid(), _sent[identity], starting)


def on_unpickle(teacher: Any, copy_of: Any) -> None:
    """Record, on a teacher just unpickled, the copy it is (see :func:`on_pickle`)."""
    if isinstance(copy_of, (tuple, list)) and len(copy_of) == 3:
        # multiprocessing sets _inheriting while a new process unpickles what it was started with
        starting = bool(copy_of[2]) or bool(getattr(multiprocessing.current_process(), "_inheriting", False))
        with _lock:
            _origins[teacher] = (os.getpid(), (int(copy_of[0]), int(copy_of[1]), starting))


def copy_of(teacher: Any) -> tuple[int, int, bool] | None:
    """(sender pid, copy number, handed over at process start) for a copy made by multiprocessing,
    else None."""
    try:
        home, copied = _origins.get(teacher, (os.getpid(), None))
    except TypeError:
        return None  # not weakly referenceable: not a tracked teacher
    if home != os.getpid():
        return (home, 1, True)  # inherited through fork with the whole memory
    return copied


def _start_time(pid: int) -> str | None:
    # Field 22 of /proc/PID/stat: a pid reused by another process has another start time.
    try:
        with open(f"/proc/{pid}/stat", "rb") as f:
            text = f.read(4096)
        return text[text.rindex(b")") + 2 :].split()[19].decode()
    except (OSError, ValueError, IndexError):
        return None


def _arm() -> None:
    """Listen for refusals in workers this process starts (once; main thread only; never over a
    handler of the user's)."""
    global _armed
    if _armed or _SIGNAL is None or threading.current_thread() is not threading.main_thread():
        return
    if signal.getsignal(_SIGNAL) not in (signal.SIG_DFL, None):
        return
    started = _start_time(os.getpid())
    if started is None:
        return
    with folder(make=True) as dfd:
        if dfd is None:
            return
        name = f"listener-{os.getpid()}"
        remove(dfd, name)  # one of a process that had this pid before
        try:
            write_new(dfd, name, started.encode())
        except OSError:
            return
    signal.signal(_SIGNAL, _on_refusal)
    _armed = True
    atexit.register(_disarm, os.getpid())
    # Registered now, after the libraries the process imported (logging among them): a fork
    # runs this before-hook first and this after-hook last, so _forking covers all the others.
    os.register_at_fork(before=_fork_starts, after_in_parent=_fork_ended)


def _fork_starts() -> None:
    global _forking
    _forking = True


def _fork_ended() -> None:
    global _forking, _deferred
    _forking = False
    if _deferred:
        # Raised from a fork's hooks, the refusal would be printed and dropped ("Exception
        # ignored"): send it again once the fork has returned.
        _deferred = False
        timer = threading.Timer(0.01, os.kill, (os.getpid(), _SIGNAL))
        timer.daemon = True
        timer.start()


def _disarm(pid: int) -> None:
    if pid != os.getpid():
        return
    with folder() as dfd:
        if dfd is None:
            return
        for name in names(dfd):
            if name == f"listener-{pid}" or name.startswith(f"refusal-{pid}-"):
                remove(dfd, name)


def before_fork() -> None:
    if _has_teachers:
        _arm()


def after_fork_in_child() -> None:
    global _armed, _lock, _forking, _deferred
    _lock = threading.RLock()  # another thread of the parent may have held it at the fork
    _sent.clear()
    _forking = _deferred = False
    if _armed and _SIGNAL is not None:
        signal.signal(_SIGNAL, signal.SIG_DFL)  # the parent listens; a worker does not
    _armed = False


def tell_parent(message: str) -> None:
    """Hand a refusal to the process that started this worker, if it listens."""
    parent = multiprocessing.parent_process()
    if parent is None or _SIGNAL is None or parent.pid is None:
        return
    with folder() as dfd:
        if dfd is None:
            return
        started = read_private(dfd, f"listener-{parent.pid}", 64)
        if started is None or started.decode(errors="replace") != _start_time(parent.pid):
            return
        name = f"refusal-{parent.pid}-{os.getpid()}-{uuid.uuid4().hex}"
        try:
            write_new(dfd, name, message.encode()[:_REFUSAL_BYTES])
            os.kill(parent.pid, _SIGNAL)
        except OSError:
            return
        # Exit only once the parent has read the refusal (it removes the file), or after a
        # bound: this worker's exit closes its pipes, and a parent that sees the pipe close
        # first raises ConnectionResetError instead (seen under load with a fixed 0.5 s wait).
        deadline = time.monotonic() + _WAIT_FOR_PARENT
        while time.monotonic() < deadline:
            try:
                os.stat(name, dir_fd=dfd, follow_symlinks=False)
            except OSError:
                break
            time.sleep(0.02)


def _on_refusal(signum: int, frame: Any) -> None:
    global _deferred
    if _forking:
        _deferred = True
        return
    messages = []
    with folder() as dfd:
        if dfd is None:
            return
        for name in names(dfd):
            if name.startswith(f"refusal-{os.getpid()}-"):
                body = read_private(dfd, name, _REFUSAL_BYTES)
                remove(dfd, name)
                if body:
                    messages.append(body.decode(errors="replace"))
    global _told_at
    # The workers of one vector environment refuse together: raise once, not again in the
    # middle of the handling of the first (the others' signals come a moment later).
    if messages and time.monotonic() - _told_at > _QUIET_SECONDS:
        _told_at = time.monotonic()
        raise WorkerRefusalError(f"A worker process refused its teacher ({len(messages)} refusal{'s' if len(messages) > 1 else ''}; the first follows). {messages[0]}")

FIX = (
    "To keep one teacher for all workers, keep it in the main process: saggriac.adapters.sb3.TeacherCallback(teacher) for Stable-Baselines3, "
    "or saggriac.adapters.gym.VectorSelectorGoals around a Gymnasium vector environment. If each process or job is meant to have its own "
    "independent teacher, build it there, give each its own copy (copy.deepcopy(teacher), or saggriac.load_selector(path) for a saved one), "
    "or pass allow_copy=True."
)

def copy_refusal(owner: str, teacher: Any, copy_of: tuple[int, int, bool]) -> ConformanceError | None:
    sender, count, starting = copy_of
    if starting and owner in _GOAL_WRAPPERS:
        how = f"a copy of a teacher, {teacher!r}, handed to this worker when it started (an environment factory of a SubprocVecEnv or an AsyncVectorEnv, or a process's arguments, captured it)"
    elif count > 1:
        how = f"copy number {count} of a teacher, {teacher!r}, that process {sender} sent to worker processes (a pool or a queue given the same teacher {count} times)"
    else:
        return None
    return ConformanceError(
        f"{owner} (pid {os.getpid()}) was given {how}. It would learn from this worker's episodes only, and the teacher in process {sender} would be "
        f"told nothing. {FIX}"
    )
