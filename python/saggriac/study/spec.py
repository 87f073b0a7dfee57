"""What a study is: runs of a base configuration for every condition, seed and point of a
parameter grid (:class:`Study`), each run a small picklable :class:`Task` that
:func:`run_task` runs into its folder."""

from __future__ import annotations

import itertools
import json
import os
import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .. import _core
from ..config import Config, check_keys
from ..errors import ParameterError, SaggriacError, StorageError
from ..runs.runner import recover, run
from ..seeding import check_seed
from ..files import MAX_JSON_BYTES, read_bounded
from ..runs.storage import MANIFEST, as_path

STUDY_FILE = "study.json"
LOCK_FILE = ".lock"
RUNS_DIR = "runs"
METRICS = ("reach_error", "pred_error", "dx_error", "n_goals", "n_regions")
STUDY_FORMAT = 1
#: A study of more seeds is a cluster's job: the seed list and per-run bookkeeping are held in memory.
MAX_SEEDS = 100_000
_SAFE_TEXT = re.compile(r"[A-Za-z0-9_.+-]+")


class IncompleteStudyWarning(UserWarning):
    """Runs of a study were left out of what was read or drawn (not finished, or partial); the
    message names them."""


class StudyError(SaggriacError):
    """Some runs of a study failed. ``failures`` maps each failed run's name to its exception;
    every other run is finished and saved."""

    def __init__(self, message: str, failures: dict[str, BaseException]):
        super().__init__(message)
        self.failures = failures


def _plain(value: Any) -> Any:
    """Numpy scalars to Python, sequences to tuples: hashable, comparable, JSON-ready."""
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, (list, tuple, np.ndarray)):
        return tuple(_plain(v) for v in value)
    return value


def _json_ready(value: Any) -> Any:
    if isinstance(value, tuple):
        return [_json_ready(v) for v in value]
    return value


