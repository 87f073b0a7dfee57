"""Where a study's runs are computed: a local process pool, or Dask (a local cluster that serves
no HTTP, a scheduler's address, a client, or a cluster object such as SLURMCluster)."""

from __future__ import annotations

import contextlib
import ctypes
import os
import math
import re
import shutil
import signal
import struct
import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from ..errors import ParameterError
from ..runs.resources import share_cores
from .spec import Task, run_task


def default_workers() -> int:
    # Honour CPU affinity (SLURM allocations, containers), where os.cpu_count() counts the node.
    if hasattr(os, "process_cpu_count"):
        return os.process_cpu_count() or 1
    if hasattr(os, "sched_getaffinity"):
        return len(os.sched_getaffinity(0)) or 1
    return os.cpu_count() or 1


def _die_with_parent(parent_pid: int, n_workers: int = 1) -> None:
    """Pool worker initializer: on Linux, be killed when the study process dies, so a killed
    study leaves no orphan still writing runs into the folder; and take a worker's share of the
    cores for the teachers' threads."""
    share_cores(n_workers)
    if sys.platform.startswith("linux"):
        try:
            ctypes.CDLL(None, use_errno=True).prctl(1, int(signal.SIGKILL))  # PR_SET_PDEATHSIG
        except (OSError, AttributeError):  # pragma: no cover - exotic libc
            return
        if os.getppid() != parent_pid:  # the parent died before prctl
            os._exit(1)


#: Relative cost of a run per micro-action, by condition; 1.0 for the others (exp2 at full scale,
#: docs/reproduction.md: ACTUATOR-RIAC 28 s, ACTUATOR-Random 11 s, the SAGG conditions 6.4 s).
#: Used only to order work, and by benchmarks to size theirs.
COST_HINT = {"actuator_riac": 4.0, "actuator_random": 1.7}


def longest_first_by_seed(tasks: list[Task]) -> list[Task]:
    """The tasks seed by seed (a partial study still compares conditions on the same seeds), the
    costliest first within a seed, so the last seed's long run does not start last and leave the
    other workers idle at the end."""
    seed_rank = {seed: i for i, seed in enumerate(dict.fromkeys(t.seed for t in tasks))}

    def cost(t: Task) -> float:
        return float(t.config.get("n_steps", 1)) * COST_HINT.get(t.condition, 1.0)

    return sorted(tasks, key=lambda t: (seed_rank[t.seed], -cost(t)))


def run_local(tasks: list[Task], out: Path, n_workers: int, on_done: Callable[[Task, Any], None]) -> None:
    import concurrent.futures as cf
    import multiprocessing

    ctx = multiprocessing.get_context("spawn")
    with cf.ProcessPoolExecutor(max_workers=n_workers, mp_context=ctx, initializer=_die_with_parent, initargs=(os.getpid(), n_workers)) as pool:
        futures = {pool.submit(run_task, t, str(out)): t for t in tasks}
        try:
            for fut in cf.as_completed(futures):
                on_done(futures[fut], fut)
        except BaseException:
            pool.shutdown(wait=False, cancel_futures=True)
            raise


def import_distributed() -> Any:
    try:
        import distributed
    except ImportError as e:
        raise ImportError(f'backend="dask" needs Dask distributed, which is not installed ({e}). Install it with: pip install "saggriac[dask]"') from e
    return distributed


@contextmanager
def local_cluster(n_workers: int) -> Iterator[Any]:
    """A Dask LocalCluster of ``n_workers`` single-threaded worker processes on 127.0.0.1 that
    serves no HTTP. Dask's scheduler always starts an HTTP server (on port 8787 when
    ``dashboard_address=None``, with a warning and another port if 8787 is taken); here it has no
    routes, listens on a free loopback port only while the cluster starts, and is then closed.
    Workers serve no routes either."""
    distributed = import_distributed()
    import dask

    quiet = {"distributed.scheduler.http.routes": [], "distributed.worker.http.routes": []}
    with dask.config.set(quiet):
        cluster = distributed.LocalCluster(
            n_workers=n_workers,
            threads_per_worker=1,
            processes=True,
            host="127.0.0.1",
            dashboard_address="127.0.0.1:0",
            worker_dashboard_address="127.0.0.1:0",
            scheduler_kwargs={"dashboard": False},
        )
    with cluster:
        server = getattr(cluster.scheduler, "http_server", None)
        if server is not None:
            server.stop()
        with distributed.Client(cluster, set_as_default=False) as client:
            client.run(_stop_worker_http)
        yield cluster


