"""Teacher-Student Curriculum Learning (Matiisen, Oliver, Cohen & Schulman, 2017)."""

from __future__ import annotations

from .ask_tell import DEFAULTS
from .task_list import TaskListSelector

_TSCL = DEFAULTS["tscl"]


class TsclSelector(TaskListSelector):
    """Teacher-Student Curriculum Learning (Matiisen, Oliver, Cohen & Schulman, arXiv:1707.00183,
    2017; IEEE TNNLS 2019) over a list of ``n_tasks`` tasks; goals are task indices, as
    :class:`DiscreteLpSelector`'s.

    A bandit over the tasks, rewarded by the student's learning progress. ``update`` is told the
    task's score (any finite number, such as a success rate). With ``variant="window"`` (the
    paper's Algorithm 3) a task's progress is the slope of a least-squares line through its last
    ``window`` scores against the steps they were told at; with ``"sampling"`` (Algorithm 4) it
    is one of its last ``window`` score changes, drawn at random. A task is chosen by
    |progress| (``absolute=True``: a task whose score falls, being forgotten, is practised again)
    with ``policy="epsilon_greedy"`` (the largest, or with probability ``epsilon`` a uniform
    task) or ``"boltzmann"`` (probability proportional to exp(progress / ``temperature``)). A
    task with too few records for a value (two scores, or one change) is tried first. The paper
    prints the sampling variant's choice as the plain argmax: ``epsilon=0``.
    """

    _kind = "tscl"
    #: What its goal modes mean, as logged (saggriac.analysis.teacher_readings).
    mode_shares = {"initial": "untried_share", "random": "uniform_share", "interest": "bandit_share"}
    competence_range = (0.0, 1.0)

    def __init__(self, n_tasks: int, seed: int = 0, *, variant: str = _TSCL["variant"], window: int = _TSCL["window"], policy: str = _TSCL["policy"], epsilon: float = _TSCL["epsilon"], temperature: float = _TSCL["temperature"], absolute: bool = _TSCL["absolute"]) -> None:
        super().__init__(n_tasks, seed, variant=variant, window=window, policy=policy, epsilon=epsilon, temperature=temperature, absolute=absolute)
