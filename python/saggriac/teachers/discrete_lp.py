"""Learning progress over a list of tasks (Kanitscheider et al. 2021)."""

from __future__ import annotations


from .ask_tell import DEFAULTS
from .task_list import TaskListSelector

_DLP = DEFAULTS["discrete_lp"]


class DiscreteLpSelector(TaskListSelector):
    """Learning progress over a list of ``n_tasks`` tasks (Kanitscheider et al., "Multi-task
    curriculum learning in a complex, visual, hard-exploration domain: Minecraft", 2021).

    Goals are task indices (``sample()`` gives ``[i]``; ``sample_task()`` the int), and the
    competence told is a success rate in [0, 1]. Each task keeps a fast moving average of its
    success and a slow one following it (step ``alpha``); its progress is the gap between the
    two after the paper's reweighting (``theta``), which stretches small success rates. Tasks
    are drawn in proportion to the sigmoid of their progress z-scored over all tasks (so tasks
    without progress keep some probability); with the same progress everywhere, uniformly.
    """

    _kind = "discrete_lp"
    competence_range = (0.0, 1.0)

    def __init__(self, n_tasks: int, seed: int = 0, *, alpha: float = _DLP["alpha"], theta: float = _DLP["theta"]) -> None:
        super().__init__(n_tasks, seed, alpha=alpha, theta=theta)
