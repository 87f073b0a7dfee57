"""Episodic SAGG-RIAC on the explauto task, 50,000 iterations, timed in one process.

    python benchmarks/bench_episodic.py [--steps 50000] [--seed 0] [--repeats 3] [--condition sagg_riac]

The `explauto` preset: 15 joints, equal links summing to 50, joint limits +-pi, goals in
[-50, 50]^2, test goals uniform in the disk of radius 50; region tree + nearest-neighbour inverse
model with Gaussian exploration noise. Prints the time of `Learner.run()` alone (its 21
evaluations included, Python start-up and import excluded), the mean reaching error on the 100
test goals, and the ratio to explauto 1.4's times on the development machine (issue 4: 160 s for
its SAGG-RIAC mode, 20 s for random goals, both for 50,000 iterations). A benchmark, not a test.
"""

from __future__ import annotations

import argparse
import platform
import statistics
import time

import saggriac
from saggriac import _core

EXPLAUTO_SECONDS = {"sagg_riac": 160.0, "sagg_random": 20.0}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--steps", type=int, default=50_000)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--condition", default="sagg_riac")
    a = p.parse_args()
    cfg = saggriac.Config.from_preset("explauto", n_steps=a.steps, condition=a.condition)
    times, last = [], None
    for _ in range(a.repeats):
        # One thread, as the core runs by default: the figures compare with explauto's.
        learner = saggriac.Learner(cfg, a.seed, threads=1)
        t0 = time.perf_counter()
        learner.run()
        times.append(time.perf_counter() - t0)
        last = learner.result()
    m = {k: last.metrics[k].to_numpy() for k in last.metrics.columns}
    prof = last.manifest["profile"]
    best, med = min(times), statistics.median(times)
    print(f"saggriac {saggriac.__version__} ({_core.GIT_COMMIT[:12]}), Python {platform.python_version()}, {platform.machine()}")
    print(f"explauto preset, condition {a.condition}, seed {a.seed}, {a.steps} iterations, {len(m['step'])} evaluations")
    print(f"Learner.run(): median {med:.3f} s, best {best:.3f} s over {a.repeats} runs ({med / a.steps * 1e6:.2f} us per iteration)")
    print(f"  of which evaluation {prof['time_evaluation']:.3f} s, goal selection and region tree {prof['time_goal_selection']:.3f} s, inverse-model search {prof['time_knn']:.3f} s")
    print(f"mean reaching error on {cfg.n_test_goals} test goals: start {m['reach_error'][0]:.3f}, at {a.steps // 2} {m['reach_error'][len(m['step']) // 2]:.3f}, end {m['reach_error'][-1]:.3f}")
    print(f"mean prediction error (nearest-neighbour forward model): end {m['pred_error'][-1]:.3f}")
    ref = EXPLAUTO_SECONDS.get(a.condition)
    if ref is not None and a.steps == 50_000:
        print(f"explauto 1.4 needed {ref:.0f} s for this on the development machine: {ref / med:,.0f}x faster (target 300x)")


if __name__ == "__main__":
    main()
