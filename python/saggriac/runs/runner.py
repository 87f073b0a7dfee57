"""Run one learner: ``run(config, seed) -> RunResult``. A top-level, picklable function."""

from __future__ import annotations

import json
import os
import platform
import shutil
import tempfile
import time
import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd

from .. import _core
from ..config import Config
from ..errors import ParameterError, StorageError
from ..reachable import ReachableSet
from .result import RunResult
from ..scale import body_scale
from ..files import MAX_JSON_BYTES, check_flag, check_seal, read_bounded, seal
from ..seeding import check_seed, derive_seeds, environment_seed
from ..testing import _joint_space
from .resources import check_run_fits, check_threads, checkpoint_bytes
from .storage import MIN_FREE_BYTES, as_path, check_output_dir, replace_dir, sibling, target_lock, write_run
from .time_budget import time_budget

CHECKPOINT_FILES = frozenset({"state.bin", "checkpoint.json"})

if TYPE_CHECKING:
    from ..environments import Environment
    from ..teachers import GoalSelectorProtocol


def _xy_columns(d: dict[str, np.ndarray]) -> pd.DataFrame:
    cols: dict[str, np.ndarray] = {}
    for k, v in d.items():
        if v.ndim == 2:
            # x, y (, z) for task-space points; numbered columns for larger spaces such as
            # ACTUATOR-RIAC's (theta, dtheta) regions.
            names = "xyz" if v.shape[1] <= 3 else [str(i) for i in range(v.shape[1])]
            for i in range(v.shape[1]):
                cols[f"{k}_{names[i]}"] = v[:, i]
        else:
            cols[k] = v
    return pd.DataFrame(cols)


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
    if config is None:
        config = Config()
    if not isinstance(config, Config):
        raise ParameterError(f"The 'config' parameter of run must be a saggriac.Config. Got {type(config).__name__} instead.", "config", repr(config))
    config = for_body(config, environment)
    seed = check_seed(seed)
    progress = check_flag(progress, "progress", "run")
    overwrite = check_flag(overwrite, "overwrite", "run")
    threads = check_threads(threads, "run")
    out = as_path(out_dir, "out_dir", "run") if out_dir is not None else None
    if checkpoint_every is not None:
        checkpoint_every = _check_checkpointing(checkpoint_every, out, environment, goal_selector)
    check_run_fits(config)
    if out is not None:
        check_output_dir(out, overwrite, _min_free(config, checkpoint_every))
    learner, info, extras = _build(config, seed, threads, environment, goal_selector, "run")
    info["overwrite"] = overwrite
    with _holding(out, overwrite):
        return _drive(learner, config, info, out, progress, checkpoint_every, extras)


def for_body(config: Config, environment: Any) -> Config:
    """The configuration of a run on ``environment``: the joint limit is the body's (its
    ``joint_space``), so a user's body states it once; ``Config.joint_limit`` is for saggriac's
    own arms. The resolved value is what run.json records."""
    if environment is None:
        return config
    limit = float(_joint_space(environment)[1][0])
    if limit == config.joint_limit:
        return config
    try:
        return config.replace(joint_limit=limit)
    except ParameterError as e:
        raise ParameterError(f"The environment's joint_space gives the joint limit {limit:g}, which a run cannot take: {e}", "environment.joint_space", f"{limit:g}") from None


def _build(config: Config, seed: int, threads: int, environment: Any, goal_selector: Any, owner: str) -> tuple[Any, dict[str, Any], dict[str, Any]]:
    """The core's learner for ``config`` and root ``seed``, the user's parts checked first; with
    the seeds (``info``) and what run.json says of the parts (``extras``). Built before any
    output is locked or made, so a refused environment or selector leaves nothing on disk."""
    learner_seed, eval_seed = derive_seeds(seed)
    extra: dict[str, Any] = {}
    extras: dict[str, Any] = {"scale": _arm_scale(config)}
    core = config.core_dict()
    if environment is not None:
        # The core calls it from its loop; check the protocol first so mistakes read plainly.
        from ..testing import check_environment_interface

        check_environment_interface(environment, config)
        extra["environment"] = environment
        extras["environment"] = f"{type(environment).__module__}.{type(environment).__qualname__}"
        if config.chain is None:
            # A user's body: the length parameters and the test goals follow its size and place.
            body = body_scale(environment, *_joint_space(environment), len(config.goal_low))
            core = config.core_dict(reach=body.reach)
            extras["scale"] = body.summary(config.lengths(body.reach))
            if body.positions is not None:
                extra["test_cloud"] = (body.configs.tolist(), body.positions.tolist())
    if goal_selector is not None:
        if config.teacher != "own":
            raise ParameterError(f"The 'goal_selector' parameter of {owner} replaces the run's teacher, and Config names teacher={config.teacher!r}: give one of them (Config(teacher='own') with a goal_selector).", "goal_selector", type(goal_selector).__name__)
        from ..testing import check_goal_selector_interface

        check_goal_selector_interface(goal_selector, config)
        if callable(getattr(goal_selector, "check_competences", None)):
            goal_selector.check_competences(config.min_c, 0.0, "a run tells (min_c to 0)")
        extra["goal_selector"] = goal_selector
        extras["goal_selector"] = f"{type(goal_selector).__module__}.{type(goal_selector).__qualname__}"
    learner = _core.Learner(core, learner_seed, eval_seed, env_seed=environment_seed(seed), **extra)
    learner.set_threads(threads)
    return learner, {"seed": seed, "learner_seed": learner_seed, "eval_seed": eval_seed}, extras


