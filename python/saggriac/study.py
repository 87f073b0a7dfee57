"""Studies: many runs (conditions x seeds x parameter grid) on all cores, on Dask, or on SLURM.

A study folder holds ``study.json`` (what the study is) and one run directory per run, at
``runs/<condition>[__key=value...]/seed<k>/``. A run directory is finished when it holds
``run.json`` (storage.write_run writes it last); finished runs are never recomputed, so a study
that was stopped is resumed by calling :func:`run_study` again. See docs/studies.md.
"""

from __future__ import annotations

import ctypes
import itertools
import json
import os
import re
import shutil
import signal
import sys
import time
import warnings
from collections.abc import Callable, Iterable, Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import pyarrow.parquet as pq

from . import _core
from .config import Config, check_keys
from .errors import ParameterError, SaggriacError, StorageError
from .files import write_file
from .runner import recover, run
from .seeding import check_seed
from .storage import MANIFEST, as_path, clear_stale_lock, run_damage

STUDY_FILE = "study.json"
LOCK_FILE = ".lock"
RUNS_DIR = "runs"
METRICS = ("reach_error", "pred_error", "dx_error", "n_goals", "n_regions")
_FORMAT = 1
_SAFE_TEXT = re.compile(r"[A-Za-z0-9_.+-]+")


class StudyError(SaggriacError):
    """Some runs of a study failed. ``failures`` maps each failed run's name to its exception;
    every other run is finished and saved."""

    def __init__(self, message: str, failures: dict[str, BaseException]):
        super().__init__(message)
        self.failures = failures


def _plain(value: Any) -> Any:
    """Numpy scalars to Python, sequences to tuples: hashable, comparable, JSON-ready."""
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, (list, tuple, np.ndarray)):
        return tuple(_plain(v) for v in value)
    return value


def _json_ready(value: Any) -> Any:
    if isinstance(value, tuple):
        return [_json_ready(v) for v in value]
    return value


