"""Running the bench: one run is a teacher on a task for one seed (:func:`run_one`, a top-level,
picklable function), written to its own file in the output folder as soon as it is done, so that
a bench killed and run again computes only the runs it has no file for, and ends with the same
numbers (each run depends on its seed alone)."""

from __future__ import annotations

import json
import os
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Iterable

import numpy as np

from .. import _core
from ..errors import SaggriacError, StorageError
from ..files import check_flag
from ..runs.resources import share_cores
from .tasks import TASKS, TIERS, tier_seeds
from .teachers import CALL_TIMEOUT, Guarded, TeacherError, TeacherSpec, alarm_handler

RUNS_DIR = "runs"


class BenchError(SaggriacError):
    """Some bench runs failed; ``failures`` maps each (task, teacher, seed) to its message. Every
    other run is saved and on the leaderboard."""

    def __init__(self, message: str, failures: dict[tuple[str, str, int], str]):
        super().__init__(message)
        self.failures = failures


@dataclass(frozen=True)
class Job:
    """One run: ``teacher`` on ``task`` with root seed ``seed``, the budget of ``tier``."""

    task: str
    tier: str
    teacher: TeacherSpec
    seed: int
    timeout: float = CALL_TIMEOUT

    @property
    def key(self) -> tuple[str, str, int]:
        return (self.task, self.teacher.label, self.seed)

    def path(self, out: Path) -> Path:
        return out / RUNS_DIR / self.tier / self.teacher.slug / self.task / f"seed{self.seed}.json"


def child_seeds(seed: int) -> tuple[int, int]:
    """(teacher's seed, task's seed) for a run's root seed: two children of a SeedSequence, in
    [0, 2**63), so that a teacher taking any non-negative int64 takes them."""
    teacher, task = np.random.SeedSequence(int(seed)).spawn(2)
    return int(teacher.generate_state(1, np.uint64)[0] >> np.uint64(1)), int(task.generate_state(1, np.uint64)[0] >> np.uint64(1))


def run_one(job: Job) -> dict[str, Any]:
    """Run ``job``; its row (task, teacher, seed, goals, area, final, seconds, and the seconds spent
    in the teacher's own sample and update), its score curve and the goals asked (thinned,
    :class:`saggriac.bench.goals.GoalLog`).
    A failing teacher raises TeacherError naming the teacher, the task and the seed."""
    budget = TASKS[job.task].budgets[job.tier]
    _task, guard, curve, seconds = play_run(job.task, job.seed, budget, lambda task, teacher_seed: Guarded(job.teacher, task, teacher_seed, job.timeout, run_seed=job.seed))
    scores = [s for _, s in curve]
    row = dict(task=job.task, teacher=job.teacher.label, seed=job.seed, goals=budget, area=float(np.mean(scores)), final=float(scores[-1]), seconds=seconds, teacher_seconds=guard.teacher_seconds, version=_core.__version__)
    return {"row": row, "curve": [[int(t), float(s)] for t, s in curve], "asked": guard.log.thinned()}


def play_run(name: str, seed: int, budget: int, guard: Callable[[Any, int], Guarded], points: int | None = None) -> tuple[Any, Guarded, list[tuple[int, float]], float]:
    """The task ``name`` built for the root seed ``seed`` and played for ``budget`` with the
    teacher ``guard(task, teacher_seed)`` builds, scored ``points`` times (default: the task's
    own number): (task, guard, score curve, wall seconds). Every run of the bench and of the
    evidence runner goes through here, so both derive the same seeds (the task's
    ``child_seeds`` if it has its own, else :func:`child_seeds`)."""
    cls = TASKS[name]
    teacher_seed, task_seed = cls.child_seeds(seed) if hasattr(cls, "child_seeds") else child_seeds(seed)
    task = cls(task_seed)
    if points is not None:
        task.points = int(points)
    start = time.perf_counter()
    with alarm_handler():
        guarded = guard(task, teacher_seed)
        curve = task.play(guarded.ask, guarded.tell, budget)
    return task, guarded, curve, time.perf_counter() - start


def _write(path: Path, record: dict[str, Any]) -> None:
    """The run's file, written whole or not at all."""
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
        tmp.write_text(json.dumps(record))
        os.replace(tmp, path)
    except OSError as e:
        raise StorageError(f"Cannot write the bench run {path}: {e.strerror or e}.") from None


