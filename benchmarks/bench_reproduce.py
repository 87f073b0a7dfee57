"""The full reproduction, timed: `saggriac reproduce` for each experiment at full scale.

    python benchmarks/bench_reproduce.py [--experiments exp1 exp2] [--seeds 15] [--first-seed 0] [--workers N] [--out DIR]

Runs `saggriac reproduce EXPERIMENT --seeds N` as a user would (a fresh study folder per
experiment, in a temporary folder unless --out is given), and prints for each experiment its
wall time and CPU time (the study's worker processes included), and for each condition the sum
and mean of its runs' own times (run.json `wall_seconds`: each study run uses one thread, so
this is its CPU time). A benchmark, not a test: issue 13's target is exp1 + exp2 together in at
most 10 minutes of wall time on a 2-core machine.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from collections import defaultdict
from pathlib import Path


def cpu_seconds() -> float:
    """CPU time of this process and of its finished children (the study's workers)."""
    own = resource.getrusage(resource.RUSAGE_SELF)
    kids = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + kids.ru_utime + kids.ru_stime


def per_condition(study: Path) -> dict[str, list[float]]:
    out: dict[str, list[float]] = defaultdict(list)
    for f in study.rglob("run.json"):
        m = json.loads(f.read_text())
        out[m["config"]["condition"]].append(m["wall_seconds"])
    return out


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--experiments", nargs="+", default=["exp1", "exp2"])
    p.add_argument("--seeds", type=int, default=15)
    p.add_argument("--first-seed", type=int, default=0, help="seeds FIRST..FIRST+N-1 (default 0; 15 replicates on a second, independent set)")
    p.add_argument("--workers", type=int, default=None, help="worker processes (default: the CLI's, all cores)")
    p.add_argument("--out", default=None, help="keep the study folders here (default: a temporary folder, removed)")
    a = p.parse_args()
    base = Path(a.out) if a.out else Path(tempfile.mkdtemp(prefix="bench-reproduce-"))
    print(f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}")
    # The CLI a user types, from this Python's environment.
    saggriac = shutil.which("saggriac", path=str(Path(sys.executable).parent)) or "saggriac"
    total_wall = total_cpu = 0.0
    for exp in a.experiments:
        study = base / f"reproduce-{exp}"
        cmd = [saggriac, "reproduce", exp, "--seeds", str(a.seeds), "--first-seed", str(a.first_seed), "--out", str(study), "--no-progress"]
        if a.workers is not None:
            cmd += ["--workers", str(a.workers)]
        c0, t0 = cpu_seconds(), time.perf_counter()
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
        wall, cpu = time.perf_counter() - t0, cpu_seconds() - c0
        total_wall += wall
        total_cpu += cpu
        print(f"\n{exp}: wall {wall:.1f} s, CPU {cpu:.1f} s (saggriac {' '.join(cmd[1:])})")
        print(f"  {'condition':16s} {'runs':>4s} {'sum s':>8s} {'mean s':>7s}")
        for cond, secs in sorted(per_condition(study).items()):
            print(f"  {cond:16s} {len(secs):>4d} {sum(secs):>8.1f} {sum(secs) / len(secs):>7.2f}")
    print(f"\nall: wall {total_wall:.1f} s ({total_wall / 60:.1f} min), CPU {total_cpu:.1f} s")
    if a.out is None:
        shutil.rmtree(base, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