def _format_value(key: str, value: Any) -> str:
    """A grid value as it appears in a directory name."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return repr(value)
    if value is None:
        return "none"
    if isinstance(value, str) and _SAFE_TEXT.fullmatch(value):
        return value
    if isinstance(value, tuple) and value:
        return ",".join(_format_value(key, v) for v in value)
    raise ParameterError(
        f"The values of grid key '{key}' must be numbers, None, strings of letters, digits and _.+- "
        f"or lists of those (they name directories). Got {value!r} instead.",
        "grid",
        repr(value),
    )


@dataclass(frozen=True)
class Task:
    """One run of a study: everything a worker needs, small and picklable."""

    name: str  # e.g. "sagg_riac__g_max=40/seed0"
    path: str  # relative to the study folder, e.g. "runs/sagg_riac__g_max=40/seed0"
    condition: str
    params: dict[str, Any]  # this run's grid point
    seed: int
    config: dict[str, Any]  # Config.to_dict() of the run


@dataclass(frozen=True)
class Study:
    """Runs of ``base`` for every condition, seed and point of ``grid`` (a dict from parameter
    names to lists of values; the product of its lists is taken)."""

    base: Config
    conditions: tuple[str, ...]
    seeds: tuple[int, ...]
    grid: dict[str, tuple] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if not isinstance(self.base, Config):
            raise ParameterError(f"The 'base' parameter of Study must be a saggriac.Config. Got {type(self.base).__name__} instead.", "base", repr(self.base))
        conditions = (self.conditions,) if isinstance(self.conditions, str) else tuple(self.conditions)
        seeds = tuple(check_seed(s) for s in ([self.seeds] if isinstance(self.seeds, (int, np.integer)) else self.seeds))
        grid = {} if self.grid is None else self.grid
        if not isinstance(grid, Mapping):
            raise ParameterError(f"The 'grid' parameter of Study must be a dict from parameter names to lists of values. Got {type(grid).__name__} instead.", "grid", repr(grid))
        for name, values in (("conditions", conditions), ("seeds", seeds)):
            if not values:
                raise ParameterError(f"The '{name}' parameter of Study must not be empty.", name, repr(values))
            if len(set(values)) != len(values):
                raise ParameterError(f"The '{name}' parameter of Study must not repeat a value. Got {values!r} instead.", name, repr(values))
        check_keys(dict(grid), source=None)
        if "condition" in grid:
            raise ParameterError("The 'grid' parameter of Study cannot hold 'condition'; list the conditions in 'conditions'.", "grid", repr(dict(grid)))
        clean: dict[str, tuple] = {}
        for key in sorted(grid):
            values = grid[key]
            if isinstance(values, (str, bytes)) or not isinstance(values, Iterable):
                raise ParameterError(f"The values of grid key '{key}' must be a list. Got {values!r} instead.", "grid", repr(values))
            values = tuple(_plain(v) for v in values)
            if not values:
                raise ParameterError(f"The values of grid key '{key}' must not be empty.", "grid", repr(values))
            names = [_format_value(key, v) for v in values]
            if len(set(names)) != len(names):
                raise ParameterError(f"The values of grid key '{key}' must be distinct. Got {values!r} instead.", "grid", repr(values))
            clean[key] = values
        object.__setattr__(self, "conditions", conditions)
        object.__setattr__(self, "seeds", seeds)
        object.__setattr__(self, "grid", clean)
        self.tasks()  # every run's configuration is checked now, before any work

    def __hash__(self) -> int:
        return hash(json.dumps(self.to_dict(), sort_keys=True))

    def points(self) -> list[dict[str, Any]]:
        """The grid points, keys in sorted order (one empty point without a grid)."""
        keys = list(self.grid)
        return [dict(zip(keys, combo)) for combo in itertools.product(*(self.grid[k] for k in keys))]

    def tasks(self) -> list[Task]:
        """Every run, seed by seed (so a partial study compares conditions on the same seeds)."""
        out = []
        for seed in self.seeds:
            for condition in self.conditions:
                for point in self.points():
                    cfg = self.base.replace(condition=condition, **point)
                    group = condition + "".join(f"__{k}={_format_value(k, v)}" for k, v in point.items())
                    name = f"{group}/seed{seed}"
                    out.append(Task(name=name, path=f"{RUNS_DIR}/{name}", condition=condition, params=point, seed=seed, config=cfg.to_dict()))
        return out

    def to_dict(self) -> dict[str, Any]:
        return {
            "base": self.base.to_dict(),
            "conditions": list(self.conditions),
            "seeds": list(self.seeds),
            "grid": {k: [_json_ready(v) for v in vals] for k, vals in self.grid.items()},
        }

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Study:
        return cls(base=Config.from_saved(d["base"]), conditions=tuple(d["conditions"]), seeds=tuple(d["seeds"]), grid=dict(d.get("grid") or {}))

    @classmethod
    def load(cls, out_dir: str | Path) -> Study:
        """The study recorded in ``out_dir/study.json``."""
        path = Path(out_dir) / STUDY_FILE
        try:
            data = json.loads(path.read_text())
        except FileNotFoundError:
            raise StorageError(f"{Path(out_dir)} is not a study folder (no {STUDY_FILE}).") from None
        except (OSError, ValueError) as e:
            raise StorageError(f"Cannot read {path}: {e}") from None
        try:
            return cls.from_dict(data["study"])
        except (KeyError, TypeError, ParameterError) as e:
            raise StorageError(f"{path} does not describe a study this version of saggriac can read: {e}") from None


def run_task(task: Task, out_root: str | os.PathLike) -> str:
    """Run one task of a study into ``out_root/task.path`` and return that path. Top-level and
    picklable, for process pools and Dask workers; a finished run is left as it is."""
    out = Path(out_root) / task.path
    # Idempotent, so a scheduler that retries a task whose result was already written is harmless.
    if not (out / MANIFEST).exists():
        # One thread per run: the study's workers already use every core.
        try:
            run(Config(**task.config), seed=task.seed, out_dir=out, progress=False, threads=1)
        except StorageError as e:
            result = getattr(e, "result", None)
            if result is None:
                raise
            # The work is done but its folder cannot be written: keep it, and say where, in a
            # message that survives the trip back from a worker process.
            raise StorageError(recover(result, out, str(e))) from None
    return str(out)


def _set_aside(run_dir: Path) -> Path:
    """Move a damaged run out of the study's way, keeping what is left of it."""
    stamp = time.strftime("%Y%m%d-%H%M%S")
    for i in range(1000):
        aside = run_dir.with_name(f".{run_dir.name}.damaged-{stamp}{'' if i == 0 else f'-{i}'}")
        if not os.path.lexists(aside):
            run_dir.rename(aside)
            return aside
    raise StorageError(f"Cannot set the damaged run {run_dir} aside: too many earlier copies beside it; delete them.")  # pragma: no cover


