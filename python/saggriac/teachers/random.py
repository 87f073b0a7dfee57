"""Goals uniform in the box: SAGG-Random's high level."""

from __future__ import annotations

from typing import Any

from .ask_tell import AskTellSelector


class RandomSelector(AskTellSelector):
    """Goals uniform in [low, high] (SAGG-Random's high level); ``update`` only records."""

    _kind = "random"
    #: What its goal modes mean, as logged (saggriac.analysis.teacher_readings).
    mode_shares = {"random": "uniform_share"}

    def __init__(self, low: Any, high: Any, seed: int = 0) -> None:
        super().__init__(low, high, seed)
