"""Sample + update throughput of every teacher, one at a time and in batches.

    python benchmarks/bench_teachers.py [--updates 1000000] [--batch 4096] [--dims 2 10] [--teachers ...]

For each teacher and each task-space dimension, times `--updates` rounds of sample + update
through the Python API: one goal at a time (`sample()` then `update()`), and in batches
(`sample_batch(B)` then `update_batch(goals, competences)`). The competence is a cheap function
of the goal (a smooth slope plus a plateau), computed with numpy outside the timed teacher
calls; the discrete teacher gets success rates of 8 tasks. Prints microseconds per sample +
update and updates per second. Single calls are capped at `--single-cap` rounds (their cost per
round does not depend on the count). A benchmark, not a test: the mixture teachers refit every
`fit_rate` updates, which dominates their cost. `sagg_riac_w` is SAGG-RIAC with saggriac 0.2's
reading of eq. 2 (`interest_divisor="window"`), not in the default list.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import saggriac as sg


# The competences below lie in [-1, 0]: the thresholds of these teachers on that scale, so
# that they move; saggriac 0.2's reading of eq. 2 as an extra row.
SETTINGS = {"spdl": {"delta": -0.5}, "goal_gan": {"success_threshold": -0.5}}
VARIANTS = {"sagg_riac_w": ("sagg_riac", {"interest_divisor": "window"})}


def make(name: str, d: int, seed: int):
    """Any registered teacher by name (over [0, 1]^d, or 8 tasks for a task-list teacher), or a
    variant of one."""
    kind, params = VARIANTS.get(name, (name, SETTINGS.get(name, {})))
    return sg.testing.example_teacher(kind, seed=seed, dim=d, n_tasks=8, **params)


def is_task_list(name: str) -> bool:
    kind = VARIANTS.get(name, (name,))[0]
    return "tasks" in sg.teachers.available()[kind].spaces


def competence(goals: np.ndarray, discrete: bool) -> np.ndarray:
    if discrete:
        return (goals[:, 0] / 8.0).clip(0, 1)
    return np.clip(-np.abs(goals - 0.3).mean(axis=1) * 2.0, -1.0, 0.0)


def timed(name: str, d: int, n: int, batch: int) -> float:
    t = make(name, d, 0)
    discrete = is_task_list(name)
    # Goal GAN labels a goal by its success rate over repeated tries: a competence that is a
    # function of the goal gives rates 0 or 1 only, and its GAN would never train (nor be timed).
    noise = np.random.default_rng(0) if name == "goal_gan" else None

    def told(g: np.ndarray) -> np.ndarray:
        c = competence(g, discrete)
        return c if noise is None else np.clip(c + noise.normal(0.0, 0.3, len(c)), -1.0, 0.0)

    spent = 0.0
    done = 0
    while done < n:
        b = min(batch, n - done)
        start = time.perf_counter()
        if batch == 1:
            g = t.sample()
            spent += time.perf_counter() - start
            c = float(told(g[None, :])[0])
            start = time.perf_counter()
            t.update(g, c)
        else:
            g = t.sample_batch(b)
            spent += time.perf_counter() - start
            c = told(g)
            start = time.perf_counter()
            t.update_batch(g, c)
        spent += time.perf_counter() - start
        done += b
    return spent / n


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--updates", type=int, default=1_000_000)
    p.add_argument("--single-cap", type=int, default=100_000)
    p.add_argument("--batch", type=int, default=4096)
    p.add_argument("--dims", type=int, nargs="+", default=[2, 10])
    p.add_argument("--teachers", nargs="+", default=list(sg.teachers.available()))
    a = p.parse_args()
    print(f"{'teacher':12} {'dim':>4} {'mode':>8} {'updates':>9} {'us/update':>10} {'updates/s':>11}")
    for name in a.teachers:
        for d in a.dims if not is_task_list(name) else [1]:
            for batch, n in ((1, min(a.updates, a.single_cap)), (a.batch, a.updates)):
                per = timed(name, d, n, batch)
                mode = "single" if batch == 1 else f"x{batch}"
                print(f"{name:12} {d:4d} {mode:>8} {n:9d} {per * 1e6:10.2f} {1 / per:11,.0f}", flush=True)


if __name__ == "__main__":
    main()
