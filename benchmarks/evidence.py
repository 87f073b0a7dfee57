"""The runner of the registered studies over the bench's tasks (issue 48): one command runs a study's
protocol, resumes it, and recomputes every table from the committed rows.

    python benchmarks/evidence.py --study sac --pilot             # the pilot's runs; resumes
    python benchmarks/evidence.py --study sac --pilot --analyse   # the pilot's numbers
    python benchmarks/evidence.py --study sac                     # the report runs; resumes
    python benchmarks/evidence.py --study sac --analyse           # comparisons.csv, results.md, figure

A study is ``docs/figures/evidence/NAME/protocol.json``, committed before its report runs (its
prose is ``docs/evidence/NAME.md``): the bench tasks it runs (any registered task, box or task
list), the teachers (the bench's names, built-in or ``pkg.mod:Class``, and ``oracle``, the task's
own oracle: ``BenchTask.oracle_teacher``), the budget per task, the scorings per run, the pilot's
and the report's seeds (and its rules, ``pilot.rules``), the decision rule, and optionally the
verdicts of an earlier study the results are set against (``earlier``) and the modules to import
that register tasks ``saggriac.bench`` does not (``modules``).

A run is (task, teacher, seed): the bench's task class built for the root seed, the bench's
guarded teacher (seeds derived as the bench derives them, :func:`saggriac.bench.runner.play_run`),
with the protocol's budget and seeds rather than the bench's tier (which runs seeds 0..N-1 only). Each finished run is written at once to
``curves.csv`` (every scoring, with the task's own measures) and ``runs.csv`` (one row: task,
learner, teacher, seed, budget, final, area, the task's own measures at the end, seconds,
cpu_seconds, teacher_seconds, commit, machine: the CPU's kind, :func:`saggriac.runs.resources.cpu_kind`); a run already in runs.csv is not run again, so a killed
study resumes. A run refused on the way (a failing teacher, a learner not trained on the
teacher's goals) goes to ``failures.csv`` with its reason, and is tried again on resuming. Runs go
seed by seed, every teacher on a seed before the next seed, so that a partial study stays paired.

``--analyse`` reads runs.csv alone: per task, each teacher against the protocol's baseline and
against the oracle, paired by seed on complete seeds, with the statistics of the deep-RL study
(benchmarks/rl_curriculum.py's ``paired_rows``: mean gain, Student t 95 % CI, paired t-test, d_z,
Holm over the family) and a paired bootstrap 95 % CI beside it, the verdict by the protocol's
rule, and the task's own notes (the arm's fold counts).
"""

from __future__ import annotations

import argparse
import importlib
import json
import math
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

sys.path.insert(0, str(Path(__file__).resolve().parent))
from rl_curriculum import commit, paired_rows, power, seeds_arg  # noqa: E402  (one place for the deep-RL study's statistics)

REPO = Path(__file__).resolve().parents[1]
ROOT = REPO / "docs" / "figures" / "evidence"
KEY = ["task", "teacher", "seed"]
TEXT = {"commit": str, "teacher": str, "task": str, "learner": str}
#: Keys protocol.json must have, and those of its rule.
NEEDED = ("study", "question", "registered", "tasks", "teachers", "budget", "scorings", "pilot", "report", "rule")
RULE = ("primary", "alpha", "correction", "meaningful", "baseline")
BOOTSTRAP = 10_000


class ProtocolError(ValueError):
    """protocol.json is missing a key or has a bad value: the message names the file, the key,
    the value and the rule."""


