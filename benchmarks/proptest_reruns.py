"""Rerun the whole Rust property suite (crates/saggriac-core/tests/properties_*.rs) many times,
each run with its own proptest seed, to measure how often it fails.

    nice -n 10 python benchmarks/proptest_reruns.py [--runs 1000] [--jobs 1] [--seed 0]

The default test command uses one fixed seed (see `DEFAULT_SEED` in tests/common/mod.rs), so it runs
the same cases every time; this script asks for other seeds through PROPTEST_RNG_SEED. It builds
the `properties_*` test binaries once (`cargo test --release --no-run`), then runs it --runs times,
up to --jobs at once (each run single-threaded), and prints the number of runs, the failures
with their seeds and failing tests, and the wall time. The seeds are drawn from --seed, so a
campaign can be repeated exactly. Failures are not written to proptest-regressions/ (parallel
runs would race on the file); replay a printed seed with

    PROPTEST_RNG_SEED=<seed> cargo test -p saggriac-core --release --test 'properties_*'

which records the case there (commit it so that it is replayed first from then on).
"""

from __future__ import annotations

import argparse
import json
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor, as_completed
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
CRATE = ROOT / "crates" / "saggriac-core"


def build() -> list[str]:
    """Build the property-test binaries (one per component) in release mode and return their paths."""
    cmd = ["cargo", "test", "--release", "-p", "saggriac-core", "--test", "properties_*", "--no-run", "--message-format=json"]
    out = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
    if out.returncode:
        sys.exit(f"building the property tests failed ({' '.join(cmd)}):\n{out.stderr[-3000:]}")
    found = []
    for line in out.stdout.splitlines():
        try:
            msg = json.loads(line)
        except json.JSONDecodeError:
            continue
        if msg.get("reason") == "compiler-artifact" and msg.get("target", {}).get("name", "").startswith("properties_") and msg.get("executable"):
            found.append(msg["executable"])
    if not found:
        sys.exit("cargo built the property tests but did not name the test executables")
    return found


def run_once(binaries: list[str], seed: int, test_threads: int, timeout: float) -> tuple[int, bool, list[str], float]:
    """One run of the whole suite (every binary) with proptest seed `seed`: (seed, passed, failing tests, seconds)."""
    env = {**os.environ, "PROPTEST_RNG_SEED": str(seed), "PROPTEST_DISABLE_FAILURE_PERSISTENCE": "1"}
    t0 = time.perf_counter()
    failed: list[str] = []
    for binary in binaries:
        try:
            out = subprocess.run([binary, f"--test-threads={test_threads}"], cwd=CRATE, env=env, capture_output=True, text=True, timeout=timeout)
        except subprocess.TimeoutExpired:
            return seed, False, [*failed, f"{Path(binary).name}: timeout after {timeout:.0f} s"], time.perf_counter() - t0
        these = re.findall(r"^test (\S+) \.\.\. FAILED$", out.stdout, flags=re.MULTILINE)
        if out.returncode and not these:
            these = [f"{Path(binary).name}: exit code {out.returncode}"]
        failed += these
    return seed, not failed, failed, time.perf_counter() - t0


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--runs", type=int, default=1000, help="number of reruns of the whole suite (default 1000)")
    p.add_argument("--jobs", type=int, default=1, help="runs at once (default 1)")
    p.add_argument("--seed", type=int, default=0, help="root seed the per-run proptest seeds are drawn from (default 0)")
    p.add_argument("--test-threads", type=int, default=1, help="test threads inside one run (default 1)")
    p.add_argument("--timeout", type=float, default=600.0, help="seconds before one run counts as failed (default 600)")
    p.add_argument("--log", type=Path, help="append one JSON line per finished run to this file")
    p.add_argument("--every", type=int, default=50, help="print progress every this many runs (default 50)")
    a = p.parse_args()
    for name in ("runs", "jobs", "test_threads", "every"):
        if getattr(a, name) < 1:
            p.error(f"--{name.replace('_', '-')} must be an int >= 1. Got {getattr(a, name)} instead.")

    rng = random.Random(a.seed)
    seeds: list[int] = []
    seen: set[int] = set()
    while len(seeds) < a.runs:
        s = rng.getrandbits(64)
        if s not in seen:
            seen.add(s)
            seeds.append(s)

    t_build = time.perf_counter()
    built = build()
    print(f"built {len(built)} property-test binaries in {time.perf_counter() - t_build:.0f} s", flush=True)
    # Run a private copy, so that rebuilding the crate during a long campaign does not swap the
    # binary under it.
    workdir = tempfile.mkdtemp(prefix="proptest-reruns-")
    binary = [shutil.copy2(b, Path(workdir) / Path(b).name) for b in built]

    t0 = time.perf_counter()
    done, failures = 0, []
    log = a.log.open("a") if a.log else None
    try:
        with ThreadPoolExecutor(max_workers=a.jobs) as pool:
            futures = [pool.submit(run_once, binary, s, a.test_threads, a.timeout) for s in seeds]
            try:
                for fut in as_completed(futures):
                    seed, ok, failed, secs = fut.result()
                    done += 1
                    if not ok:
                        failures.append((seed, failed))
                        print(f"run {done}: seed {seed} FAILED: {', '.join(failed)}", flush=True)
                    if log:
                        log.write(json.dumps({"seed": seed, "ok": ok, "failed": failed, "seconds": round(secs, 3)}) + "\n")
                        log.flush()
                    if done % a.every == 0 and done < a.runs:
                        wall = time.perf_counter() - t0
                        print(f"{done}/{a.runs} runs, {len(failures)} failed, {wall:.0f} s ({done / wall * 60:.1f} runs/min)", flush=True)
            except KeyboardInterrupt:
                for fut in futures:
                    fut.cancel()
                print("interrupted; summary of the runs that finished:", flush=True)
    finally:
        if log:
            log.close()
        shutil.rmtree(workdir, ignore_errors=True)

    wall = time.perf_counter() - t0
    print(f"runs: {done} of {a.runs} (root seed {a.seed}, jobs {a.jobs}, test threads {a.test_threads})")
    print(f"failures: {len(failures)}")
    for seed, failed in sorted(failures):
        print(f"  PROPTEST_RNG_SEED={seed}: {', '.join(failed)}")
    print(f"wall time: {wall:.0f} s ({done / wall * 60 if wall else 0:.1f} runs/min)")
    sys.exit(1 if failures or done < a.runs else 0)


if __name__ == "__main__":
    main()
