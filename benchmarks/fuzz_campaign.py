"""The long fuzzing campaign: the Hypothesis properties of tests/config/test_config_fuzz.py
(parameter values), tests/teachers/test_teacher_fuzz.py (ask/tell sequences),
tests/teachers/test_new_teachers_fuzz.py (the field's teachers: constructors and calls),
tests/teachers/test_ownership_claims.py (the teacher claim's file-system states),
tests/runs/test_run_fuzz.py (tiny runs) and tests/runs/test_storage_fuzz.py (targets,
permissions, concurrent runs, corrupted files) with many more examples, and the Rust proptest
properties with more cases.

    python benchmarks/fuzz_campaign.py [--examples 4000] [--rust-cases 2048]

Prints how many generated inputs each property saw and whether anything failed. CI runs the
same properties with 60 examples each (and the Rust ones with their default case counts).
"""

from __future__ import annotations

import argparse
import ast
import os
import re
import subprocess
import sys
import time


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--examples", type=int, default=4000)
    p.add_argument("--rust-cases", type=int, default=2048)
    a = p.parse_args()
    t0 = time.perf_counter()
    env = {**os.environ, "SAGGRIAC_FUZZ_EXAMPLES": str(a.examples)}
    files = ["tests/config/test_config_fuzz.py", "tests/teachers/test_teacher_fuzz.py", "tests/teachers/test_new_teachers_fuzz.py", "tests/teachers/test_ownership_claims.py", "tests/runs/test_run_fuzz.py", "tests/runs/test_storage_fuzz.py"]
    py = subprocess.run([sys.executable, "-m", "pytest", "-q", "-s", "-p", "no:cacheprovider", *files], env=env, capture_output=True, text=True)
    # Each fuzz file prints the counts of its own properties.
    counts = {k: v for found in re.findall(r"fuzz examples: (\{.*\})", py.stdout) for k, v in ast.literal_eval(found).items()}
    storage = re.search(r"storage fuzz cases: (.*)", py.stdout)
    print(f"Python (Hypothesis), {a.examples} examples per property: {counts or '?'}")
    print(f"Python (Hypothesis), storage scenarios: {storage.group(1) if storage else '?'}; {py.stdout.strip().splitlines()[-1]}")
    env = {**os.environ, "PROPTEST_CASES": str(a.rust_cases)}
    # One test target per component (tests/properties_*.rs).
    rs = subprocess.run(["cargo", "test", "--release", "-q", "-p", "saggriac-core", "--test", "properties_*"], env=env, capture_output=True, text=True)
    summary = [line for line in rs.stdout.splitlines() if line.startswith("test result")]
    passed = sum(int(m) for line in summary for m in re.findall(r"(\d+) passed", line))
    print(f"Rust (proptest), {a.rust_cases} cases per property: {len(summary)} targets, {passed} properties passed" if summary else f"Rust (proptest): {rs.stderr[-500:]}")
    print(f"wall time {time.perf_counter() - t0:.0f} s")
    if py.returncode or rs.returncode:
        print(py.stdout[-3000:], rs.stdout[-3000:], rs.stderr[-3000:])
        sys.exit(1)


if __name__ == "__main__":
    main()
