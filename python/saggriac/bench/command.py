"""``saggriac bench``: the command's parser arguments and what it prints."""

from __future__ import annotations

import argparse
import math
import os
import sys
from pathlib import Path
from typing import Any

import pandas as pd

from ..errors import ParameterError
from ..teachers import available
from . import shipped
from .runner import BenchError
from .expert import BUILTIN, LEVELS
from .suite import BenchResult, builtin_specs, run_bench, with_variants
from .tasks import TASKS, TIERS, in_tier, missing_extra, tier_seeds
from .teachers import CALL_TIMEOUT, parse_teacher


def add_arguments(b: argparse.ArgumentParser) -> None:
    b.add_argument("--list", action="store_true", help="print the tasks (space, learner, budget per tier, expected time) and the built-in teachers, and stop")
    b.add_argument("--teacher", action="append", default=[], metavar="NAME_OR_PATH", help="a built-in teacher's name, or a class by import path: pkg.mod:Class or path/file.py:Class (repeatable), with @low or @high for expert knowledge at that level; every built-in teacher is on the board too")
    b.add_argument("--teacher-param", action="append", default=[], metavar="KEY=VALUE", help="a keyword argument of the --teacher classes (values read as TOML: 3, 0.5, true, \"text\")")
    b.add_argument("--tier", default="quick", choices=list(TIERS), help="quick (5 seeds), standard (10) or full (20 seeds, the studies' budgets); default quick")
    b.add_argument("--out", help="output folder (default bench-TIER); rerunning the same command there resumes it")
    b.add_argument("--seeds", type=int, help="seeds 0..N-1 (default: the tier's)")
    b.add_argument("--tasks", help="comma-separated subset of the tasks (default: all)")
    b.add_argument("--workers", type=int, help="worker processes (default: all cores; 1 runs in this process)")
    b.add_argument("--scheduler", help="address of a running Dask scheduler to run on (the per-call bound is not enforced there)")
    b.add_argument("--timeout", type=float, default=CALL_TIMEOUT, help=f"seconds one call of a teacher may take (default {CALL_TIMEOUT:g})")
    b.add_argument("--rerun", action="store_true", help="rerun the built-in teachers instead of reading the results shipped with the package, and say whether they differ")
    b.add_argument("--write-shipped", action="store_true", help="(maintainers) with --rerun: write the built-in teachers' runs as the package's shipped results of the tier")
    b.add_argument("--no-expert", action="store_true", help="leave out the teachers given expert knowledge (adr@low, adr@high, ...; a NAME@LEVEL asked for by --teacher still runs)")
    b.add_argument("--no-progress", action="store_true", help="no progress bar")


def run_seconds() -> dict[str, dict[str, tuple[float, bool]]]:
    """Per tier and task in it, the seconds of one run and whether they were measured: the tier's
    shipped runs' mean where they ship; else an estimate, the quick tier's measured mean scaled by
    the budget, or the task's ``cpu_per_unit`` (measured by its study's pilot) times its budget
    (NaN where neither exists)."""
    measured = {tier: (lambda ship: {} if ship is None else ship[0].groupby("task").seconds.mean().to_dict())(shipped.load(tier)) for tier in TIERS}
    out: dict[str, dict[str, tuple[float, bool]]] = {}
    for tier in TIERS:
        out[tier] = {}
        for name, cls in TASKS.items():
            budget = cls.budgets[tier]
            if budget is None:
                continue
            if name in measured[tier]:
                out[tier][name] = (float(measured[tier][name]), True)
            elif name in measured["quick"] and cls.budgets["quick"]:
                out[tier][name] = (float(measured["quick"][name]) * budget / cls.budgets["quick"], False)
            else:
                out[tier][name] = (budget * cls.cpu_per_unit if cls.cpu_per_unit else math.nan, False)
    return out


def tier_hours(seconds: dict[str, tuple[float, bool]], tier: str) -> tuple[float, float]:
    """CPU hours of ``tier`` for one box teacher on its box tasks, and for every built-in teacher
    (each on the tasks of its spaces, the expert variants on the tasks that declare knowledge)."""
    n = {name: len(tier_seeds(name, tier)) for name in seconds}  # a study's task takes its own seeds in the full tier
    one = sum(s * n[name] for name, (s, _) in seconds.items() if TASKS[name].space == "box" and not math.isnan(s)) / 3600
    specs = builtin_specs(True)
    every = sum(s * n[name] * sum(1 for spec in specs if spec.takes(TASKS[name].space) and (not spec.level or TASKS[name].declares_knowledge())) for name, (s, _) in seconds.items() if not math.isnan(s))
    return one, every / 3600