def read_protocol(path: Path) -> dict[str, Any]:
    """protocol.json, checked: every key there, every task registered, every teacher known, a
    budget (or null, before the pilot fixed it) and report seeds for every task."""
    from saggriac.bench import TASKS, parse_teacher
    from saggriac.bench.teachers import ORACLE

    try:
        p = json.loads(path.read_text())
    except (OSError, ValueError) as e:
        raise ProtocolError(f"Cannot read the protocol {path}: {e}.") from None
    missing = [k for k in NEEDED if k not in p]
    if missing:
        raise ProtocolError(f"The protocol {path} must have the keys {', '.join(NEEDED)}; it has no {', '.join(missing)}.")
    for module in p.get("modules", []):
        importlib.import_module(module)  # a module that registers tasks of the study's own
    unknown = [t for t in p["tasks"] if t not in TASKS]
    if unknown:
        raise ProtocolError(f"The 'tasks' of the protocol {path} must be bench tasks ({', '.join(TASKS)}). Got {unknown} instead.")
    for t in p["teachers"]:
        if t != ORACLE:
            parse_teacher(t)
        elif not all(TASKS[k].has_oracle() for k in p["tasks"]):
            raise ProtocolError(f"The 'teachers' of the protocol {path} name 'oracle', and the tasks {[k for k in p['tasks'] if not TASKS[k].has_oracle()]} have none.")
    for part in ("budget", "report"):
        if set(p[part]) != set(p["tasks"]):
            raise ProtocolError(f"The '{part}' of the protocol {path} must have one entry per task {p['tasks']}. Got {sorted(p[part])} instead.")
    for k, b in {**p["budget"], **p["pilot"].get("budget", {})}.items():
        if b is not None and (isinstance(b, bool) or not isinstance(b, int) or b <= 0):
            raise ProtocolError(f"The budget of {k!r} in the protocol {path} must be an int > 0 (or null before the pilot). Got {b!r} instead.")
    s = p["scorings"]
    if isinstance(s, bool) or not isinstance(s, int) or s < 1:
        raise ProtocolError(f"The 'scorings' of the protocol {path} must be an int >= 1. Got {s!r} instead.")
    bad = [k for k in RULE if k not in p["rule"]]
    if bad or p["rule"]["correction"] != "holm" or p["rule"]["baseline"] not in p["teachers"] or p["rule"]["primary"] != "final":
        raise ProtocolError(f"The 'rule' of the protocol {path} must have {', '.join(RULE)}, with correction 'holm', primary 'final' (the bench's score at the budget) and a baseline among the teachers. Got {p['rule']!r} instead.")
    return p


def plan(p: dict[str, Any], pilot: bool) -> list[tuple[str, str, int, int]]:
    """The runs (task, teacher, seed, budget) of the report or the pilot: task by task in the
    protocol's order, then seed by seed, every teacher on a seed before the next (a partial study
    stays paired). A teacher runs on the tasks of the spaces it takes, as in the bench."""
    from saggriac.bench import TASKS, parse_teacher
    from saggriac.bench.teachers import ORACLE

    part = p["pilot"] if pilot else p
    teachers = part.get("teachers", p["teachers"])
    budgets = part.get("budget", p["budget"])
    jobs = []
    for task in part.get("tasks", p["tasks"]):
        budget = budgets[task]
        if budget is None:
            raise ProtocolError(f"The protocol of {p['study']!r} has no budget for {task!r} yet (null): the pilot fixes it (--pilot, then write it into protocol.json).")
        seeds = seeds_arg(str(p["pilot"]["seeds"] if pilot else p["report"][task]))
        space = TASKS[task].space
        for seed in seeds:
            jobs += [(task, t, seed, budget) for t in teachers if t == ORACLE or parse_teacher(t).takes(space)]
    return jobs


def one_run_safely(job: tuple) -> tuple[list[dict] | None, dict | None, str | None]:
    """:func:`one_run`, or the message of a refused run: a teacher that failed (TeacherError:
    raised, took longer than the timeout, asked a goal outside the space) or a learner that did
    not train on the teacher's goals (ConformanceError). Anything else is a bug and stops the study."""
    from saggriac.bench import TeacherError
    from saggriac.errors import ConformanceError

    try:
        return (*one_run(job), None)
    except (TeacherError, ConformanceError) as e:
        return None, None, f"{type(e).__name__}: {e}"


