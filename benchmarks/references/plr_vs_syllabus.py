"""PLR (saggriac) against Syllabus's PLR TaskSampler (syllabus-rl 0.7), state by state.

Distribution: our teacher draws every level and is told a score; Syllabus's sampler is forced
through the same draws (its staleness update, as its own draw makes it) and the same scores
(``update_task_score``). Before each draw, our probability of each level at that draw
(``PlrSelector.probabilities()``) is compared with Syllabus's: uniform over the unseen levels
before its fill threshold ``rho`` is reached, then ``replay_prob`` (1 once every level is seen)
times ``sample_weights()`` plus the rest uniform over the unseen levels. Each scenario prints the
largest absolute difference over all its states and levels.

Syllabus ranks scores with ``scores.argsort()``, reversed. Which of a tied group takes which
rank is numpy's sort order; with a stable sort that is the later level first, the rule ours
follows (``ties="order"``). numpy's default sort is not stable (on machines with AVX-512 it
orders ties by its vectorised sort), so each scenario is compared twice: against Syllabus with
its scores' ``argsort`` made stable (nothing else changed), and against Syllabus as installed.

Speed: sample + update through each Python API, interleaved blocks in one sitting.

    python benchmarks/references/plr_vs_syllabus.py            # needs the syllabus extra
"""

from __future__ import annotations

import time
from typing import Callable

import numpy as np
from syllabus.curricula.plr.task_sampler import TaskSampler

import saggriac as sg


class _StableArgsort(np.ndarray):
    """Syllabus's score array with a stable ``argsort``: ties in the order of the levels."""

    def argsort(self, *args, **kwargs):  # noqa: ANN002, ANN003, ANN201 - numpy's signature
        return np.asarray(self).argsort(kind="stable")


def syllabus_sampler(n: int, *, temperature: float = 0.1, staleness_coef: float = 0.1, replay_prob: float = 0.0, stable: bool = True) -> TaskSampler:
    """Syllabus's sampler with the paper's transforms and the ``fixed`` schedule: replays once
    one level in n is seen (rho = 1/n), with probability ``replay_prob``, always once all are
    (``replay_prob=0``: every level once, then replays only)."""
    s = TaskSampler(tasks=list(range(n)), num_steps=1, num_actors=1, strategy="value_l1", replay_schedule="fixed", score_transform="rank", temperature=temperature, rho=1.0 if replay_prob == 0 else 1.0 / n, replay_prob=replay_prob, alpha=1.0, staleness_coef=staleness_coef, staleness_transform="power", staleness_temperature=1.0)
    if stable:
        s.task_scores = s.task_scores.view(_StableArgsort)
    return s


def ours(n: int, seed: int, *, temperature: float = 0.1, staleness_coef: float = 0.1, replay_prob: float = 0.0) -> sg.PlrSelector:
    """Ours with the same schedule: ``fixed`` replays with probability ``replay_prob`` once a level
    is seen, always once all are."""
    return sg.PlrSelector(n, seed=seed, score="told", replay_schedule="fixed", replay_prob=replay_prob, temperature=temperature, staleness_coef=staleness_coef)


def syllabus_next(s: TaskSampler) -> np.ndarray:
    """The probability of each level at Syllabus's next draw (its ``sample()`` without an
    evaluator: new levels until ``rho`` is reached, then a replay with probability
    ``replay_prob``, 1 once every level is seen)."""
    unseen = s.unseen_task_weights > 0
    new = unseen / unseen.sum() if unseen.any() else np.zeros(len(unseen))
    if s._proportion_filled < s.rho:
        return new
    q = 1.0 if not unseen.any() else s.replay_prob
    return q * np.asarray(s.sample_weights(), dtype=np.float64) + (1 - q) * new