def read_done(job: Job, out: Path) -> dict[str, Any] | None:
    """The saved record of ``job``, or None if it has none (a damaged file counts as none)."""
    path = job.path(out)
    try:
        record = json.loads(path.read_text())
    except (OSError, ValueError):
        return None
    row = record.get("row", {}) if isinstance(record, dict) else {}
    if (row.get("task"), row.get("teacher"), row.get("seed"), row.get("goals")) != (job.task, job.teacher.label, job.seed, TASKS[job.task].budgets[job.tier]):
        return None
    return record


def _one_safely(job: Job) -> tuple[Job, dict[str, Any] | None, str | None]:
    try:
        return job, run_one(job), None
    except TeacherError as e:
        return job, None, str(e)


def execute(jobs: list[Job], out: Path, workers: int, scheduler: Any = None, progress: bool = True) -> tuple[list[dict[str, Any]], dict[tuple[str, str, int], str]]:
    """Run ``jobs`` (on ``workers`` processes, in this process if 1, or on the Dask scheduler at
    ``scheduler``), each written to its file as it finishes. The records, and the failures by key."""
    from tqdm.auto import tqdm

    progress = check_flag(progress, "progress", "execute")
    records: list[dict[str, Any]] = []
    failures: dict[tuple[str, str, int], str] = {}
    bar = tqdm(total=len(jobs), unit="run", desc="bench", disable=not progress or not jobs)

    def done(job: Job, record: dict[str, Any] | None, error: str | None) -> None:
        if record is not None:
            _write(job.path(out), record)
            records.append(record)
        else:
            failures[job.key] = error or "failed"
            bar.set_postfix(failed=len(failures))
        bar.update(1)

    try:
        for job, record, error in _results(jobs, workers, scheduler):
            done(job, record, error)
    finally:
        bar.close()
    return records, failures


def _results(jobs: list[Job], workers: int, scheduler: Any) -> Iterable[tuple[Job, dict[str, Any] | None, str | None]]:
    if not jobs:
        return
    if scheduler is not None:
        from ..study.backends import import_distributed

        distributed = import_distributed()
        with distributed.Client(scheduler, set_as_default=False) as client:
            futures = [client.submit(_one_safely, j, pure=False) for j in jobs]
            for fut in distributed.as_completed(futures):
                yield fut.result()
        return
    if workers <= 1:
        for j in jobs:
            yield _one_safely(j)
        return
    import concurrent.futures as cf
    import multiprocessing

    with cf.ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("spawn"), initializer=share_cores, initargs=(workers,)) as pool:
        futures = [pool.submit(_one_safely, j) for j in jobs]
        try:
            for fut in cf.as_completed(futures):
                yield fut.result()
        except BaseException:
            pool.shutdown(wait=False, cancel_futures=True)
            raise


def plan(teachers: list[TeacherSpec], tasks: list[str], tier: str, seeds: Iterable[int] | None, timeout: float) -> list[Job]:
    """Every run of ``teachers`` on ``tasks`` (each teacher on the tasks of the spaces it takes and
    that can tell it what it asks to be told; a teacher given expert knowledge on the tasks that
    declare it), seed by seed, so that a partial bench still pairs teachers on the same seeds.
    ``seeds`` None: each task's seeds in the tier (:func:`tier_seeds`)."""
    if tier not in TIERS:
        raise SaggriacError(f"The 'tier' parameter of saggriac bench must be one of {', '.join(TIERS)}. Got {tier!r} instead.")
    fixed = None if seeds is None else [int(s) for s in seeds]
    per_task = {task: set(tier_seeds(task, tier) if fixed is None else fixed) for task in tasks}
    order = sorted(set().union(*per_task.values())) if per_task else []
    return [Job(task, tier, spec, seed, timeout) for seed in order for task in tasks if seed in per_task[task] for spec in teachers
            if spec.takes(TASKS[task].space) and spec.told in TASKS[task].tells and (not spec.level or TASKS[task].declares_knowledge())]


def failure_message(failures: dict[tuple[str, str, int], str], out: Path, n_jobs: int) -> str:
    lines = "\n".join(f"  {msg}" for msg in list(failures.values())[:20])
    more = f"\n  ... and {len(failures) - 20} more" if len(failures) > 20 else ""
    return f"{len(failures)} of {n_jobs} bench runs failed; every other run is saved in {out / RUNS_DIR} and on the leaderboard, and the same command redoes only the failed ones:\n{lines}{more}"


def timed(work: Callable[[], Any]) -> tuple[Any, float]:
    start = time.perf_counter()
    value = work()
    return value, time.perf_counter() - start
