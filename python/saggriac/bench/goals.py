"""Each teacher's goals over time: what a run's teacher asked, kept thinned (:class:`saggriac.bench.goal_log.GoalLog`), as a
long table (:func:`goals_table`) and as one figure per task (:func:`goals_figures`), the goals of
each teacher on its first seed coloured by when they were asked."""

from __future__ import annotations

from pathlib import Path
from typing import Any, Iterable

import pandas as pd

from .tasks import TASKS

COLUMNS = ["task", "teacher", "seed", "call", "dim", "value"]


def goals_table(records: Iterable[dict[str, Any]]) -> pd.DataFrame:
    """The goals of every record that has them, one row per (run, call, dimension)."""
    rows = [(r["row"]["task"], r["row"]["teacher"], int(r["row"]["seed"]), int(g[0]), d, float(v)) for r in records for g in r.get("asked", ()) for d, v in enumerate(g[1:])]
    return pd.DataFrame(rows, columns=COLUMNS)


def first_seed(goals: pd.DataFrame) -> pd.DataFrame:
    """Each (task, teacher)'s goals on the lowest seed it has goals for."""
    if goals.empty:
        return goals
    lowest = goals.groupby(["task", "teacher"]).seed.transform("min")
    return goals[goals.seed == lowest]


def goals_figures(goals: pd.DataFrame, folder: Path) -> list[Path]:
    """One figure per task, ``folder/<task>.png``: each teacher's goals on its first seed, coloured
    from early (dark) to late (yellow). A box task shows its first two dimensions (the box's
    bounds as limits) or, in 1-D, the goal against the call; a task list, the task's index
    against the call."""
    from matplotlib.figure import Figure

    from .report import short

    goals = first_seed(goals)
    folder.mkdir(parents=True, exist_ok=True)
    written = []
    for task, sub in goals.groupby("task", sort=False):
        cls = TASKS.get(str(task))
        teachers = list(dict.fromkeys(sub.teacher))
        cols = min(5, len(teachers))
        nrows = -(-len(teachers) // cols)
        width, height = 2.6 * cols, 2.5 * nrows + 0.5
        fig = Figure(figsize=(width, height))
        dims = int(sub.dim.max()) + 1
        box = cls(0) if cls is not None and cls.space == "box" and dims >= 2 else None
        # The box's panels share its limits: tick labels on the outer panels only. Margins in
        # inches, fixed: a tight layout drew every figure twice, most of the bench's plotting time.
        axes = fig.subplots(nrows, cols, squeeze=False, sharex=box is not None, sharey=box is not None)
        fig.subplots_adjust(left=0.4 / width, right=1 - 0.1 / width, bottom=0.3 / height, top=1 - 0.55 / height, wspace=0.25 if box is not None else 0.35, hspace=0.3)
        for ax, teacher in zip(axes.ravel(), teachers):
            wide = sub[sub.teacher == teacher].pivot(index="call", columns="dim", values="value").sort_index()
            calls = wide.index.to_numpy(float)
            colour = dict(c=calls, cmap="viridis", s=6, vmin=calls.min(), vmax=calls.max())
            if box is not None:
                ax.scatter(wide[0], wide[1], **colour)
                ax.set_xlim(box.low[0], box.high[0])
                ax.set_ylim(box.low[1], box.high[1])
            else:
                ax.scatter(calls, wide[0], **colour)
            ax.set_title(short(str(teacher)), fontsize=8)
            ax.tick_params(labelsize=6)
            ax.locator_params(nbins=4)
        for ax in axes.ravel()[len(teachers):]:
            ax.set_visible(False)
        space = "" if cls is None else (f"dimensions 1-2 of {dims}" if cls.space == "box" and dims >= 2 else ("goal against call" if cls.space == "box" else "task index against call"))
        fig.suptitle(f"{task}: goals asked, first seed, early (dark) to late (yellow); {space}", fontsize=9)
        path = folder / f"{task}.png"
        fig.savefig(path, dpi=80)
        written.append(path)
    return written
