"""``run_bench``: every teacher asked for, and every built-in teacher, on every task of a tier, into
an output folder that holds the runs, the curves, the leaderboard and its figures. The teachers
that take expert knowledge are also run with it, at each level, as entries of their own
(``adr@low``, ``adr@high``; :mod:`saggriac.bench.expert`), unless ``expert=False``. The built-in
teachers' runs come from the shipped results when they hold them (same task, seed and budget),
unless ``rerun``; a run already in the folder is kept; the rest is computed."""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterable, Sequence

import numpy as np
import pandas as pd

from .. import _core
from ..errors import ParameterError, StorageError
from ..files import as_path, check_flag
from ..study.backends import default_workers
from ..teachers import available
from . import report, shipped
from .goals import COLUMNS as GOAL_COLUMNS
from .goals import goals_figures, goals_table
from .runner import BenchError, execute, failure_message, plan, read_done, timed
from .tasks import TASKS, TIERS, in_tier, missing_extra, tier_seeds
from .teachers import CALL_TIMEOUT, REFERENCE, TeacherSpec, parse_teacher


def with_variants(specs: Iterable[TeacherSpec], expert: bool) -> list[TeacherSpec]:
    """``specs``, each followed by its expert variants if ``expert`` (a spec given a level is
    itself only)."""
    return [v for s in specs for v in [s, *(s.variants() if expert else [])]]


def builtin_specs(expert: bool) -> list[TeacherSpec]:
    """The built-in teachers, each followed by its expert variants if ``expert``."""
    return with_variants([TeacherSpec(n) for n in available()], expert)


@dataclass
class BenchResult:
    out: Path
    runs: pd.DataFrame
    curves: pd.DataFrame
    board: pd.DataFrame
    computed: int
    kept: int
    from_shipped: int
    wall_seconds: float
    workers: int
    written: dict[str, Path] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)
    #: The goals asked (:func:`saggriac.bench.goals.goals_table`): every computed or kept run's,
    #: and the shipped runs' on each task's first seed.
    goals: pd.DataFrame = field(default_factory=lambda: pd.DataFrame(columns=GOAL_COLUMNS))

    def cpu_seconds(self, teacher: str) -> float:
        """The seconds of all of ``teacher``'s runs (each run timed in its own process)."""
        return float(self.runs[self.runs.teacher == teacher].seconds.sum())