def _arm_scale(config: Config) -> dict[str, Any]:
    """run.json's "scale" for the built-in body: its reach and the lengths that follow it."""
    return {"reach": config.reach, "source": "chain" if config.chain is not None else "arm", **config.lengths()}


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


class CheckpointWarning(UserWarning):
    """A checkpoint could not be written; the run goes on and the last good checkpoint stays."""


def _check_checkpointing(every: Any, out: Path | None, environment: Any, goal_selector: Any) -> int:
    """``checkpoint_every`` as a plain int (a numpy one would not go into checkpoint.json)."""
    if isinstance(every, (bool, np.bool_)) or not isinstance(every, (int, np.integer)) or every < 1:
        raise ParameterError(f"The 'checkpoint_every' parameter of run must be an int >= 1 (time steps). Got {every!r} instead.", "checkpoint_every", repr(every))
    if out is None:
        raise ParameterError("The 'checkpoint_every' parameter of run needs out_dir, where the checkpoint is kept. Got out_dir=None.", "checkpoint_every", repr(every))
    if environment is not None or goal_selector is not None:
        raise ParameterError("The 'checkpoint_every' parameter of run is not available with a user's environment or goal selector (saggriac cannot save their state).", "checkpoint_every", repr(every))
    return int(every)


def _check_provenance(ck: Path, info: dict[str, Any], every: Any) -> None:
    """checkpoint.json's own values must agree with each other before anything is resumed."""
    try:
        seed = check_seed(info["seed"])
    except ParameterError:
        raise StorageError(f"The checkpoint {ck} is damaged: its seed {info['seed']!r} is not a seed.") from None
    if derive_seeds(seed) != (info["learner_seed"], info["eval_seed"]):
        raise StorageError(f"The checkpoint {ck} is inconsistent: its learner and evaluation seeds are not those of seed {seed}. Start the run over: run it again without --resume.")
    if isinstance(every, bool) or not isinstance(every, int) or every < 1:
        raise StorageError(f"The checkpoint {ck} is damaged: checkpoint_every is {every!r}, not an int >= 1.")
    if not isinstance(info["overwrite"], bool):
        raise StorageError(f"The checkpoint {ck} is damaged: overwrite is {info['overwrite']!r}, not true or false.")


def checkpoint_dir(out: str | Path) -> Path:
    """Where the checkpoint of the run that will be written to ``out`` is kept."""
    out = Path(out)
    return sibling(Path(out), ".checkpoint")


def _write_checkpoint(out: Path, state: bytes, info: dict[str, Any], config: Config, steps: int, every: int) -> None:
    """Replace the checkpoint atomically: the state and a readable description."""
    meta = {"config": config.to_dict(), "steps": steps, "checkpoint_every": every, **info, "version": _core.__version__, "git_commit": _core.GIT_COMMIT}

    def fill(tmp: Path) -> None:
        (tmp / "state.bin").write_bytes(state)
        (tmp / "checkpoint.json").write_text(json.dumps(seal(meta), indent=2, sort_keys=True))

    replace_dir(checkpoint_dir(out), fill, "the checkpoint", replace=_is_checkpoint)


def _is_checkpoint(path: Path) -> bool:
    """A checkpoint folder saggriac wrote (and may replace): its two files and nothing else."""
    try:
        return path.is_dir() and not path.is_symlink() and set(os.listdir(path)) <= CHECKPOINT_FILES and (path / "state.bin").exists()
    except OSError:
        return False


