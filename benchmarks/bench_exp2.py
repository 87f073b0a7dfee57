"""End-to-end speed of one exp2 run (the paper's second experiment), one core.

    python benchmarks/bench_exp2.py [--steps 200000] [--seed 0] [--knn-index blocks] [--set KEY=VALUE ...]

Prints micro-actions per second, where the time goes (kNN, local fits, region tree and goal
selection, evaluation), the learning curve it produced and the final errors. A benchmark, not a
test: numbers depend on the machine; compare runs made on the same machine in one session.
"""

from __future__ import annotations

import argparse
import platform
import time

import saggriac
from saggriac.cli import parse_overrides


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--preset", default="exp2")
    p.add_argument("--steps", type=int, default=None)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--knn-index", default="blocks", choices=["blocks", "brute_force"])
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    args = p.parse_args()
    overrides = parse_overrides(args.set)
    overrides["knn_index"] = args.knn_index
    if args.steps is not None:
        overrides["n_steps"] = args.steps
    cfg = saggriac.Config.from_preset(args.preset, **overrides)

    t0 = time.perf_counter()
    res = saggriac.run(cfg, seed=args.seed)
    wall = time.perf_counter() - t0
    prof = res.manifest["profile"]
    learn = prof["time_total"] - prof["time_evaluation"]
    n = cfg.n_steps
    print(f"saggriac {saggriac.__version__} ({res.manifest['git_commit'][:12]}), Python {platform.python_version()}, {platform.machine()}")
    print(f"preset {args.preset}, condition {cfg.condition}, seed {args.seed}, knn_index {cfg.knn_index}, {n} micro-actions")
    print(f"wall time (run + {len(res.steps)} evaluations): {wall:.2f} s")
    print(f"micro-actions per second, learning only: {n / learn:,.0f}  ({learn / n * 1e6:.1f} us per micro-action)")
    print(f"micro-actions per second, with evaluations: {n / wall:,.0f}")
    print(f"stored samples at the end: {int(res.metrics['n_samples'].iloc[-1])}")
    print("time split (s):")
    other = learn - prof["time_knn"] - prof["time_fit"] - prof["time_goal_selection"]
    for name, v in [("kNN (learning)", prof["time_knn"]), ("local fits + J+ (learning)", prof["time_fit"]), ("region tree + goal selection", prof["time_goal_selection"]), ("arm, memory inserts, rest of loop", other), ("evaluation (all points)", prof["time_evaluation"])]:
        print(f"  {name:36s} {v:8.3f}  ({100 * v / prof['time_total']:5.1f} %)")
    print(f"micro-actions: {prof['reaching_steps']} reaching, {prof['exploration_steps']} exploration ({prof['explorations']} phases); test micro-actions in evaluation: {prof['test_steps']}")
    us_test = prof["time_evaluation"] / max(prof["test_steps"], 1) * 1e6
    print(f"evaluation cost: {us_test:.1f} us per test micro-action (kNN + fit + J+ on the scratch arm)")
    print("learning curve (step, reaching error, prediction error, goals, regions):")
    for _, r in res.metrics.iterrows():
        print(f"  {int(r.step):>7} {r.reach_error:9.3f} {r.pred_error:9.3f} {int(r.n_goals):>6} {int(r.n_regions):>5}")
    print(f"final reaching error {res.final_reach_error:.3f}, final prediction error {res.final_pred_error:.3f}")


if __name__ == "__main__":
    main()