def _format_value(key: str, value: Any) -> str:
    """A grid value as it appears in a directory name."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return repr(value)
    if value is None:
        return "none"
    if isinstance(value, str) and _SAFE_TEXT.fullmatch(value):
        return value
    if isinstance(value, tuple) and value:
        return ",".join(_format_value(key, v) for v in value)
    raise ParameterError(
        f"The values of grid key '{key}' must be numbers, None, strings of letters, digits and _.+- "
        f"or lists of those (they name directories). Got {value!r} instead.",
        "grid",
        repr(value),
    )


def _check_seeds(seeds: Any) -> tuple[int, ...]:
    """The seeds as ints, refused past MAX_SEEDS before more are read (a range of 10**9 is not
    walked through)."""
    if isinstance(seeds, (int, np.integer)):
        seeds = [seeds]
    try:
        head = list(itertools.islice(iter(seeds), MAX_SEEDS + 1))
    except TypeError:
        raise ParameterError(f"The 'seeds' parameter of Study must be an int or a list of ints. Got {seeds!r} instead.", "seeds", repr(seeds)) from None
    if len(head) > MAX_SEEDS:
        try:
            got = f"{len(seeds)} seeds"
        except (TypeError, OverflowError):
            got = f"more than {MAX_SEEDS} seeds"
        rule = f"a list of at most {MAX_SEEDS} seeds (a study of more is a cluster's job: the seed list and per-run bookkeeping are held in memory)"
        raise ParameterError(f"The 'seeds' parameter of Study must be {rule}. Got {got} instead.", "seeds", got)
    return tuple(check_seed(s) for s in head)


@dataclass(frozen=True)
class Task:
    """One run of a study: everything a worker needs, small and picklable."""

    name: str  # e.g. "sagg_riac__g_max=40/seed0"
    path: str  # relative to the study folder, e.g. "runs/sagg_riac__g_max=40/seed0"
    condition: str
    params: dict[str, Any]  # this run's grid point
    seed: int
    config: dict[str, Any]  # Config.to_dict() of the run


@dataclass(frozen=True)
class Study:
    """Runs of ``base`` for every condition, seed and point of ``grid`` (a dict from parameter
    names to lists of values; the product of its lists is taken)."""

    base: Config
    conditions: tuple[str, ...]
    seeds: tuple[int, ...]
    grid: dict[str, tuple] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if not isinstance(self.base, Config):
            raise ParameterError(f"The 'base' parameter of Study must be a saggriac.Config. Got {type(self.base).__name__} instead.", "base", repr(self.base))
        conditions = (self.conditions,) if isinstance(self.conditions, str) else tuple(self.conditions)
        seeds = _check_seeds(self.seeds)
        grid = {} if self.grid is None else self.grid
        if not isinstance(grid, Mapping):
            raise ParameterError(f"The 'grid' parameter of Study must be a dict from parameter names to lists of values. Got {type(grid).__name__} instead.", "grid", repr(grid))
        for name, values in (("conditions", conditions), ("seeds", seeds)):
            if not values:
                raise ParameterError(f"The '{name}' parameter of Study must not be empty.", name, repr(values))
            if len(set(values)) != len(values):
                raise ParameterError(f"The '{name}' parameter of Study must not repeat a value. Got {values!r} instead.", name, repr(values))
        check_keys(dict(grid), source=None)
        if "condition" in grid:
            raise ParameterError("The 'grid' parameter of Study cannot hold 'condition'; list the conditions in 'conditions'.", "grid", repr(dict(grid)))
        clean: dict[str, tuple] = {}
        for key in sorted(grid):
            values = grid[key]
            if isinstance(values, (str, bytes)) or not isinstance(values, Iterable):
                raise ParameterError(f"The values of grid key '{key}' must be a list. Got {values!r} instead.", "grid", repr(values))
            values = tuple(_plain(v) for v in values)
            if not values:
                raise ParameterError(f"The values of grid key '{key}' must not be empty.", "grid", repr(values))
            names = [_format_value(key, v) for v in values]
            if len(set(names)) != len(names):
                raise ParameterError(f"The values of grid key '{key}' must be distinct. Got {values!r} instead.", "grid", repr(values))
            clean[key] = values
        object.__setattr__(self, "conditions", conditions)
        object.__setattr__(self, "seeds", seeds)
        object.__setattr__(self, "grid", clean)
        self.tasks()  # every run's configuration is checked now, before any work

    def __hash__(self) -> int:
        return hash(json.dumps(self.to_dict(), sort_keys=True))

    def points(self) -> list[dict[str, Any]]:
        """The grid points, keys in sorted order (one empty point without a grid)."""
        keys = list(self.grid)
        return [dict(zip(keys, combo)) for combo in itertools.product(*(self.grid[k] for k in keys))]

    def tasks(self) -> list[Task]:
        """Every run, seed by seed (so a partial study compares conditions on the same seeds)."""
        # A run's configuration does not depend on its seed: built and checked once per group.
        groups = []
        for condition in self.conditions:
            for point in self.points():
                cfg = self.base.replace(condition=condition, **point).to_dict()
                groups.append((condition + "".join(f"__{k}={_format_value(k, v)}" for k, v in point.items()), condition, point, cfg))
        out = []
        for seed in self.seeds:
            for group, condition, point, cfg in groups:
                name = f"{group}/seed{seed}"
                out.append(Task(name=name, path=f"{RUNS_DIR}/{name}", condition=condition, params=dict(point), seed=seed, config=dict(cfg)))
        return out

    def to_dict(self) -> dict[str, Any]:
        return {
            "base": self.base.to_dict(),
            "conditions": list(self.conditions),
            "seeds": list(self.seeds),
            "grid": {k: [_json_ready(v) for v in vals] for k, vals in self.grid.items()},
        }

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Study:
        return cls(base=Config.from_saved(d["base"], d.get("version")), conditions=tuple(d["conditions"]), seeds=tuple(d["seeds"]), grid=dict(d.get("grid") or {}))

    @classmethod
    def load(cls, out_dir: str | Path) -> Study:
        """The study recorded in ``out_dir/study.json``."""
        given = as_path(out_dir, "out_dir", "Study.load")
        if given.name == STUDY_FILE and not given.is_dir():
            raise StorageError(f"{given} is a study's description; give the study folder ({given.parent}) instead.")
        path = given / STUDY_FILE
        try:
            data = json.loads(read_bounded(path, "a study.json", MAX_JSON_BYTES))
        except FileNotFoundError:
            raise StorageError(f"{given} is not a study folder (no {STUDY_FILE}).") from None
        except StorageError:
            raise
        except (OSError, ValueError) as e:
            raise StorageError(f"Cannot read {path}: {e}") from None
        try:
            return cls.from_dict(data["study"])
        except (KeyError, TypeError, ParameterError) as e:
            raise StorageError(f"{path} does not describe a study this version of saggriac ({_core.__version__}) can read{_written_by(data)}: {e}") from None


def _written_by(data: Any) -> str:
    """The saggriac a study.json records as its writer, for a message ("" if it records none)."""
    version = data.get("created_with", {}).get("saggriac") if isinstance(data, dict) and isinstance(data.get("created_with"), dict) else None
    return f" (it was written by saggriac {version})" if isinstance(version, str) else ""


def run_task(task: Task, out_root: str | os.PathLike) -> str:
    """Run one task of a study into ``out_root/task.path`` and return that path. Top-level and
    picklable, for process pools and Dask workers; a finished run is left as it is."""
    out = Path(out_root) / task.path
    # Idempotent, so a scheduler that retries a task whose result was already written is harmless.
    if not (out / MANIFEST).exists():
        # One thread per run: the study's workers already use every core.
        try:
            run(Config(**task.config), seed=task.seed, out_dir=out, progress=False, threads=1)
        except StorageError as e:
            result = getattr(e, "result", None)
            if result is None:
                raise
            # The work is done but its folder cannot be written: keep it, and say where, in a
            # message that survives the trip back from a worker process.
            raise StorageError(recover(result, out, str(e))) from None
    return str(out)