@dataclass
class StudyResult:
    path: Path
    study: Study
    n_computed: int  # runs computed by this call
    n_skipped: int  # runs already finished before this call
    #: Damaged runs found and recomputed by this call: name -> what was wrong, where it was set aside.
    repaired: dict[str, str] = field(default_factory=dict)

    def frame(self) -> pd.DataFrame:
        """The learning curves of every finished run, tidy (see :func:`load_study`)."""
        return load_study(self.path)


def _default_workers() -> int:
    # Honour CPU affinity (SLURM allocations, containers), where os.cpu_count() counts the node.
    if hasattr(os, "process_cpu_count"):
        return os.process_cpu_count() or 1
    if hasattr(os, "sched_getaffinity"):
        return len(os.sched_getaffinity(0)) or 1
    return os.cpu_count() or 1


def _write_json_atomic(path: Path, data: dict[str, Any]) -> None:
    write_file(path, lambda tmp: tmp.write_text(json.dumps(data, indent=2, sort_keys=True)), what=path.name, overwrite=True)


@contextmanager
def _folder_lock(out: Path) -> Iterator[None]:
    """Hold an exclusive lock on the study folder: a second run_study on it would delete the
    first one's temporary directories. The kernel drops the lock when the process dies."""
    try:
        import fcntl
    except ImportError:  # pragma: no cover - Windows: no advisory locks here
        yield
        return
    fd = os.open(out / LOCK_FILE, os.O_RDWR | os.O_CREAT, 0o644)
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise StorageError(f"Another run_study is writing to {out}; wait for it to finish (or stop it) first.") from None
        except OSError as e:  # pragma: no cover - file systems without flock
            warnings.warn(f"Cannot lock {out} ({e.strerror}); do not run two run_study on this folder at once.", RuntimeWarning, stacklevel=4)
        yield
    finally:
        os.close(fd)


def _describe_difference(old: dict[str, Any], new: dict[str, Any]) -> str:
    diffs = []
    for key in ("conditions", "seeds", "grid"):
        if old.get(key) != new.get(key):
            diffs.append(f"{key} {old.get(key)!r} -> {new.get(key)!r}")
    old_base, new_base = old.get("base", {}), new.get("base", {})
    for key in sorted(set(old_base) | set(new_base)):
        if key != "condition" and old_base.get(key) != new_base.get(key):
            diffs.append(f"base.{key} {old_base.get(key)!r} -> {new_base.get(key)!r}")
    return "; ".join(diffs[:6]) + ("; ..." if len(diffs) > 6 else "")


def _runs_of(study: Study) -> dict[str, tuple[int, dict[str, Any]]]:
    return {t.path: (t.seed, t.config) for t in study.tasks()}


def _check_study_folder(out: Path) -> None:
    """A study goes into a new or empty folder, or a study folder; never into a user's folder."""
    try:
        _check_study_place(out)
    except StorageError:
        raise
    except OSError as e:
        raise StorageError(f"Cannot use {out} as a study folder: {e.strerror or e}.") from None


def _check_study_place(out: Path) -> None:
    if out.is_symlink() or (out.exists() and not out.is_dir()):
        raise StorageError(f"{out} is not a folder; a study needs a folder of its own. Choose another out_dir.")
    if out.is_dir() and not (out / STUDY_FILE).exists():
        entries = sorted(n for n in os.listdir(out) if n != LOCK_FILE and not (n.startswith(f".{STUDY_FILE}.") and n.endswith(".tmp")))
        if (out / RUNS_DIR).exists():
            raise StorageError(f"{out} holds a {RUNS_DIR}/ folder but no {STUDY_FILE}; it was not made by run_study. Choose another out_dir.")
        if entries:
            shown = ", ".join(entries[:5]) + (" ..." if len(entries) > 5 else "")
            raise StorageError(f"{out} is a folder run_study did not make (it holds {shown}); a study goes into a new or empty folder. Choose another out_dir.")


