"""What a teacher is doing, read from its history and regions while it teaches: the numbers its
paper plots, as a flat dict that a logger takes (SB3's ``TeacherCallback`` writes them as
``teacher/<name>``). numpy only, so a training loop can call it at every rollout.

Each built-in teacher names its reader here (its class's ``reading``) and what its goal modes
mean (``mode_shares``); ``READERS`` and ``SHARES`` gather them by the registry's name. The numbers that describe goals asked or told "lately" cover a
window of the teacher's history, from ``asked_from`` and ``told_from`` (positions in
``history()``) to its end; the totals (``asked``, ``told``) are the teacher's own, so they go on
across a save and a resume.
"""

from __future__ import annotations

from typing import Any, Callable

import numpy as np

from ..errors import ParameterError
from ..teachers import MODES, available

#: What each kind's goal modes mean, as the share of the window's goals logged under that name
#: (modes not listed are not counted apart), from each class's ``mode_shares``. A mode's meaning
#: is the teacher's: ADR's "random" draws are uniform in its current ranges, not in the box, and
#: Goal GAN's "global" ones are replays of goals labelled before.
SHARES: dict[str, dict[str, str]] = {kind: dict(cls.mode_shares) for kind, cls in available().items()}

#: Goal GAN's goals of intermediate difficulty as the paper defines and plots them (Florensa et
#: al. 2018, Sec. 4.1 and Fig. 2): a success rate in [R_MIN, R_MAX] over the goal's attempts, an
#: attempt a success when its competence is >= SUCCESS (competences in [0, 1]).
GOID_R_MIN, GOID_R_MAX, GOID_SUCCESS = 0.1, 0.9, 0.5


def kind_of(teacher: Any) -> str | None:
    """The registry's name of a built-in teacher (or of a subclass of one); None for any other."""
    for kind, cls in available().items():
        if isinstance(teacher, cls):
            return kind
    return None


def _window(h: dict[str, np.ndarray], asked_from: int, told_from: int) -> dict[str, np.ndarray]:
    out = {k: v[asked_from:] for k, v in h.items() if k.startswith("asked_")}
    out.update({k: v[told_from:] for k, v in h.items() if k.startswith("told_")})
    return out


def _index(name: str, value: Any) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 0:
        raise ParameterError(f"The '{name}' parameter of teacher_readings must be an int >= 0 (a position in the teacher's history). Got {value!r} instead.", name, repr(value))
    return int(value)


def teacher_readings(teacher: Any, asked_from: int = 0, told_from: int = 0) -> dict[str, Any]:
    """The teacher's readings: ``asked`` and ``told`` (its totals), ``competence`` (mean told in
    the window), the shares of the window's goals by what drew them (``SHARES``), and what its
    paper plots (see each ``_<kind>`` reader). Scalars are floats; per-region or per-task lists
    are numpy arrays (a logger's histograms). A teacher that is not saggriac's gets an empty dict."""
    asked_from, told_from = _index("asked_from", asked_from), _index("told_from", told_from)
    kind = kind_of(teacher)
    if kind is None:
        return {}
    h = teacher.history()
    w = _window(h, asked_from, told_from)
    out: dict[str, Any] = {"asked": len(h["asked_goal"]), "told": len(h["told_goal"])}
    if len(w["told_competence"]):
        out["competence"] = float(np.mean(w["told_competence"]))
    names = SHARES.get(kind, {})
    if len(w["asked_mode"]) and names:
        modes = np.array([MODES[int(m)] for m in w["asked_mode"]])
        for label in dict.fromkeys(names.values()):
            out[label] = float(np.isin(modes, [m for m, n in names.items() if n == label]).mean())
    reader = READERS.get(kind)
    if reader is not None:
        out.update(reader(teacher, h, w))
    return out


def _per_dimension(out: dict[str, Any], name: str, values: np.ndarray) -> None:
    for i, v in enumerate(np.asarray(values, dtype=float)):
        out[f"{name}_{i}"] = float(v)


