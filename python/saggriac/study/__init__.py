"""Studies: many runs (conditions x seeds x parameter grid) on all cores, on Dask, or on SLURM.

A study folder holds ``study.json`` (what the study is) and one run directory per run, at
``runs/<condition>[__key=value...]/seed<k>/``. A run directory is finished when it holds
``run.json`` (storage.write_run writes it last); finished runs are never recomputed, so a study
that was stopped is resumed by calling :func:`run_study` again. See docs/studies.md.

The parts: ``spec`` (Study, Task, run_task), ``folder`` (study.json, the lock, finished and
damaged runs), ``backends`` (the process pool and Dask); here, running and loading a study.
"""

from __future__ import annotations

import os
import sys
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import pyarrow.parquet as pq

from ..errors import ParameterError, StorageError
from ..files import check_flag
from ..runs.result import run_stopped_early
from ..runs.storage import MANIFEST, as_path, clear_stale_lock, read_manifest, run_damage
from .backends import COST_HINT, SCHEDULER_TIMEOUT, WORKER_TIMEOUT, check_scheduler, default_workers, import_distributed, longest_first_by_seed, run_dask, run_local, check_cluster, check_scheduler_type, check_worker_timeout, local_cluster
from .folder import check_or_write_spec, check_study_folder, folder_lock, is_finished, remove_leftovers, set_aside
from .spec import LOCK_FILE, METRICS, RUNS_DIR, STUDY_FILE, IncompleteStudyWarning, Study, StudyError, Task, run_task


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


