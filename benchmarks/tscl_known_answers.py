"""TSCL on the task lists of tests/teachers/test_tscl.py, printed as numbers: the means the
tests compare with their bounds, for both variants and both policies.

    python benchmarks/tscl_known_answers.py [--seeds 10]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import saggriac  # noqa: E402
from tests.teachers.test_tscl import Uniform, forgetting, noisy, unlocking  # noqa: E402


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--seeds", type=int, default=10)
    seeds = range(p.parse_args().seeds)
    print(f"seeds 0-{len(seeds) - 1}; steps to master a hard-gated chain of 6 tasks, uniform: {np.mean([unlocking(Uniform(6, s)) for s in seeds]):.1f}")
    for variant in ("window", "sampling"):
        for policy in ("epsilon_greedy", "boltzmann"):
            steps = np.mean([unlocking(saggriac.TsclSelector(6, seed=s, variant=variant, policy=policy)) for s in seeds])
            print(f"{variant:8s} {policy:14s} chain steps {steps:6.1f}")
        for sd in (0.02, 0.3):
            share = np.mean([noisy(saggriac.TsclSelector(2, seed=s, variant=variant), s, sd) for s in seeds])
            print(f"{variant:8s} noisy task (sd {sd}): share of goals {share:.3f}")
        kept = np.mean([forgetting(saggriac.TsclSelector(3, seed=s, variant=variant)) for s in seeds])
        signed = np.mean([forgetting(saggriac.TsclSelector(3, seed=s, variant=variant, absolute=False)) for s in seeds])
        print(f"{variant:8s} forgetting: least-known task's mean score {kept:.3f} by |progress|, {signed:.3f} signed")


if __name__ == "__main__":
    main()
