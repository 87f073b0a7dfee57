"""The result of one run: learning curves as numpy arrays and the records as DataFrames."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from ..config import Config
from .storage import read_run


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
        manifest, tables = read_run(Path(path))
        empty = pd.DataFrame()
        return cls(
            config=Config.from_saved(manifest["config"]),
            seed=manifest["seed"],
            metrics=tables["metrics"],
            goals=tables.get("goals", empty),
            attempts=tables.get("attempts", empty),
            regions=tables.get("regions", empty),
            manifest=manifest,
            path=Path(path),
        )

    def __repr__(self) -> str:
        return (
            f"RunResult(condition={self.config.condition!r}, seed={self.seed}, steps={int(self.steps[-1])}, "
            f"final_reach_error={self.final_reach_error:.3f}, final_pred_error={self.final_pred_error:.3f})"
        )