def one_run(job: tuple) -> tuple[list[dict], dict]:
    """One run, (task, teacher, seed, budget, scorings, timeout, commit, modules) (a top-level
    function, for a pool of fresh processes, which import the protocol's modules): its rows of
    curves.csv and runs.csv."""
    from saggriac.bench import TASKS, parse_teacher
    from saggriac.bench.runner import play_run
    from saggriac.bench.teachers import ORACLE, Guarded, GuardedOracle
    from saggriac.runs.resources import cpu_kind

    task_name, teacher, seed, budget, scorings, timeout, code, modules = job
    for module in modules:
        importlib.import_module(module)
    cpu = time.process_time()
    if teacher == ORACLE:
        build = lambda task, s: GuardedOracle(task, s, timeout, run_seed=seed)
    else:
        spec = parse_teacher(teacher)
        build = lambda task, s: Guarded(spec, task, s, timeout, run_seed=seed)
    task, guard, curve, seconds = play_run(task_name, seed, budget, build, points=scorings)
    cpu = time.process_time() - cpu
    own = task.own_measures()
    if own and len(own) != len(curve):
        raise RuntimeError(f"The task {task_name!r} gave {len(own)} own measures for {len(curve)} scorings (seed {seed}, teacher {teacher}).")
    if not curve or curve[-1][0] != budget:
        raise RuntimeError(f"Run {task_name}/{teacher}/{seed}: the last scoring was at {curve[-1][0] if curve else None}, not at the budget {budget}.")
    base = dict(task=task_name, teacher=teacher, seed=seed, budget=budget)
    curves = [dict(base, step=int(t), score=float(s), **(own[i] if own else {})) for i, (t, s) in enumerate(curve)]
    scores = [s for _, s in curve]
    row = dict(task=task_name, learner=TASKS[task_name].learner, teacher=teacher, seed=seed, budget=budget, final=float(scores[-1]), area=float(np.mean(scores)))
    row.update({f"final_{k}": v for k, v in (own[-1] if own else {}).items()})
    # The CPU's kind with the commit: deep-RL runs agree to the bit only on one kind (docs/bench.md).
    row.update(seconds=seconds, cpu_seconds=cpu, teacher_seconds=guard.teacher_seconds, commit=code, machine=cpu_kind())
    return curves, row


# ---------------------------------------------------------------- storage


def read_table(path: Path) -> pd.DataFrame:
    return pd.read_csv(path, dtype=TEXT) if path.exists() else pd.DataFrame()


def write_table(path: Path, table: pd.DataFrame, what: str) -> None:
    from saggriac.files import write_file

    write_file(path, lambda tmp: table.to_csv(tmp, index=False), what=what, overwrite=True)


def keys(table: pd.DataFrame) -> set[tuple[str, str, int]]:
    return set() if table.empty else {(a, b, int(c)) for a, b, c in table[KEY].itertuples(index=False, name=None)}