def compare(n: int, draws: int, scores: Callable[[np.random.Generator, int], float], seed: int = 0, **kw: float) -> tuple[float, float, int]:
    """Our draws and scores forced on Syllabus's sampler (stable sort, and as installed): the
    largest |difference| of the next draw's probabilities over every state, for each, and how
    many levels were drawn right after themselves."""
    t = ours(n, seed, **kw)
    stable, installed = syllabus_sampler(n, **kw), syllabus_sampler(n, stable=False, **kw)
    rng = np.random.default_rng(seed)
    worst, worst_installed, repeats, last = 0.0, 0.0, 0, -1
    for _ in range(draws):
        p = t.probabilities()
        worst = max(worst, float(np.abs(p - syllabus_next(stable)).max()))
        worst_installed = max(worst_installed, float(np.abs(p - syllabus_next(installed)).max()))
        k = t.sample_task()
        repeats += k == last
        last = k
        score = float(np.float32(scores(rng, k)))  # Syllabus keeps scores in float32
        t.update(k, score)
        for s in (stable, installed):
            s._update_staleness(k)
            s.update_task_score(0, k, score, score, 1, running_mean=True)
    return worst, worst_installed, repeats


#: name, levels, draws, score of a drawn level, parameters: the states ours and Syllabus differed
#: on before issue 46 (ties, zero scores beside unseen levels, staleness), and distinct scores.
SCENARIOS: list[tuple[str, int, int, Callable[[np.random.Generator, int], float], dict[str, float]]] = [
    ("distinct scores, 20 levels", 20, 2000, lambda r, k: r.uniform(0, 1), {}),
    ("ties: scores in {0, 0.5, 1}", 20, 2000, lambda r, k: r.integers(0, 3) / 2, {}),
    ("ties, temperature 1", 20, 2000, lambda r, k: r.integers(0, 3) / 2, {"temperature": 1.0}),
    ("unseen levels beside zero scores, replay_prob 0.5", 30, 2000, lambda r, k: r.choice([0.0, 0.0, 0.5, 1.0]), {"replay_prob": 0.5}),
    ("negative scores beside unseen levels, replay_prob 0.5", 30, 2000, lambda r, k: r.choice([-1.0, -0.5, 0.0, 0.5]), {"replay_prob": 0.5}),
    ("staleness only (coefficient 1), 10 levels", 10, 2000, lambda r, k: r.uniform(0, 1), {"staleness_coef": 1.0}),
    ("staleness 0.5, 3 levels, ties", 3, 2000, lambda r, k: r.integers(0, 2) / 2, {"staleness_coef": 0.5}),
]


def timing(n: int, reps: int = 5, block: int = 4000, seed: int = 1) -> dict[str, float]:
    rng = np.random.default_rng(seed)
    scores = rng.uniform(0, 1, 200_000)
    res: dict[str, list[float]] = {"ours": [], "syllabus": []}
    t, s = ours(n, seed), syllabus_sampler(n, stable=False)
    # Warm both past the unseen phase.
    for i in range(n):
        k = t.sample_task()
        t.update(k, scores[i])
        k = s.sample()
        s.update_task_score(0, k, scores[i], scores[i], 1, running_mean=True)
    j = n
    for _ in range(reps):
        a = time.perf_counter()
        for i in range(block):
            k = t.sample_task()
            t.update(k, scores[j + i])
        res["ours"].append((time.perf_counter() - a) / block * 1e6)
        a = time.perf_counter()
        for i in range(block // 10):
            k = s.sample()
            s.update_task_score(0, k, scores[j + i], scores[j + i], 1, running_mean=True)
        res["syllabus"].append((time.perf_counter() - a) / (block // 10) * 1e6)
        j += block
    return {k: float(np.median(v)) for k, v in res.items()}


def main() -> None:
    print("largest |difference| of the next draw's probabilities, over every state and level")
    print(f"{'scenario':56s} {'states':>6s} {'Syllabus, stable sort':>22s} {'Syllabus as installed':>22s} {'same level twice':>17s}")
    for name, n, draws, scores, kw in SCENARIOS:
        worst, installed, repeats = compare(n, draws, scores, **kw)
        print(f"{name:56s} {draws:6d} {worst:22.2e} {installed:22.2e} {repeats:17d}")
    tied = np.random.default_rng(0).integers(0, 3, 20).astype(np.float32)
    print(f"(same level twice: our draws equal to the draw before. numpy {np.__version__}: its default argsort keeps 20 tied scores in order here: {np.array_equal(tied.argsort(), tied.argsort(kind='stable'))})")
    print("time per sample + update (us, median of 5 interleaved blocks)")
    for n in (10, 100, 1000):
        r = timing(n)
        print(f"n = {n:5d}: ours {r['ours']:.2f} us, Syllabus {r['syllabus']:.1f} us, ratio {r['syllabus'] / r['ours']:.0f}x")


if __name__ == "__main__":
    main()