def _tree(teacher: Any, h: dict[str, np.ndarray], w: dict[str, np.ndarray]) -> dict[str, Any]:
    """SAGG-RIAC and RIAC (Baranes & Oudeyer 2010, Fig. 3; Portelas et al. 2019): the regions
    goals are drawn from (the tree's leaves) and their interests."""
    r = teacher.regions()
    leaf = np.asarray(r["is_leaf"], dtype=bool)
    interest = np.asarray(r["interest"], dtype=float)[leaf]
    out: dict[str, Any] = {"regions": int(max(1, leaf.sum()))}
    if interest.size:
        out.update(interest_max=float(interest.max()), interest_mean=float(interest.mean()), interest=interest)
    return out


def _adr(teacher: Any, h: dict[str, np.ndarray], w: dict[str, np.ndarray]) -> dict[str, Any]:
    """ADR (Akkaya et al. 2019, Fig. 12-13): its current range [phi_L, phi_H] of every dimension,
    and their mean share of the box's widths."""
    r = teacher.regions()
    lo, hi = np.asarray(r["low"][0], dtype=float), np.asarray(r["high"][0], dtype=float)
    out: dict[str, Any] = {}
    _per_dimension(out, "low", lo)
    _per_dimension(out, "high", hi)
    width = np.asarray(teacher.high, dtype=float) - np.asarray(teacher.low, dtype=float)
    out["range_share"] = float(np.mean(np.divide(hi - lo, width, out=np.ones_like(width), where=width > 0)))
    return out


def _spdl(teacher: Any, h: dict[str, np.ndarray], w: dict[str, np.ndarray]) -> dict[str, Any]:
    """SPDL (Klink et al. 2020, Fig. 3-4): the context distribution's mean and standard deviation
    per dimension (box units), its KL divergence to the target, and the expected competence,
    estimated as the mean competence told since its last update (the goals its next update
    weighs; the core does not expose its own importance-weighted estimate)."""
    r = teacher.regions()
    lo, hi = np.asarray(r["low"][0], dtype=float), np.asarray(r["high"][0], dtype=float)
    out: dict[str, Any] = {}
    _per_dimension(out, "mean", (lo + hi) / 2)
    _per_dimension(out, "std", (hi - lo) / 2)
    out["kl_to_target"] = float(r["interest"][0])
    n = int(r["n_measurements"][0])
    if n:
        out["expected_competence"] = float(np.mean(h["told_competence"][-n:]))
    return out


def _mixture(teacher: Any, h: dict[str, np.ndarray], w: dict[str, np.ndarray]) -> dict[str, Any]:
    """ALP-GMM and Covar-GMM (Portelas et al. 2019, Fig. 2; Moulin-Frier et al. 2014): how many
    of the mixture's components drew the window's goals (the core does not expose the components'
    means, covariances or progress; the figure draws each one's goals as an ellipse)."""
    drawn = np.asarray(w["asked_region"])
    return {"components_drawn": int(np.unique(drawn[drawn >= 0]).size)}