def run_study(p: dict[str, Any], out: Path, pilot: bool, workers: int, timeout: float, progress: bool = True) -> int:
    """Every run of the plan not yet in ``out/runs.csv``, each written at once (curves first;
    a run is done when its row is in runs.csv, and curves of a run killed between the two writes
    are dropped). The number of runs made."""
    from tqdm import tqdm

    out.mkdir(parents=True, exist_ok=True)
    runs, curves = read_table(out / "runs.csv"), read_table(out / "curves.csv")
    jobs = plan(p, pilot)
    want = {(t, b) for t, _, _, b in jobs}
    if not runs.empty:
        mine = {j[0] for j in jobs}
        clash = runs[[t in mine and (t, int(b)) not in want for t, b in zip(runs["task"], runs["budget"])]]
        if len(clash):
            raise ProtocolError(f"{out / 'runs.csv'} holds runs of {sorted(set(clash['task']))} with budgets {sorted(set(clash['budget'].astype(int)))}, and the protocol's are {sorted(want)}: the runs would not be comparable. Move them away, or fix the protocol.")
    done = keys(runs)
    if not curves.empty:
        orphan = [k not in done for k in zip(curves["task"], curves["teacher"], curves["seed"].astype(int))]
        curves = curves[~np.array(orphan, bool)]
    todo = [j for j in jobs if j[:3] not in done]
    print(f"{len(todo)} runs to do, {len(jobs) - len(todo)} already in {out / 'runs.csv'}", file=sys.stderr)
    code = commit()
    modules = tuple(p.get("modules", []))
    args = [(task, teacher, seed, budget, int(p["scorings"]), timeout, code, modules) for task, teacher, seed, budget in todo]
    if workers == 1:
        results, pool = map(one_run_safely, args), None
    else:
        import multiprocessing as mp

        from saggriac.runs.resources import share_cores

        pool = mp.get_context("spawn").Pool(workers, initializer=share_cores, initargs=(workers,))
        results = pool.imap(one_run_safely, args)
    failed = read_table(out / "failures.csv")
    try:
        for job, (c, r, error) in zip(args, tqdm(results, total=len(args), desc=f"{p['study']}{' pilot' if pilot else ''}", disable=not progress)):
            if error is not None:
                # Kept apart, with its reason; the run is tried again when the study resumes.
                row = pd.DataFrame([dict(task=job[0], teacher=job[1], seed=job[2], budget=job[3], error=error, commit=code)])
                failed = pd.concat([failed, row], ignore_index=True) if len(failed) else row
                write_table(out / "failures.csv", failed, "the failed runs")
                print(f"run {job[0]}/{job[1]}/{job[2]} failed: {error}", file=sys.stderr)
                continue
            curves = pd.concat([curves, pd.DataFrame(c)], ignore_index=True) if len(curves) else pd.DataFrame(c)
            runs = pd.concat([runs, pd.DataFrame([r])], ignore_index=True) if len(runs) else pd.DataFrame([r])
            write_table(out / "curves.csv", curves, "the curves")
            write_table(out / "runs.csv", runs, "the runs")
    finally:
        if pool is not None:
            pool.close()
            pool.join()
    return len(args)


# ---------------------------------------------------------------- analysis


def bootstrap_ci(d: np.ndarray, seed: int, resamples: int = BOOTSTRAP) -> tuple[float, float]:
    """Percentile 95 % interval of the mean of the paired differences ``d``, resampling seeds."""
    d = np.asarray(d, float)
    rng = np.random.default_rng(seed)
    means = d[rng.integers(0, len(d), (resamples, len(d)))].mean(axis=1)
    return float(np.quantile(means, 0.025)), float(np.quantile(means, 0.975))


def verdict(gain: float, p: float, alpha: float) -> str:
    if not (p < alpha):
        return "no difference shown"
    return "helps" if gain > 0 else "hurts"


def complete(runs: pd.DataFrame, teachers: list[str]) -> tuple[pd.DataFrame, list[int]]:
    """The runs on seeds every one of ``teachers`` has run."""
    has = runs.groupby("seed")["teacher"].apply(set)
    seeds = sorted(int(s) for s, ts in has.items() if set(teachers) <= ts)
    return runs[runs["seed"].isin(seeds)], seeds


