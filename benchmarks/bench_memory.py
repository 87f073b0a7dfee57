"""Memory per stored sample, with 1,000,000 samples at n = 15 (issue 13: at most 300; 360 since
issue 49 item 2).

    python benchmarks/bench_memory.py [--samples 1000000] [--joints 15]

Builds and runs the Rust example `memory_probe`, which stores a random walk in the sensorimotor
memory (sample arrays plus the block index) and reports the growth of its resident memory per
sample. The stated bound is 360 bytes per sample at n = 15 (docs/performance.md); the script
says whether it holds. A benchmark, not a test.
"""

from __future__ import annotations

import argparse
import re
import subprocess
import sys

BOUND = {15: 360}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--samples", type=int, default=1_000_000)
    p.add_argument("--joints", type=int, default=15)
    a = p.parse_args()
    cmd = ["cargo", "run", "--quiet", "--release", "-p", "saggriac-core", "--example", "memory_probe", "--", str(a.samples), str(a.joints)]
    out = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout.strip()
    print(out)
    per = float(re.search(r"([\d.]+) bytes per sample", out).group(1))
    bound = BOUND.get(a.joints)
    if bound is not None:
        print(f"bound {bound} bytes per sample at n = {a.joints}: {'holds' if per <= bound else 'EXCEEDED'}")
        if per > bound:
            sys.exit(1)


if __name__ == "__main__":
    main()
