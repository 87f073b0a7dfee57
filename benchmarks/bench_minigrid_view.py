"""MiniGrid's observation against saggriac's array view, per rl-minigrid grade, timed in one process.

    python benchmarks/bench_minigrid_view.py [--steps 5000] [--seed 0]

For each grade of the rl-minigrid task, one random walk (all seven actions, a new layout at every
episode's end) is played twice from the same seed: with MiniGrid's own ``gen_obs`` and with
:class:`saggriac.bench.minigrid_view.ArrayView`. Prints the CPU microseconds (``time.process_time``)
per environment step (reset included) of each, their ratio, and whether the two walks saw the same
observations (they must). Needs the minigrid extra. A benchmark, not a test.
"""

from __future__ import annotations

import argparse
import time

import numpy as np


def walk(env, seed: int, steps: int) -> tuple[float, list[bytes]]:
    """CPU seconds for ``steps`` random steps, and a digest of every observation."""
    rng = np.random.default_rng(seed)
    seen = []
    start = time.process_time()
    obs, _ = env.reset(seed=int(rng.integers(1 << 30)))
    for _ in range(steps):
        obs, _, term, trunc, _ = env.step(int(rng.integers(env.action_space.n)))
        seen.append(obs["image"].tobytes())
        if term or trunc:
            obs, _ = env.reset(seed=int(rng.integers(1 << 30)))
    return time.process_time() - start, seen


def main() -> None:
    from minigrid.minigrid_env import MiniGridEnv

    from saggriac.bench.minigrid import GRADES, _grade_env

    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--steps", type=int, default=5000)
    p.add_argument("--seed", type=int, default=0)
    a = p.parse_args()
    print("| grade | MiniGrid's gen_obs (us a step) | array view (us a step) | ratio | same observations |")
    print("|---|---|---|---|---|")
    for g, grade in enumerate(GRADES):
        own = _grade_env(g)
        own.gen_obs = MiniGridEnv.gen_obs.__get__(own)  # MiniGrid's way, on the same level
        slow, a_seen = walk(own, a.seed, a.steps)
        fast, b_seen = walk(_grade_env(g), a.seed, a.steps)
        print(f"| {g} {grade} | {slow / a.steps * 1e6:.0f} | {fast / a.steps * 1e6:.0f} | {slow / fast:.2f} | {a_seen == b_seen} |")


if __name__ == "__main__":
    main()
