"""One teacher's CPU per sample + update, and a hash of the goals it drew (to compare builds).

    python benchmarks/bench_teacher_bits.py DIM UPDATES SELECTOR

SELECTOR is a class of saggriac (AlpGmmSelector, CovarGmmSelector, ...), built on [0, 1]^DIM with
seed 3 and told a cheap, deterministic competence of each goal through `sample()` then
`update()`. Prints microseconds of CPU (`time.process_time`) per sample + update and the first
16 hex digits of the sha-256 of every goal drawn: two builds that give the same hash drew the
same goals bit for bit. Also prints the wall time per sample + update (`time.perf_counter`):
the mixtures' refits run on several threads (issue 49), which the CPU time counts as spent
and only the wall time shows as saved. Run it with PYTHONPATH set to each build's folder, alternating, to
compare speed (issue 37: `docs/performance.md`). A benchmark, not a test.
"""

from __future__ import annotations

import hashlib
import sys
import time

import numpy as np

import saggriac as sg


def main() -> None:
    d, n, name = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
    teacher = getattr(sg, name)([0.0] * d, [1.0] * d, seed=3)
    h = hashlib.sha256()
    t0, w0 = time.process_time(), time.perf_counter()
    for i in range(n):
        g = np.asarray(teacher.sample())
        c = float(np.clip(g[0] * 0.7 + 0.3 * np.sin(7 * g[1]) + 0.001 * (i % 97), 0, 1))
        teacher.update(g, c)
        h.update(g.tobytes())
    cpu, wall = time.process_time() - t0, time.perf_counter() - w0
    print(f"{name} d={d} n={n}: {cpu / n * 1e6:.1f} us per sample + update, goals sha256 {h.hexdigest()[:16]}, wall {wall / n * 1e6:.1f} us")


if __name__ == "__main__":
    main()
