"""Prioritized Level Replay (Jiang, Grefenstette & Rocktäschel, ICML 2021)."""

from __future__ import annotations

import numpy as np

from .ask_tell import DEFAULTS
from .task_list import TaskListSelector

_PLR = DEFAULTS["plr"]


class PlrSelector(TaskListSelector):
    """Prioritized Level Replay (Jiang, Grefenstette & Rocktäschel, ICML 2021) over a list of
    ``n_tasks`` levels; goals are level indices, as :class:`DiscreteLpSelector`'s.

    Each draw is a new level (uniform among the levels never drawn) or a replay: with
    ``replay_schedule="proportionate"`` (the paper's) a replay has probability |seen| / n_tasks,
    with ``"fixed"`` probability ``replay_prob`` (always once every level is seen). A replay draws
    a seen level from (1 - ``staleness_coef``) P_S + ``staleness_coef`` P_C: P_S ranks the levels'
    scores (weight rank^(-1/``temperature``)), P_C is proportional to the draws since a level was
    last drawn (0 for the level drawn last, as in the authors' code). With ``ties="order"`` (the
    default, the authors' code's and Syllabus's rule) every level is ranked, unseen ones at score
    0, and levels of equal score take distinct ranks, the later level in the list first; with
    ``ties="average"`` the seen levels alone are ranked and tied ones share the mean of their
    ranks. With ``score="progress"`` (the default), ``update`` is told a competence and a
    level's score is the change of its competence since its previous tell (0 on the first); with
    ``score="told"``, the value told is the score itself (the paper's: the learner's positive or
    L1 value loss on the level's last episode, which
    :class:`saggriac.adapters.sb3.TeacherCallback` computes from SB3's rollouts).
    """

    _kind = "plr"
    #: What its goal modes mean, as logged (saggriac.analysis.teacher_readings).
    mode_shares = {"initial": "new_share", "interest": "replay_share"}
    competence_range = (0.0, 1.0)

    def __init__(self, n_tasks: int, seed: int = 0, *, temperature: float = _PLR["temperature"], staleness_coef: float = _PLR["staleness_coef"], replay_schedule: str = _PLR["replay_schedule"], replay_prob: float = _PLR["replay_prob"], score: str = _PLR["score"], ties: str = _PLR["ties"]) -> None:
        super().__init__(n_tasks, seed, temperature=temperature, staleness_coef=staleness_coef, replay_schedule=replay_schedule, replay_prob=replay_prob, score=score, ties=ties)

    def probabilities(self) -> np.ndarray:
        """The probability of each level at the next draw (a new level or a replay), as the
        teacher stands now; drawing changes it (staleness), and so does telling (scores)."""
        p = self._inner.task_probabilities()
        assert p is not None  # PLR always says
        return p