def compare(runs: pd.DataFrame, p: dict[str, Any], task: str) -> pd.DataFrame:
    """The task's comparisons: every teacher against the baseline (the decision family) and every
    teacher but the baseline against the oracle (secondary), on the primary measure (the final
    score, higher is better), paired on complete seeds, Holm within each family."""
    from saggriac.bench.teachers import ORACLE

    rule = p["rule"]
    base = rule["baseline"]
    r = runs[runs["task"] == task]
    teachers = [t for t in p["teachers"] if t in set(r["teacher"])]
    r, seeds = complete(r, teachers)
    if base not in teachers or len(seeds) < 2:
        return pd.DataFrame()
    wide = r.pivot(index="seed", columns="teacher", values="final")
    others = [t for t in teachers if t != base]
    families = [("against the baseline", [(t, base) for t in others])]
    if ORACLE in teachers and base != ORACLE:
        families.append(("against the oracle", [(t, ORACLE) for t in others if t != ORACLE]))
    tables = []
    for family, pairs in families:
        if not pairs:
            continue
        t = paired_rows(wide, pairs, "final", "higher", family)
        boot = p.get("bootstrap", {})
        cis = [bootstrap_ci(wide[a].to_numpy() - wide[b].to_numpy(), int(boot.get("seed", 0)), int(boot.get("resamples", BOOTSTRAP))) for a, b in pairs]
        t["boot_low"], t["boot_high"] = [c[0] for c in cis], [c[1] for c in cis]
        t["verdict"] = [verdict(g, q, float(rule["alpha"])) for g, q in zip(t["gain"], t["p_holm"])]
        if family == "against the baseline":
            # The verdicts an earlier study gave (protocol's "earlier"), and whether each holds.
            earlier = p.get("earlier", {}).get("verdicts", {}).get(task, {})
            t["earlier"] = [earlier.get(a, "") for a in t["a"]]
            t["holds"] = [("" if not e else "yes" if e == v else "no") for e, v in zip(t["earlier"], t["verdict"])]
        tables.append(t)
    return pd.concat(tables, ignore_index=True).assign(task=task, seeds=len(seeds)) if tables else pd.DataFrame()


def fmt(x: Any, digits: int = 3, sign: bool = False) -> str:
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "-"
    return f"{x:+.{digits}f}" if sign else f"{x:.{digits}f}"


