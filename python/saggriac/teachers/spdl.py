"""Self-paced deep RL (Klink et al., NeurIPS 2020; JMLR 2021)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from .ask_tell import DEFAULTS, AskTellSelector

_SPDL = DEFAULTS["spdl"]


class SpdlSelector(AskTellSelector):
    """SPDL, self-paced deep RL, over the box [low, high], in either of its papers' forms.

    Goals are drawn from a Gaussian context distribution p (in the box scaled to [0, 1]) and
    clipped to the box. Every ``update_every`` told goals, once ``warmup`` were told, p moves
    toward the target mu:

    - ``form="delta"`` (default; Klink et al., JMLR 2021): p minimises KL(p || mu) subject to an
      expected competence >= ``delta`` (self-normalised importance weights over the goals told
      since the last update) and KL(p || p_old) <= ``epsilon``. Where the mean competence told
      is below ``delta``, p moves back within the KL bound toward where competence was higher
      (the most it can find there, then the p nearest mu that meets ``delta``); where nothing
      told is better, p stays.
    - ``form="alpha"`` (Klink et al., NeurIPS 2020; TeachMyAgent's): one natural-gradient step
      on E_p[competence] - alpha KL(p || mu) of size KL(p_old || p) = ``epsilon``, alpha =
      ``alpha_zeta`` x mean competence / KL(p || mu), 0 while the update's number is below
      ``alpha_offset``.

    Start and target: ``init_mean``, ``target_mean`` (positions in [0, 1]) and ``init_std``,
    ``target_std`` (box widths) take one number for every dimension or a list, one per
    dimension; ``init_cov``, ``target_cov`` take a d x d covariance in box widths squared in
    place of the standard deviations. ``covariance="full"`` lets p learn correlations (and keeps
    a covariance's; at most 10 dimensions), ``"diagonal"`` (default) one standard deviation per
    dimension. ``regions()`` gives p as one row: mean +- one standard deviation, its KL to mu as
    interest. ``delta`` is in the units of the competence told (the default for [0, 1]; through
    ``Config(teacher="spdl")`` it is moved to the run's [min_c, 0], and one outside is refused).
    """

    _kind = "spdl"
    reading = "spdl"
    competence_range = (0.0, 1.0)

    def __init__(
        self,
        low: Any,
        high: Any,
        seed: int = 0,
        *,
        init_mean: float | Sequence[float] = _SPDL["init_mean"],
        init_std: float | Sequence[float] = _SPDL["init_std"],
        target_mean: float | Sequence[float] = _SPDL["target_mean"],
        target_std: float | Sequence[float] = _SPDL["target_std"],
        epsilon: float = _SPDL["epsilon"],
        delta: float = _SPDL["delta"],
        update_every: int = _SPDL["update_every"],
        warmup: int = _SPDL["warmup"],
        form: str = _SPDL["form"],
        covariance: str = _SPDL["covariance"],
        alpha_offset: int = _SPDL["alpha_offset"],
        alpha_zeta: float = _SPDL["alpha_zeta"],
        init_cov: Any = None,
        target_cov: Any = None,
    ) -> None:
        super().__init__(
            low,
            high,
            seed,
            init_mean=init_mean,
            init_std=init_std,
            target_mean=target_mean,
            target_std=target_std,
            epsilon=epsilon,
            delta=delta,
            update_every=update_every,
            warmup=warmup,
            form=form,
            covariance=covariance,
            alpha_offset=alpha_offset,
            alpha_zeta=alpha_zeta,
            init_cov=init_cov,
            target_cov=target_cov,
        )
