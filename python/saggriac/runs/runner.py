"""Run one learner: ``run(config, seed) -> RunResult``, a top-level, picklable function, and
``resume(out_dir)``. Both build a :class:`~saggriac.runs.learner.Learner` and drive it through
its public ``run``; this module owns the run's folder: its lock, its checkpoints (written from
the learner's ``on_stop``) and the writing of the result."""

from __future__ import annotations

import os
import re
import tempfile
import time
import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..config import Config
from ..errors import ParameterError, StorageError
from ..files import check_flag
from . import checkpoint
from .checkpoint import CheckpointWarning, check_every, checkpoint_dir, find_checkpoint, remove_checkpoint
from .learner import Learner
from .resources import check_threads, checkpoint_bytes
from .result import RunResult
from .storage import CHECKPOINT_INODES, MIN_FREE_BYTES, MIN_FREE_INODES, as_path, check_output_dir, reason, target_lock, write_run

if TYPE_CHECKING:
    from ..bodies.environments import Environment
    from ..teachers import GoalSelectorProtocol

def run(
    config: Config | None = None,
    seed: int = 0,
    out_dir: str | Path | None = None,
    progress: bool = False,
    overwrite: bool = False,
    *,
    environment: Environment | None = None,
    goal_selector: GoalSelectorProtocol | None = None,
    checkpoint_every: int | None = None,
    threads: int | None = None,
) -> RunResult:
    """Run one learner for ``config.n_steps`` time steps (micro-actions, or movements when episodic) and return its result.

    With ``out_dir`` the run directory is written atomically (manifest ``run.json`` with the
    resolved configuration, seeds, version and git commit; Parquet tables for metrics, goals,
    attempts and regions). ``progress`` shows a progress bar with the current reaching error.

    ``checkpoint_every=N`` (with ``out_dir``) saves the learner's whole state at the first
    evaluation at or after every N steps, atomically, next to ``out_dir``; ``resume(out_dir)``
    continues an interrupted run from there to the same result, bit for bit.

    ``threads`` evaluations may use, learning's included (default: every core this process may
    use). Evaluations then run while learning goes on; the results are the same bits whatever
    the number. Runs with motor or sensor noise, a user's environment, or the episodic paradigm
    evaluate in the learning thread.
    """
    progress = check_flag(progress, "progress", "run")
    overwrite = check_flag(overwrite, "overwrite", "run")
    out = as_path(out_dir, "out_dir", "run") if out_dir is not None else None
    if checkpoint_every is not None:
        checkpoint_every = _check_checkpointing(checkpoint_every, out, environment, goal_selector)
    learner = Learner(config, seed, environment=environment, goal_selector=goal_selector, threads=threads, caller="run")
    if out is not None:
        check_output_dir(out, overwrite, _min_free(learner.config, checkpoint_every), _min_inodes(checkpoint_every))
    learner.info.overwrite = overwrite
    with _holding(out, overwrite):
        _learn(learner, progress, out, checkpoint_every)
        return _save(learner, out)


def _learn(learner: Learner, progress: bool, out: Path | None, every: int | None) -> None:
    """Run ``learner`` to the end of its budget, checkpointing for ``out`` every ``every`` steps."""
    if every is None:
        learner.run(progress=progress)
    else:
        learner.run(progress=progress, stop_every=every, on_stop=lambda lr: _checkpoint_on_the_way(lr, out, every))


def _checkpoint_on_the_way(learner: Learner, out: Path, every: int) -> None:
    info = learner.info
    try:
        checkpoint.write_checkpoint(out, learner.checkpoint(), info.for_checkpoint(), learner.config, learner.steps, every)
        info.last_checkpoint = learner.steps
    except OSError as e:  # a StorageError, or any other write failure: the run goes on
        # Losing a checkpoint only costs what a later interruption would redo; losing the run
        # would cost everything.
        last = info.last_checkpoint if info.last_checkpoint is not None else info.resumed_at
        kept = f"the last good checkpoint (step {last}) is kept" if last is not None else "there is no earlier checkpoint"
        warnings.warn(f"The checkpoint at step {learner.steps} could not be written ({e}); the run goes on and {kept}.", CheckpointWarning, stacklevel=5)


@contextmanager
def _holding(out: Path | None, overwrite: bool) -> Iterator[None]:
    """Lock the target for the whole run; look at it again once the lock is held, since another
    run may have finished there while this one was starting."""
    if out is None:
        yield
        return
    with target_lock(out):
        check_output_dir(out, overwrite)
        yield