def analyse(p: dict[str, Any], out: Path, pilot: bool = False) -> str:
    """comparisons.csv, results.md and evidence.png in ``out``, from ``out/runs.csv`` (and the
    figure from curves.csv) alone. The text of results.md."""
    from saggriac.bench import TASKS

    runs = read_table(out / "runs.csv")
    if runs.empty:
        raise ProtocolError(f"--analyse reads {out / 'runs.csv'}, which has no runs.")
    jobs = plan(p, pilot)
    failed = read_table(out / "failures.csv")
    if len(failed):
        failed = failed[[k not in keys(runs) for k in zip(failed["task"], failed["teacher"], failed["seed"].astype(int))]]
    lines = [f"# {p['study']}{' (pilot)' if pilot else ''}: results recomputed from runs.csv", "", f"Question: {p['question']}", ""]
    tables = []
    for task in dict.fromkeys(j[0] for j in jobs):
        r = runs[runs["task"] == task]
        want = [j for j in jobs if j[0] == task]
        done = len(keys(r) & {j[:3] for j in want})
        teachers = list(dict.fromkeys(j[1] for j in want))
        lines += [f"## {task}: {TASKS[task].learner}", "", f"{done} of the protocol's {len(want)} runs done ({len(teachers)} teachers, budget {want[0][3]} {TASKS[task].unit}).", ""]
        refused = failed[failed["task"] == task] if len(failed) else failed
        if len(refused):
            lines += ["Refused on the way (failures.csv; tried again when the study resumes): " + "; ".join(f"{x.teacher} seed {int(x.seed)}: {x.error}" for x in refused.itertuples()), ""]
        if done < len(want):
            lines += ["**Interim: not every run of the protocol is done; these numbers decide nothing.**", ""]
        if r.empty:
            continue
        lines += [machines_line(r), ""]
        own = [c for c in r.columns if c.startswith("final_") and r[c].notna().any()]
        lines += ["| teacher | runs | final (mean ± sd) | area | " + "".join(f"{c} | " for c in own) + "CPU s per run |", "|---|---|---|---|" + "---|" * len(own) + "---|"]
        for t in teachers:
            x = r[r["teacher"] == t]
            if len(x):
                cells = "".join(f"{fmt(x[c].mean())} | " for c in own)
                lines.append(f"| {t} | {len(x)} | {fmt(x['final'].mean())} ± {fmt(x['final'].std(ddof=1))} | {fmt(x['area'].mean())} | {cells}{x['cpu_seconds'].mean():.0f} |")
        notes = TASKS[task].notes(r)
        if notes:
            lines += ["", *notes]
        table = compare(r, p, task)
        if len(table):
            tables.append(table)
            lines += ["", f"Paired on {int(table['seeds'].iloc[0])} complete seeds; gain = the teacher's final score minus the other's (positive: the teacher's learner ends better); Holm within each family; verdict at alpha {p['rule']['alpha']}.", ""]
            source = p.get("earlier", {}).get("source")
            if source:
                lines += [f"Earlier verdicts: {source}.", ""]
            lines += ["| family | teacher | against | gain | 95 % CI (t) | 95 % CI (bootstrap) | p | p (Holm) | d_z | verdict | earlier | holds |", "|---|---|---|---|---|---|---|---|---|---|---|---|"]
            for _, x in table.iterrows():
                was, holds = (x.get("earlier"), x.get("holds")) if isinstance(x.get("earlier"), str) else ("", "")
                lines.append(f"| {x['family']} | {x['a']} | {x['b']} | {fmt(x['gain'], sign=True)} | [{fmt(x['ci_low'], sign=True)}, {fmt(x['ci_high'], sign=True)}] | [{fmt(x['boot_low'], sign=True)}, {fmt(x['boot_high'], sign=True)}] | {x['p_value']:.3g} | {x['p_holm']:.3g} | {fmt(x['d_z'], 2)} | {x['verdict']} | {was} | {holds} |")
            if done == len(want):
                lines += ["", *detectable_lines(table, p)]
        lines.append("")
    comparisons = pd.concat(tables, ignore_index=True) if tables else pd.DataFrame()
    write_table(out / "comparisons.csv", comparisons, "the comparisons")
    if pilot:
        lines += pilot_lines(runs, p, read_table(out / "curves.csv"))
    text = "\n".join(lines) + "\n"
    from saggriac.files import write_file

    write_file(out / "results.md", lambda tmp: Path(tmp).write_text(text), what="the results", overwrite=True)
    figure(out, read_table(out / "curves.csv"))
    return text


def machines_line(runs: pd.DataFrame) -> str:
    """Which kinds of CPU made the runs (their ``machine`` column; rows made before it was kept
    say nothing). Deep-RL runs of one seed agree to the bit only on one kind: a study spanning
    kinds is a fair comparison, but a rerun matches its rows only on the kind that made them."""
    kinds = runs["machine"].fillna("not recorded").value_counts() if "machine" in runs else pd.Series({"not recorded": len(runs)})
    return "Kind of CPU the runs were made on (runs.csv's machine): " + "; ".join(f"{k} ({n} runs)" for k, n in kinds.items()) + "."


