"""The bench's answer: the leaderboard (every teacher on every task, each compared with ``random``
on the same seeds) and its figures."""

from __future__ import annotations

import warnings
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd

from ..analysis.statistics import holm, paired
from .tasks import TASKS
from .teachers import REFERENCE

if TYPE_CHECKING:
    from matplotlib.figure import Figure

COLUMNS = ["task", "teacher", "seeds", "area", "area_sd", "final", "final_sd", "diff_area", "ci_low", "ci_high", "p_holm", "diff_final", "rank", "us_per_goal", "teacher_us_per_goal"]


def leaderboard(runs: pd.DataFrame) -> pd.DataFrame:
    """One row per (task, teacher): the means over seeds of the area under the score curve and of
    the final score (both higher is better), the paired difference of the area to ``random`` on
    the seeds both have (mean, 95 % CI) with its paired t-test's p-value Holm-adjusted over every
    row of the board, the same difference for the final score, the rank on the task by area (1 is
    best; ties share the best rank), the microseconds per goal (teacher and task together) and
    those spent in the teacher's own sample and update (NaN for runs made before they were timed)."""
    rows = []
    for task in [t for t in TASKS if t in set(runs.task)] + sorted(set(runs.task) - set(TASKS)):
        sub = runs[runs.task == task]
        ref = sub[sub.teacher == REFERENCE].set_index("seed")
        for teacher, r in sub.groupby("teacher", sort=False):
            r = r.set_index("seed")
            row = dict(task=task, teacher=teacher, seeds=len(r), area=r.area.mean(), area_sd=r.area.std(), final=r.final.mean(), final_sd=r.final.std(),
                       diff_area=np.nan, ci_low=np.nan, ci_high=np.nan, p_value=np.nan, diff_final=np.nan, us_per_goal=1e6 * (r.seconds / r.goals).mean(),
                       teacher_us_per_goal=1e6 * (r.teacher_seconds / r.goals).mean() if "teacher_seconds" in r else np.nan)
            both = r.index.intersection(ref.index)
            if teacher != REFERENCE and len(both) >= 2:
                d = paired(r.area.loc[both].to_numpy(), ref.area.loc[both].to_numpy())
                row.update(diff_area=d["mean_diff"], ci_low=d["ci_low"], ci_high=d["ci_high"], p_value=d["p_value"])
                row["diff_final"] = float((r.final.loc[both] - ref.final.loc[both]).mean())
            rows.append(row)
    board = pd.DataFrame(rows, columns=[*COLUMNS, "p_value"])
    board["p_holm"] = holm(board.p_value.to_numpy(float))
    board["rank"] = board.groupby("task").area.rank(ascending=False, method="min").astype(int)
    order = {t: i for i, t in enumerate(dict.fromkeys(board.task))}
    board["order"] = board.task.map(order)
    return board.sort_values(["order", "rank", "teacher"]).reset_index(drop=True)[COLUMNS]


def short(label: str) -> str:
    """A teacher's label for a figure: a file path's folders left out."""
    return label.rsplit("/", 1)[-1]


