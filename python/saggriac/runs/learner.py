"""One learner, step by step: what :func:`saggriac.run` does, in the open.

    learner = saggriac.Learner(saggriac.Config.from_preset("exp1"), seed=0)
    learner.run(until=10_000)          # stops after the first evaluation at or after step 10,000
    learner.test_set()["goals"]        # the fixed test goals of this seed
    learner.run()                      # on to the end of the budget
    result = learner.result()          # a RunResult, as run() returns it (result.save(path))

``learner.save_checkpoint(out_dir, checkpoint_every=N)`` saves it as ``run(..., out_dir=...,
checkpoint_every=N)`` does on the way; ``saggriac.resume(out_dir)`` then runs it to the end, and
``Learner.from_checkpoint(out_dir)`` reads it back. ``learner.run(stop_every=N, on_stop=f)``
calls ``f(learner)`` at the first evaluation at or after each multiple of N: how a run writes its
checkpoints.

``run(config, seed, ...)`` is this class run to the end with its result written (runs/runner.py
builds a Learner, drives it through ``run`` and owns the run's folder); the two give the same
bits, however the run is cut into pieces. A learner stops only after an evaluation (``Config.schedule()``), at the end
of the goal attempt during which it fell: that is where its state is whole, and where
``checkpoint()`` may be taken. With ``threads`` > 1 evaluations run beside learning, so the
learner may go on a few attempts past that evaluation before it sees it (the results are the
same bits either way); with ``threads=1`` it stops right there.
"""

from __future__ import annotations

import platform
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from .. import _core
from ..config import Config
from ..errors import ParameterError, StorageError
from ..files import as_path, check_flag
from ..bodies.reachable import ReachableSet
from ..bodies.scale import body_scale
from ..seeding import check_seed, derive_seeds, environment_seed
from ..testing import joint_space_of
from .checkpoint import START_OVER, check_every, find_checkpoint, read_description, read_state, save_checkpoint
from .resources import check_run_fits, check_threads, checkpoint_bytes
from .result import RunResult
from .run_info import RunInfo
from .time_budget import time_budget