def pilot_lines(runs: pd.DataFrame, p: dict[str, Any], curves: pd.DataFrame | None = None) -> list[str]:
    """The pilot's cost and spread, per task, and the protocol's pilot rules applied (its
    ``pilot.rules``, if any): ``budget`` (the largest multiple of ``step`` in [min, max] whose
    ``runs`` runs fit ``cpu_seconds`` at the pilot's mean CPU seconds per unit) and ``learns``
    (the first scoring of ``task`` where the mean ``start`` minus the mean ``measure`` reaches
    ``min_drop``, and whether the budget reaches it)."""
    lines = ["## The pilot's cost and spread", "", "| task | runs | CPU s per 1,000 units | wall s per 1,000 units | final: mean | final: sd |", "|---|---|---|---|---|---|"]
    for task, r in runs.groupby("task", sort=False):
        lines.append(f"| {task} | {len(r)} | {(r['cpu_seconds'] / r['budget'] * 1000).mean():.3f} | {(r['seconds'] / r['budget'] * 1000).mean():.3f} | {fmt(r['final'].mean())} | {fmt(r['final'].std(ddof=1))} |")
    rules = p["pilot"].get("rules", {})
    budget = None
    if "budget" in rules:
        b = rules["budget"]
        t = float((runs["cpu_seconds"] / runs["budget"]).mean())
        fits = [x for x in range(int(b["min"]), int(b["max"]) + 1, int(b["step"])) if b["runs"] * t * x <= b["cpu_seconds"]]
        budget = max(fits) if fits else int(b["min"])
        lines += ["", f"Rule budget: {b['runs']} runs x {t * 1000:.3f} CPU s per 1,000 x B / 1,000 <= {b['cpu_seconds']} s -> B = {budget} ({b['runs'] * t * budget / 3600:.2f} CPU hours projected)" + ("" if fits else f"; even {b['min']} does not fit")]
    if "learns" in rules and curves is not None and not curves.empty:
        r = rules["learns"]
        c = curves[curves["task"] == r["task"]]
        drop = (c.groupby("step")[r["start"]].mean() - c.groupby("step")[r["measure"]].mean()).sort_index()
        first = next((int(st) for st, v in drop.items() if v >= r["min_drop"]), None)
        at = float(drop.get(budget, math.nan)) if budget is not None else math.nan
        lines += ["", f"Rule learns ({r['task']}): mean {r['start']} - mean {r['measure']} by scoring: " + ", ".join(f"{int(st)}: {v:+.3f}" for st, v in drop.items()), f"first scoring with a drop >= {r['min_drop']}: {first}; at B = {budget}: {fmt(at, sign=True)} -> " + ("holds" if at >= r["min_drop"] else "does not hold")]
    return lines + [""]


def figure(out: Path, curves: pd.DataFrame) -> None:
    if curves.empty:
        return
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    tasks = list(dict.fromkeys(curves["task"]))
    fig, axes = plt.subplots(1, len(tasks), figsize=(6 * len(tasks), 4.2), squeeze=False)
    for ax, task in zip(axes[0], tasks):
        c = curves[curves["task"] == task]
        for t in dict.fromkeys(c["teacher"]):
            g = c[c["teacher"] == t].groupby("step")["score"]
            m, s, n = g.mean(), g.std(ddof=1).fillna(0.0), g.count()
            ax.plot(m.index, m.values, label=t)
            ax.fill_between(m.index, m - s / np.sqrt(n), m + s / np.sqrt(n), alpha=0.15)
        from saggriac.bench import TASKS

        ax.set(xlabel=TASKS[task].unit if task in TASKS else "budget spent", ylabel="score (higher is better)", title=f"{task} (mean ± s.e.)")
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "evidence.png", dpi=100)
    plt.close(fig)


# ---------------------------------------------------------------- the command


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--study", required=True, help="the study's name: reads ROOT/NAME/protocol.json")
    ap.add_argument("--root", type=Path, default=ROOT, help=f"where the studies' folders are (default: {ROOT.relative_to(REPO)})")
    ap.add_argument("--pilot", action="store_true", help="the pilot's runs (in NAME/pilot/), not the report's")
    ap.add_argument("--analyse", action="store_true", help="only recompute comparisons.csv, results.md and the figure from runs.csv")
    ap.add_argument("--workers", type=int, default=1, help="runs at a time, one process each (default 1)")
    ap.add_argument("--timeout", type=float, default=None, help="seconds one teacher call may take (default: the bench's)")
    ap.add_argument("--power", action="store_true", help="print the power of the protocol's size for its meaningful effect and stop")
    a = ap.parse_args(argv)
    from saggriac.bench import CALL_TIMEOUT

    folder = a.root / a.study
    try:
        p = read_protocol(folder / "protocol.json")
        out = folder / "pilot" if a.pilot else folder
        if a.power:
            print(power_lines(p))
        elif a.analyse:
            print(analyse(p, out, a.pilot))
        else:
            if isinstance(a.workers, bool) or a.workers < 1:
                ap.error(f"--workers must be an int >= 1; got {a.workers}")
            run_study(p, out, a.pilot, a.workers, CALL_TIMEOUT if a.timeout is None else a.timeout)
            print(analyse(p, out, a.pilot))
    except ProtocolError as e:
        ap.exit(2, f"evidence.py: {e}\n")