def tight(fig: "Figure", **kw: Any) -> None:
    """Tight layout where it fits; long names may not, and then the figure is kept as it is."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        fig.tight_layout(**kw)


def _p(p: float) -> str:
    return "" if np.isnan(p) else (f"{p:.2g}" if p >= 1e-4 else "<1e-4")


def markdown(board: pd.DataFrame, header: list[str]) -> str:
    """The leaderboard as Markdown: a table per task."""
    lines = [*header, ""]
    for task, sub in board.groupby("task", sort=False):
        cls = TASKS.get(str(task))
        lines += [f"## {task}" + (f" ({cls.space}: {cls.learner})" if cls else ""), ""]
        lines += ["| rank | teacher | seeds | area | final | area - random [95 % CI] | Holm p | final - random | µs/goal | teacher µs/goal |", "|---|---|---|---|---|---|---|---|---|---|"]
        for r in sub.itertuples():
            diff = "" if np.isnan(r.diff_area) else f"{r.diff_area:+.3f} [{r.ci_low:+.3f}, {r.ci_high:+.3f}]"
            final_diff = "" if np.isnan(r.diff_final) else f"{r.diff_final:+.3f}"
            teacher_us = "" if np.isnan(r.teacher_us_per_goal) else f"{r.teacher_us_per_goal:.0f}"
            lines.append(f"| {r.rank} | {r.teacher} | {r.seeds} | {r.area:.3f} ± {r.area_sd:.3f} | {r.final:.3f} ± {r.final_sd:.3f} | {diff} | {_p(r.p_holm)} | {final_diff} | {r.us_per_goal:.0f} | {teacher_us} |")
        lines.append("")
    return "\n".join(lines)


def curves_figure(curves: pd.DataFrame, path: Path) -> Path:
    """The mean score curve of every teacher on every task (±1 sd over seeds shaded)."""
    from matplotlib.figure import Figure

    tasks = [t for t in TASKS if t in set(curves.task)] + sorted(set(curves.task) - set(TASKS))
    cols = min(4, max(1, len(tasks)))
    nrows = -(-len(tasks) // cols)
    fig = Figure(figsize=(4.2 * cols, 3.3 * nrows + 0.8))
    axes = fig.subplots(nrows, cols, squeeze=False)
    teachers = list(dict.fromkeys(curves.teacher))
    colours = {t: f"C{i % 10}" for i, t in enumerate(teachers)}
    styles = {t: ("-", "--", ":")[i // 10 % 3] for i, t in enumerate(teachers)}
    for ax, task in zip(axes.ravel(), tasks):
        for teacher, c in curves[curves.task == task].groupby("teacher", sort=False):
            g = c.groupby("step").score
            mu, sd = g.mean(), g.std().fillna(0.0)
            ax.plot(mu.index, mu.to_numpy(), ls=styles[teacher], color=colours[teacher], label=short(teacher), lw=1.2)
            ax.fill_between(mu.index, (mu - sd).to_numpy(), (mu + sd).to_numpy(), color=colours[teacher], alpha=0.08)
        cls = TASKS.get(task)
        ax.set_title(task, fontsize=10)
        ax.set_xlabel(cls.unit if cls else "goals", fontsize=8)
        ax.tick_params(labelsize=7)
    for ax in axes.ravel()[len(tasks):]:
        ax.set_visible(False)
    axes[0][0].set_ylabel("score (higher is better)", fontsize=8)
    handles = [h for h in axes.ravel()[0].get_legend_handles_labels()[0]]
    labels = [h.get_label() for h in handles]
    seen = {lab for lab in labels}
    for ax in axes.ravel()[1 : len(tasks)]:
        for h in ax.get_legend_handles_labels()[0]:
            if h.get_label() not in seen:
                seen.add(h.get_label())
                handles.append(h)
    fig.legend(handles, [h.get_label() for h in handles], loc="lower center", ncol=min(6, len(handles)), fontsize=8, frameon=False)
    tight(fig, rect=(0, 0.8 / (3.3 * nrows + 0.8) + 0.02, 1, 1))
    fig.savefig(path, dpi=90)
    return path


def rank_figure(board: pd.DataFrame, path: Path) -> Path:
    """The teacher x task map of ranks (1 is best on the task; blank: not run there)."""
    from matplotlib.figure import Figure

    tasks = list(dict.fromkeys(board.task))
    mean_rank = board.groupby("teacher")["rank"].mean().sort_values()
    teachers = list(mean_rank.index)
    grid = board.pivot(index="teacher", columns="task", values="rank").reindex(index=teachers, columns=tasks)
    fig = Figure(figsize=(1.0 + 0.7 * len(tasks), 1.2 + 0.35 * len(teachers)))
    ax = fig.subplots()
    im = ax.imshow(grid.to_numpy(float), cmap="viridis_r", aspect="auto")
    for i in range(len(teachers)):
        for j in range(len(tasks)):
            v = grid.iat[i, j]
            if not np.isnan(v):
                ax.text(j, i, f"{int(v)}", ha="center", va="center", fontsize=7, color="w" if v > grid.max().max() / 2 else "k")
    ax.set_xticks(range(len(tasks)), tasks, rotation=45, ha="right", fontsize=8)
    ax.set_yticks(range(len(teachers)), [short(t) for t in teachers], fontsize=8)
    ax.set_title("rank by area on each task (1 is best)", fontsize=9)
    fig.colorbar(im, ax=ax, shrink=0.8)
    tight(fig)
    fig.savefig(path, dpi=90)
    return path
