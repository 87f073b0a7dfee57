"""The paper's experiments as one-command studies: the four conditions x seeds, then the
figures (Fig. 2-5 style) and the statistics table, all written into one folder."""

from __future__ import annotations

import warnings
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from ..analysis import plots, splits, statistics
from ..config import CONDITIONS, PRESETS, Config
from ..errors import InputError, ParameterError, StorageError
from ..files import as_path, check_flag, write_file
from ..bodies.reachable import ReachableSet
from ..runs.result import RunResult, run_stopped_early
from ..runs.storage import read_manifest, signed_integers
from . import IncompleteStudyWarning, Study, load_study, run_study
from .backends import WORKER_TIMEOUT
from .spec import MAX_SEEDS

FIGURES = "figures"


def _atomic(path: Path, write: Any) -> Path:
    """Write a file of the study folder through a temporary sibling (``files.write_file``): it
    replaces only a regular file of that name, never a link, folder or device put there."""
    return write_file(path, write, what=path.name, overwrite=True)


def _complete(run_dir: Path) -> bool:
    """A finished run: its run.json is there and it spent its whole budget (a partial run, saved
    from a learner stopped early, is not drawn beside finished ones)."""
    if not (run_dir / "run.json").exists():
        return False
    manifest = read_manifest(run_dir)
    return run_stopped_early(manifest, pd.read_parquet(run_dir / "metrics.parquet", columns=["step"])) is None


def matching_preset(config: Config) -> str | None:
    """The preset ``config`` is, up to its number of steps and its condition (the two things a
    study of a preset changes), or None."""
    mine = config.to_dict()
    for name in PRESETS:
        if Config.from_preset(name, n_steps=config.n_steps, condition=config.condition).to_dict() == mine:
            return name
    return None


def study_title(study: Study) -> str:
    """Title of a study's figures, from what its folder records: "exp1: 2 seed(s), 5000 time
    steps" for a study of a preset, the same without the name otherwise."""
    preset = matching_preset(study.base)
    return f"{preset + ': ' if preset else ''}{len(study.seeds)} seed(s), {study.base.n_steps} time steps"


def reproduce(
    experiment: str,
    out_dir: str | Path | None = None,
    seeds: int = 15,
    steps: int | None = None,
    conditions: tuple[str, ...] = CONDITIONS,
    backend: str = "local",
    n_workers: int | None = None,
    scheduler: Any = None,
    progress: bool = True,
    worker_timeout: float = WORKER_TIMEOUT,
    first_seed: int = 0,
) -> dict[str, Path]:
    """Run experiment 'exp1' or 'exp2' (every condition, seeds first_seed..first_seed+seeds-1),
    then write the figures and statistics. Finished runs in ``out_dir`` are reused (the study
    resumes). ``first_seed`` lets a second, independent set of seeds replicate the first."""
    if experiment not in PRESETS:
        raise ParameterError(f"The 'experiment' parameter must be one of {', '.join(map(repr, PRESETS))}. Got {experiment!r} instead.", "experiment", repr(experiment))
    if isinstance(seeds, (bool, np.bool_)) or not isinstance(seeds, (int, np.integer)) or not 1 <= seeds <= MAX_SEEDS:
        raise ParameterError(f"The 'seeds' parameter of reproduce must be an int in [1, {MAX_SEEDS}]. Got {seeds!r} instead.", "seeds", repr(seeds))
    seeds = int(seeds)
    progress = check_flag(progress, "progress", "reproduce")
    if isinstance(first_seed, (bool, np.bool_)) or not isinstance(first_seed, (int, np.integer)) or not 0 <= first_seed <= MAX_SEEDS:
        raise ParameterError(f"The 'first_seed' parameter of reproduce must be an int in [0, {MAX_SEEDS}]. Got {first_seed!r} instead.", "first_seed", repr(first_seed))
    first_seed = int(first_seed)
    base = Config.from_preset(experiment, **({} if steps is None else {"n_steps": steps}))
    out = as_path(out_dir, "out_dir", "reproduce") if out_dir is not None else Path(f"reproduce-{experiment}")
    study = Study(base=base, conditions=tuple(conditions), seeds=tuple(range(first_seed, first_seed + seeds)))
    run_study(study, out, backend=backend, n_workers=n_workers, scheduler=scheduler, progress=progress, worker_timeout=worker_timeout)
    return make_report(out)