def detectable_lines(table: pd.DataFrame, p: dict[str, Any]) -> list[str]:
    """What a complete study could detect at the spread its report runs show (the registrations
    promise it: their pilots' SDs rest on few seeds): for each teacher against the baseline, the
    SD of the paired differences, the smallest gain with 80 % power at Holm's first step (alpha /
    family) and its last (alpha), and the power for the registered meaningful gain."""
    alpha = float(p["rule"]["alpha"])
    mine = table[table["family"] == "against the baseline"]
    family, n = len(mine), int(mine["seeds"].iloc[0])
    grid = np.round(np.arange(0.05, 5.0, 0.01), 2)
    need = [next((x for x in grid if power(n, x, q) >= 0.8), math.nan) for q in (alpha / family, alpha)]
    meaningful = p["rule"].get("meaningful", {})
    score = next((float(v) for k, v in meaningful.items() if k not in ("d_z", "d_z_note")), None)
    what = f"a gain of {score:g}" if score is not None else f"d_z {float(meaningful['d_z']):g}"
    lines = [f"What {n} seeds could detect at the spread seen (paired t-test, 80 % power: d_z {need[0]:.2f} at Holm's first step, alpha {alpha:g} / {family}; {need[1]:.2f} at its last, alpha {alpha:g}); "
             f"the registered meaningful effect is {what}:", "",
             f"| teacher | against | SD of the paired difference | smallest gain detected (first / last step) | power for {what} (first / last step) |", "|---|---|---|---|---|"]
    for _, x in mine.iterrows():
        sd = abs(x["gain"] / x["d_z"]) if x["d_z"] else math.nan
        d = (score / sd if sd > 0 else math.inf) if score is not None else float(meaningful["d_z"])
        lines.append(f"| {x['a']} | {x['b']} | {fmt(sd)} | {fmt(need[0] * sd)} / {fmt(need[1] * sd)} | {power(n, d, alpha / family):.2f} / {power(n, d, alpha):.2f} |")
    return lines


def power_lines(p: dict[str, Any]) -> str:
    """Power of the paired t-test at the protocol's meaningful d_z, per task: at Holm's first
    step (alpha / family) and its last (alpha), and the d_z with 80 % power at each."""
    alpha, d = float(p["rule"]["alpha"]), float(p["rule"]["meaningful"]["d_z"])
    family = len([t for t in p["teachers"] if t != p["rule"]["baseline"]])
    grid = np.round(np.arange(0.2, 3.0, 0.01), 2)
    lines = [f"| task | seeds | power at d_z {d} (alpha {alpha} / {family} / {alpha}) | d_z for 80 % power (first / last step) |", "|---|---|---|---|"]
    for task in p["tasks"]:
        n = len(seeds_arg(str(p["report"][task])))
        need = [next((x for x in grid if power(n, x, q) >= 0.8), math.nan) for q in (alpha / family, alpha)]
        lines.append(f"| {task} | {n} | {power(n, d, alpha / family):.2f} / {power(n, d, alpha):.2f} | {need[0]:.2f} / {need[1]:.2f} |")
    return "\n".join(lines)


if __name__ == "__main__":
    main()
