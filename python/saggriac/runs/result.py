"""The result of one run: learning curves as numpy arrays and the records as DataFrames."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from ..config import Config
from .storage import read_run


def run_stopped_early(manifest: dict[str, Any], metrics: pd.DataFrame | None = None) -> str | None:
    """Why the run of ``manifest`` is not a finished one (it stopped at step N of M), or None.

    run.json records the steps done since saggriac 0.6; for an older one, a run whose last
    evaluation is not the schedule's last was stopped early (``metrics``: its metrics table)."""
    steps = manifest.get("steps")
    if isinstance(steps, dict):
        if steps.get("finished") is True:
            return None
        return f"it stopped at step {steps.get('done')} of {steps.get('of')} (a partial run, saved from a learner stopped early)"
    if metrics is None or not len(metrics):
        return None
    try:
        last = Config.from_saved(manifest["config"], manifest.get("version")).schedule()[-1]
    except (KeyError, TypeError, ValueError, OSError):  # an unreadable config is reported where the run is read
        return None
    got = int(metrics["step"].iloc[-1])
    if got < last:
        return f"its last evaluation is at step {got}, the schedule's last at step {last} (a partial run, saved from a learner stopped early)"
    return None


@dataclass
class RunResult:
    config: Config
    seed: int
    metrics: pd.DataFrame
    goals: pd.DataFrame
    attempts: pd.DataFrame
    regions: pd.DataFrame
    manifest: dict[str, Any]
    path: Path | None = None

    @property
    def steps(self) -> np.ndarray:
        return self.metrics["step"].to_numpy()

    @property
    def reach_error(self) -> np.ndarray:
        return self.metrics["reach_error"].to_numpy()

    @property
    def pred_error(self) -> np.ndarray:
        return self.metrics["pred_error"].to_numpy()

    @property
    def finished(self) -> bool:
        """Whether the run spent its whole budget (``config.n_steps``); False for the result of
        a learner stopped early (``Learner.run(until=...)``)."""
        return run_stopped_early(self.manifest, self.metrics) is None

    @property
    def steps_done(self) -> int | None:
        """Time steps the learner did (run.json's ``steps.done``); None for a partial run saved
        by saggriac 0.5.0, whose run.json did not record it."""
        steps = self.manifest.get("steps")
        if isinstance(steps, dict):
            return steps.get("done")
        return self.config.n_steps if self.finished else None

    @property
    def final_reach_error(self) -> float:
        return float(self.reach_error[-1])

    @property
    def final_pred_error(self) -> float:
        return float(self.pred_error[-1])

    def save(self, path: str | Path, overwrite: bool = False) -> Path:
        """Write this result as a run directory (atomically, as ``saggriac.run`` does)."""
        from ..files import check_flag
        from .storage import as_path, check_output_dir, target_lock, write_run

        out = as_path(path, "path", "RunResult.save")
        overwrite = check_flag(overwrite, "overwrite", "RunResult.save")
        check_output_dir(out, overwrite)
        tables = {"metrics": self.metrics, "goals": self.goals, "attempts": self.attempts, "regions": self.regions}
        with target_lock(out, what="save"):
            self.path = write_run(out, self.manifest, tables, overwrite)
        return self.path

    @classmethod
    def load(cls, path: str | Path) -> RunResult:
        from .storage import as_path

        path = as_path(path, "path", "RunResult.load")
        manifest, tables = read_run(path)
        empty = pd.DataFrame()
        return cls(
            config=Config.from_saved(manifest["config"], manifest.get("version")),
            seed=manifest["seed"],
            metrics=tables["metrics"],
            goals=tables.get("goals", empty),
            attempts=tables.get("attempts", empty),
            regions=tables.get("regions", empty),
            manifest=manifest,
            path=Path(path),
        )

    def __repr__(self) -> str:
        partial = "" if self.finished else f", partial: stopped at step {self.steps_done if self.steps_done is not None else int(self.steps[-1])} of {self.config.n_steps}"
        return (
            f"RunResult(condition={self.config.condition!r}, seed={self.seed}, steps={int(self.steps[-1])}{partial}, "
            f"final_reach_error={self.final_reach_error:.3f}, final_pred_error={self.final_pred_error:.3f})"
        )