class Learner:
    """A learner of ``config`` with root seed ``seed`` (the seeds of every part derive from it:
    saggriac.seeding), on the built-in body or ``environment``, with its own high level or
    ``goal_selector``; ``threads`` as for :func:`saggriac.run`. ``caller`` is the name its
    messages give for what was called (``run`` passes "run")."""

    def __init__(self, config: Config | None = None, seed: int = 0, *, environment: Any = None, goal_selector: Any = None, threads: int | None = None, caller: str = "Learner") -> None:
        owner = caller
        if config is None:
            config = Config()
        if not isinstance(config, Config):
            raise ParameterError(f"The 'config' parameter of {owner} must be a saggriac.Config. Got {type(config).__name__} instead.", "config", repr(config))
        self.config = config = for_body(config, environment)
        self.seed = check_seed(seed)
        threads = check_threads(threads, owner)
        check_run_fits(config)
        self._inner, self.info, self._extras = _build(config, self.seed, threads, environment, goal_selector, owner)
        self._wall = 0.0

    @classmethod
    def from_checkpoint(cls, out_dir: str | Path, threads: int | None = None) -> Learner:
        """The learner whose checkpoint was saved for ``out_dir`` (by ``run(...,
        checkpoint_every=N)`` or :meth:`save_checkpoint`), exactly as it was; its ``info`` holds
        the checkpoint's seeds, overwrite flag and ``checkpoint_every``. Nothing is written."""
        threads = check_threads(threads, "Learner.from_checkpoint")
        ck = find_checkpoint(as_path(out_dir, "out_dir", "Learner.from_checkpoint"))
        config, saved, every = read_description(ck)
        # At most twice the largest state its configuration can make.
        state = read_state(ck, 2 * checkpoint_bytes(config))
        self = cls.__new__(cls)
        self.config, self.seed, self._wall = config, saved["seed"], 0.0
        self._inner = _core.Learner.restore(config.core_dict(), state)
        self._inner.set_threads(threads)
        if tuple(self._inner.seeds) != (saved["learner_seed"], saved["eval_seed"]):
            raise StorageError(f"The checkpoint {ck} is inconsistent: state.bin was made by a run with other seeds than checkpoint.json records (seed {saved['seed']}). {START_OVER}")
        self.info = RunInfo(saved["seed"], saved["learner_seed"], saved["eval_seed"], overwrite=saved["overwrite"], resumed_at=self.steps, checkpoint_every=every)
        self._extras = {"scale": _arm_scale(config)}
        return self

    @property
    def saves_state(self) -> bool:
        """Whether its whole state can be saved: not with a user's environment or goal selector,
        whose state saggriac cannot hold."""
        return "environment" not in self._extras and "goal_selector" not in self._extras

    @property
    def steps(self) -> int:
        """Time steps done (micro-actions, or movements in the episodic paradigm)."""
        return int(self._inner.steps)

    @property
    def seeds(self) -> tuple[int, int]:
        """The (learner, evaluation) seeds derived from the root seed."""
        return (self.info.learner_seed, self.info.eval_seed)

    @property
    def done(self) -> bool:
        """Whether the step budget (``config.n_steps``) is spent."""
        return self.steps >= self.config.n_steps

    def run(self, until: int | None = None, progress: bool = False, *, stop_every: int | None = None, on_stop: Callable[[Learner], Any] | None = None) -> bool:
        """Learn until the first evaluation at or after step ``until`` (default: the end of the
        budget), then to the end of that goal attempt; ``progress`` shows a progress bar. With
        ``stop_every=N`` and ``on_stop``, call ``on_stop(self)`` at the first evaluation at or
        after each multiple of N before the end (where the state is whole: a checkpoint may be
        taken), and go on. Returns True once the budget is spent."""
        progress = check_flag(progress, "progress", "Learner.run")
        target = self.config.n_steps if until is None else until
        if isinstance(target, (bool, np.bool_)) or not isinstance(target, (int, np.integer)) or target < 0:
            raise ParameterError(f"The 'until' parameter of Learner.run must be an int >= 0 (a time step) or None (the end of the budget). Got {until!r} instead.", "until", repr(until))
        if (stop_every is None) != (on_stop is None):
            raise ParameterError(f"The 'stop_every' and 'on_stop' parameters of Learner.run go together (stop every N steps, to call on_stop). Got stop_every={stop_every!r} and on_stop={on_stop!r}.", "stop_every", repr(stop_every))
        if stop_every is not None:
            if isinstance(stop_every, (bool, np.bool_)) or not isinstance(stop_every, (int, np.integer)) or stop_every < 1:
                raise ParameterError(f"The 'stop_every' parameter of Learner.run must be an int >= 1 (time steps). Got {stop_every!r} instead.", "stop_every", repr(stop_every))
            if not callable(on_stop):
                raise ParameterError(f"The 'on_stop' parameter of Learner.run must be a function of the learner. Got {on_stop!r} instead.", "on_stop", repr(on_stop))
            stop_every = int(stop_every)
        # A numpy integer compares into a numpy bool, which the core does not read as a stop.
        self._advance(int(target), progress, stop_every, on_stop)
        return self.done

    def _advance(self, target: int, progress: bool, every: int | None, on_stop: Callable[[Learner], Any] | None) -> None:
        """The one loop of every run: learn until the first evaluation at or after ``target``,
        with a progress bar if asked; with ``every``, stop at the first evaluation at or after
        each multiple of it to call ``on_stop``, and go on."""
        n = self.config.n_steps
        bar = None
        if progress:
            from tqdm.auto import tqdm

            bar = tqdm(total=n, initial=self.steps, unit="step", unit_scale=True, desc=f"{self.config.condition} seed {self.seed}")
        due = None if every is None else (self.steps // every + 1) * every

        def on_eval(row: dict[str, Any]) -> bool:
            if bar is not None:
                bar.update(row["step"] - bar.n)
                bar.set_postfix(reach=f"{row['reach_error']:.2f}", pred=f"{row['pred_error']:.2f}", goals=row["n_goals"])
            # Stop (between goal attempts) at the target, or to write a checkpoint once one is due.
            return row["step"] < target and not (due is not None and due <= row["step"] < n)

        t0 = time.perf_counter()
        try:
            if self.done or not (self.steps < target or self.steps == 0):
                return
            while not self._inner.run(on_eval) and self.steps < n:
                if due is None or self.steps < due:
                    return  # stopped at the target
                on_stop(self)
                due = (self.steps // every + 1) * every
                if self.steps >= target:
                    return
        finally:
            self._wall += time.perf_counter() - t0
            if bar is not None:
                bar.close()

    def test_set(self) -> dict[str, Any]:
        """The fixed test sets of this seed: ``goals`` (the reaching test), ``configs``, ``true_x``
        and the rest of the forward-model test (see docs/parameters.md, ``test_configs``)."""
        return dict(self._inner.test_set())

    def checkpoint(self) -> bytes:
        """The learner's whole state, as ``run(..., checkpoint_every=N)`` saves it."""
        return bytes(self._inner.checkpoint())

    def save_checkpoint(self, out_dir: str | Path, checkpoint_every: int, overwrite: bool = False) -> Path:
        """Save the learner's whole state as the checkpoint of the run that is to be written to
        ``out_dir``, as ``run(config, seed, out_dir, overwrite, checkpoint_every=N)`` saves it on
        the way: ``saggriac.resume(out_dir)`` then runs it to the end of the budget, checkpointing
        every ``checkpoint_every`` steps, and writes the result there. Returns the checkpoint's
        folder (beside ``out_dir``)."""
        owner = "Learner.save_checkpoint"
        out = as_path(out_dir, "out_dir", owner)
        every = check_every(checkpoint_every, owner)
        overwrite = check_flag(overwrite, "overwrite", owner)
        if not self.saves_state:
            raise ParameterError(f"{owner} is not available with a user's environment or goal selector (saggriac cannot save their state).", "checkpoint_every", repr(every))
        return save_checkpoint(out, self.checkpoint(), self.info.for_checkpoint(), self.config, self.steps, every, overwrite)

    def result(self) -> RunResult:
        """What was learnt so far, as :func:`saggriac.run` returns it (nothing is written;
        ``result().save(path)`` writes it)."""
        return _result(self._inner, self.config, self.info, self._extras, self._wall)

    def __repr__(self) -> str:
        return f"Learner(condition={self.config.condition!r}, seed={self.seed}, steps={self.steps} of {self.config.n_steps})"


def for_body(config: Config, environment: Any) -> Config:
    """The configuration of a run on ``environment``: the joint limit is the body's (its
    ``joint_space``), so a user's body states it once; ``Config.joint_limit`` is for saggriac's
    own arms. The resolved value is what run.json records."""
    if environment is None:
        return config
    limit = float(joint_space_of(environment)[1][0])
    if limit == config.joint_limit:
        return config
    try:
        return config.replace(joint_limit=limit)
    except ParameterError as e:
        raise ParameterError(f"The environment's joint_space gives the joint limit {limit:g}, which a run cannot take: {e}", "environment.joint_space", f"{limit:g}") from None


def _build(config: Config, seed: int, threads: int, environment: Any, goal_selector: Any, owner: str) -> tuple[Any, RunInfo, dict[str, Any]]:
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
            body = body_scale(environment, *joint_space_of(environment), len(config.goal_low))
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
    return learner, RunInfo(seed, learner_seed, eval_seed), extras


def _arm_scale(config: Config) -> dict[str, Any]:
    """run.json's "scale" for the built-in body: its reach and the lengths that follow it."""
    return {"reach": config.reach, "source": "chain" if config.chain is not None else "arm", **config.lengths()}


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


def _result(learner: Any, config: Config, info: RunInfo, extras: dict[str, Any], wall: float) -> RunResult:
    """What ``learner`` has done so far, as a run's result: its four tables and run.json."""
    seed = info.seed
    metrics = pd.DataFrame(learner.metrics())
    goals = _xy_columns(learner.goals())
    attempts = _xy_columns(learner.attempts())
    regions = _xy_columns(learner.regions())
    manifest = {
        "config": config.to_dict(),
        "seed": seed,
        "learner_seed": info.learner_seed,
        "eval_seed": info.eval_seed,
        "version": _core.__version__,
        "git_commit": _core.GIT_COMMIT,
        "python": platform.python_version(),
        "wall_seconds": wall,
        "profile": learner.profile(),
        **extras,
    }
    if info.resumed_at is not None:
        manifest["resumed_at_step"] = info.resumed_at
    # A learner stopped early (Learner.run(until=...)) saves a result too: say how far it got.
    manifest["steps"] = {"done": int(learner.steps), "of": int(config.n_steps), "finished": bool(learner.steps >= config.n_steps)}
    reach = None if "environment" in extras else config.reach
    manifest["test_set"] = _test_set_summary(learner.test_set(), config, extras["scale"]["reach"])
    reachable = ReachableSet(config) if reach is not None and config.chain is not None else reach
    manifest["time_budget"] = time_budget(goals, manifest["profile"], config.n_steps, reachable)
    return RunResult(config=config, seed=seed, metrics=metrics, goals=goals, attempts=attempts, regions=regions, manifest=manifest, path=None)


__all__ = ["Learner", "RunInfo"]