def _stop_worker_http(dask_worker: Any) -> None:
    """Run in each worker of :func:`local_cluster`: close its (route-less) HTTP server."""
    server = getattr(dask_worker, "http_server", None)
    if server is not None:
        server.stop()


@contextmanager
def _dask_client(distributed: Any, scheduler: Any, n_workers: int) -> Iterator[Any]:
    if isinstance(scheduler, distributed.Client):
        yield scheduler  # the caller's client: theirs to close
    elif scheduler is None:
        with local_cluster(n_workers) as cluster, distributed.Client(cluster, set_as_default=False) as client:
            yield client
    else:  # an address, or a cluster object (LocalCluster, dask_jobqueue.SLURMCluster, ...)
        try:
            client = distributed.Client(scheduler, set_as_default=False, timeout=SCHEDULER_TIMEOUT)
        except (OSError, TimeoutError, ValueError) as e:
            raise ParameterError(f"The 'scheduler' parameter of run_study names a Dask scheduler that does not answer within {SCHEDULER_TIMEOUT} s: {scheduler!r} ({type(e).__name__}: {e}).", "scheduler", repr(scheduler)) from None
        with client:
            yield client


#: Seconds to wait for a Dask scheduler to answer before giving up.
SCHEDULER_TIMEOUT = 10


def check_scheduler(address: str) -> None:
    """Refuse, before anything is written, an address that is not one, a scheduler that does
    not answer within SCHEDULER_TIMEOUT seconds (Dask itself waits 30 s, then may hang on exit),
    and a tcp:// peer that does not greet as a Dask scheduler (see _not_a_scheduler)."""
    import socket

    rule = "an address such as 'tcp://HOST:PORT'"
    web = re.fullmatch(r"(https?)://\[?([A-Za-z0-9_.:-]*?)\]?(?::(\d{1,5}))?(/.*)?", address.strip())
    if web is not None:
        # Dask would try it for 20 s and end in a TimeoutError that names neither cause.
        scheme, host = web.group(1), web.group(2) or "127.0.0.1"
        port = int(web.group(3) or (443 if scheme == "https" else 80))
        raise ParameterError(
            f"The 'scheduler' parameter of run_study must be {rule}: a Dask scheduler speaks Dask's own protocol over tcp:// (port 8786 unless set), "
            f"not {scheme}://, which is its dashboard's (port 8787). Got {address!r}; {_what_answers(host, port, scheme)}.",
            "scheduler",
            repr(address),
        )
    m = re.fullmatch(r"(?:(tcp|tls)://)?\[?([A-Za-z0-9_.:-]*?)\]?:(\d{1,5})", address.strip())
    if m is None:
        if re.fullmatch(r"[a-z]+://.+", address.strip()):
            return  # another Dask protocol (ucx://, inproc://): Dask checks it, with the timeout
        raise ParameterError(f"The 'scheduler' parameter of run_study must be {rule}. Got {address!r} instead.", "scheduler", repr(address))
    host, port = m.group(2) or "127.0.0.1", int(m.group(3))
    if not 0 < port < 65536:
        raise ParameterError(f"The 'scheduler' parameter of run_study must be {rule} with a port in 1..65535. Got {address!r} instead.", "scheduler", repr(address))
    try:
        conn = socket.create_connection((host, port), timeout=SCHEDULER_TIMEOUT)
    except OSError as e:
        raise ParameterError(f"The 'scheduler' parameter of run_study names {address!r}, where no Dask scheduler answers within {SCHEDULER_TIMEOUT} s ({e.strerror or e}). Start it (dask scheduler) or check the address.", "scheduler", repr(address)) from None
    with conn:
        # A TLS server waits for the client's hello: only a plain tcp:// peer can be heard first.
        what = None if m.group(1) == "tls" else _not_a_scheduler(conn)
    if what is not None:
        raise ParameterError(
            f"The 'scheduler' parameter of run_study names {address!r}, where no Dask scheduler answers: {what}. Check the address "
            "(a scheduler prints its own as 'Scheduler at: tcp://HOST:PORT').",
            "scheduler",
            repr(address),
        )


#: Seconds to wait for a web server's first line.
PROBE_TIMEOUT = 3.0


#: Seconds to wait for the greeting a Dask scheduler sends as soon as it accepts a connection.
GREETING_TIMEOUT = 5.0

#: The greeting's size is read as Dask reads it (a native u64); a handshake is a few dozen bytes.
_FRAME = struct.Struct("Q")
_MAX_GREETING = 1 << 16


def _recv(conn: Any, n: int) -> bytes:
    """Up to ``n`` bytes: fewer only if the peer closed the connection."""
    data = b""
    while len(data) < n:
        chunk = conn.recv(n - len(data))
        if not chunk:
            break
        data += chunk
    return data


