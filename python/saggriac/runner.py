"""Run one learner: ``run(config, seed) -> RunResult``. A top-level, picklable function."""

from __future__ import annotations

import platform
import time
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from . import _core
from .config import Config
from .errors import ParameterError, StorageError
from .result import RunResult
from .seeding import check_seed, derive_seeds, environment_seed
from .storage import check_output_dir, write_run


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
    environment: Any = None,
    goal_selector: Any = None,
) -> RunResult:
    """Run one learner for ``config.n_steps`` time steps (micro-actions, or movements when episodic) and return its result.

    With ``out_dir`` the run directory is written atomically (manifest ``run.json`` with the
    resolved configuration, seeds, version and git commit; Parquet tables for metrics, goals,
    attempts and regions). ``progress`` shows a progress bar with the current reaching error.
    """
    if config is None:
        config = Config()
    if not isinstance(config, Config):
        raise ParameterError(f"The 'config' parameter of run must be a saggriac.Config. Got {type(config).__name__} instead.", "config", repr(config))
    seed = check_seed(seed)
    out = Path(out_dir) if out_dir is not None else None
    if out is not None:
        check_output_dir(out, overwrite)
    learner_seed, eval_seed = derive_seeds(seed)
    extra = {}
    if environment is not None:
        # The core calls it from its loop; check the protocol first so mistakes read plainly.
        from .testing import check_environment_interface

        check_environment_interface(environment, config)
        extra["environment"] = environment
    if goal_selector is not None:
        from .testing import check_goal_selector_interface

        check_goal_selector_interface(goal_selector, config)
        extra["goal_selector"] = goal_selector
    learner = _core.Learner(config.core_dict(), learner_seed, eval_seed, env_seed=environment_seed(seed), **extra)

    bar = None
    if progress:
        from tqdm.auto import tqdm

        bar = tqdm(total=config.n_steps, unit="step", unit_scale=True, desc=f"{config.condition} seed {seed}")

    def on_eval(row: dict[str, Any]) -> bool:
        if bar is not None:
            bar.update(row["step"] - bar.n)
            bar.set_postfix(reach=f"{row['reach_error']:.2f}", pred=f"{row['pred_error']:.2f}", goals=row["n_goals"])
        return True

    t0 = time.perf_counter()
    try:
        learner.run(on_eval)
    finally:
        if bar is not None:
            bar.close()
    wall = time.perf_counter() - t0

    metrics = pd.DataFrame(learner.metrics())
    goals = _xy_columns(learner.goals())
    attempts = _xy_columns(learner.attempts())
    regions = _xy_columns(learner.regions())
    manifest = {
        "config": config.to_dict(),
        "seed": seed,
        "learner_seed": learner_seed,
        "eval_seed": eval_seed,
        "version": _core.__version__,
        "git_commit": _core.GIT_COMMIT,
        "python": platform.python_version(),
        "wall_seconds": wall,
        "profile": learner.profile(),
    }
    if environment is not None:
        manifest["environment"] = f"{type(environment).__module__}.{type(environment).__qualname__}"
    if goal_selector is not None:
        manifest["goal_selector"] = f"{type(goal_selector).__module__}.{type(goal_selector).__qualname__}"
    result = RunResult(config=config, seed=seed, metrics=metrics, goals=goals, attempts=attempts, regions=regions, manifest=manifest, path=None)
    if out is not None:
        try:
            result.path = write_run(out, manifest, {"metrics": metrics, "goals": goals, "attempts": attempts, "regions": regions}, overwrite)
        except StorageError as e:
            # The disk filled up or vanished after the work was done: keep the work.
            e.result = result
            e.args = (f"{e} The result is kept in this exception's .result; save it elsewhere with .result.save(path).",)
            raise
    return result
