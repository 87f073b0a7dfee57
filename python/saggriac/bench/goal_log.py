"""What a run's teacher asked, in order, kept thinned: the record behind the figures of each
teacher's goals over time (:mod:`saggriac.bench.goals`). A leaf: the guard that feeds it
imports it, and it imports nothing of the bench."""

from __future__ import annotations

from typing import Any

import numpy as np

#: Goals kept per run: enough to see where a teacher looks and how that moves, few enough that a
#: run's file stays small.
KEPT = 200


class GoalLog:
    """The goals asked in one run, in order (a box's goal as its floats, a task list's as its
    index)."""

    def __init__(self) -> None:
        self._goals: list[np.ndarray] = []

    def add(self, goal: Any) -> None:
        # A copy (the teacher may reuse its array); the floats are made for the kept few only.
        self._goals.append(np.array(goal, float).reshape(-1))

    def __len__(self) -> int:
        return len(self._goals)

    def thinned(self, kept: int = KEPT) -> list[list[float]]:
        """At most ``kept`` goals evenly spaced over the run, first and last included, each as
        [call, *goal] with call counted from 1."""
        n = len(self._goals)
        picks = range(n) if n <= kept else np.unique(np.linspace(0, n - 1, kept).round().astype(int))
        return [[float(i + 1), *self._goals[i].tolist()] for i in picks]
