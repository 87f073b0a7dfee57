"""Episodic SAGG-RIAC on the explauto task, 50,000 iterations, timed in one process.

    python benchmarks/bench_episodic.py [--steps 50000] [--seed 0] [--repeats 3] [--condition sagg_riac]

The `explauto` preset: 15 joints, equal links summing to 50, joint limits +-pi, goals in
[-50, 50]^2, test goals uniform in the disk of radius 50; region tree + nearest-neighbour inverse
model with Gaussian exploration noise. Prints the CPU time (`time.process_time`, so a busy
machine inflates it little) of the constructor `Learner(cfg, seed, threads=1)` (it builds the
test set: the least-norm IK of the test configurations) and of `Learner.run()` (its 21
evaluations included), Python start-up and import excluded; the mean reaching error on the 100
test goals; and the ratio to explauto 1.4's times on the development machine (issue 4: 160 s for
its SAGG-RIAC mode, 20 s for random goals, both for 50,000 iterations), for constructor + run
(what `saggriac run` does) and for the loop alone. A benchmark, not a test.
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
    ctor, times, last = [], [], None
    for _ in range(a.repeats):
        # One thread, as the core runs by default: the figures compare with explauto's.
        t0 = time.process_time()
        learner = saggriac.Learner(cfg, a.seed, threads=1)
        t1 = time.process_time()
        learner.run()
        ctor.append(t1 - t0)
        times.append(time.process_time() - t1)
        last = learner.result()
    assert last is not None
    m = {k: last.metrics[k].to_numpy() for k in last.metrics.columns}
    prof = last.manifest["profile"]
    best, med = min(times), statistics.median(times)
    both = statistics.median(c + t for c, t in zip(ctor, times))
    print(f"saggriac {saggriac.__version__} ({_core.GIT_COMMIT[:12]}), Python {platform.python_version()}, {platform.machine()}")
    print(f"explauto preset, condition {a.condition}, seed {a.seed}, {a.steps} iterations, {len(m['step'])} evaluations; CPU seconds")
    print(f"Learner(): median {statistics.median(ctor):.3f} s, best {min(ctor):.3f} s (builds the test set)")
    print(f"Learner.run(): median {med:.3f} s, best {best:.3f} s over {a.repeats} runs ({med / a.steps * 1e6:.2f} us per iteration)")
    print(f"both: median {both:.3f} s")
    print(f"  run's own wall timers: evaluation {prof['time_evaluation']:.3f} s, goal selection and region tree {prof['time_goal_selection']:.3f} s, inverse-model search {prof['time_knn']:.3f} s")
    print(f"mean reaching error on {cfg.n_test_goals} test goals: start {m['reach_error'][0]:.3f}, at {a.steps // 2} {m['reach_error'][len(m['step']) // 2]:.3f}, end {m['reach_error'][-1]:.3f}")
    print(f"mean prediction error (nearest-neighbour forward model): end {m['pred_error'][-1]:.3f}")
    ref = EXPLAUTO_SECONDS.get(a.condition)
    if ref is not None and a.steps == 50_000:
        print(f"explauto 1.4 needed {ref:.0f} s for this on the development machine: {ref / both:,.0f}x faster with the constructor, {ref / med:,.0f}x for the loop alone")


if __name__ == "__main__":
    main()
