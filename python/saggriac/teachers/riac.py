"""RIAC, as the baseline of Portelas et al. (CoRL 2019)."""

from __future__ import annotations

from typing import Any

from .ask_tell import DEFAULTS, AskTellSelector

_RIAC = DEFAULTS["riac"]


class RiacSelector(AskTellSelector):
    """RIAC as the baseline of Portelas et al. (CoRL 2019), after R-IAC (Baranes & Oudeyer,
    IEEE TAMD 2009), over the box [low, high] of any dimension.

    A region's absolute learning progress (ALP) is the change of mean competence between the
    older and the newer half of what it recorded. A region holding more than ``max_region_size``
    measurements is split by the best of ``split_attempts`` random cuts: the one whose children's
    ALP differ most, each child keeping at least ``min_child_share`` of the measurements and
    ``min_dims_range_ratio`` of the box's width in every dimension. Goals: a region drawn by ALP,
    uniform in it (``p_alp``); uniform in the box (``p_random``); or near the worst goal of a
    region drawn by ALP (the rest).
    """

    _kind = "riac"
    #: What its goal modes mean, as logged (saggriac.analysis.teacher_readings).
    mode_shares = {"global": "uniform_share", "interest": "alp_share", "lowest_competence": "worst_share"}
    reading = "tree"

    def __init__(self, low: Any, high: Any, seed: int = 0, *, max_region_size: int = _RIAC["max_region_size"], split_attempts: int = _RIAC["split_attempts"], min_child_share: float = _RIAC["min_child_share"], min_dims_range_ratio: float = _RIAC["min_dims_range_ratio"], p_alp: float = _RIAC["p_alp"], p_random: float = _RIAC["p_random"]) -> None:
        super().__init__(low, high, seed, max_region_size=max_region_size, split_attempts=split_attempts, min_child_share=min_child_share, min_dims_range_ratio=min_dims_range_ratio, p_alp=p_alp, p_random=p_random)