def _check_or_write_spec(out: Path, study: Study) -> None:
    path = out / STUDY_FILE
    if path.exists():
        old = Study.load(out)
        # The same study is the same set of runs at the same places (order does not matter).
        if _runs_of(old) != _runs_of(study):
            raise StorageError(
                f"{path} holds a different study ({_describe_difference(old.to_dict(), study.to_dict())}). "
                "A folder holds one study: choose another out_dir, or delete this one to start over."
            )
        return
    if (out / RUNS_DIR).exists():
        raise StorageError(f"{out} holds a {RUNS_DIR}/ folder but no {STUDY_FILE}; it was not made by run_study. Choose another out_dir.")
    for leftover in out.glob(f".{STUDY_FILE}.*.tmp"):
        leftover.unlink(missing_ok=True)
    _write_json_atomic(path, {"format": _FORMAT, "study": study.to_dict(), "created_with": {"saggriac": _core.__version__, "git_commit": _core.GIT_COMMIT}})


def _is_finished(out: Path, task: Task) -> bool | str:
    """True for a finished, intact run of this task; False for none; for a damaged one, the
    reason. Raises if a finished run is of another configuration."""
    run_dir = out / task.path
    manifest = run_dir / MANIFEST
    if not manifest.exists():
        return False
    damage = run_damage(run_dir)
    if damage is not None:
        return damage
    data = json.loads(manifest.read_text())
    try:
        same = data["seed"] == task.seed and Config.from_saved(data["config"]) == Config(**task.config)
    except (KeyError, TypeError, ParameterError, StorageError) as e:
        return f"{manifest} does not describe a run this version of saggriac can read ({e})"
    if not same:
        raise StorageError(f"{run_dir} holds a finished run of another configuration or seed; delete it to have the run redone.")
    return True


def _remove_leftovers(out: Path, task: Task) -> None:
    """Remove the temporary directories that storage.write_run left when a process was killed."""
    parent = (out / task.path).parent
    try:
        names = os.listdir(parent)
    except (FileNotFoundError, NotADirectoryError):
        return
    prefix = f".{Path(task.path).name}."
    for name in names:
        if name.startswith(prefix) and name.endswith(".tmp"):
            shutil.rmtree(parent / name)


def _die_with_parent(parent_pid: int) -> None:
    """Pool worker initializer: on Linux, be killed when the study process dies, so a killed
    study leaves no orphan still writing runs into the folder."""
    if sys.platform.startswith("linux"):
        try:
            ctypes.CDLL(None, use_errno=True).prctl(1, int(signal.SIGKILL))  # PR_SET_PDEATHSIG
        except (OSError, AttributeError):  # pragma: no cover - exotic libc
            return
        if os.getppid() != parent_pid:  # the parent died before prctl
            os._exit(1)


# Relative cost of a run per micro-action, by condition (exp2 at full scale, docs/reproduction.md:
# ACTUATOR-RIAC 28 s, ACTUATOR-Random 11 s, the SAGG conditions 6.4 s). Used only to order work.
_COST_HINT = {"actuator_riac": 4.0, "actuator_random": 1.7}


def _longest_first_by_seed(tasks: list[Task]) -> list[Task]:
    """The tasks seed by seed (a partial study still compares conditions on the same seeds), the
    costliest first within a seed, so the last seed's long run does not start last and leave the
    other workers idle at the end."""
    seed_rank = {seed: i for i, seed in enumerate(dict.fromkeys(t.seed for t in tasks))}

    def cost(t: Task) -> float:
        return float(t.config.get("n_steps", 1)) * _COST_HINT.get(t.condition, 1.0)

    return sorted(tasks, key=lambda t: (seed_rank[t.seed], -cost(t)))


def _run_local(tasks: list[Task], out: Path, n_workers: int, on_done: Callable[[Task, Any], None]) -> None:
    import concurrent.futures as cf
    import multiprocessing

    ctx = multiprocessing.get_context("spawn")
    with cf.ProcessPoolExecutor(max_workers=n_workers, mp_context=ctx, initializer=_die_with_parent, initargs=(os.getpid(),)) as pool:
        futures = {pool.submit(run_task, t, str(out)): t for t in tasks}
        try:
            for fut in cf.as_completed(futures):
                on_done(futures[fut], fut)
        except BaseException:
            pool.shutdown(wait=False, cancel_futures=True)
            raise