def run_study(
    study: Study,
    out_dir: str | Path,
    backend: str = "local",
    n_workers: int | None = None,
    scheduler: Any = None,
    progress: bool = True,
    worker_timeout: float = WORKER_TIMEOUT,
) -> StudyResult:
    """Run every unfinished run of ``study`` into ``out_dir`` and return a :class:`StudyResult`.

    ``backend="local"`` uses a process pool of ``n_workers`` (default: the usable cores).
    ``backend="dask"`` uses Dask distributed: a new LocalCluster of ``n_workers`` processes when
    ``scheduler`` is None, else the scheduler at a given address (str), a given ``Client``, or a
    cluster object such as ``dask_jobqueue.SLURMCluster``; with a given scheduler or cluster, the
    study fails with a ParameterError if no worker has joined within ``worker_timeout`` seconds
    (a SLURMCluster whose jobs never start). Finished runs are never recomputed;
    if some runs fail, the others still finish and a :class:`StudyError` names the failures.
    """
    if not isinstance(study, Study):
        raise ParameterError(f"The 'study' parameter of run_study must be a saggriac.Study. Got {type(study).__name__} instead.", "study", repr(study))
    if backend not in ("local", "dask"):
        raise ParameterError(f"The 'backend' parameter of run_study must be one of 'local', 'dask'. Got {backend!r} instead.", "backend", repr(backend))
    progress = check_flag(progress, "progress", "run_study")
    if n_workers is not None and (isinstance(n_workers, (bool, np.bool_)) or not isinstance(n_workers, (int, np.integer)) or n_workers < 1):
        raise ParameterError(f"The 'n_workers' parameter of run_study must be an int >= 1 or None. Got {n_workers!r} instead.", "n_workers", repr(n_workers))
    n_workers = None if n_workers is None else int(n_workers)
    if scheduler is not None and backend != "dask":
        raise ParameterError("The 'scheduler' parameter of run_study needs backend='dask'.", "scheduler", repr(scheduler))
    if scheduler is not None and n_workers is not None:
        raise ParameterError("The 'n_workers' parameter of run_study applies only to workers it starts itself; size the given Dask cluster instead.", "n_workers", repr(n_workers))
    if backend == "dask":
        distributed = import_distributed()  # fail before writing anything
        check_scheduler_type(distributed, scheduler)
        if isinstance(scheduler, str):
            check_scheduler(scheduler)
        check_cluster(scheduler)
    worker_timeout = check_worker_timeout(worker_timeout, "run_study")
    out = as_path(out_dir, "out_dir", "run_study").resolve()  # absolute: workers may run elsewhere (Dask, SLURM)
    check_study_folder(out)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise StorageError(f"Cannot create the study folder {out}: {e.strerror}.") from None

    with folder_lock(out):
        check_or_write_spec(out, study)
        tasks = study.tasks()
        pending = []
        repaired: dict[str, str] = {}
        for task in tasks:
            clear_stale_lock(out / task.path)
            state = is_finished(out, task)
            if state is True:
                continue
            if state is False and os.path.lexists(out / task.path) and (not (out / task.path).is_dir() or os.listdir(out / task.path)):
                state = f"it holds files but no {MANIFEST} (unfinished, or its {MANIFEST} was lost)"
            if isinstance(state, str):
                aside = set_aside(out / task.path)
                repaired[task.name] = f"{state}; set aside as {aside.name}"
                print(f"saggriac: {task.name} is damaged ({state}); it is set aside as {aside} and recomputed.", file=sys.stderr)
            remove_leftovers(out, task)
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
                workers = min(n_workers or default_workers(), len(pending))
                pending = longest_first_by_seed(pending)
                if backend == "local":
                    run_local(pending, out, workers, on_done)
                else:
                    run_dask(pending, out, workers, scheduler, on_done, worker_timeout)
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
    columns ``condition, seed, <grid keys>, step, metric, value``. Runs not finished (no
    run.json, or a partial run saved from a learner stopped early) are left out, and an
    :class:`IncompleteStudyWarning` names them."""
    out = as_path(out_dir, "out_dir", "load_study")
    study = Study.load(out)
    keys = list(study.grid)
    parts = []
    left_out: list[str] = []
    tasks = study.tasks()
    for task in tasks:
        run_dir = out / task.path
        if not (run_dir / MANIFEST).exists():
            left_out.append(f"{task.path} (not finished: no {MANIFEST})")
            continue
        damage = run_damage(run_dir)
        if damage is not None:
            raise StorageError(f"{run_dir} is damaged: {damage}. Run the study again on {out} (saggriac reproduce, or run_study) to set it aside and recompute it.")
        # Runs from before a metric existed leave it out (dx_error came with saggriac 0.2).
        have = set(pq.read_schema(run_dir / "metrics.parquet").names)
        metrics = [k for k in METRICS if k in have]
        m = pd.read_parquet(run_dir / "metrics.parquet", columns=["step", *metrics])
        early = run_stopped_early(read_manifest(run_dir), m)
        if early is not None:
            left_out.append(f"{task.path} ({early})")
            continue
        n = len(m) * len(metrics)
        cols: dict[str, Any] = {"condition": [task.condition] * n, "seed": np.full(n, task.seed, dtype=np.int64)}
        for k in keys:
            cols[k] = [task.params[k]] * n
        cols["step"] = np.tile(m["step"].to_numpy(np.int64), len(metrics))
        cols["metric"] = np.repeat(np.array(metrics, dtype=object), len(m))
        cols["value"] = np.concatenate([m[k].to_numpy(np.float64) for k in metrics])
        parts.append(pd.DataFrame(cols))
    if left_out:
        shown = "; ".join(left_out[:10]) + (f"; and {len(left_out) - 10} more" if len(left_out) > 10 else "")
        warnings.warn(f"{len(left_out)} of {len(tasks)} runs of the study {out} are left out: {shown}. Run the study again (run_study, or saggriac reproduce) to finish them.", IncompleteStudyWarning, stacklevel=2)
    if not parts:
        empty = {"condition": pd.Series(dtype=str), "seed": pd.Series(dtype=np.int64)}
        empty.update({k: pd.Series(dtype=object) for k in keys})
        empty.update(step=pd.Series(dtype=np.int64), metric=pd.Series(dtype=str), value=pd.Series(dtype=np.float64))
        return pd.DataFrame(empty)
    return pd.concat(parts, ignore_index=True)


_COST_HINT = COST_HINT  # its former, private name (older scripts import it from here)

__all__ = ["Study", "Task", "StudyResult", "StudyError", "IncompleteStudyWarning", "run_study", "load_study", "run_task", "local_cluster", "METRICS", "STUDY_FILE", "LOCK_FILE", "RUNS_DIR", "SCHEDULER_TIMEOUT", "WORKER_TIMEOUT", "COST_HINT"]
