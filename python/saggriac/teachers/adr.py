"""Automatic Domain Randomization (Akkaya et al. 2019)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from .ask_tell import DEFAULTS, AskTellSelector

_ADR = DEFAULTS["adr"]


class AdrSelector(AskTellSelector):
    """Automatic Domain Randomization (OpenAI: Akkaya et al., "Solving Rubik's Cube with a Robot
    Hand", 2019, Algorithm 1) over the box [low, high] of any dimension.

    Goals are uniform in the current ranges [phi_L, phi_H] of every dimension, which start at an
    initial region: a single value (``initial_width=0``, the paper's) at ``initial`` of each
    dimension's width from low (0.5: the box's centre); ``initial_width > 0`` starts from a box
    of that share of each width around it. ``initial``, ``initial_width`` and ``step`` take one
    number for every dimension or a list, one per dimension (a start thin in one parameter and
    wide in another, TeachMyAgent's expert knowledge). With probability ``boundary_prob`` one
    dimension, drawn uniformly, is set to its low or high bound; the competence told for such a
    goal joins that bound's buffer. Once ``buffer_size`` competences are there, their mean moves
    the bound by ``step`` of the dimension's width: outwards if >= ``t_high``, inwards if
    <= ``t_low`` (never past the other bound), and the buffer is cleared.

    ``t_low`` and ``t_high`` are in the units of the competence told: the defaults suit a success
    rate or task progress in [0, 1] (SB3's ``TeacherCallback``, Syllabus). A run's competence
    lies in [min_c, 0]: ``Config(teacher="adr")`` moves the defaults there (-0.8, -0.2 for
    min_c = -1); a run, ``TeacherCallback`` and ``SelectorCurriculum`` refuse thresholds their
    competences cannot meet (:meth:`check_competences`). ``bounds`` gives the current ranges.
    """

    _kind = "adr"
    #: What its goal modes mean, as logged (saggriac.analysis.teacher_readings).
    mode_shares = {"interest": "boundary_share"}
    reading = "adr"
    competence_range = (0.0, 1.0)

    def __init__(self, low: Any, high: Any, seed: int = 0, *, boundary_prob: float = _ADR["boundary_prob"], buffer_size: int = _ADR["buffer_size"], t_low: float = _ADR["t_low"], t_high: float = _ADR["t_high"], step: float | Sequence[float] = _ADR["step"], initial: float | Sequence[float] = _ADR["initial"], initial_width: float | Sequence[float] = _ADR["initial_width"]) -> None:
        super().__init__(low, high, seed, boundary_prob=boundary_prob, buffer_size=buffer_size, t_low=t_low, t_high=t_high, step=step, initial=initial, initial_width=initial_width)

    @property
    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """The current ranges: (phi_L, phi_H), one value per dimension."""
        r = self.regions()
        return r["low"][0], r["high"][0]
