"""Overhead of a Python environment in the Rust loop, against the built-in arm.

    python benchmarks/bench_python_env.py [--steps 20000] [--paradigm micro_actions|episodic]

Runs the same configuration and seed with the built-in arm and with
`saggriac.bodies.environments.PlanarArm` (the same arm in pure Python: identical results, checked here),
and prints the extra time per call into Python. A Python environment cannot be copied, so the
evaluation's test reaches also run on it; the calls counted are the learning steps plus the test
micro-actions. A benchmark, not a test.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

import saggriac
from saggriac.bodies.environments import PlanarArm


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--steps", type=int, default=20_000)
    p.add_argument("--paradigm", default="micro_actions", choices=["micro_actions", "episodic"])
    a = p.parse_args()
    if a.paradigm == "episodic":
        cfg = saggriac.Config.from_preset("explauto", n_steps=a.steps)
        env = PlanarArm(joint_limit=math.pi)
    else:
        cfg = saggriac.Config.from_preset("exp1", n_steps=a.steps)
        env = PlanarArm()
    t0 = time.perf_counter()
    builtin = saggriac.run(cfg, seed=0)
    t_builtin = time.perf_counter() - t0
    t0 = time.perf_counter()
    python = saggriac.run(cfg, seed=0, environment=env)
    t_python = time.perf_counter() - t0
    same = np.array_equal(builtin.reach_error, python.reach_error) and builtin.goals.equals(python.goals)
    prof = python.manifest["profile"]
    calls = a.steps + prof["test_steps"] + (cfg.n_test_configs if a.paradigm == "micro_actions" else 0)
    print(f"saggriac {saggriac.__version__}, {a.paradigm}, {a.steps} steps, seed 0 (identical results: {same})")
    print(f"built-in arm:      {t_builtin:7.2f} s ({t_builtin / a.steps * 1e6:7.1f} us per learning step)")
    print(f"Python PlanarArm:  {t_python:7.2f} s ({t_python / a.steps * 1e6:7.1f} us per learning step)")
    print(f"calls into the Python environment: {calls} ({a.steps} learning steps, {prof['test_steps']} test steps)")
    print(f"overhead: {(t_python - t_builtin) / calls * 1e6:.1f} us per call")


if __name__ == "__main__":
    main()