def make_report(out_dir: str | Path, title: str | None = None) -> dict[str, Path]:
    """Figures and statistics of a study folder, from its saved results only: the same figures
    ``reproduce`` wrote (titles come from :func:`study_title` unless ``title`` is given)."""
    out = Path(out_dir)
    study = Study.load(out)
    frame = load_study(out)
    if frame.empty:
        raise StorageError(f"{out} holds no finished run yet.")
    figs = out / FIGURES
    try:
        figs.mkdir(exist_ok=True)
    except OSError as e:
        raise StorageError(f"Cannot create {figs}: {e.strerror or e}.") from e
    title = title or study_title(study)
    written: dict[str, Path] = {}
    written["curves"] = plots.plot_curves(frame, figs / "curves.png", title, "movements" if study.base.paradigm == "episodic" else "micro-actions")
    written["arm"] = plots.plot_arm(study.base, figs / "arm.png")
    for cond in ("sagg_riac", "sagg_random"):
        for task in study.tasks():
            run_dir = out / task.path
            if task.condition == cond and _complete(run_dir):
                name = f"goals_{cond}_seed{task.seed}.png"
                written[f"goals_{cond}"] = plots.plot_goal_histograms(run_dir, figs / name)
                break
    try:
        written.update(write_stats(out, frame))
    except InputError as e:
        warnings.warn(f"{e} The figures are written; stats.csv and stats.md are not.", IncompleteStudyWarning, stacklevel=2)
    budget = time_budget_summary(out)
    if not budget.empty:
        written["time_budget_csv"] = _atomic(out / "time_budget.csv", lambda p: budget.to_csv(p, index=False))
    null = split_null_model(out)
    if not null.empty:
        written["splits_csv"] = _atomic(out / "splits.csv", lambda p: null.to_csv(p, index=False))
    return written


def write_stats(out_dir: str | Path, frame: pd.DataFrame | None = None) -> dict[str, Path]:
    """stats.csv and stats.md: the ANOVA and paired tests by seed at the end and at checkpoints."""
    out = Path(out_dir)
    frame = load_study(out) if frame is None else frame
    table = statistics.compare(frame)
    if table.empty:
        raise InputError(f"No statistics can be computed for the study {out}: {_why_no_stats(frame)}{_left_out(out)}.")
    csv = _atomic(out / "stats.csv", lambda p: table.to_csv(p, index=False))
    md = _atomic(out / "stats.md", lambda p: p.write_text(statistics.to_markdown(table)))
    return {"stats_csv": csv, "stats_md": md}


def _why_no_stats(frame: pd.DataFrame) -> str:
    """Why statistics.compare found nothing to test in ``frame``."""
    if frame.empty:
        return "it holds no finished run"
    conditions = sorted(set(frame["condition"]))
    if len(conditions) < 2:
        return f"the tests compare conditions and its finished runs are all of {conditions[0]}"
    seeds = frame.groupby("condition")["seed"].nunique()
    return "the tests pair runs of the same seed and need at least 2 seeds finished in each condition; finished seeds: " + ", ".join(f"{c} {n}" for c, n in seeds.items())


