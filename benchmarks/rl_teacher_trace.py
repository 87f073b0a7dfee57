"""Rerun one run of the RL curriculum study and print where its teacher ended (docs/rl_curriculum.md,
"Diagnostics"): the final distance, to compare with the committed runs.csv, and the teacher's
``bounds`` (ADR) or ``regions()`` at the end.

    python benchmarks/rl_teacher_trace.py adr 500 --reward dense
    python benchmarks/rl_teacher_trace.py adr 600 --reward sparse
"""

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import rl_curriculum as study  # noqa: E402


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("teacher")
    p.add_argument("seed", type=int)
    p.add_argument("--reward", choices=study.REWARDS, default="dense")
    a = p.parse_args()
    kept = {}
    make = study.make_teacher

    def keep(name, seed):
        kept["teacher"] = make(name, seed)
        return kept["teacher"]

    # The study's own run, with the teacher it builds kept aside.
    study.make_teacher = keep
    rows = study.one_run((a.reward, a.teacher, a.seed, study.BUDGET, study.BUDGET // 10, study.THRESHOLDS[a.reward], "trace"))
    t = kept["teacher"]
    print(f"final distance {rows[-1]['distance']!r}, success {rows[-1]['success']}")
    print("bounds", t.bounds) if hasattr(t, "bounds") else print("regions", t.regions())


if __name__ == "__main__":
    main()