def _min_free(config: Config, every: int | None) -> int:
    """Disk space a run needs beside its target: the result, and with checkpoints two of them at
    once (the new one is written before the old one is removed)."""
    return MIN_FREE_BYTES + (2 * checkpoint_bytes(config) if every is not None else 0)


def _min_inodes(every: int | None) -> int:
    """Inodes a run needs beside its target: the result's, and with checkpoints two of them."""
    return MIN_FREE_INODES + (2 * CHECKPOINT_INODES if every is not None else 0)


def _check_checkpointing(every: Any, out: Path | None, environment: Any, goal_selector: Any) -> int:
    """``checkpoint_every`` as a plain int, where a checkpoint can be kept."""
    every = check_every(every, "run")
    if out is None:
        raise ParameterError("The 'checkpoint_every' parameter of run needs out_dir, where the checkpoint is kept. Got out_dir=None.", "checkpoint_every", repr(every))
    if environment is not None or goal_selector is not None:
        raise ParameterError("The 'checkpoint_every' parameter of run is not available with a user's environment or goal selector (saggriac cannot save their state).", "checkpoint_every", repr(every))
    return every


def _save(learner: Learner, out: Path | None) -> RunResult:
    """The finished learner's result, written to ``out`` (its checkpoint then removed)."""
    result = learner.result()
    if out is not None:
        tables = {"metrics": result.metrics, "goals": result.goals, "attempts": result.attempts, "regions": result.regions}
        try:
            result.path = write_run(out, result.manifest, tables, learner.info.overwrite)
        except OSError as e:
            # The disk filled up or vanished after the work was done: keep the work, whatever
            # the OSError (no free inode or an immutable folder as well as no free byte).
            err = e if isinstance(e, StorageError) else StorageError(f"Could not write the run to {out}: {reason(e)}.")
            err.result = result
            err.args = (f"{err} The result is kept in this exception's .result; save it elsewhere with .result.save(path).",)
            if err is e:
                raise
            raise err from None
        remove_checkpoint(out)
    return result


def recover(result: RunResult, out: Path, why: str) -> str:
    """Save a finished result that could not be written to ``out`` in a recovery folder beside it
    (else in the current folder, else the temporary folder); return a message saying why and
    where it went."""
    said = why.split(" The result is kept")[0]
    stamp = time.strftime("%Y%m%d-%H%M%S")
    name = Path(os.path.abspath(out)).name or "run"
    group = Path(os.path.abspath(out)).parent.name
    if re.fullmatch(r"seed\d+", name):
        # A study's run (runs/GROUP/seedN): the seed alone does not say whose result this is,
        # least of all away from the study. The group names the condition and grid point.
        name = f"{group if group and len(group) <= 150 else result.config.condition}-{name}"
    for parent in (Path(os.path.abspath(out)).parent, Path.cwd(), Path(tempfile.gettempdir())):
        place = next((p for i in range(100) if not os.path.lexists(p := parent / f"{name}.recovered-{stamp}{'' if i == 0 else f'-{i}'}")), None)
        if place is None:
            continue
        try:
            saved = result.save(place)
        except (StorageError, OSError):
            continue
        return f"{said} The finished result was saved to {saved} instead; move it where you want it (to {out} for a study to count it without recomputing)."
    return f"{said} The result could not be saved anywhere else either (tried beside {out}, the current folder and the temporary folder)."


def resume(out_dir: str | Path, progress: bool = False, threads: int | None = None) -> RunResult:
    """Continue the interrupted run whose checkpoint sits next to ``out_dir`` (written by
    ``run(..., out_dir=..., checkpoint_every=N)``), to the same result the run would have given
    without the interruption, and write it to ``out_dir``. ``threads`` as for ``run``."""
    progress = check_flag(progress, "progress", "resume")
    threads = check_threads(threads, "resume")
    out = as_path(out_dir, "out_dir", "resume")
    find_checkpoint(out)  # refused before the lock is made if there is nothing to resume
    with target_lock(out):
        learner = Learner.from_checkpoint(out, threads)
        # The old checkpoint is on the disk already: room for one more.
        check_output_dir(out, learner.info.overwrite, MIN_FREE_BYTES + checkpoint_bytes(learner.config), MIN_FREE_INODES + CHECKPOINT_INODES)
        _learn(learner, progress, out, learner.info.checkpoint_every)
        return _save(learner, out)


__all__ = ["run", "resume", "recover", "checkpoint_dir", "CheckpointWarning"]
