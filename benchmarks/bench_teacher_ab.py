"""Two builds' mixture teachers side by side (issue 49 item 4): `bench_teacher_bits.py` run by
each build's Python in turn, in rounds, every run a row of a CSV.

    python benchmarks/bench_teacher_ab.py --old OLD/bin/python --new NEW/bin/python \
        --out docs/figures/performance/teacher_ab_mix49.csv [--rounds 4] [--old-path DIR]
    python benchmarks/bench_teacher_ab.py --analyse docs/figures/performance/teacher_ab_mix49.csv

Each round runs every case (2-D 6,000 updates and 10-D 2,500, ALP-GMM and Covar-GMM) with the
old build then the new (odd rounds) or the new then the old (even rounds), in separate
processes with PYTHONPATH unset (or set to `--old-path` / `--new-path`: a folder holding a
`saggriac` package with its compiled `_core`, for a build whose installed package no longer
matches its extension), and records each run's CPU and wall microseconds per sample +
update, the goals' hash and the 1-minute load average when it started. `--analyse` prints, per
case, the old/new ratios of each round (> 1: new faster), their median, and whether every run
of the case drew the same goals. A benchmark, not a test.
"""

from __future__ import annotations

import argparse
import csv
import os
import re
import statistics
import subprocess
import sys
from pathlib import Path

CASES = [(2, 6000, "AlpGmmSelector"), (2, 6000, "CovarGmmSelector"), (10, 2500, "AlpGmmSelector"), (10, 2500, "CovarGmmSelector")]
FIELDS = ["round", "build", "dim", "updates", "selector", "cpu_us", "wall_us", "goals_sha256", "load1"]
LINE = re.compile(r": ([\d.]+) us per sample \+ update, goals sha256 (\w+), wall ([\d.]+) us")


def one(python: str, path: str | None, d: int, n: int, name: str) -> tuple[float, float, str]:
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    if path:
        env["PYTHONPATH"] = path
    script = Path(__file__).with_name("bench_teacher_bits.py")
    out = subprocess.run([python, str(script), str(d), str(n), name], env=env, capture_output=True, text=True, check=True).stdout
    m = LINE.search(out)
    if m is None:
        raise SystemExit(f"unexpected output of {python}: {out!r}")
    return float(m.group(1)), float(m.group(3)), m.group(2)


def run(args: argparse.Namespace) -> None:
    out = Path(args.out)
    new_file = not out.exists()
    done = 0
    if not new_file:
        with out.open(newline="") as f:
            done = max((int(r["round"]) for r in csv.DictReader(f)), default=0)
    with out.open("a", newline="") as f:
        w = csv.DictWriter(f, FIELDS)
        if new_file:
            w.writeheader()
        for rnd in range(done + 1, done + args.rounds + 1):
            old, new = ("old", args.old, args.old_path), ("new", args.new, args.new_path)
            order = [old, new] if rnd % 2 else [new, old]
            for d, n, name in CASES:
                for build, python, path in order:
                    load1 = os.getloadavg()[0]
                    cpu, wall, sha = one(python, path, d, n, name)
                    w.writerow({"round": rnd, "build": build, "dim": d, "updates": n, "selector": name, "cpu_us": cpu, "wall_us": wall, "goals_sha256": sha, "load1": f"{load1:.2f}"})
                    f.flush()
                    print(f"round {rnd} {build} {name} d={d}: cpu {cpu} wall {wall} us, {sha}, load {load1:.2f}", flush=True)


def analyse(path: str) -> None:
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    loads = [float(r["load1"]) for r in rows]
    print(f"{len(rows)} runs, load average (1 min) {min(loads):.1f}-{max(loads):.1f}, median {statistics.median(loads):.1f}")
    for d, n, name in CASES:
        case = [r for r in rows if int(r["dim"]) == d and r["selector"] == name]
        same = len({r["goals_sha256"] for r in case}) == 1
        for measure in ("cpu_us", "wall_us"):
            ratios = []
            for rnd in sorted({int(r["round"]) for r in case}):
                by = {r["build"]: float(r[measure]) for r in case if int(r["round"]) == rnd}
                ratios.append(by["old"] / by["new"])
            med = statistics.median(ratios)
            print(f"{name} d={d} n={n} {measure[:-3]}: old/new per round {' '.join(f'{x:.2f}' for x in ratios)}, median {med:.2f}; same goals in every run: {same}")


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--old")
    p.add_argument("--new")
    p.add_argument("--old-path")
    p.add_argument("--new-path")
    p.add_argument("--out")
    p.add_argument("--rounds", type=int, default=4)
    p.add_argument("--analyse")
    a = p.parse_args()
    if a.analyse:
        analyse(a.analyse)
    elif a.old and a.new and a.out:
        run(a)
    else:
        sys.exit("give --old, --new and --out, or --analyse CSV")


if __name__ == "__main__":
    main()
