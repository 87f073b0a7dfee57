"""Where a run's time went (docs/reproduction.md, "What is measured"): micro-actions by kind,
goals attempted, steps per goal inside and outside the reachable area, and the share of time by
goal-selection mode. Written into run.json as ``time_budget`` and summed up by ``reproduce``.

A goal's time is the micro-actions from its start to its end (subgoals, exploration phases and
the timeout included). Whether a goal is reachable is known only for the built-in bodies (the ball
of radius = arm length around the base; a chain's sampled reachable set, ``saggriac.bodies.reachable``);
for a user's environment those entries are absent.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
import pandas as pd

from ..teachers import MODES
from ..bodies.reachable import ReachableSet


def time_budget(goals: pd.DataFrame, profile: Mapping[str, Any], n_steps: int, reach: float | ReachableSet | None) -> dict[str, Any]:
    """The time budget of one run from its goals table and run.json profile; ``reach`` is the
    arm's length, or the set a chain reaches (None when the body's reach is unknown)."""
    kinds = {k: int(profile.get(f"{k}_steps", 0)) for k in ("reaching", "exploration", "babbling")}
    total = max(sum(kinds.values()), 1)
    out: dict[str, Any] = {
        "micro_actions": kinds,
        "share_exploration": kinds["exploration"] / total,
        "goals": int(len(goals)),
    }
    if len(goals) == 0:
        return out
    steps = (goals["step_end"] - goals["step_start"]).to_numpy(np.int64)
    out["steps_per_goal"] = float(steps.mean())
    out["share_by_mode"] = {MODES.get(int(m), str(m)): float(steps[(goals["mode"] == m).to_numpy()].sum() / max(steps.sum(), 1)) for m in sorted(goals["mode"].unique())}
    out["goals_by_mode"] = {MODES.get(int(m), str(m)): int((goals["mode"] == m).sum()) for m in sorted(goals["mode"].unique())}
    if reach is not None:
        cols = sorted(c for c in goals.columns if c.startswith("goal_") and c != "goal_index")
        if isinstance(reach, ReachableSet):
            inside = reach.contains(goals[cols].to_numpy(np.float64))
        else:
            radius = np.sqrt((goals[cols].to_numpy(np.float64) ** 2).sum(axis=1))
            inside = radius <= reach
        out["goals_reachable"] = int(inside.sum())
        out["steps_per_reachable_goal"] = float(steps[inside].mean()) if inside.any() else None
        out["steps_per_unreachable_goal"] = float(steps[~inside].mean()) if (~inside).any() else None
        out["share_on_reachable_goals"] = float(steps[inside].sum() / max(n_steps, 1))
    return out