def _check_int(name: str, value: Any, low: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or int(value) < low:
        raise ParameterError(f"The '{name}' parameter of run_bench must be an int >= {low}. Got {value!r} instead.", name, repr(value))
    return int(value)


def run_bench(
    teachers: Sequence[str | TeacherSpec] = (),
    out: str | os.PathLike[str] = "bench",
    tier: str = "quick",
    seeds: int | None = None,
    tasks: Sequence[str] | None = None,
    workers: int | None = None,
    timeout: float = CALL_TIMEOUT,
    rerun: bool = False,
    progress: bool = True,
    scheduler: Any = None,
    expert: bool = True,
) -> BenchResult:
    """Bench ``teachers`` (built-in names, import paths 'pkg.mod:Class' or TeacherSpec; 'NAME@low'
    or 'NAME@high' given expert knowledge at that level) among the built-in teachers on the tasks
    of ``tier`` (seeds 0 .. ``seeds`` - 1; the tier's number by default) into the folder ``out``;
    see :class:`BenchResult`. With ``expert`` (default), every teacher that takes expert knowledge
    is also run at each level. Raises :class:`BenchError` after writing everything else if some
    runs failed."""
    rerun, progress = check_flag(rerun, "rerun", "run_bench"), check_flag(progress, "progress", "run_bench")
    expert = check_flag(expert, "expert", "run_bench")
    if tier not in TIERS:
        raise ParameterError(f"The 'tier' parameter of run_bench must be one of {', '.join(TIERS)}. Got {tier!r} instead.", "tier", repr(tier))
    n_seeds = TIERS[tier] if seeds is None else _check_int("seeds", seeds, 1)
    n_workers = default_workers() if workers is None else _check_int("workers", workers, 1)
    if isinstance(timeout, bool) or not isinstance(timeout, (int, float)) or not 0 < timeout < 1e6:
        raise ParameterError(f"The 'timeout' parameter of run_bench must be seconds in (0, 1e6). Got {timeout!r} instead.", "timeout", repr(timeout))
    notes: list[str] = []
    if tasks is None:
        names = [t for t in TASKS if in_tier(t, tier) and missing_extra(t) is None]
        left_out = [f"{t} (needs {missing_extra(t)})" for t in TASKS if in_tier(t, tier) and missing_extra(t) is not None]
        if left_out:
            notes.append(f"Tasks left out, their extra not installed: {', '.join(left_out)}.")
    else:
        names = list(tasks)
    for t in names:
        if t not in TASKS:
            raise ParameterError(f"The 'tasks' parameter of run_bench must name tasks of the bench ({', '.join(TASKS)}). Got {t!r} instead.", "tasks", repr(t))
        if not in_tier(t, tier):
            raise ParameterError(f"The bench task {t!r} is not in the tier {tier!r} (it is in {', '.join(x for x in TIERS if in_tier(t, x))}). Give another tier, or leave the task out.", "tasks", repr(t))
        if missing_extra(t) is not None:
            raise ParameterError(f"The bench task {t!r} needs {missing_extra(t)}.", "tasks", repr(t))
    specs = with_variants([t if isinstance(t, TeacherSpec) else parse_teacher(t) for t in teachers], expert)
    # Every built-in spec whose runs may ship (the expert variants too); those on the board.
    builtins = builtin_specs(True)
    board_builtins = builtin_specs(expert)
    everyone = board_builtins + [s for s in specs if s not in board_builtins]
    folder = as_path(out, "out", "run_bench")
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise StorageError(f"Cannot create the bench folder {folder}: {e.strerror or e}.") from None

    jobs = plan(everyone, names, tier, None if seeds is None else range(n_seeds), float(timeout))
    ship = shipped.load(tier)
    records: list[dict[str, Any]] = []
    from_ship = 0
    todo = []
    ship_rows: dict[tuple[str, str, int, int], dict[str, Any]] = {}
    ship_curves: dict[tuple[str, str, int], list[list[float]]] = {}
    ship_goals: dict[tuple[str, str, int], list[list[float]]] = {}
    if ship is not None:
        s_runs, s_curves, meta = ship
        ship_rows = {(r["task"], r["teacher"], int(r["seed"]), int(r["goals"])): r for r in s_runs.to_dict("records")}
        for key, c in s_curves.groupby(["task", "teacher", "seed"], sort=False):
            ship_curves[(key[0], key[1], int(key[2]))] = c[["step", "score"]].to_numpy().tolist()
        for key, g in shipped.load_goals(tier).groupby(["task", "teacher", "seed"], sort=False):
            wide = g.pivot(index="call", columns="dim", values="value").sort_index()
            ship_goals[(key[0], key[1], int(key[2]))] = np.column_stack([wide.index.to_numpy(float), wide.to_numpy(float)]).tolist()
        if meta.get("version") != _core.__version__:
            notes.append(f"The shipped results of the tier {tier!r} were made by saggriac {meta.get('version')}; this is saggriac {_core.__version__}. Pass --rerun to compute the built-in teachers with this version.")
    for job in jobs:
        key4 = (*job.key, TASKS[job.task].budgets[tier])
        if not rerun and job.teacher in builtins and key4 in ship_rows:
            records.append({"row": {**ship_rows[key4], "source": "shipped"}, "curve": ship_curves[job.key], "asked": ship_goals.get(job.key, [])})
            from_ship += 1
            continue
        saved = read_done(job, folder)
        if saved is not None:
            records.append({**saved, "row": {**saved["row"], "source": "kept from the folder"}})
        else:
            todo.append(job)
    kept = len(records) - from_ship
    missing = sorted({j.teacher.label for j in todo if j.teacher in builtins and not rerun})
    if missing and ship is not None:
        notes.append(f"Built-in teachers not in the shipped results of this tier (or not for these seeds and tasks), computed here: {', '.join(missing)}.")
    n_workers = min(n_workers, max(1, len(todo)))
    (new, failures), wall = timed(lambda: execute(todo, folder, n_workers, scheduler, progress))
    records += [{**r, "row": {**r["row"], "source": "computed"}} for r in new]

    runs = pd.DataFrame([r["row"] for r in records])
    curves = pd.DataFrame([dict(task=r["row"]["task"], teacher=r["row"]["teacher"], seed=r["row"]["seed"], step=int(s), score=float(v)) for r in records for s, v in r["curve"]])
    if rerun and ship is not None and not runs.empty:
        notes += compare_with_shipped(runs[runs.source == "computed"], ship[0], ship[2])
    goals = goals_table(records)
    written = write_outputs(folder, runs, curves, goals, tier, seeds_text(names, tier, None if seeds is None else n_seeds), notes)
    board = pd.read_csv(written["leaderboard_csv"]) if "leaderboard_csv" in written else pd.DataFrame(columns=report.COLUMNS)
    result = BenchResult(folder, runs, curves, board, len(new), kept, from_ship, wall, n_workers, written, notes, goals)
    if failures:
        errors = pd.DataFrame([dict(task=k[0], teacher=k[1], seed=k[2], error=m) for k, m in failures.items()])
        errors.to_csv(folder / "errors.csv", index=False)
        err = BenchError(failure_message(failures, folder, len(todo)), failures)
        err.result = result  # type: ignore[attr-defined]
        raise err
    if (folder / "errors.csv").exists():
        (folder / "errors.csv").unlink()
    return result


def compare_with_shipped(runs: pd.DataFrame, ship_runs: pd.DataFrame, meta: dict[str, Any]) -> list[str]:
    """What a rerun of the built-in teachers says against the shipped results: the same numbers,
    or how many runs differ and which saggriac made the shipped ones."""
    both = runs.merge(ship_runs, on=["task", "teacher", "seed", "goals"], suffixes=("", "_shipped"))
    if both.empty:
        return []
    differ = both[(both.area != both.area_shipped) | (both.final != both.final_shipped)]
    if differ.empty:
        return [f"Rerun: the {len(both)} runs shipped for these teachers, tasks and seeds were recomputed and are the same numbers."]
    by = ", ".join(sorted(set(differ.teacher)))
    return [f"Rerun: {len(differ)} of {len(both)} shipped runs differ ({by}; largest area change {float((differ.area - differ.area_shipped).abs().max()):.3g}). "
            f"The shipped ones were made by saggriac {meta.get('version')}, these by saggriac {_core.__version__}."]


def seeds_text(names: Sequence[str], tier: str, n_seeds: int | None) -> str:
    """The seeds of a bench in words: "seeds 0-4", or with the tasks that take a study's own."""
    if n_seeds is not None:
        return f"seeds 0-{n_seeds - 1}"
    own = [f"{t} {min(s)}-{max(s)}" for t in names for s in [tier_seeds(t, tier)] if s != list(range(TIERS[tier]))]
    return f"seeds 0-{TIERS[tier] - 1}" + (f" (their studies' seeds: {', '.join(own)})" if own else "")


def write_outputs(folder: Path, runs: pd.DataFrame, curves: pd.DataFrame, goals: pd.DataFrame, tier: str, seeds: str, notes: Iterable[str]) -> dict[str, Path]:
    """runs.parquet, curves.parquet, goals.parquet, leaderboard.csv and .md and the figures
    (curves.png, ranks.png, goals/<task>.png), into ``folder``."""
    written: dict[str, Path] = {}
    if runs.empty:
        return written
    runs = runs.sort_values(["task", "teacher", "seed"]).reset_index(drop=True)
    curves = curves.sort_values(["task", "teacher", "seed", "step"]).reset_index(drop=True)
    try:
        runs.to_parquet(folder / "runs.parquet", index=False)
        curves.to_parquet(folder / "curves.parquet", index=False)
        goals.to_parquet(folder / "goals.parquet", index=False)
        board = report.leaderboard(runs)
        board.to_csv(folder / "leaderboard.csv", index=False)
        sources = runs.groupby("source").size().to_dict()
        header = [f"# saggriac bench: tier {tier}, {seeds}", "",
                  f"saggriac {_core.__version__}. Area: mean of the score curve; final: the score after the budget (both higher is better). "
                  f"Differences to {REFERENCE} are paired by seed, with a 95 % t interval; p: paired t-test, Holm-adjusted over every row. "
                  f"Rank: by area on the task. µs/goal: teacher and task together. Runs: " + ", ".join(f"{n} {k}" for k, n in sorted(sources.items())) + ".", *[f"\n{n}" for n in notes]]
        (folder / "leaderboard.md").write_text(report.markdown(board, header))
    except OSError as e:
        raise StorageError(f"Cannot write the bench's results to {folder}: {e.strerror or e}.") from None
    written.update(runs=folder / "runs.parquet", curves=folder / "curves.parquet", goals=folder / "goals.parquet", leaderboard_csv=folder / "leaderboard.csv", leaderboard_md=folder / "leaderboard.md")
    written["curves_png"] = report.curves_figure(curves, folder / "curves.png")
    written["ranks_png"] = report.rank_figure(board, folder / "ranks.png")
    if not goals.empty:
        written["goals_png"] = folder / "goals"
        goals_figures(goals, folder / "goals")
    return written