def _import_distributed() -> Any:
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
    distributed = _import_distributed()
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


def _check_scheduler(address: str) -> None:
    """Refuse, before anything is written, an address that is not one or a scheduler that does
    not answer within SCHEDULER_TIMEOUT seconds (Dask itself waits 30 s, then may hang on exit)."""
    import socket

    rule = "an address such as 'tcp://HOST:PORT'"
    m = re.fullmatch(r"(?:(tcp|tls)://)?\[?([A-Za-z0-9_.:-]*?)\]?:(\d{1,5})", address.strip())
    if m is None:
        if re.fullmatch(r"[a-z]+://.+", address.strip()):
            return  # another Dask protocol (ucx://, inproc://): Dask checks it, with the timeout
        raise ParameterError(f"The 'scheduler' parameter of run_study must be {rule}. Got {address!r} instead.", "scheduler", repr(address))
    host, port = m.group(2) or "127.0.0.1", int(m.group(3))
    if not 0 < port < 65536:
        raise ParameterError(f"The 'scheduler' parameter of run_study must be {rule} with a port in 1..65535. Got {address!r} instead.", "scheduler", repr(address))
    try:
        socket.create_connection((host, port), timeout=SCHEDULER_TIMEOUT).close()
    except OSError as e:
        raise ParameterError(f"The 'scheduler' parameter of run_study names {address!r}, where no Dask scheduler answers within {SCHEDULER_TIMEOUT} s ({e.strerror or e}). Start it (dask scheduler) or check the address.", "scheduler", repr(address)) from None


def _run_dask(tasks: list[Task], out: Path, n_workers: int, scheduler: Any, on_done: Callable[[Task, Any], None]) -> None:
    distributed = _import_distributed()
    with _dask_client(distributed, scheduler, n_workers) as client:
        futures = {client.submit(run_task, t, str(out), pure=False): t for t in tasks}
        try:
            for fut in distributed.as_completed(list(futures), loop=client.loop):
                on_done(futures.pop(fut), fut)
        except BaseException:
            client.cancel(list(futures))
            raise