def _left_out(out: Path) -> str:
    """The study's runs that are not finished, with why, as load_study names them ("" if none):
    the warning that names them is lost when the statistics are then refused (saggriac stats)."""
    names = []
    for task in Study.load(out).tasks():
        run_dir = out / task.path
        if not (run_dir / "run.json").exists():
            names.append(f"{task.path} (not finished: no run.json)")
            continue
        early = run_stopped_early(read_manifest(run_dir), pd.read_parquet(run_dir / "metrics.parquet", columns=["step"]))
        if early is not None:
            names.append(f"{task.path} ({early})")
    if not names:
        return ""
    return "; left out: " + "; ".join(names[:10]) + (f"; and {len(names) - 10} more" if len(names) > 10 else "")


# The time budget's columns, in the order shown (shares are of all micro-actions of a run).
BUDGET_COLUMNS = ("goals", "share_exploration", "steps_per_goal", "goals_reachable", "steps_per_reachable_goal", "steps_per_unreachable_goal", "share_on_reachable_goals")


def time_budget_summary(out_dir: str | Path) -> pd.DataFrame:
    """Per condition, the mean over finished runs of each entry of run.json's ``time_budget``
    (goals attempted, share of exploration, steps per goal inside and outside the reachable
    area, share of time on reachable goals, and the share of time of each selection mode)."""
    out = Path(out_dir)
    rows = []
    for task in Study.load(out).tasks():
        if not _complete(out / task.path):
            continue
        tb = read_manifest(out / task.path).get("time_budget")
        if tb is None:  # a run from before saggriac 0.2
            continue
        row: dict[str, Any] = {"condition": task.condition, **{k: tb.get(k) for k in BUDGET_COLUMNS}}
        row.update({f"share_mode_{k}": v for k, v in tb.get("share_by_mode", {}).items()})
        rows.append(row)
    if not rows:
        return pd.DataFrame()
    frame = pd.DataFrame(rows)
    numeric = frame.drop(columns="condition").apply(pd.to_numeric, errors="coerce")
    summary = numeric.groupby(frame["condition"], sort=False).mean()
    summary.insert(0, "runs", frame.groupby("condition", sort=False).size())
    return summary.reset_index()


def split_null_model(out_dir: str | Path, n_parts: int = 4) -> pd.DataFrame:
    """Fig. 3's split statistic with its null model: for each seed, the mean share of reachable
    area of the regions SAGG-RIAC split, per quarter of its splits, beside the same for the tree
    SAGG-Random's measurements build when replayed (``splits.replay_regions``). Empty unless the
    study has both SAGG conditions."""
    out = Path(out_dir)
    study = Study.load(out)
    rows = []
    for task in study.tasks():
        run_dir = out / task.path
        if task.condition not in ("sagg_riac", "sagg_random") or not _complete(run_dir):
            continue
        manifest = read_manifest(run_dir)
        cfg = Config.from_saved(manifest["config"], manifest.get("version"))
        if task.condition == "sagg_riac":
            regions, label = signed_integers(pd.read_parquet(run_dir / "regions.parquet")), "sagg_riac"
        else:
            regions, label = splits.replay_regions(signed_integers(pd.read_parquet(run_dir / "attempts.parquet")), cfg), "sagg_random_replayed"
        reach = ReachableSet(cfg) if cfg.chain is not None else cfg.reach
        for part, share in enumerate(splits.split_shares(regions, reach, n_parts)):
            rows.append({"tree": label, "seed": task.seed, **task.params, "part": part + 1, "reachable_share": share})
    frame = pd.DataFrame(rows)
    if frame.empty or set(frame["tree"]) != {"sagg_riac", "sagg_random_replayed"}:
        return pd.DataFrame()
    return frame


def final_summary(out_dir: str | Path) -> pd.DataFrame:
    """Mean and standard deviation of each metric at the last step, per condition."""
    frame = load_study(out_dir)
    last = frame[frame["step"] == frame["step"].max()]
    return last.groupby(["metric", "condition"])["value"].agg(["mean", "std", "count"]).reset_index()


__all__ = ["reproduce", "make_report", "write_stats", "final_summary", "time_budget_summary", "split_null_model", "study_title", "matching_preset", "RunResult"]