def goal_rates(told_goal: np.ndarray, told_competence: np.ndarray, success: float = GOID_SUCCESS) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Each distinct told goal (rounded to float32, as a told goal is matched to the asked one):
    the goals, their numbers of attempts, their success rates (competence >= ``success``) and,
    for each tell, the goal it was."""
    g = np.ascontiguousarray(np.asarray(told_goal, dtype=np.float32))
    if len(g) == 0:
        return g, np.zeros(0, dtype=int), np.zeros(0), np.zeros(0, dtype=int)
    # Each row as one opaque value: np.unique of those is twice as fast as by rows (48 against
    # 113 ms for 100,000 tells of 50,000 goals).
    rows = g.view(np.dtype((np.void, g.dtype.itemsize * g.shape[1]))).ravel()
    _, first, inverse, counts = np.unique(rows, return_index=True, return_inverse=True, return_counts=True)
    goals, inverse = g[first], inverse.ravel()
    wins = np.bincount(inverse, weights=(np.asarray(told_competence) >= success).astype(float), minlength=len(goals))
    return goals, counts, wins / counts, inverse


def attempts_per_goal(asked_goal: np.ndarray) -> int:
    """Goal GAN asks each goal it proposes n_rollouts times in a row: the most common length of
    a run of equal goals in what it asked (1 when nothing was asked)."""
    a = np.asarray(asked_goal)
    if len(a) == 0:
        return 1
    starts = np.flatnonzero(np.r_[True, np.any(a[1:] != a[:-1], axis=1)])
    runs = np.diff(np.r_[starts, len(a)])
    return int(np.bincount(runs[:-1] if len(runs) > 1 else runs).argmax())


def _goal_gan(teacher: Any, h: dict[str, np.ndarray], w: dict[str, np.ndarray]) -> dict[str, Any]:
    """Goal GAN (Florensa et al. 2018, Fig. 2 and 4): the share of goals of intermediate
    difficulty among the goals told in the window that have all their attempts (a goal's rate is
    over all its attempts so far), with the paper's bounds (``GOID_*``; not the teacher's own
    r_min, r_max and success_threshold, which the core does not expose), for competences in
    [0, 1] only."""
    comp = np.asarray(h["told_competence"], dtype=float)
    n_window = len(w["told_goal"])
    if n_window == 0 or comp.min() < 0.0 or comp.max() > 1.0:
        return {}
    _, counts, rates, inverse = goal_rates(h["told_goal"], comp)
    done = counts >= attempts_per_goal(h["asked_goal"])
    recent = np.zeros(len(counts), dtype=bool)
    recent[inverse[len(comp) - n_window :]] = True
    if not (done & recent).any():
        return {}
    r = rates[done & recent]
    return {"goid_share": float(np.mean((r >= GOID_R_MIN) & (r <= GOID_R_MAX))), "labelled": int(done.sum())}


def _task_list(teacher: Any, h: dict[str, np.ndarray], w: dict[str, np.ndarray]) -> dict[str, Any]:
    """The task-list teachers (as PLR's paper plots it, Jiang et al. 2021, Fig. 3): per task, its
    share of the window's draws (the teacher's sampling distribution as drawn: the core does not expose the probabilities it draws from) and the
    last value told for it (PLR's score with ``score="told"``, else its competence; NaN before
    its first tell), and the number of tasks told at least once."""
    n = int(teacher.n_tasks)
    asked = np.asarray(w["asked_goal"], dtype=float).ravel().round().astype(int)
    share = np.bincount(asked, minlength=n)[:n] / max(len(asked), 1)
    told_task = np.asarray(h["told_goal"], dtype=float).ravel().round().astype(int)
    last = np.full(n, np.nan)
    if len(told_task):
        # The last tell of each task: the first of each in the reversed order.
        tasks, first = np.unique(told_task[::-1], return_index=True)
        last[tasks] = np.asarray(h["told_competence"], dtype=float)[len(told_task) - 1 - first]
    out: dict[str, Any] = {"tasks_told": int(np.isfinite(last).sum())}
    for i in range(n):
        out[f"task_{i}/share"] = float(share[i])
        out[f"task_{i}/last_told"] = float(last[i])
    return out


#: The readers by the name a teacher class gives in ``reading``.
_BY_READING = {"tree": _tree, "task_list": _task_list, "mixture": _mixture, "adr": _adr, "spdl": _spdl, "goal_gan": _goal_gan}


#: Each built-in teacher's reader, by the registry's name (from its class's ``reading``).
READERS: dict[str, Callable[[Any, dict[str, np.ndarray], dict[str, np.ndarray]], dict[str, Any]] | None] = {kind: None if cls.reading is None else _BY_READING[cls.reading] for kind, cls in available().items()}
