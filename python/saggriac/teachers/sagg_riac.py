"""SAGG-RIAC's high level (Baranes & Oudeyer, IROS 2010) as an ask/tell teacher."""

from __future__ import annotations

from typing import Any

from .ask_tell import DEFAULTS, AskTellSelector

_SAGG = DEFAULTS["sagg_riac"]


class SaggRiacSelector(AskTellSelector):
    """SAGG-RIAC's high level over the box [low, high] of any dimension.

    Goals come from a region drawn by interest (``p_interest``), from the whole box
    (``p_global``) or from the region of lowest mean competence (``p_lowest``). A region holding
    more than ``g_max`` measurements is split where the interest of its two halves differs most;
    interest is the competence progress over the last ``zeta`` measurements (eq. 2), divided by
    ``zeta`` for every region as the paper prints it. ``interest_divisor="window"`` divides a
    region holding fewer than ``zeta`` measurements by its own count instead (saggriac <= 0.2).

    ``mode3`` is how mode 3 reads the paper: ``"lowest_competence"`` (the default, the paper's)
    draws uniformly in the region of lowest mean competence; ``"interest_worst"`` (beyond the
    paper, as RIAC's third mode in Portelas et al., CoRL 2019) draws a region by interest and a
    goal about the worst goal it holds, a Gaussian of sd ``mode3_sigma`` times the box's width,
    clipped to the region (docs/parameters.md, "Mode 3").
    """

    _kind = "sagg_riac"
    #: What its goal modes mean, as logged (saggriac.analysis.teacher_readings).
    mode_shares = {"initial": "uniform_share", "global": "uniform_share", "interest": "interest_share", "lowest_competence": "lowest_share"}
    reading = "tree"

    def __init__(self, low: Any, high: Any, seed: int = 0, *, g_max: int = _SAGG["g_max"], zeta: int = _SAGG["zeta"], min_child: int = _SAGG["min_child"], interest_divisor: str = _SAGG["interest_divisor"], p_interest: float = _SAGG["p_interest"], p_global: float = _SAGG["p_global"], p_lowest: float = _SAGG["p_lowest"], mode3: str = _SAGG["mode3"], mode3_sigma: float = _SAGG["mode3_sigma"]) -> None:
        super().__init__(low, high, seed, g_max=g_max, zeta=zeta, min_child=min_child, interest_divisor=interest_divisor, p_interest=p_interest, p_global=p_global, p_lowest=p_lowest, mode3=mode3, mode3_sigma=mode3_sigma)
