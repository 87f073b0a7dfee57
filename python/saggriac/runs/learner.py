"""One learner, step by step: what :func:`saggriac.run` does, in the open.

    learner = saggriac.Learner(saggriac.Config.from_preset("exp1"), seed=0)
    learner.run(until=10_000)          # stops after the first evaluation at or after step 10,000
    learner.test_set()["goals"]        # the fixed test goals of this seed
    learner.run()                      # on to the end of the budget
    result = learner.result()          # a RunResult, as run() returns it (result.save(path))

``learner.save_checkpoint(out_dir, checkpoint_every=N)`` saves it as ``run(..., out_dir=...,
checkpoint_every=N)`` does on the way; ``saggriac.resume(out_dir)`` then runs it to the end.

``run(config, seed, ...)`` is this class run to the end with its result written; the two give
the same bits, however the run is cut into pieces. A learner stops only after an evaluation
(``Config.schedule()``), at the end of the goal attempt during which it fell: that is where its
state is whole, and where ``checkpoint()`` may be taken. With ``threads`` > 1 evaluations run
beside learning, so the learner may go on a few attempts past that evaluation before it sees
it (the results are the same bits either way); with ``threads=1`` it stops right there.
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

import numpy as np

from ..config import Config
from ..errors import ParameterError
from ..files import as_path, check_flag
from ..seeding import check_seed
from .resources import check_run_fits, check_threads
from .result import RunResult
from .runner import _build, _result, _write_checkpoint, checkpoint_dir, for_body
from .storage import check_output_dir, target_lock


class Learner:
    """A learner of ``config`` with root seed ``seed`` (the seeds of every part derive from it:
    saggriac.seeding), on the built-in body or ``environment``, with its own high level or
    ``goal_selector``; ``threads`` as for :func:`saggriac.run`."""

    def __init__(self, config: Config | None = None, seed: int = 0, *, environment: Any = None, goal_selector: Any = None, threads: int | None = None) -> None:
        if config is None:
            config = Config()
        if not isinstance(config, Config):
            raise ParameterError(f"The 'config' parameter of Learner must be a saggriac.Config. Got {type(config).__name__} instead.", "config", repr(config))
        self.config = config = for_body(config, environment)
        self.seed = check_seed(seed)
        check_run_fits(config)
        self._inner, self._info, self._extras = _build(config, self.seed, check_threads(threads, "Learner"), environment, goal_selector, "Learner")
        self._wall = 0.0

    @property
    def steps(self) -> int:
        """Time steps done (micro-actions, or movements in the episodic paradigm)."""
        return int(self._inner.steps)

    @property
    def seeds(self) -> tuple[int, int]:
        """The (learner, evaluation) seeds derived from the root seed."""
        return (self._info["learner_seed"], self._info["eval_seed"])

    @property
    def done(self) -> bool:
        """Whether the step budget (``config.n_steps``) is spent."""
        return self.steps >= self.config.n_steps

    def run(self, until: int | None = None, progress: bool = False) -> bool:
        """Learn until the first evaluation at or after step ``until`` (default: the end of the
        budget), then to the end of that goal attempt; ``progress`` shows a progress bar.
        Returns True once the budget is spent."""
        progress = check_flag(progress, "progress", "Learner.run")
        target = self.config.n_steps if until is None else until
        if isinstance(target, (bool, np.bool_)) or not isinstance(target, (int, np.integer)) or target < 0:
            raise ParameterError(f"The 'until' parameter of Learner.run must be an int >= 0 (a time step) or None (the end of the budget). Got {until!r} instead.", "until", repr(until))
        # A numpy integer compares into a numpy bool, which the core does not read as a stop.
        target = int(target)
        bar = None
        if progress:
            from tqdm.auto import tqdm

            bar = tqdm(total=self.config.n_steps, initial=self.steps, unit="step", unit_scale=True, desc=f"{self.config.condition} seed {self.seed}")

        def on_eval(row: dict[str, Any]) -> bool:
            if bar is not None:
                bar.update(row["step"] - bar.n)
                bar.set_postfix(reach=f"{row['reach_error']:.2f}")
            return bool(row["step"] < target)

        t0 = time.perf_counter()
        try:
            if not self.done and (self.steps < target or self.steps == 0):
                self._inner.run(on_eval)
        finally:
            self._wall += time.perf_counter() - t0
            if bar is not None:
                bar.close()
        return self.done

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
        every = checkpoint_every
        if isinstance(every, (bool, np.bool_)) or not isinstance(every, (int, np.integer)) or every < 1:
            raise ParameterError(f"The 'checkpoint_every' parameter of {owner} must be an int >= 1 (time steps). Got {every!r} instead.", "checkpoint_every", repr(every))
        overwrite = check_flag(overwrite, "overwrite", owner)
        if "environment" in self._extras or "goal_selector" in self._extras:
            raise ParameterError(f"{owner} is not available with a user's environment or goal selector (saggriac cannot save their state).", "checkpoint_every", repr(every))
        # Refuse now a target that resume() could not write to.
        check_output_dir(out, overwrite)
        with target_lock(out):
            _write_checkpoint(out, self.checkpoint(), {**self._info, "overwrite": overwrite}, self.config, self.steps, int(every))
        return checkpoint_dir(out)

    def result(self) -> RunResult:
        """What was learnt so far, as :func:`saggriac.run` returns it (nothing is written;
        ``result().save(path)`` writes it)."""
        return _result(self._inner, self.config, self._info, self._extras, self._wall)

    def __repr__(self) -> str:
        return f"Learner(condition={self.config.condition!r}, seed={self.seed}, steps={self.steps} of {self.config.n_steps})"


__all__ = ["Learner"]
