"""Teachers over a list of tasks: goals are task indices."""

from __future__ import annotations

from typing import Any

import numpy as np

from ..values import as_numbers
from .ask_tell import AskTellSelector


class TaskListSelector(AskTellSelector):
    """A teacher over a list of ``n_tasks`` tasks: its goals are task indices (``sample()`` gives
    ``[i]``, ``sample_task()`` the int) and ``update`` takes an index or ``[index]``. Syllabus's
    ``DiscreteTaskSpace`` takes any of them (:class:`saggriac.adapters.syllabus.SelectorCurriculum`)."""

    spaces = ("tasks",)
    reading = "task_list"

    def __init__(self, n_tasks: int, seed: int, **params: Any) -> None:
        # The goals are task indices: no box.
        super().__init__([], [], seed, n_tasks=n_tasks, **params)

    @property
    def n_tasks(self) -> int:
        """The number of tasks."""
        return int(round(float(self.high[0]))) + 1

    def sample_task(self) -> int:
        """The next task's index."""
        return int(self.sample()[0])

    def update(self, goal: Any, competence: float) -> int | None:
        """Report what was obtained on task ``goal`` (an index, or ``[index]``)."""
        return super().update(np.atleast_1d(as_numbers("goal", goal)), competence)