def _greeting(head: bytes, conn: Any) -> bytes | None:
    """The whole of a Dask message that starts with ``head`` (its 8-byte size), or None if what
    follows is not laid out as one: a count of frames, their sizes, then the frames."""
    if len(head) < _FRAME.size:
        return None
    (size,) = _FRAME.unpack(head[: _FRAME.size])
    if not 2 * _FRAME.size <= size <= _MAX_GREETING:
        return None
    try:
        body = _recv(conn, size)
    except OSError:
        return None
    if len(body) < size:
        return None
    (n_frames,) = _FRAME.unpack_from(body)
    if not 1 <= n_frames <= (size - _FRAME.size) // _FRAME.size:
        return None
    lengths = struct.unpack_from(f"{n_frames}Q", body, _FRAME.size)
    return head + body if _FRAME.size * (1 + n_frames) + sum(lengths) == size else None


def _described(data: bytes) -> str:
    """What sent ``data``, in words."""
    if data.startswith(b"HTTP/"):
        lines = data.decode("latin-1").splitlines()
        server = next((ln.split(":", 1)[1].strip() for ln in lines if ln.lower().startswith("server:")), None)
        return (
            f"an HTTP server answers there (it replied {lines[0].strip()!r}" + (f", server {server!r}" if server else "") + "), perhaps a Dask "
            "dashboard: the scheduler itself speaks Dask's protocol on another port, 8786 unless set"
        )
    return f"what answers there does not speak Dask's protocol (it sent {data[:40]!r})"


def _not_a_scheduler(conn: Any) -> str | None:
    """None if the peer of ``conn`` greets as a Dask scheduler does, else what it is, in words.

    A scheduler sends its handshake as soon as it accepts (distributed.comm.core), and Dask's
    client waits for it without a bound: a silent peer hangs ``Client()``, and an HTTP reply is
    read as a frame size of exabytes (MemoryError). So the greeting is awaited here for
    GREETING_TIMEOUT seconds; only a silent peer is then sent an HTTP request, to name it."""
    conn.settimeout(GREETING_TIMEOUT)
    try:
        head = conn.recv(_FRAME.size)
    except TimeoutError:
        head = None
    except OSError as e:
        return f"the connection was accepted, then failed ({e.strerror or e})"
    if head is not None:
        if not head:
            return "something accepted the connection and closed it without a word"
        with contextlib.suppress(OSError):
            head += _recv(conn, _FRAME.size - len(head))
        greeting = _greeting(head, conn)
        if greeting is None:
            return _described(head + _peek(conn))
        # Sent back as our own handshake: the scheduler then logs no connection closed mid-handshake.
        with contextlib.suppress(OSError):
            conn.sendall(greeting)
        return None
    waited = GREETING_TIMEOUT + PROBE_TIMEOUT
    try:
        conn.sendall(b"HEAD / HTTP/1.0\r\n\r\n")
        conn.settimeout(PROBE_TIMEOUT)
        reply = conn.recv(_FRAME.size)
    except TimeoutError:
        return f"something accepted the connection but said nothing in {waited:g} s (a Dask scheduler greets at once)"
    except OSError as e:
        return f"something accepted the connection, said nothing in {GREETING_TIMEOUT:g} s, then failed ({e.strerror or e})"
    if not reply:
        return f"something accepted the connection, said nothing in {GREETING_TIMEOUT:g} s, then closed it"
    with contextlib.suppress(OSError):
        reply += _recv(conn, _FRAME.size - len(reply))
    if _greeting(reply, conn) is not None:
        return None  # a scheduler slow to greet (it then logs our request as a bad message)
    return _described(reply + _peek(conn))


def _peek(conn: Any) -> bytes:
    """What else the peer sends within a moment (the rest of an HTTP status line and headers)."""
    conn.settimeout(0.5)
    try:
        return conn.recv(1024)
    except OSError:
        return b""