def listing() -> str:
    rows = []
    seconds = run_seconds()
    for name, cls in TASKS.items():
        row: dict[str, Any] = dict(task=name, space=cls.space, learner=cls.learner)
        for tier in TIERS:
            budget = cls.budgets[tier]
            row[f"{tier} ({TIERS[tier]} seeds)"] = "-" if budget is None else f"{budget:,} {cls.unit}"
        cells = []
        for tier in TIERS:
            s, measured = seconds[tier].get(name, (None, True))
            cells.append("-" if s is None else "?" if math.isnan(s) else f"{'' if measured else '~'}{s:.3g}")
        row["s/run: quick / standard / full"] = " / ".join(cells)
        rows.append(row)
    table = pd.DataFrame(rows).to_string(index=False)
    names = ", ".join(f"{n} ({'/'.join(c.spaces)})" for n, c in available().items())
    variants = ", ".join(s.label for s in builtin_specs(True) if s.level)
    expert = (f"\nwith expert knowledge (box tasks, TeachMyAgent's levels; docs/bench.md): {variants}\n"
              f"  {', '.join(BUILTIN)} without a level: no knowledge (their defaults); @{LEVELS[0]}: a start drawn at random in the box, the whole box as target; "
              f"@{LEVELS[1]}: the easy region and the target each task declares (--no-expert leaves them out)")
    hours = []
    for tier in TIERS:
        one, every = tier_hours(seconds[tier], tier)
        unknown = [n for n, (s, _) in seconds[tier].items() if math.isnan(s)]
        own = "; a task a registered study ran takes its study's seeds" if any(in_tier(n, tier) and tier_seeds(n, tier) != list(range(TIERS[tier])) for n in TASKS) else ""
        hours.append(f"  {tier} ({TIERS[tier]} seeds{own}): one box teacher about {one:.2g} CPU h, every built-in teacher about {every:.2g} CPU h" + (f" (without {', '.join(unknown)}: no measure yet)" if unknown else ""))
    needs = [f"{n} needs {missing_extra(n)}" for n in TASKS if missing_extra(n) is not None]
    missing = f"\nnot installed: {'; '.join(needs)} (left out of the bench until it is)" if needs else ""
    return (f"{table}\n\n'-': not in that tier (deep RL is not in the quick tier). s/run: the shipped runs' mean seconds per run where they ship; "
            f"'~' an estimate (the quick tier's scaled by the budget, or the CPU seconds per step its study's pilot measured)\nbuilt-in teachers: {names}{expert}\n"
            f"all tasks of a tier, all installed or not:\n" + "\n".join(hours) + missing)


def _teacher_params(pairs: list[str], parse_value: Any) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for p in pairs:
        if "=" not in p or not p.split("=", 1)[0].strip().isidentifier():
            raise ParameterError(f"The '--teacher-param' parameter of saggriac bench must be KEY=VALUE with KEY a Python name. Got {p!r} instead.", "teacher-param", p)
        k, v = (x.strip() for x in p.split("=", 1))
        if k in out:
            raise ParameterError(f"The '--teacher-param' parameter of saggriac bench gives {k!r} twice; give it once.", "teacher-param", p)
        out[k] = parse_value(v)
    return out


def run_command(args: argparse.Namespace, parse_value: Any) -> int:
    if args.list:
        print(listing())
        return 0
    # As `python -m` does: a teacher module in the current folder is found by its import path.
    if os.getcwd() not in sys.path:
        sys.path.insert(0, os.getcwd())
    params = _teacher_params(args.teacher_param, parse_value)
    if params and not args.teacher:
        raise ParameterError("The '--teacher-param' parameter of saggriac bench applies to the --teacher classes; give --teacher too.", "teacher-param", repr(args.teacher_param))
    specs = [parse_teacher(t, params) for t in args.teacher]
    if args.write_shipped and not args.rerun:
        raise ParameterError("The '--write-shipped' parameter of saggriac bench needs --rerun (the shipped results are written from runs made now).", "write-shipped", "True")
    tasks = None if args.tasks is None else [t.strip() for t in args.tasks.split(",")]
    out = Path(args.out or f"bench-{args.tier}")
    try:
        result = run_bench(specs, out=out, tier=args.tier, seeds=args.seeds, tasks=tasks, workers=args.workers, timeout=args.timeout, rerun=args.rerun, progress=not args.no_progress, scheduler=args.scheduler, expert=not args.no_expert)
        rc = 0
    except BenchError as e:
        print(f"saggriac: error: {e}", file=sys.stderr)
        result, rc = e.result, 1  # type: ignore[attr-defined]
    report(result, with_variants(specs, not args.no_expert))
    if args.write_shipped and rc == 0:
        builtin = result.runs[result.runs.teacher.isin([s.label for s in builtin_specs(True)])]
        curves = result.curves.merge(builtin[["task", "teacher", "seed"]], on=["task", "teacher", "seed"])
        goals = result.goals.merge(builtin[["task", "teacher", "seed"]], on=["task", "teacher", "seed"])
        seeds = sorted(set(builtin.seed))
        command = f"saggriac bench --tier {args.tier} --rerun --write-shipped" + (f" --seeds {args.seeds}" if args.seeds else "") + (f" --tasks {','.join(tasks)}" if tasks else "") + (" --no-expert" if args.no_expert else "")
        for p in shipped.write(args.tier, builtin, curves, goals, seeds, command):
            print(f"shipped results: {p}")
    return rc


def report(result: BenchResult, specs: list[Any]) -> None:
    for note in result.notes:
        print(note)
    board = result.board
    mine = [s.label for s in specs]
    if not board.empty:
        shown = board[board.teacher.isin(mine)] if mine else board
        print(shown[["task", "teacher", "seeds", "area", "final", "diff_area", "ci_low", "ci_high", "p_holm", "rank"]].to_string(index=False, float_format=lambda v: f"{v:.3g}"))
    print(f"\n{result.computed} runs computed in {result.wall_seconds:.1f} s on {result.workers} worker(s); {result.kept} kept from {result.out}; {result.from_shipped} from the shipped results")
    for label in mine:
        cpu = result.cpu_seconds(label)
        print(f"{label}: {cpu:.1f} s of CPU over its {int((result.runs.teacher == label).sum())} runs (about {cpu / max(1, result.workers):.1f} s on {result.workers} worker(s))")
    for name, path in result.written.items():
        print(f"{name}: {path}")
