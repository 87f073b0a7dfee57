"""Two builds of saggriac side by side: CPU time of the same runs, interleaved, as ratios.

    python benchmarks/bench_ab.py --old DIR --new DIR [--case exp2:sagg_riac ...] [--reps 3]

DIR is a folder holding a `saggriac` package (the Python code with its compiled `_core`), such
as a worktree's `python/` or a copy of an installed wheel's package. One long-lived worker
process per build (imports paid once) runs each case in turn: rep 1 old then new, later reps
new then old. A case is `PRESET:CONDITION[:N_EVALS]` (full scale, seed 0, one thread; N_EVALS=1
evaluates at the start and the end only) and is timed as `Learner(cfg, 0, threads=1)` plus
`Learner.run()`, each by `time.process_time()` (CPU, not wall: the machine may be busy).
Prints per case the CPU seconds of each build, the speed ratio old/new pair by pair (> 1: the
new build is faster) and both final reaching errors, which show whether the work was the same.
A benchmark, not a test.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys

WORKER = r"""
import json, sys, time
import saggriac
for line in sys.stdin:
    case = json.loads(line)
    kw = {"condition": case["condition"]}
    if case.get("n_evals"):
        kw["n_evals"] = case["n_evals"]
    cfg = saggriac.Config.from_preset(case["preset"], **kw)
    t0 = time.process_time()
    learner = saggriac.Learner(cfg, case.get("seed", 0), threads=1)
    t1 = time.process_time()
    learner.run()
    t2 = time.process_time()
    res = learner.result()
    out = {"ctor": t1 - t0, "run": t2 - t1, "final": float(res.final_reach_error), "file": saggriac.__file__}
    print(json.dumps(out), flush=True)
"""


def worker(path: str) -> subprocess.Popen:
    env = dict(os.environ, PYTHONPATH=path, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
    return subprocess.Popen([sys.executable, "-c", WORKER], stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True, env=env)


def ask(p: subprocess.Popen, case: dict) -> dict:
    assert p.stdin is not None and p.stdout is not None
    p.stdin.write(json.dumps(case) + "\n")
    p.stdin.flush()
    return json.loads(p.stdout.readline())


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--old", required=True)
    ap.add_argument("--new", required=True)
    ap.add_argument("--case", action="append", default=None)
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--seed", type=int, default=0)
    a = ap.parse_args()
    cases = a.case or ["exp2:sagg_riac"]
    builds = {"old": worker(a.old), "new": worker(a.new)}
    for spec in cases:
        parts = spec.split(":")
        case = {"preset": parts[0], "condition": parts[1], "seed": a.seed}
        if len(parts) > 2:
            case["n_evals"] = int(parts[2])
        got: dict[str, list[dict]] = {"old": [], "new": []}
        for rep in range(a.reps):
            for b in ("old", "new") if rep == 0 else ("new", "old"):
                got[b].append(ask(builds[b], case))
        tot = {b: [r["ctor"] + r["run"] for r in got[b]] for b in got}
        ratios = [o / n for o, n in zip(tot["old"], tot["new"])]
        print(f"{spec}: CPU s old {' '.join(f'{t:.3f}' for t in tot['old'])} | new {' '.join(f'{t:.3f}' for t in tot['new'])}")
        ctor = {b: statistics.median(r["ctor"] for r in got[b]) for b in got}
        print(f"  constructor median old {ctor['old']:.3f} new {ctor['new']:.3f} ({ctor['old'] / ctor['new']:.2f}x); speed old/new {' '.join(f'{r:.2f}' for r in ratios)} (median {statistics.median(ratios):.2f})")
        print(f"  final reaching error old {got['old'][0]['final']!r} new {got['new'][0]['final']!r}", flush=True)
    for p in builds.values():
        assert p.stdin is not None
        p.stdin.close()
        p.wait()


if __name__ == "__main__":
    main()
