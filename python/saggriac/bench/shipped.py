"""The built-in teachers' results that ship with the package, one set per tier, so that a user's
teacher is placed among them without rerunning them: ``results/<tier>_runs.parquet`` (one row
per run), ``results/<tier>_curves.parquet`` (their score curves), ``results/<tier>_goals.parquet``
(each teacher's goals on each task's first seed, thinned, their first two dimensions: the figures
of goals over time) and
``results/<tier>.json`` (the saggriac version that made them, the seeds and the command)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pandas as pd

from .. import _core
from ..errors import StorageError
from .goals import COLUMNS as GOAL_COLUMNS
from .goals import first_seed

RESULTS = Path(__file__).parent / "results"


def paths(tier: str, folder: Path = RESULTS) -> tuple[Path, Path, Path]:
    return folder / f"{tier}_runs.parquet", folder / f"{tier}_curves.parquet", folder / f"{tier}.json"


#: The goals' dimensions that ship: the figures show the first two.
SHIPPED_DIMS = 2


def goals_path(tier: str, folder: Path = RESULTS) -> Path:
    return folder / f"{tier}_goals.parquet"


def load_goals(tier: str, folder: Path = RESULTS) -> pd.DataFrame:
    """The goals shipped for ``tier`` (:func:`saggriac.bench.goals.goals_table`'s columns), empty if
    none ship."""
    path = goals_path(tier, folder)
    if not path.is_file():
        return pd.DataFrame(columns=GOAL_COLUMNS)
    try:
        return pd.read_parquet(path)
    except (OSError, ValueError) as e:
        raise StorageError(f"Cannot read the bench's shipped goals for the tier {tier!r} in {path}: {e}. Reinstall saggriac, or pass --rerun.") from None


def load(tier: str, folder: Path = RESULTS) -> tuple[pd.DataFrame, pd.DataFrame, dict[str, Any]] | None:
    """(runs, curves, meta) shipped for ``tier``, or None if none ship."""
    runs_p, curves_p, meta_p = paths(tier, folder)
    if not (runs_p.is_file() and curves_p.is_file() and meta_p.is_file()):
        return None
    try:
        return pd.read_parquet(runs_p), pd.read_parquet(curves_p), json.loads(meta_p.read_text())
    except (OSError, ValueError) as e:
        raise StorageError(f"Cannot read the bench's shipped results for the tier {tier!r} in {folder}: {e}. Reinstall saggriac, or pass --rerun.") from None


def write(tier: str, runs: pd.DataFrame, curves: pd.DataFrame, goals: pd.DataFrame, seeds: list[int], command: str, folder: Path = RESULTS) -> list[Path]:
    """Write the built-in teachers' runs of a finished bench as the shipped results of ``tier``,
    with their goals on each task's first seed only, first two dimensions (the figures show no
    other)."""
    runs_p, curves_p, meta_p = paths(tier, folder)
    folder.mkdir(parents=True, exist_ok=True)
    runs = runs.drop(columns=[c for c in ("source",) if c in runs]).sort_values(["task", "teacher", "seed"]).reset_index(drop=True)
    curves = curves.sort_values(["task", "teacher", "seed", "step"]).reset_index(drop=True)
    runs.to_parquet(runs_p, index=False)
    curves.to_parquet(curves_p, index=False)
    goals = goals[goals.dim < SHIPPED_DIMS]
    first_seed(goals).sort_values(["task", "teacher", "seed", "call", "dim"]).reset_index(drop=True).to_parquet(goals_path(tier, folder), index=False)
    meta = {"version": _core.__version__, "tier": tier, "seeds": [int(s) for s in seeds], "teachers": sorted(set(runs.teacher)), "tasks": sorted(set(runs.task)), "command": command}
    meta_p.write_text(json.dumps(meta, indent=1) + "\n")
    return [runs_p, curves_p, goals_path(tier, folder), meta_p]
