"""Teachers (goal selectors) on their own, ask/tell style: SAGG-RIAC and the field's other
learning-progress teachers as curricula for any learner. ``saggriac.teachers`` is the same
module under its former name.

    teacher = SaggRiacSelector(low=[0, 0], high=[1, 1], seed=0)
    for _ in range(1000):
        goal = teacher.sample()
        competence = my_learner.try_goal(goal)   # a float (|c| <= 1e100), higher is better (paper: <= 0)
        teacher.update(goal, competence)

The region tree, the interest (competence progress) and the three goal modes are the Rust core's,
the same code the run loop uses.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Protocol, runtime_checkable

import numpy as np

from .. import _core
from ..errors import InputError, ParameterError, StorageError
from ..files import MAX_TEACHER_BYTES, as_path, check_flag, read_bounded, starts_with, write_file
from ..values import as_numbers as _numbers
from . import ownership

# Every teacher's parameters and defaults are the core's (one declaration): each class below
# takes exactly those of its kind, with those defaults (tests/core/test_stub.py checks it).
_DEFAULTS: dict[str, dict[str, Any]] = _core.teacher_defaults()
_SAGG, _RIAC, _DLP, _ALP, _COVAR, _ADR, _PLR = (_DEFAULTS[k] for k in ("sagg_riac", "riac", "discrete_lp", "alp_gmm", "covar_gmm", "adr", "plr"))
_SPDL, _GAN = _DEFAULTS["spdl"], _DEFAULTS["goal_gan"]

#: The first bytes of a teacher saved by ``save(path)``.
MAGIC = b"saggriac-teacher\n"

#: Names of the mode codes in ``history()["asked_mode"]`` and ``last_mode``.
MODES = {0: "initial", 1: "interest", 2: "global", 3: "lowest_competence", 4: "random", 5: "external"}


@runtime_checkable
class GoalSelectorProtocol(Protocol):
    """What the run loop needs from a goal selector (built-in or written in Python)."""

    low: np.ndarray
    high: np.ndarray

    def sample(self) -> np.ndarray: ...

    def update(self, goal: np.ndarray, competence: float) -> Any: ...


def _vector(name: str, value: Any, dim: int | None = None) -> np.ndarray:
    arr = np.ascontiguousarray(_numbers(name, value))
    if arr.ndim != 1 or (dim is not None and arr.shape[0] != dim):
        want = f"shape ({dim},)" if dim is not None else "a 1-D array"
        raise InputError(f"{name} must have {want}; got shape {arr.shape}.")
    return arr


def _int_param(owner: str, name: str, value: Any, low: int, high: int) -> int:
    """An int argument in [low, high): numpy ints are taken, floats and bools refused (never
    truncated), and the range is checked here so the core's fixed-width ints never overflow
    (the core checks each parameter's own rule)."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not low <= int(value) < high:
        # The parameter's own rule where the core states one: the same text as for a value out of range.
        rule = _core.teacher_param_rule(name) or f"an int in [{low}, 2**{high.bit_length() - 1})"
        raise ParameterError(f"The '{name}' parameter of {owner} must be {rule}. Got {value!r} instead.", name, repr(value))
    return int(value)


def _float_param(owner: str, name: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        rule = _core.teacher_param_rule(name) or "a float"
        raise ParameterError(f"The '{name}' parameter of {owner} must be {rule}. Got {value!r} instead.", name, repr(value))
    return float(value)


def _typed(owner: str, name: str, value: Any, default: Any) -> Any:
    """``value`` as the type of the parameter's default: numpy scalars taken, floats and bools
    never taken for ints (the core checks each parameter's own rule)."""
    if isinstance(default, bool):
        return check_flag(value, name, owner)
    if isinstance(default, int):
        return _int_param(owner, name, value, 0, 2**63)
    if isinstance(default, float):
        return _float_param(owner, name, value)
    if not isinstance(value, str):
        raise ParameterError(f"The '{name}' parameter of {owner} must be a str. Got {value!r} instead.", name, repr(value))
    return value


class _AskTellSelector:
    _kind = ""
    #: The competences the teacher takes (saggriac.testing.check_goal_selector tells these).
    competence_range = (-1.0, 0.0)

    def __init__(self, low: Any, high: Any, seed: int, **params: Any) -> None:
        owner = type(self).__name__
        lo, hi = _vector("low", low), _vector("high", high)
        seed = _int_param(owner, "seed", seed, 0, 2**64)
        self._inner = _core.AskTell(self._kind, lo.tolist(), hi.tolist(), seed, {k: _typed(owner, k, v, _DEFAULTS[self._kind][k]) for k, v in params.items()})
        self.last_mode: str | None = None
        self.last_region: int | None = None

    def check_competences(self, lo: float, hi: float, whence: str) -> None:
        """Refuse (ParameterError) a threshold that competences in [lo, hi], told by ``whence``,
        can never meet, or always meet: ADR's ``t_low`` / ``t_high``, SPDL's ``delta``, Goal
        GAN's ``success_threshold``. A run, ``TeacherCallback`` and ``SelectorCurriculum`` call
        it with the competences they tell, so that a teacher never sits still without a word."""
        self._inner.check_competences(float(lo), float(hi), whence)

    @property
    def seed(self) -> int:
        """The seed of the teacher's generator."""
        return int(self._inner.seed)

    @property
    def dim(self) -> int:
        return self._inner.dim

    @property
    def low(self) -> np.ndarray:
        return self._inner.low

    @property
    def high(self) -> np.ndarray:
        return self._inner.high

    def sample(self) -> np.ndarray:
        """Next goal (1-D array). Its mode and region are in ``last_mode`` / ``last_region``."""
        goal, mode, region = self._inner.sample()
        self.last_mode = MODES[mode]
        self.last_region = None if region < 0 else region
        return goal

    def sample_batch(self, n: int) -> np.ndarray:
        """``n`` goals at once, shape (n, dim): as n calls of ``sample()`` without updates."""
        n = _int_param(f"{type(self).__name__}.sample_batch", "n", n, 0, 2**63)
        return self._inner.sample_batch(n)

    def update(self, goal: Any, competence: float) -> int | None:
        """Report the competence obtained for ``goal``. Returns the region that recorded it."""
        g = _vector("goal", goal, self.dim)
        c = _numbers("competence", competence)
        if c.ndim != 0:
            raise InputError(f"competence must be one float; got shape {c.shape}.")
        r = self._inner.update(g, float(c))
        return None if r < 0 else int(r)

    def update_batch(self, goals: Any, competences: Any) -> np.ndarray:
        """Report many competences at once (goals shape (n, dim)). A bad row changes nothing."""
        g = np.ascontiguousarray(_numbers("goals", goals))
        c = np.ascontiguousarray(_numbers("competences", competences))
        if g.ndim != 2 or c.ndim != 1 or g.shape[0] != c.shape[0]:
            raise InputError(f"goals must have shape (n, {self.dim}) and competences shape (n,); got {g.shape} and {c.shape}.")
        return self._inner.update_batch(g, c)

    def regions(self) -> dict[str, np.ndarray]:
        """Every region (inner nodes too): bounds, interest, measurements, split, depth."""
        return self._inner.regions()

    def leaves(self) -> dict[str, np.ndarray]:
        """The current leaves only: the regions goals are drawn from."""
        r = self.regions()
        keep = r["is_leaf"]
        return {k: v[keep] for k, v in r.items()}

    @property
    def n_regions(self) -> int:
        """Number of leaves (1 before the first split)."""
        return max(1, int(self.regions()["is_leaf"].sum()))

    def history(self) -> dict[str, np.ndarray]:
        """What was asked (goal, mode, region) and told (goal, competence, region), in order."""
        return self._inner.history()

    def __repr__(self) -> str:
        return f"{type(self).__name__}(dim={self.dim}, seed={self.seed}, regions={self.n_regions})"

    def __new__(cls, *args: Any, **kwargs: Any) -> "_AskTellSelector":
        obj = super().__new__(cls)
        obj._identity = ownership.new_identity()  # see teachers/ownership.py; pickle keeps it
        return obj

    # Saving: pickle goes through the core's own encoding, so a restored teacher asks exactly
    # the goals the original would have asked next. The copy keeps the teacher's identity (a
    # teacher sent to a worker is the same teacher); copy.copy/deepcopy make a new teacher.
    def __getstate__(self) -> dict[str, Any]:
        return {"teacher": bytes(self._inner.save()), "last_mode": self.last_mode, "last_region": self.last_region, "identity": self._identity}

    def __deepcopy__(self, memo: dict[int, Any]) -> "_AskTellSelector":
        state = self.__getstate__()
        del state["identity"]
        obj = type(self).__new__(type(self))
        obj.__setstate__(state)
        return obj

    def __copy__(self) -> "_AskTellSelector":
        return self.__deepcopy__({})  # no shallow copy: a teacher's state is one object

    def __setstate__(self, state: dict[str, Any]) -> None:
        inner = _core.AskTell.restore(state["teacher"])
        if inner.kind != self._kind:
            raise InputError(f"The saved teacher is a {inner.kind!r} teacher, not a {type(self).__name__}.")
        self._inner = inner
        self.last_mode, self.last_region = state["last_mode"], state["last_region"]
        if "identity" in state:
            self._identity = state["identity"]

    def save(self, path: str | os.PathLike[str], overwrite: bool = False) -> Path:
        """Write the teacher (parameters, state, history) to the file ``path``, atomically;
        :func:`load_selector` reads it back. An existing file is replaced only with
        ``overwrite=True``, and only if it is a teacher file saggriac saved: a link, a device, a
        FIFO or any other file is refused before anything is written."""
        owner = f"{type(self).__name__}.save"
        overwrite = check_flag(overwrite, "overwrite", owner)
        path = as_path(path, "path", owner)
        if path.is_dir() and not path.is_symlink():
            raise StorageError(f"{path} is a folder; give the path of a file to save the teacher to.")
        data = MAGIC + bytes(self._inner.save())
        return write_file(path, lambda tmp: tmp.write_bytes(data), what="a teacher", overwrite=overwrite, ours=starts_with(MAGIC))


def load_selector(path: str | os.PathLike[str]) -> _AskTellSelector:
    """The teacher saved by ``save(path)``, as an instance of its class, continuing where it stopped."""
    path = as_path(os.fspath(path) if isinstance(path, os.PathLike) else path, "path", "load_selector", kind="file")
    try:
        data = read_bounded(path, "a saved teacher", MAX_TEACHER_BYTES)
    except (FileNotFoundError, NotADirectoryError) as e:
        raise StorageError(f"Cannot read {path}: {e.strerror or e}.") from None
    if not data.startswith(MAGIC):
        raise InputError(f"{path} is not a teacher saved by saggriac (it does not start with {MAGIC!r}).")
    inner = _core.AskTell.restore(data[len(MAGIC) :])
    cls = _CLASSES[inner.kind]
    obj = cls.__new__(cls)
    obj._inner, obj.last_mode, obj.last_region = inner, None, None
    return obj


class SaggRiacSelector(_AskTellSelector):
    """SAGG-RIAC's high level over the box [low, high] of any dimension.

    Goals come from a region drawn by interest (``p_interest``), from the whole box
    (``p_global``) or from the region of lowest mean competence (``p_lowest``). A region holding
    more than ``g_max`` measurements is split where the interest of its two halves differs most;
    interest is the competence progress over the last ``zeta`` measurements (eq. 2), divided by
    ``zeta`` for every region as the paper prints it. ``interest_divisor="window"`` divides a
    region holding fewer than ``zeta`` measurements by its own count instead (saggriac <= 0.2).
    """

    _kind = "sagg_riac"

    def __init__(self, low: Any, high: Any, seed: int = 0, *, g_max: int = _SAGG["g_max"], zeta: int = _SAGG["zeta"], min_child: int = _SAGG["min_child"], interest_divisor: str = _SAGG["interest_divisor"], p_interest: float = _SAGG["p_interest"], p_global: float = _SAGG["p_global"], p_lowest: float = _SAGG["p_lowest"]) -> None:
        super().__init__(low, high, seed, g_max=g_max, zeta=zeta, min_child=min_child, interest_divisor=interest_divisor, p_interest=p_interest, p_global=p_global, p_lowest=p_lowest)


class RandomSelector(_AskTellSelector):
    """Goals uniform in [low, high] (SAGG-Random's high level); ``update`` only records."""

    _kind = "random"

    def __init__(self, low: Any, high: Any, seed: int = 0) -> None:
        super().__init__(low, high, seed)


class RiacSelector(_AskTellSelector):
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

    def __init__(self, low: Any, high: Any, seed: int = 0, *, max_region_size: int = _RIAC["max_region_size"], split_attempts: int = _RIAC["split_attempts"], min_child_share: float = _RIAC["min_child_share"], min_dims_range_ratio: float = _RIAC["min_dims_range_ratio"], p_alp: float = _RIAC["p_alp"], p_random: float = _RIAC["p_random"]) -> None:
        super().__init__(low, high, seed, max_region_size=max_region_size, split_attempts=split_attempts, min_child_share=min_child_share, min_dims_range_ratio=min_dims_range_ratio, p_alp=p_alp, p_random=p_random)


class TaskListSelector(_AskTellSelector):
    """A teacher over a list of ``n_tasks`` tasks: its goals are task indices (``sample()`` gives
    ``[i]``, ``sample_task()`` the int) and ``update`` takes an index or ``[index]``. Syllabus's
    ``DiscreteTaskSpace`` takes any of them (:class:`saggriac.adapters.syllabus.SelectorCurriculum`)."""

    def __init__(self, n_tasks: int, seed: int, **params: Any) -> None:
        # The goals are task indices: no box.
        super().__init__([], [], seed, n_tasks=n_tasks, **params)

    @property
    def n_tasks(self) -> int:
        """The number of tasks."""
        return int(round(float(self.high[0]))) + 1

    def sample_task(self) -> int:
        """The next task's index."""
        return int(self.sample()[0])

    def update(self, goal: Any, competence: float) -> int | None:
        """Report what was obtained on task ``goal`` (an index, or ``[index]``)."""
        return super().update(np.atleast_1d(_numbers("goal", goal)), competence)


class DiscreteLpSelector(TaskListSelector):
    """Learning progress over a list of ``n_tasks`` tasks (Kanitscheider et al., "Multi-task
    curriculum learning in a complex, visual, hard-exploration domain: Minecraft", 2021).

    Goals are task indices (``sample()`` gives ``[i]``; ``sample_task()`` the int), and the
    competence told is a success rate in [0, 1]. Each task keeps a fast moving average of its
    success and a slow one following it (step ``alpha``); its progress is the gap between the
    two after the paper's reweighting (``theta``), which stretches small success rates. Tasks
    are drawn in proportion to the sigmoid of their progress z-scored over all tasks (so tasks
    without progress keep some probability); with the same progress everywhere, uniformly.
    """

    _kind = "discrete_lp"
    competence_range = (0.0, 1.0)

    def __init__(self, n_tasks: int, seed: int = 0, *, alpha: float = _DLP["alpha"], theta: float = _DLP["theta"]) -> None:
        super().__init__(n_tasks, seed, alpha=alpha, theta=theta)


class AlpGmmSelector(_AskTellSelector):
    """ALP-GMM (Portelas, Colas, Hofmann & Oudeyer, CoRL 2019) over the box [low, high].

    A told task's absolute learning progress (ALP) is |competence - competence of the nearest
    earlier task|. Every ``fit_rate`` tasks, Gaussian mixtures of 2 to ``max_components``
    components are fitted to the last ``fit_rate`` (task, ALP) pairs and the one of lowest AIC
    is kept. Goals are uniform for the first ``bootstrap`` tasks and then with probability
    ``random_task_ratio``; otherwise from a component drawn in proportion to its mean ALP.
    Tasks are scaled to [0, 1] per dimension inside the teacher.
    """

    _kind = "alp_gmm"

    def __init__(self, low: Any, high: Any, seed: int = 0, *, fit_rate: int = _ALP["fit_rate"], max_components: int = _ALP["max_components"], random_task_ratio: float = _ALP["random_task_ratio"], bootstrap: int = _ALP["bootstrap"]) -> None:
        super().__init__(low, high, seed, fit_rate=fit_rate, max_components=max_components, random_task_ratio=random_task_ratio, bootstrap=bootstrap)


class CovarGmmSelector(_AskTellSelector):
    """Covar-GMM (Moulin-Frier, Nguyen & Oudeyer, 2014) over the box [low, high].

    Gaussian mixtures over (time, task, competence) of the last ``fit_rate`` tasks, refitted
    every ``fit_rate`` tasks with the number of components chosen by AIC. A component's progress
    is its covariance of time and competence; goals come from a component drawn in proportion
    to its absolute progress (positive progress only with ``absolute_lp=False``), with the
    bootstrap and random share of :class:`AlpGmmSelector`.
    """

    _kind = "covar_gmm"

    def __init__(self, low: Any, high: Any, seed: int = 0, *, fit_rate: int = _COVAR["fit_rate"], max_components: int = _COVAR["max_components"], random_task_ratio: float = _COVAR["random_task_ratio"], bootstrap: int = _COVAR["bootstrap"], absolute_lp: bool = _COVAR["absolute_lp"]) -> None:
        super().__init__(low, high, seed, fit_rate=fit_rate, max_components=max_components, random_task_ratio=random_task_ratio, bootstrap=bootstrap, absolute_lp=absolute_lp)


class AdrSelector(_AskTellSelector):
    """Automatic Domain Randomization (OpenAI: Akkaya et al., "Solving Rubik's Cube with a Robot
    Hand", 2019, Algorithm 1) over the box [low, high] of any dimension.

    Goals are uniform in the current ranges [phi_L, phi_H] of every dimension, which start at an
    initial region: a single value (``initial_width=0``, the paper's) at ``initial`` of each
    dimension's width from low (0.5: the box's centre). With probability ``boundary_prob`` one
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
    competence_range = (0.0, 1.0)

    def __init__(self, low: Any, high: Any, seed: int = 0, *, boundary_prob: float = _ADR["boundary_prob"], buffer_size: int = _ADR["buffer_size"], t_low: float = _ADR["t_low"], t_high: float = _ADR["t_high"], step: float = _ADR["step"], initial: float = _ADR["initial"], initial_width: float = _ADR["initial_width"]) -> None:
        super().__init__(low, high, seed, boundary_prob=boundary_prob, buffer_size=buffer_size, t_low=t_low, t_high=t_high, step=step, initial=initial, initial_width=initial_width)

    @property
    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """The current ranges: (phi_L, phi_H), one value per dimension."""
        r = self.regions()
        return r["low"][0], r["high"][0]


class PlrSelector(TaskListSelector):
    """Prioritized Level Replay (Jiang, Grefenstette & Rocktäschel, ICML 2021) over a list of
    ``n_tasks`` levels; goals are level indices, as :class:`DiscreteLpSelector`'s.

    Each draw is a new level (uniform among the levels never drawn) or a replay: with
    ``replay_schedule="proportionate"`` (the paper's) a replay has probability |seen| / n_tasks,
    with ``"fixed"`` probability ``replay_prob`` (always once every level is seen). A replay draws
    a seen level from (1 - ``staleness_coef``) P_S + ``staleness_coef`` P_C: P_S ranks the levels'
    scores (weight rank^(-1/``temperature``)), P_C is proportional to the draws since a level was
    last drawn. With ``score="progress"`` (the default), ``update`` is told a competence and a
    level's score is the change of its competence since its previous tell (0 on the first); with
    ``score="told"``, the value told is the score itself (the paper's: the learner's value loss,
    mean |GAE|, on the level's last episode).
    """

    _kind = "plr"
    competence_range = (0.0, 1.0)

    def __init__(self, n_tasks: int, seed: int = 0, *, temperature: float = _PLR["temperature"], staleness_coef: float = _PLR["staleness_coef"], replay_schedule: str = _PLR["replay_schedule"], replay_prob: float = _PLR["replay_prob"], score: str = _PLR["score"]) -> None:
        super().__init__(n_tasks, seed, temperature=temperature, staleness_coef=staleness_coef, replay_schedule=replay_schedule, replay_prob=replay_prob, score=score)


class SpdlSelector(_AskTellSelector):
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
    competence_range = (0.0, 1.0)

    def __init__(self, low: Any, high: Any, seed: int = 0, *, init_mean: float = _SPDL["init_mean"], init_std: float = _SPDL["init_std"], target_mean: float = _SPDL["target_mean"], target_std: float = _SPDL["target_std"], epsilon: float = _SPDL["epsilon"], delta: float = _SPDL["delta"], update_every: int = _SPDL["update_every"], warmup: int = _SPDL["warmup"]) -> None:
        super().__init__(low, high, seed, init_mean=init_mean, init_std=init_std, target_mean=target_mean, target_std=target_std, epsilon=epsilon, delta=delta, update_every=update_every, warmup=warmup)


class GoalGanSelector(_AskTellSelector):
    """Goal GAN (Florensa, Held, Geng & Abbeel, ICML 2018) over the box [low, high].

    Each proposed goal is asked ``n_rollouts`` times in a row; a told competence >=
    ``success_threshold`` is a success, and the goal's success rate labels it good when it lies
    in [``r_min``, ``r_max``] (intermediate difficulty). Every ``update_size`` labelled goals
    holding a good one, a least-squares GAN with goal labels is trained (``gan_iterations``
    steps, Adam with ``learning_rate``): the discriminator scores good goals high, bad and
    generated goals low. Goals come from the generator (noise of dimension ``noise_dim``, two
    hidden layers of ``hidden`` ReLU units) and, with probability ``p_old``, from the goals
    labelled so far; until the first training they are uniform in the box. The networks are
    saggriac's own (no deep-learning framework). ``success_threshold`` is in the units of the
    competence told (the default for [0, 1]; through ``Config(teacher="goal_gan")`` it is moved to
    the run's [min_c, 0], and one every attempt would fail or pass is refused).
    """

    _kind = "goal_gan"
    competence_range = (0.0, 1.0)

    def __init__(self, low: Any, high: Any, seed: int = 0, *, success_threshold: float = _GAN["success_threshold"], r_min: float = _GAN["r_min"], r_max: float = _GAN["r_max"], n_rollouts: int = _GAN["n_rollouts"], update_size: int = _GAN["update_size"], gan_iterations: int = _GAN["gan_iterations"], p_old: float = _GAN["p_old"], noise_dim: int = _GAN["noise_dim"], hidden: int = _GAN["hidden"], learning_rate: float = _GAN["learning_rate"]) -> None:
        super().__init__(low, high, seed, success_threshold=success_threshold, r_min=r_min, r_max=r_max, n_rollouts=n_rollouts, update_size=update_size, gan_iterations=gan_iterations, p_old=p_old, noise_dim=noise_dim, hidden=hidden, learning_rate=learning_rate)


def _subclasses(cls: type) -> list[type]:
    return [d for c in cls.__subclasses__() for d in [c, *_subclasses(c)]]


#: Each teacher's class, by kind: the classes above (a new teacher is one more class).
_CLASSES: dict[str, type[_AskTellSelector]] = {c._kind: c for c in _subclasses(_AskTellSelector) if c._kind}
