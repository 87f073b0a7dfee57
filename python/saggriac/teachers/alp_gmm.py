"""ALP-GMM (Portelas, Colas, Hofmann & Oudeyer, CoRL 2019)."""

from __future__ import annotations

from typing import Any

from .ask_tell import DEFAULTS, AskTellSelector

_ALP = DEFAULTS["alp_gmm"]


class AlpGmmSelector(AskTellSelector):
    """ALP-GMM (Portelas, Colas, Hofmann & Oudeyer, CoRL 2019) over the box [low, high].

    A told task's absolute learning progress (ALP) is |competence - competence of the nearest
    earlier task|. Every ``fit_rate`` tasks, Gaussian mixtures of 2 to ``max_components``
    components are fitted to the last ``fit_rate`` (task, ALP) pairs and the one of lowest AIC
    is kept. Goals are uniform for the first ``bootstrap`` tasks and then with probability
    ``random_task_ratio``; otherwise from a component drawn in proportion to its mean ALP.
    Tasks are scaled to [0, 1] per dimension inside the teacher.
    """

    _kind = "alp_gmm"
    #: What its goal modes mean, as logged (saggriac.analysis.teacher_readings).
    mode_shares = {"global": "uniform_share", "interest": "mixture_share"}
    reading = "mixture"

    def __init__(self, low: Any, high: Any, seed: int = 0, *, fit_rate: int = _ALP["fit_rate"], max_components: int = _ALP["max_components"], random_task_ratio: float = _ALP["random_task_ratio"], bootstrap: int = _ALP["bootstrap"]) -> None:
        super().__init__(low, high, seed, fit_rate=fit_rate, max_components=max_components, random_task_ratio=random_task_ratio, bootstrap=bootstrap)