def _what_answers(host: str, port: int, scheme: str) -> str:
    """What answers an HTTP request at host:port, in words (its status line and server)."""
    import socket

    if scheme == "https":
        return f"saggriac did not look at what answers at {host}:{port} (https)"
    try:
        with socket.create_connection((host, port), timeout=PROBE_TIMEOUT) as s:
            s.settimeout(PROBE_TIMEOUT)
            s.sendall(f"HEAD / HTTP/1.0\r\nHost: {host}\r\n\r\n".encode())
            head = s.recv(4096).decode("latin-1")
    except OSError as e:
        return f"nothing answers at {host}:{port} ({e.strerror or e})"
    lines = head.splitlines()
    if not lines or not lines[0].startswith("HTTP/"):
        return f"what answers at {host}:{port} is not a web server ({head[:60]!r})"
    server = next((ln.split(":", 1)[1].strip() for ln in lines if ln.lower().startswith("server:")), None)
    dashboard = " (Tornado: likely Dask's dashboard; its scheduler is then at tcp://HOST:8786)" if server and "tornado" in server.lower() else ""
    return f"at {host}:{port} a web server answers {lines[0].strip()!r}" + (f", server {server!r}" if server else "") + dashboard


#: Seconds to wait for the first Dask worker to join a given scheduler or cluster before giving up.
WORKER_TIMEOUT = 120.0


def check_worker_timeout(value: Any, owner: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not (math.isfinite(value) and value > 0):
        raise ParameterError(f"The 'worker_timeout' parameter of {owner} must be a number of seconds > 0. Got {value!r} instead.", "worker_timeout", repr(value))
    return float(value)


def check_scheduler_type(distributed: Any, scheduler: Any) -> None:
    """Refuse what Dask's Client takes for neither an address nor a cluster."""
    # Dask's own test: a cluster is any object with a scheduler_address (SpecCluster, SLURMCluster).
    if scheduler is None or isinstance(scheduler, (str, distributed.Client)) or hasattr(scheduler, "scheduler_address"):
        return
    raise ParameterError(
        "The 'scheduler' parameter of run_study must be a Dask scheduler's address (a str such as 'tcp://HOST:8786'), a "
        f"distributed.Client, or a cluster object such as LocalCluster or dask_jobqueue.SLURMCluster. Got {scheduler!r} instead.",
        "scheduler",
        repr(scheduler),
    )


def check_cluster(scheduler: Any) -> None:
    """Refuse, before anything is written, a dask-jobqueue cluster whose job submission command
    is not on this machine (SLURMCluster without sbatch): its jobs can never start, and Dask
    says so only in an asynchronous traceback while the study would wait."""
    command = getattr(getattr(scheduler, "job_cls", None), "submit_command", None)
    if isinstance(command, str) and command.split() and shutil.which(command.split()[0]) is None:
        raise ParameterError(
            f"The 'scheduler' parameter of run_study is a {type(scheduler).__name__} whose jobs are submitted with {command.split()[0]!r}, "
            "which is not on this machine's PATH: no worker could ever start. Run the study on a login node of the cluster (where "
            f"{command.split()[0]} works), or use backend='local'.",
            "scheduler",
            type(scheduler).__name__,
        )


def _failed_jobs(scheduler: Any) -> list[str]:
    """Jobs of a dask-jobqueue cluster that never got a job id (their submission failed)."""
    jobs = getattr(scheduler, "workers", None)
    if not isinstance(jobs, dict):
        return []
    return [str(name) for name, job in jobs.items() if hasattr(job, "job_id") and job.job_id is None]


def _wait_for_a_worker(client: Any, scheduler: Any, timeout: float) -> None:
    try:
        client.wait_for_workers(1, timeout=timeout)
    except TimeoutError:
        what = type(scheduler).__name__ if not isinstance(scheduler, str) else f"the scheduler at {scheduler}"
        failed = _failed_jobs(scheduler)
        hint = (
            f"its jobs {', '.join(failed)} have no job id (their submission failed: see Dask's messages above, and check the queue command, "
            "the account and the partition)"
            if failed
            else "check that the cluster was given workers (cluster.scale(jobs=...) or cluster.adapt(...)), that its jobs start (squeue, or "
            "your queue's own command) and that the workers can reach the scheduler"
        )
        raise ParameterError(
            f"The 'scheduler' parameter of run_study names {what}, where no Dask worker joined within {timeout:g} s: {hint}. "
            "Nothing was run; worker_timeout= gives the workers more time.",
            "scheduler",
            what,
        ) from None


def run_dask(tasks: list[Task], out: Path, n_workers: int, scheduler: Any, on_done: Callable[[Task, Any], None], worker_timeout: float = WORKER_TIMEOUT) -> None:
    distributed = import_distributed()
    with _dask_client(distributed, scheduler, n_workers) as client:
        if scheduler is not None:
            _wait_for_a_worker(client, scheduler, worker_timeout)
        futures = {client.submit(run_task, t, str(out), pure=False): t for t in tasks}
        try:
            for fut in distributed.as_completed(list(futures), loop=client.loop):
                on_done(futures.pop(fut), fut)
        except BaseException:
            client.cancel(list(futures))
            raise
