"""The new teachers' costs at their limits (issue 44, item 5): the numbers behind SPDL's bound on
its dimension and ADR's eviction of pending boundary samples.

    python benchmarks/bench_teacher_limits.py spdl 10 20 30
    python benchmarks/bench_teacher_limits.py adr 1500000 2200000 10000000

`spdl D...`: CPU seconds of 300 `sample()` + `update(goal, 0.5)` in [0, 1]^D (seed 1; with the
defaults, two COBYLA updates). `adr N...`: CPU seconds of `AdrSelector([0, 0], [1, 1])
.sample_batch(N)` (past 10^6 pending boundary samples the oldest are forgotten), with the first
16 hex digits of the goals' sha-256, to compare builds. A benchmark, not a test.
"""

from __future__ import annotations

import hashlib
import sys
import time

import numpy as np

import saggriac as sg


def main() -> None:
    what, sizes = sys.argv[1], [int(v) for v in sys.argv[2:]]
    for n in sizes:
        t0 = time.process_time()
        if what == "spdl":
            t = sg.SpdlSelector(np.zeros(n), np.ones(n), seed=1)
            for _ in range(300):
                t.update(t.sample(), 0.5)
            print(f"SPDL d={n}: 300 updates {time.process_time() - t0:.2f} s CPU", flush=True)
        else:
            goals = sg.AdrSelector([0, 0], [1, 1]).sample_batch(n)
            digest = hashlib.sha256(goals.tobytes()).hexdigest()[:16]
            print(f"ADR sample_batch({n}): {time.process_time() - t0:.2f} s CPU, goals sha256 {digest}", flush=True)


if __name__ == "__main__":
    main()
