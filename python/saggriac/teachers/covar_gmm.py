"""Covar-GMM (Moulin-Frier, Nguyen & Oudeyer, 2014)."""

from __future__ import annotations

from typing import Any

from .ask_tell import DEFAULTS, AskTellSelector

_COVAR = DEFAULTS["covar_gmm"]


class CovarGmmSelector(AskTellSelector):
    """Covar-GMM (Moulin-Frier, Nguyen & Oudeyer, 2014) over the box [low, high].

    Gaussian mixtures over (time, task, competence) of the last ``fit_rate`` tasks, refitted
    every ``fit_rate`` tasks with the number of components chosen by AIC. A component's progress
    is its covariance of time and competence; goals come from a component drawn in proportion
    to its absolute progress (positive progress only with ``absolute_lp=False``), with the
    bootstrap and random share of :class:`AlpGmmSelector`.
    """

    _kind = "covar_gmm"
    #: What its goal modes mean, as logged (saggriac.analysis.teacher_readings).
    mode_shares = {"global": "uniform_share", "interest": "mixture_share"}
    reading = "mixture"

    def __init__(self, low: Any, high: Any, seed: int = 0, *, fit_rate: int = _COVAR["fit_rate"], max_components: int = _COVAR["max_components"], random_task_ratio: float = _COVAR["random_task_ratio"], bootstrap: int = _COVAR["bootstrap"], absolute_lp: bool = _COVAR["absolute_lp"]) -> None:
        super().__init__(low, high, seed, fit_rate=fit_rate, max_components=max_components, random_task_ratio=random_task_ratio, bootstrap=bootstrap, absolute_lp=absolute_lp)
