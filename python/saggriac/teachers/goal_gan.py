"""Goal GAN (Florensa, Held, Geng & Abbeel, ICML 2018)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from .ask_tell import DEFAULTS, AskTellSelector

_GAN = DEFAULTS["goal_gan"]


class GoalGanSelector(AskTellSelector):
    """Goal GAN (Florensa, Held, Geng & Abbeel, ICML 2018) over the box [low, high].

    Each proposed goal is asked ``n_rollouts`` times in a row; a told competence >=
    ``success_threshold`` is a success, and the goal's success rate labels it good when it lies
    in [``r_min``, ``r_max``] (intermediate difficulty). Every ``update_size`` labelled goals
    holding a good one, a least-squares GAN with goal labels is trained (``gan_iterations``
    steps, Adam with ``learning_rate``): the discriminator scores good goals high, bad and
    generated goals low. Goals come from the generator (noise of dimension ``noise_dim``, two
    hidden layers of ``hidden`` ReLU units) and, with probability ``p_old``, from the goals
    labelled so far; until the first training they are uniform in the first goals' box: at
    ``initial`` of each dimension's width from low, ``initial_width`` of it wide (0.5 and 1: the
    whole box), one number for every dimension or a list, one per dimension (the paper starts
    from goals its initial policy reaches). The networks are
    saggriac's own (no deep-learning framework). ``success_threshold`` is in the units of the
    competence told (the default for [0, 1]; through ``Config(teacher="goal_gan")`` it is moved to
    the run's [min_c, 0], and one every attempt would fail or pass is refused).
    """

    _kind = "goal_gan"
    #: What its goal modes mean, as logged (saggriac.analysis.teacher_readings).
    mode_shares = {"initial": "uniform_share", "interest": "generated_share", "global": "replay_share"}
    reading = "goal_gan"
    competence_range = (0.0, 1.0)

    def __init__(self, low: Any, high: Any, seed: int = 0, *, success_threshold: float = _GAN["success_threshold"], r_min: float = _GAN["r_min"], r_max: float = _GAN["r_max"], n_rollouts: int = _GAN["n_rollouts"], update_size: int = _GAN["update_size"], gan_iterations: int = _GAN["gan_iterations"], p_old: float = _GAN["p_old"], noise_dim: int = _GAN["noise_dim"], hidden: int = _GAN["hidden"], learning_rate: float = _GAN["learning_rate"], initial: float | Sequence[float] = _GAN["initial"], initial_width: float | Sequence[float] = _GAN["initial_width"]) -> None:
        super().__init__(low, high, seed, success_threshold=success_threshold, r_min=r_min, r_max=r_max, n_rollouts=n_rollouts, update_size=update_size, gan_iterations=gan_iterations, p_old=p_old, noise_dim=noise_dim, hidden=hidden, learning_rate=learning_rate, initial=initial, initial_width=initial_width)
