"""Self-paced deep RL (Klink et al., NeurIPS 2020; JMLR 2021)."""

from __future__ import annotations

from typing import Any

from .ask_tell import DEFAULTS, AskTellSelector

_SPDL = DEFAULTS["spdl"]


class SpdlSelector(AskTellSelector):
    """SPDL, self-paced deep RL (Klink et al., NeurIPS 2020), in its form with a performance
    threshold (Klink et al., JMLR 2021), over the box [low, high].

    Goals are drawn from a Gaussian context distribution p (diagonal covariance, in the box
    scaled to [0, 1]) and clipped to the box. Every ``update_every`` told goals, once ``warmup``
    were told, p moves toward the target mu: it minimises KL(p || mu) subject to an expected
    competence >= ``delta`` (importance-weighted from the goals told since the last update) and
    KL(p || p_old) <= ``epsilon``. While the mean competence told is below ``delta``, p stays.
    Both Gaussians have one mean (``init_mean``, ``target_mean``: a position in [0, 1]) and
    one standard deviation (``init_std``, ``target_std``: box widths) for every dimension.
    ``regions()`` gives p as one row: mean +- one standard deviation, its KL to mu as interest.
    ``delta`` is in the units of the competence told (the default for [0, 1]; through
    ``Config(teacher="spdl")`` it is moved to the run's [min_c, 0], and one outside is refused).
    """

    _kind = "spdl"
    reading = "spdl"
    competence_range = (0.0, 1.0)

    def __init__(self, low: Any, high: Any, seed: int = 0, *, init_mean: float = _SPDL["init_mean"], init_std: float = _SPDL["init_std"], target_mean: float = _SPDL["target_mean"], target_std: float = _SPDL["target_std"], epsilon: float = _SPDL["epsilon"], delta: float = _SPDL["delta"], update_every: int = _SPDL["update_every"], warmup: int = _SPDL["warmup"]) -> None:
        super().__init__(low, high, seed, init_mean=init_mean, init_std=init_std, target_mean=target_mean, target_std=target_std, epsilon=epsilon, delta=delta, update_every=update_every, warmup=warmup)