def _test_set_summary(t: dict[str, Any], config: Config, reach: float | None) -> dict[str, Any]:
    """What the forward-model metric was measured on, and its no-learning values."""
    true_x = np.asarray(t["true_x"], dtype=float)
    out: dict[str, Any] = {
        "configs": t["kind"],
        "n_configs": int(len(true_x)),
        # Predicting the origin (what an empty memory gives) and predicting no motion.
        "pred_error_no_learning": float(np.linalg.norm(true_x, axis=1).mean()) if len(true_x) else None,
        "dx_error_no_learning": 1.0,
    }
    residuals = np.asarray(t["ik_residuals"], dtype=float)
    if t["kind"] == "ik_min_norm":
        scale = reach if reach is not None else config.reach
        out["unreached_goals"] = int((residuals > _core.IK_TOLERANCE * scale).sum())
        out["max_ik_residual"] = float(residuals.max()) if len(residuals) else 0.0
        out["mean_config_norm"] = float(np.linalg.norm(np.asarray(t["configs"], dtype=float), axis=1).mean())
    return out


def _drive(learner: Any, config: Config, info: dict[str, Any], out: Path | None, progress: bool, every: int | None, extras: dict[str, Any]) -> RunResult:
    """Run ``learner`` to the end of its budget, checkpointing if asked, and save the result."""
    seed = info["seed"]
    bar = None
    if progress:
        from tqdm.auto import tqdm

        bar = tqdm(total=config.n_steps, initial=learner.steps, unit="step", unit_scale=True, desc=f"{config.condition} seed {seed}")
    next_checkpoint = None if every is None else (learner.steps // every + 1) * every

    def on_eval(row: dict[str, Any]) -> bool:
        if bar is not None:
            bar.update(row["step"] - bar.n)
            bar.set_postfix(reach=f"{row['reach_error']:.2f}", pred=f"{row['pred_error']:.2f}", goals=row["n_goals"])
        # Stop (between goal attempts) to write a checkpoint once one is due.
        return not (next_checkpoint is not None and next_checkpoint <= row["step"] < config.n_steps)

    t0 = time.perf_counter()
    try:
        while not learner.run(on_eval) and learner.steps < config.n_steps:
            try:
                _write_checkpoint(out, learner.checkpoint(), info, config, learner.steps, every)
                info["last_checkpoint"] = learner.steps
            except StorageError as e:
                # Losing a checkpoint only costs what a later interruption would redo; losing
                # the run would cost everything.
                last = info.get("last_checkpoint", info.get("resumed_at"))
                kept = f"the last good checkpoint (step {last}) is kept" if last is not None else "there is no earlier checkpoint"
                warnings.warn(f"The checkpoint at step {learner.steps} could not be written ({e}); the run goes on and {kept}.", CheckpointWarning, stacklevel=2)
            next_checkpoint = (learner.steps // every + 1) * every
    finally:
        if bar is not None:
            bar.close()
    wall = time.perf_counter() - t0

    result = _result(learner, config, info, extras, wall)
    metrics, goals, attempts, regions, manifest = result.metrics, result.goals, result.attempts, result.regions, result.manifest
    if out is not None:
        try:
            result.path = write_run(out, manifest, {"metrics": metrics, "goals": goals, "attempts": attempts, "regions": regions}, info["overwrite"])
        except StorageError as e:
            # The disk filled up or vanished after the work was done: keep the work.
            e.result = result
            e.args = (f"{e} The result is kept in this exception's .result; save it elsewhere with .result.save(path).",)
            raise
        if _is_checkpoint(checkpoint_dir(out)):
            shutil.rmtree(checkpoint_dir(out), ignore_errors=True)
    return result


def _result(learner: Any, config: Config, info: dict[str, Any], extras: dict[str, Any], wall: float) -> RunResult:
    """What ``learner`` has done so far, as a run's result: its four tables and run.json."""
    seed = info["seed"]
    metrics = pd.DataFrame(learner.metrics())
    goals = _xy_columns(learner.goals())
    attempts = _xy_columns(learner.attempts())
    regions = _xy_columns(learner.regions())
    manifest = {
        "config": config.to_dict(),
        "seed": seed,
        "learner_seed": info["learner_seed"],
        "eval_seed": info["eval_seed"],
        "version": _core.__version__,
        "git_commit": _core.GIT_COMMIT,
        "python": platform.python_version(),
        "wall_seconds": wall,
        "profile": learner.profile(),
        **extras,
    }
    if info.get("resumed_at") is not None:
        manifest["resumed_at_step"] = info["resumed_at"]
    # A learner stopped early (Learner.run(until=...)) saves a result too: say how far it got.
    manifest["steps"] = {"done": int(learner.steps), "of": int(config.n_steps), "finished": bool(learner.steps >= config.n_steps)}
    reach = None if "environment" in extras else config.reach
    manifest["test_set"] = _test_set_summary(learner.test_set(), config, extras["scale"]["reach"])
    reachable = ReachableSet(config) if reach is not None and config.chain is not None else reach
    manifest["time_budget"] = time_budget(goals, manifest["profile"], config.n_steps, reachable)
    return RunResult(config=config, seed=seed, metrics=metrics, goals=goals, attempts=attempts, regions=regions, manifest=manifest, path=None)


def recover(result: RunResult, out: Path, why: str) -> str:
    """Save a finished result that could not be written to ``out`` in a recovery folder beside it
    (else in the current folder, else the temporary folder); return a message saying why and
    where it went."""
    reason = why.split(" The result is kept")[0]
    stamp = time.strftime("%Y%m%d-%H%M%S")
    name = Path(os.path.abspath(out)).name or "run"
    for parent in (Path(os.path.abspath(out)).parent, Path.cwd(), Path(tempfile.gettempdir())):
        place = next((p for i in range(100) if not os.path.lexists(p := parent / f"{name}.recovered-{stamp}{'' if i == 0 else f'-{i}'}")), None)
        if place is None:
            continue
        try:
            saved = result.save(place)
        except (StorageError, OSError):
            continue
        return f"{reason} The finished result was saved to {saved} instead; move it where you want it (to {out} for a study to count it without recomputing)."
    return f"{reason} The result could not be saved anywhere else either (tried beside {out}, the current folder and the temporary folder)."


def resume(out_dir: str | Path, progress: bool = False, threads: int | None = None) -> RunResult:
    """Continue the interrupted run whose checkpoint sits next to ``out_dir`` (written by
    ``run(..., out_dir=..., checkpoint_every=N)``), to the same result the run would have given
    without the interruption, and write it to ``out_dir``. ``threads`` as for ``run``."""
    progress = check_flag(progress, "progress", "resume")
    threads = check_threads(threads, "resume")
    out = as_path(out_dir, "out_dir", "resume")
    ck = checkpoint_dir(out)
    try:
        found = os.path.lexists(ck)
        finished = (out / "run.json").exists()
    except OSError as e:
        raise StorageError(f"Cannot look for a checkpoint of {out}: {e.strerror or e}.") from None
    if not found:
        if finished:
            raise StorageError(f"{out} already holds a finished run; there is nothing to resume.")
        raise StorageError(f"No checkpoint for {out} (looked for {ck}). Start the run with checkpoint_every (--checkpoint-every) to be able to resume it.")
    start_over = "Start the run over: run it again without --resume."
    if ck.is_symlink() or not ck.is_dir():
        raise StorageError(f"The checkpoint {ck} is damaged: it is not a folder (saggriac writes a folder holding state.bin and checkpoint.json). {start_over}")
    for name in sorted(CHECKPOINT_FILES):
        if not os.path.lexists(ck / name):
            raise StorageError(f"The checkpoint {ck} is damaged: it has no {name}. {start_over}")
    with target_lock(out):
        try:
            meta = json.loads(read_bounded(ck / "checkpoint.json", "a checkpoint.json", MAX_JSON_BYTES))
            if not isinstance(meta, dict):
                raise TypeError("not a JSON object")
            info = {k: meta[k] for k in ("seed", "learner_seed", "eval_seed", "overwrite")}
            every = meta["checkpoint_every"]
        except (OSError, ValueError, KeyError, TypeError, UnicodeDecodeError) as e:
            raise StorageError(f"The checkpoint {ck} is damaged: checkpoint.json cannot be read ({e}). {start_over}") from None
        check_seal(meta, ck / "checkpoint.json")
        config = Config.from_saved(meta["config"])
        _check_provenance(ck, info, every)
        # The old checkpoint is on the disk already: room for one more.
        check_output_dir(out, info["overwrite"], MIN_FREE_BYTES + checkpoint_bytes(config))
        try:
            # At most twice the largest state its configuration can make.
            state = read_bounded(ck / "state.bin", "a checkpoint's state.bin", 2 * checkpoint_bytes(config))
        except (OSError, StorageError) as e:
            raise StorageError(f"The checkpoint {ck} is damaged: {e} {start_over}") from None
        learner = _core.Learner.restore(config.core_dict(), state)
        if tuple(learner.seeds) != (info["learner_seed"], info["eval_seed"]):
            raise StorageError(f"The checkpoint {ck} is inconsistent: state.bin was made by a run with other seeds than checkpoint.json records (seed {info['seed']}). Start the run over: run it again without --resume.")
        learner.set_threads(threads)
        info["resumed_at"] = learner.steps
        return _drive(learner, config, info, out, progress, every, {"scale": _arm_scale(config)})