def run_study(
    study: Study,
    out_dir: str | Path,
    backend: str = "local",
    n_workers: int | None = None,
    scheduler: Any = None,
    progress: bool = True,
) -> StudyResult:
    """Run every unfinished run of ``study`` into ``out_dir`` and return a :class:`StudyResult`.

    ``backend="local"`` uses a process pool of ``n_workers`` (default: the usable cores).
    ``backend="dask"`` uses Dask distributed: a new LocalCluster of ``n_workers`` processes when
    ``scheduler`` is None, else the scheduler at a given address (str), a given ``Client``, or a
    cluster object such as ``dask_jobqueue.SLURMCluster``. Finished runs are never recomputed;
    if some runs fail, the others still finish and a :class:`StudyError` names the failures.
    """
    if not isinstance(study, Study):
        raise ParameterError(f"The 'study' parameter of run_study must be a saggriac.Study. Got {type(study).__name__} instead.", "study", repr(study))
    if backend not in ("local", "dask"):
        raise ParameterError(f"The 'backend' parameter of run_study must be one of 'local', 'dask'. Got {backend!r} instead.", "backend", repr(backend))
    if n_workers is not None and (isinstance(n_workers, bool) or not isinstance(n_workers, int) or n_workers < 1):
        raise ParameterError(f"The 'n_workers' parameter of run_study must be an int >= 1 or None. Got {n_workers!r} instead.", "n_workers", repr(n_workers))
    if scheduler is not None and backend != "dask":
        raise ParameterError("The 'scheduler' parameter of run_study needs backend='dask'.", "scheduler", repr(scheduler))
    if scheduler is not None and n_workers is not None:
        raise ParameterError("The 'n_workers' parameter of run_study applies only to workers it starts itself; size the given Dask cluster instead.", "n_workers", repr(n_workers))
    if backend == "dask":
        _import_distributed()  # fail before writing anything
        if isinstance(scheduler, str):
            _check_scheduler(scheduler)
    out = as_path(out_dir, "out_dir", "run_study").resolve()  # absolute: workers may run elsewhere (Dask, SLURM)
    _check_study_folder(out)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise StorageError(f"Cannot create the study folder {out}: {e.strerror}.") from None

    with _folder_lock(out):
        _check_or_write_spec(out, study)
        tasks = study.tasks()
        pending = []
        repaired: dict[str, str] = {}
        for task in tasks:
            clear_stale_lock(out / task.path)
            state = _is_finished(out, task)
            if state is True:
                continue
            if state is False and os.path.lexists(out / task.path) and (not (out / task.path).is_dir() or os.listdir(out / task.path)):
                state = f"it holds files but no {MANIFEST} (unfinished, or its {MANIFEST} was lost)"
            if isinstance(state, str):
                aside = _set_aside(out / task.path)
                repaired[task.name] = f"{state}; set aside as {aside.name}"
                print(f"saggriac: {task.name} is damaged ({state}); it is set aside as {aside} and recomputed.", file=sys.stderr)
            _remove_leftovers(out, task)
            pending.append(task)
        n_skipped = len(tasks) - len(pending)
        failures: dict[str, BaseException] = {}
        if pending:
            from tqdm.auto import tqdm

            bar = tqdm(total=len(tasks), initial=n_skipped, unit="run", desc="study", disable=not progress)

            def on_done(task: Task, fut: Any) -> None:
                try:
                    fut.result()
                except Exception as e:  # reported together once every run is done
                    failures[task.name] = e
                    bar.set_postfix(failed=len(failures))
                bar.update(1)

            try:
                workers = min(n_workers or _default_workers(), len(pending))
                pending = _longest_first_by_seed(pending)
                if backend == "local":
                    _run_local(pending, out, workers, on_done)
                else:
                    _run_dask(pending, out, workers, scheduler, on_done)
            finally:
                bar.close()
    if failures:
        lines = "\n".join(f"  {name}: {type(e).__name__}: {e}" for name, e in failures.items())
        err = StudyError(
            f"{len(failures)} of {len(pending)} runs failed; the others are saved in {out / RUNS_DIR} "
            f"and run_study on the same folder redoes only the failed ones:\n{lines}",
            failures,
        )
        raise err from next(iter(failures.values()))
    return StudyResult(path=out, study=study, n_computed=len(pending), n_skipped=n_skipped, repaired=repaired)


def load_study(out_dir: str | Path) -> pd.DataFrame:
    """The learning curves of every finished run of a study, one row per (run, step, metric):
    columns ``condition, seed, <grid keys>, step, metric, value``. Unfinished runs are left out."""
    out = Path(out_dir)
    study = Study.load(out)
    keys = list(study.grid)
    parts = []
    for task in study.tasks():
        run_dir = out / task.path
        if not (run_dir / MANIFEST).exists():
            continue
        damage = run_damage(run_dir)
        if damage is not None:
            raise StorageError(f"{run_dir} is damaged: {damage}. Run the study again on {out} (saggriac reproduce, or run_study) to set it aside and recompute it.")
        # Runs from before a metric existed leave it out (dx_error came with saggriac 0.2).
        have = set(pq.read_schema(run_dir / "metrics.parquet").names)
        metrics = [k for k in METRICS if k in have]
        m = pd.read_parquet(run_dir / "metrics.parquet", columns=["step", *metrics])
        n = len(m) * len(metrics)
        cols: dict[str, Any] = {"condition": [task.condition] * n, "seed": np.full(n, task.seed, dtype=np.int64)}
        for k in keys:
            cols[k] = [task.params[k]] * n
        cols["step"] = np.tile(m["step"].to_numpy(np.int64), len(metrics))
        cols["metric"] = np.repeat(np.array(metrics, dtype=object), len(m))
        cols["value"] = np.concatenate([m[k].to_numpy(np.float64) for k in metrics])
        parts.append(pd.DataFrame(cols))
    if not parts:
        empty = {"condition": pd.Series(dtype=str), "seed": pd.Series(dtype=np.int64)}
        empty.update({k: pd.Series(dtype=object) for k in keys})
        empty.update(step=pd.Series(dtype=np.int64), metric=pd.Series(dtype=str), value=pd.Series(dtype=np.float64))
        return pd.DataFrame(empty)
    return pd.concat(parts, ignore_index=True)
