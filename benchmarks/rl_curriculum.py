"""A deep-RL student (Stable-Baselines3's PPO) learning to reach with a teacher choosing its goals.

    python benchmarks/rl_curriculum.py --reward dense          # the report runs; resumes
    python benchmarks/rl_curriculum.py --reward sparse
    python benchmarks/rl_curriculum.py --analyse               # every table, from curves.csv
    python benchmarks/rl_curriculum.py --power                 # the protocol's power table

The protocol, the decision rule and the results are in docs/rl_curriculum.md. The student is PPO
(SB3's defaults, 4 environments in one process, one torch thread) on a saggriac goal arm: 3
joints, reach 1, goals in the box [-2, 2]^2, of which the arm reaches the disc of radius 1 (a
fifth of the box), with a dense reward (minus the distance) or a sparse one (-1 until reached).
Every ``--every`` steps the deterministic policy is scored on the same 200 test goals, uniform in
the reachable disc. A teacher chooses the goal of every training episode through
:class:`saggriac.adapters.sb3.TeacherCallback` and is told the episode's closeness
``max(0, 1 - final distance / reach)``. ``--teachers`` takes the names of saggriac's teachers
of a continuous box (every class of ``saggriac.teachers`` built from ``(low, high, seed)``, by
its kind: random, sagg_riac, riac, alp_gmm, covar_gmm, ...) and ``oracle``, uniform over the
goals the body reaches (:class:`saggriac.bench.oracle.OracleTeacher`).

Seed s gives PPO's seed, the environments' seeds and the teacher's seed (children of
SeedSequence(s)); every teacher runs with the same s, so runs are paired by seed. A run is
(reward, teacher, seed): each finished run is appended to ``--out/curves.csv`` (every scoring)
and ``runs.csv`` (one row) at once, and a run already there is not run again, so the study may
stop and resume at any point. ``--analyse`` recomputes ``runs.csv``, ``comparisons.csv``,
``results.md`` and ``rl_curriculum.png`` from ``curves.csv`` alone.
"""

from __future__ import annotations

import argparse
import inspect
import math
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd
from tqdm import tqdm

from saggriac.bench.oracle import OracleTeacher
from saggriac.bench.rl import ARM, FOLD_TIP, GOAL_BLIND, N_ENVS, THRESHOLDS, arm_config, arm_reach, evaluate, folded, make_env, run_seeds, test_goals, train  # noqa: F401 (make_env: the study's environment, for its tests; FOLD_TIP and folded: the fold, shared with the evidence runner)
from saggriac.runs.resources import cpu_kind

REPO = Path(__file__).resolve().parents[1]
OUT = REPO / "docs" / "figures" / "rl_curriculum"
REWARDS = ("dense", "sparse")
# The task, fixed in the protocol before any run, and the distance within which a goal is
# reached per variant (the pilot's rule 2 moved sparse's from 0.2 to 0.3; docs/rl_curriculum.md,
# "The pilot"): the bench's deep-RL task, saggriac.bench.rl, which runs this study's code.
TASK = ARM
# Environment steps per run (the pilot's rule 1 set it) and scorings per run.
BUDGET = 120_000
SCORINGS = 10
REPORT_SEEDS = {"dense": list(range(500, 524)), "sparse": list(range(600, 612))}
PILOT_SEEDS = [102, 103]
NAMES = {"random": "random", "oracle": "oracle", "sagg_riac": "SAGG-RIAC", "riac": "RIAC", "alp_gmm": "ALP-GMM", "covar_gmm": "Covar-GMM", "adr": "ADR", "spdl": "SPDL", "goal_gan": "GoalGAN"}
# The teachers expected by the protocol (for the status of the study): every box teacher of
# saggriac plus the oracle; the field's three count once they are in saggriac.
EXPECTED_TEACHERS = 9
KEY = ["reward", "teacher", "seed"]
#: Columns of curves.csv and runs.csv read as text: pandas would read a commit hash such as
#: 540e725 as a number (inf), and a resumed study would write that back.
TEXT = {"commit": str}


def box_teachers() -> dict[str, type]:
    """saggriac's teachers of a continuous goal box, by kind: every class of saggriac.teachers
    with a kind whose constructor takes (low, high, seed)."""
    import saggriac.teachers as teachers

    found = {}
    for obj in vars(teachers).values():
        kind = getattr(obj, "_kind", "") if isinstance(obj, type) else ""
        if kind and list(inspect.signature(obj.__init__).parameters)[1:4] == ["low", "high", "seed"]:
            found[kind] = obj
    return found


def teacher_names() -> list[str]:
    return ["random", "oracle", *sorted(k for k in box_teachers() if k != "random")]


def make_teacher(name: str, seed: int):
    if name == "oracle":
        return OracleTeacher(arm_config(), seed)
    return box_teachers()[name](list(TASK["goal_low"]), list(TASK["goal_high"]), seed=seed)


def commit() -> str:
    """The code's commit, with "+dirty" if tracked files differ from it."""
    try:
        head = subprocess.run(["git", "-C", str(REPO), "rev-parse", "--short", "HEAD"], capture_output=True, text=True, check=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", str(REPO), "diff", "--quiet", "HEAD", "--", "benchmarks", "python", "crates"]).returncode != 0
        return head + ("+dirty" if dirty else "")
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def one_run(job: tuple) -> list[dict]:
    """One run: its scorings as rows of curves.csv. ``job``: (reward, teacher, seed, steps, every,
    threshold, commit[, joints]); with free joints (a protocol's task option) each scoring also
    records ``tip_spread`` (:func:`saggriac.bench.rl.evaluate`)."""
    reward, name, seed, steps, every, threshold, code, *rest = job
    joints = rest[0] if rest else "limited"
    reach = arm_reach()
    goals = test_goals(reach)
    rows: list[dict] = []
    # With the commit, the CPU's kind: deep-RL runs agree to the bit only on one kind (docs/bench.md).
    machine = cpu_kind()
    start, cpu = time.perf_counter(), time.process_time()

    def score(step: int, model, teacher) -> None:
        told = [g for g, _ in teacher.history]
        recent = np.array(told[-200:]) if told else np.zeros((0, 2))
        extra: dict[str, float] = {}
        success, distance = evaluate(model, goals, reward, threshold, joints, extra)
        share = float(np.mean(np.linalg.norm(recent, axis=1) <= reach)) if len(recent) else float("nan")
        # The limited arm's rows keep the second study's columns; the free arm's add its spread.
        spread = {} if joints == "limited" else dict(joints=joints, tip_spread=extra["tip_spread"])
        rows.append(dict(reward=reward, teacher=name, seed=seed, budget=steps, threshold=threshold, step=step, success=success, distance=distance, episodes=len(told), reachable_share=share, **spread, seconds=time.perf_counter() - start, cpu_seconds=time.process_time() - cpu, commit=code, machine=machine))

    train(reward, threshold, make_teacher(name, run_seeds(seed)[2]), seed, steps, every, score, joints=joints)
    if rows[-1]["step"] != steps:
        raise RuntimeError(f"run {reward}/{name}/{seed}: the last scoring was at step {rows[-1]['step']}, not at the budget {steps}")
    return rows


# ---------------------------------------------------------------- tables and statistics


def runs_table(curves: pd.DataFrame) -> pd.DataFrame:
    """One row per run, from its curve: final and half-budget outcomes, areas, focus, cost."""
    rows = []
    for (reward, teacher, seed), c in curves.groupby(KEY, sort=False):
        c = c.sort_values("step")
        budget = int(c["budget"].iloc[0])
        at = c.set_index("step")
        trained = c[c["step"] > 0]
        final, half = at.loc[budget], at.loc[budget // 2] if budget // 2 in at.index else None
        rows.append(dict(
            reward=reward, teacher=teacher, seed=int(seed), final_success=final["success"], final_distance=final["distance"],
            auc=trained["success"].mean(), auc_distance=trained["distance"].mean(),
            half_success=np.nan if half is None else half["success"], half_distance=np.nan if half is None else half["distance"],
            start_success=at.loc[0, "success"], start_distance=at.loc[0, "distance"],
            reachable_share=trained["reachable_share"].mean(), final_reachable_share=final["reachable_share"], episodes=int(final["episodes"]),
            budget=budget, threshold=final["threshold"], seconds=final["seconds"], cpu_seconds=final["cpu_seconds"], commit=final["commit"],
            **({"final_tip_spread": final["tip_spread"]} if "tip_spread" in c else {}),
            **({"machine": final["machine"]} if "machine" in c else {}),
        ))
    return pd.DataFrame(rows)


def paired_rows(wide: pd.DataFrame, pairs: list[tuple[str, str]], metric: str, better: str, family: str) -> pd.DataFrame:
    """For each (a, b): the paired gain of a over b (b - a for a metric where lower is better,
    a - b otherwise; positive: a is better), its 95 % CI, t-test and d_z; Holm over the rows."""
    from saggriac.analysis.statistics import holm, paired

    rows = []
    for a, b in pairs:
        sign = -1.0 if better == "lower" else 1.0
        r = paired(sign * wide[a].to_numpy(), sign * wide[b].to_numpy())
        rows.append(dict(family=family, metric=metric, a=a, b=b, n=len(wide), mean_a=wide[a].mean(), mean_b=wide[b].mean(), gain=r["mean_diff"], ci_low=r["ci_low"], ci_high=r["ci_high"], t=r["statistic"], p_value=r["p_value"], d_z=r["effect"]))
    table = pd.DataFrame(rows)
    if len(table):
        table["p_holm"] = holm(table["p_value"].to_numpy())
        table["verdict"] = [("helps" if g > 0 else "hurts") if p < 0.05 else "no difference shown" for g, p in zip(table["gain"], table["p_holm"])]
    return table


def analyse_reward(runs: pd.DataFrame, reward: str) -> tuple[pd.DataFrame, list[str], dict]:
    """The decision and secondary families of one variant, on its complete seeds."""
    r = runs[runs["reward"] == reward]
    teachers = [t for t in teacher_order(r["teacher"].unique())]
    counts = r.groupby("seed")["teacher"].nunique()
    seeds = sorted(counts.index[counts == len(teachers)])
    r = r[r["seed"].isin(seeds)]
    info = dict(teachers=teachers, seeds=seeds)
    if "random" not in teachers or len(seeds) < 2:
        return pd.DataFrame(), teachers, info
    others = [t for t in teachers if t != "random"]
    learners = [t for t in others if t != "oracle"]

    def wide(metric: str) -> pd.DataFrame:
        return r.pivot(index="seed", columns="teacher", values=metric)

    tables = [paired_rows(wide("final_distance"), [(t, "random") for t in others], "final_distance", "lower", "primary")]
    if "oracle" in teachers and learners:
        vs = paired_rows(wide("final_distance"), [(t, "oracle") for t in learners], "final_distance", "lower", "against the oracle")
        w = wide("final_distance")
        oracle_gain = (w["random"] - w["oracle"]).mean()
        vs["share_of_oracle_gain"] = [(w["random"] - w[t]).mean() / oracle_gain if oracle_gain != 0 else np.nan for t in learners]
        tables.append(vs)
    for metric, better in (("final_success", "higher"), ("auc", "higher"), ("auc_distance", "lower"), ("half_distance", "lower"), ("half_success", "higher")):
        tables.append(paired_rows(wide(metric), [(t, "random") for t in others], metric, better, "secondary"))
    # Has random's curve flattened? Its distance over the last fifth of the budget (last two scorings).
    return pd.concat(tables, ignore_index=True).assign(reward=reward), teachers, info


def teacher_order(names) -> list[str]:
    known = list(NAMES)
    return sorted(names, key=lambda t: (known.index(t) if t in known else len(known), t))


def flattening(curves: pd.DataFrame, reward: str, seeds: list[int]) -> dict | None:
    """Random's final distance minus its distance at 0.8 B (paired over seeds): how much its
    curve still moves over the last fifth of the budget (its last two scorings)."""
    from saggriac.analysis.statistics import paired

    c = curves[(curves["reward"] == reward) & (curves["teacher"] == "random") & curves["seed"].isin(seeds)]
    if c.empty:
        return None
    budget = int(c["budget"].iloc[0])
    w = c.pivot(index="seed", columns="step", values="distance")
    earlier = int(round(0.8 * budget))
    if earlier not in w.columns or len(w) < 2:
        return None
    return dict(step=earlier, budget=budget, **paired(w[budget].to_numpy(), w[earlier].to_numpy()))


def task_options(out: Path) -> dict[str, str]:
    """The task's changes a study registers in ``out/protocol.json`` ("task": {"joints": "free"});
    none for the second study and its replication."""
    import json

    path = out / "protocol.json"
    given = json.loads(path.read_text()).get("task", {}) if path.exists() else {}
    unknown = sorted(set(given) - {"joints"})
    if unknown:
        raise SystemExit(f"{path}: the task options {unknown} are unknown; a protocol may change only 'joints'")
    return {k: str(v) for k, v in given.items()}


def design(out: Path) -> dict[str, dict]:
    """The report runs of the study in ``out``: per reward, its seeds and teachers. A study of
    its own (a replication) registers them in ``out/protocol.json`` before its runs; without
    one, the second study's (REPORT_SEEDS, every teacher)."""
    path = out / "protocol.json"
    if path.exists():
        import json

        given = json.loads(path.read_text())
        return {r: {"seeds": seeds_arg(v["seeds"]), "teachers": list(v["teachers"])} for r, v in given["report"].items()}
    return {r: {"seeds": REPORT_SEEDS[r], "teachers": None} for r in REWARDS}


def status(curves: pd.DataFrame, plan: dict[str, dict] | None = None) -> list[str]:
    """Which runs of the protocol (``plan``, from :func:`design`) are done and which remain."""
    lines = []
    known = len(teacher_names())
    plan = plan or {r: {"seeds": REPORT_SEEDS[r], "teachers": None} for r in REWARDS}
    for reward, want_runs in plan.items():
        c = curves[curves["reward"] == reward] if len(curves) else curves
        done = c.drop_duplicates(KEY) if len(c) else c
        seeds = want_runs["seeds"]
        report = done[done["seed"].isin(seeds)] if len(done) else done
        n_teachers = EXPECTED_TEACHERS if want_runs["teachers"] is None else len(want_runs["teachers"])
        named = f"{n_teachers} teachers" if want_runs["teachers"] is None else ", ".join(want_runs["teachers"])
        lines.append(f"- {reward}: {len(report)} of the protocol's {n_teachers * len(seeds)} runs done ({named} x seeds {seeds[0]}-{seeds[-1]}; {known} teachers exist in this checkout)")
    return lines


def settings_line(runs: pd.DataFrame) -> str:
    """The task and the learner as the runs used them, so that a page quoting them quotes a table."""
    from stable_baselines3 import PPO

    from saggriac.bench.rl import EPISODE_STEPS, N_TEST

    budgets = sorted(set(runs["budget"].astype(int))) if len(runs) else [BUDGET]
    n_steps = inspect.signature(PPO.__init__).parameters["n_steps"].default
    return (f"Settings: a {TASK['n_joints']}-joint arm of length {TASK['arm_length']}, joint limits +-{TASK['joint_limit']:.4f}, joint step {TASK['max_joint_step']}; "
            f"goals in [{TASK['goal_low'][0]}, {TASK['goal_high'][0]}] x [{TASK['goal_low'][1]}, {TASK['goal_high'][1]}]; episodes of {EPISODE_STEPS} steps; "
            f"{N_ENVS} environments; {N_TEST} test goals; reached within {', '.join(f'{k} {v}' for k, v in THRESHOLDS.items())}; "
            f"budget {', '.join(map(str, budgets))} steps, {SCORINGS} scorings; PPO's defaults ({n_steps} steps per environment between updates).")


def cost_lines(runs: pd.DataFrame) -> list[str]:
    """What the runs cost, per reward and in all, by their own clocks."""
    if not len(runs):
        return []
    parts = [f"{r} {runs.loc[runs['reward'] == r, 'cpu_seconds'].sum() / 3600:.2f}" for r in REWARDS if (runs["reward"] == r).any()]
    return [f"Cost: {len(runs)} runs, {runs['cpu_seconds'].sum() / 3600:.2f} CPU hours ({', '.join(parts)}), {runs['seconds'].sum() / 3600:.2f} wall hours; "
            f"{runs['cpu_seconds'].mean():.0f} CPU s a run on average."]


def fmt(x: float, digits: int = 3, sign: bool = False) -> str:
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "-"
    return f"{x:+.{digits}f}" if sign else f"{x:.{digits}f}"


def fold_line(runs: pd.DataFrame, teachers: list[str]) -> str:
    if "final_tip_spread" in runs:
        blind = runs["final_tip_spread"] < GOAL_BLIND
        counts = ", ".join(f"{NAMES.get(t, t)} {int(blind[runs['teacher'] == t].sum())}/{int((runs['teacher'] == t).sum())}" for t in teachers)
        return f"Runs whose final policy ends at one tip whatever the goal (goal-blind; free joints cannot fold): {counts}." + near_blind(runs, teachers)
    fold = folded(runs)
    counts = ", ".join(f"{NAMES.get(t, t)} {int(fold[runs['teacher'] == t].sum())}/{int((runs['teacher'] == t).sum())}" for t in teachers)
    return f"Runs whose final policy folds the arm onto its joint limits (the tip at ({FOLD_TIP[0]:.4g}, 0) for every goal): {counts}."


#: A look chosen after the free-joint runs (docs/rl_curriculum.md says so): a final tip spread
#: below this is a student that ends near one place whatever the goal.
NEAR_BLIND = 0.2


def near_blind(runs: pd.DataFrame, teachers: list[str]) -> str:
    """Descriptive, not registered: the runs whose final tips spread less than NEAR_BLIND, per
    teacher, the gap around it, and how both groups end."""
    spread = runs["final_tip_spread"]
    low = spread < NEAR_BLIND
    if not low.any() or low.all():
        return ""
    counts = ", ".join(f"{NAMES.get(t, t)} {int(low[runs['teacher'] == t].sum())}/{int((runs['teacher'] == t).sum())}" for t in teachers)
    oracle = spread[runs["teacher"] == "oracle"]
    lines = [f"\n\nNot registered (chosen after the runs): runs whose final tips spread less than {NEAR_BLIND} (nearly goal-blind): {counts}.",
             f"Spreads: every run below {spread[low].max():.2f} or above {spread[~low].min():.2f}" + (f"; the oracle's {oracle.min():.2f}-{oracle.max():.2f}" if len(oracle) else "") + ".",
             f"Nearly blind: {int(low.sum())} runs, final distance {runs.loc[low, 'final_distance'].mean():.3f}, success {runs.loc[low, 'final_success'].mean():.3f}; "
             f"the other {int((~low).sum())}: {runs.loc[~low, 'final_distance'].mean():.3f}, {runs.loc[~low, 'final_success'].mean():.3f}."]
    return "\n".join(lines)


def analyse(out: Path) -> str:
    """Every table of the page, recomputed from ``out/curves.csv``."""
    from saggriac.files import write_file

    curves = read_table(out / "curves.csv")
    runs = runs_table(curves)
    write_file(out / "runs.csv", lambda tmp: runs.to_csv(tmp, index=False), what="the runs table", overwrite=True)
    plan = design(out)
    lines = ["# RL curriculum: results recomputed from curves.csv", "", "Status of the protocol's report runs:", "", *status(curves, plan), "", settings_line(runs), "", *cost_lines(runs), ""]
    all_tables = []
    for reward in REWARDS:
        if not (runs["reward"] == reward).any():
            continue
        table, teachers, info = analyse_reward(runs, reward)
        r = runs[(runs["reward"] == reward) & runs["seed"].isin(info["seeds"])]
        seeds = info["seeds"]
        want = plan.get(reward, {"seeds": REPORT_SEEDS[reward], "teachers": None})
        complete = (len(teachers) >= EXPECTED_TEACHERS if want["teachers"] is None else set(want["teachers"]) <= set(teachers)) and set(want["seeds"]) <= set(seeds)
        budget = int(r["budget"].iloc[0]) if len(r) else 0
        head = f"## {reward} reward: {len(seeds)} complete seeds ({', '.join(map(str, seeds[:3]))}{', ...' if len(seeds) > 3 else ''}), {len(teachers)} teachers, {budget} steps"
        lines += [head, ""]
        if not complete:
            lines += ["**Interim: the protocol's runs of this variant are not all done; these numbers decide nothing.**", ""]
        lines += ["| teacher | final distance (mean ± sd) | final success | AUC (success) | AUC (distance) | distance at B/2 | goals in reach | s per run | CPU s per run |", "|---|---|---|---|---|---|---|---|---|"]
        for t in teachers:
            x = r[r["teacher"] == t]
            if len(x):
                lines.append(f"| {NAMES.get(t, t)} | {fmt(x['final_distance'].mean())} ± {fmt(x['final_distance'].std(ddof=1))} | {fmt(x['final_success'].mean())} | {fmt(x['auc'].mean())} | {fmt(x['auc_distance'].mean())} | {fmt(x['half_distance'].mean())} | {fmt(x['reachable_share'].mean(), 2)} | {x['seconds'].mean():.0f} | {x['cpu_seconds'].mean():.0f} |")
        lines += ["", fold_line(r, teachers)]
        flat = flattening(curves, reward, seeds)
        if flat:
            lines += ["", f"Random's final distance minus its distance at {flat['step']} steps (last fifth of the budget): {fmt(flat['mean_diff'], sign=True)} [{fmt(flat['ci_low'], sign=True)}, {fmt(flat['ci_high'], sign=True)}], p = {flat['p_value']:.3g}."]
        for family, title in (("primary", "primary: final distance, each teacher against random (gain = random's distance - the teacher's; Holm over the family)"), ("against the oracle", "what the oracle says: final distance, each teacher against the oracle (gain = oracle's - the teacher's); share of the oracle's gain over random"), ("secondary", "secondary (each metric its own Holm family; gain > 0: the teacher is better)")):
            part = table[table["family"] == family] if len(table) else table
            if not len(part):
                continue
            extra = "share_of_oracle_gain" in part.columns and family == "against the oracle"
            lines += ["", f"### {title}", "", "| metric | teacher | against | gain | 95 % CI | t | p | p (Holm) | d_z | verdict |" + (" share of oracle's gain |" if extra else ""), "|---|---|---|---|---|---|---|---|---|---|" + ("---|" if extra else "")]
            for _, x in part.iterrows():
                row = f"| {x['metric']} | {NAMES.get(x['a'], x['a'])} | {NAMES.get(x['b'], x['b'])} | {fmt(x['gain'], sign=True)} | [{fmt(x['ci_low'], sign=True)}, {fmt(x['ci_high'], sign=True)}] | {fmt(x['t'], 2)} | {x['p_value']:.3g} | {x['p_holm']:.3g} | {fmt(x['d_z'], 2)} | {x['verdict']} |"
                lines.append(row + (f" {fmt(x['share_of_oracle_gain'], 2)} |" if extra else ""))
        lines.append("")
        all_tables.append(table)
    comparisons = pd.concat(all_tables, ignore_index=True) if all_tables else pd.DataFrame()
    write_file(out / "comparisons.csv", lambda tmp: comparisons.to_csv(tmp, index=False), what="the comparisons", overwrite=True)
    text = "\n".join(lines) + "\n"
    write_file(out / "results.md", lambda tmp: Path(tmp).write_text(text), what="the results", overwrite=True)
    figure(out, curves)
    return text


def figure(out: Path, curves: pd.DataFrame) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rewards = [r for r in REWARDS if (curves["reward"] == r).any()]
    fig, axes = plt.subplots(len(rewards), 2, figsize=(11, 4 * len(rewards)), squeeze=False)
    for (ax, bx), reward in zip(axes, rewards):
        c = curves[curves["reward"] == reward]
        for t in teacher_order(c["teacher"].unique()):
            g = c[c["teacher"] == t].groupby("step")["distance"]
            m, s, n = g.mean(), g.std(ddof=1), g.count()
            ax.plot(m.index, m.values, label=NAMES.get(t, t))
            ax.fill_between(m.index, m - s / np.sqrt(n), m + s / np.sqrt(n), alpha=0.15)
            f = c[(c["teacher"] == t) & (c["step"] > 0)].groupby("step")["reachable_share"].mean()
            bx.plot(f.index, f.values, label=NAMES.get(t, t))
        ax.set(xlabel="environment steps", ylabel="mean final distance to reachable test goals", title=f"{reward} reward: PPO student (mean ± s.e.; lower is better)")
        bx.set(xlabel="environment steps", ylabel="share of the last 200 goals in reach", title="teachers' focus (a fifth of the box is in reach)")
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "rl_curriculum.png", dpi=110)
    plt.close(fig)


# ---------------------------------------------------------------- power


def power(n: int, d: float, alpha: float) -> float:
    """Power of a two-sided paired t-test with n pairs at effect d_z (noncentral t)."""
    from scipy import stats

    df, nc = n - 1, d * math.sqrt(n)
    crit = stats.t.ppf(1 - alpha / 2, df)
    return float(stats.nct.sf(crit, df, nc) + np.nan_to_num(stats.nct.cdf(-crit, df, nc)))


def power_table(family: int = EXPECTED_TEACHERS - 1) -> str:
    first = 0.05 / family
    grid = np.round(np.arange(0.2, 2.5, 0.01), 2)
    lines = [f"power of a paired t-test: Holm's first step (alpha = 0.05 / {family}) / its last (alpha = 0.05)", "", "| seeds | d_z 0.5 | d_z 0.75 | d_z 1.0 | d_z 1.25 | d_z for 80 % power |", "|---|---|---|---|---|---|"]
    for n in (12, 24, 28):
        cells = [f"{power(n, d, first):.2f} / {power(n, d, 0.05):.2f}" for d in (0.5, 0.75, 1.0, 1.25)]
        need = [next(d for d in grid if power(n, d, a) >= 0.8) for a in (first, 0.05)]
        lines.append(f"| {n} | " + " | ".join(cells) + f" | {need[0]:.2f} / {need[1]:.2f} |")
    seeds = next(n for n in range(3, 200) if power(n, 0.75, first) >= 0.8)
    lines += ["", f"seeds for 80 % power at d_z = 0.75, Holm's first step: {seeds}"]
    return "\n".join(lines)


def pilot_rules(curves: pd.DataFrame) -> str:
    """The protocol's two pilot rules, applied to the pilot's curves (random, tuning seeds, dense
    and sparse, 200,000 steps): the budget from the cost, the sparse threshold from learning."""
    runs = runs_table(curves)
    per_k = float((runs["seconds"] / runs["budget"] * 1000).mean())
    n_runs = EXPECTED_TEACHERS * (len(REPORT_SEEDS["dense"]) + len(REPORT_SEEDS["sparse"]))
    fits = [b for b in range(100_000, 400_001, 20_000) if n_runs * per_k * b / 1000 <= 0.9 * 8 * 3600]
    budget = max(fits) if fits else 100_000
    sparse = runs[runs["reward"] == "sparse"]
    learnt = float((sparse["final_success"] - sparse["start_success"]).mean())
    lines = [
        f"pilot: {len(runs)} runs; {per_k:.3f} wall s per 1,000 steps (CPU {float((runs['cpu_seconds'] / runs['budget'] * 1000).mean()):.3f}); per run: " + ", ".join(f"{r.reward} {r.seed}: {r.seconds:.0f} s" for r in runs.itertuples()),
        f"rule 1: {n_runs} runs x {per_k:.3f} s x B / 1,000 <= 25,920 s -> B = {budget} ({n_runs * per_k * budget / 3600 / 1000:.2f} core-hours)" + ("" if fits else " (even 100,000 exceeds the allowance)"),
        f"rule 2: sparse random's final success minus its start: {learnt:+.3f} -> sparse threshold {0.3 if learnt <= 0.02 else 0.2}",
    ]
    return "\n".join(lines)


# ---------------------------------------------------------------- the command


def seeds_arg(text: str) -> list[int]:
    out: list[int] = []
    for part in text.split(","):
        a, _, b = part.partition("-")
        out += list(range(int(a), int(b or a) + 1))
    return out


def read_table(path: Path) -> pd.DataFrame:
    """curves.csv or runs.csv as written: the commit stays text."""
    return pd.read_csv(path, dtype=TEXT)


def load_curves(out: Path) -> pd.DataFrame:
    path = out / "curves.csv"
    return read_table(path) if path.exists() else pd.DataFrame(columns=[*KEY, "budget", "threshold", "step"])


def main(argv: list[str] | None = None) -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", type=Path, default=OUT, help=f"where curves.csv and the tables are (default: {OUT.relative_to(REPO)})")
    p.add_argument("--reward", choices=REWARDS, default="dense", help="the student's reward: dense (minus the distance) or sparse (-1 until reached)")
    p.add_argument("--seeds", type=seeds_arg, default=None, help="default: the protocol's report seeds of the variant (--out/protocol.json's, else dense 500-523, sparse 600-611); tuning seeds: 100-114")
    p.add_argument("--steps", type=int, default=BUDGET, help=f"environment steps per run (default: the protocol's budget, {BUDGET})")
    p.add_argument("--every", type=int, default=None, help=f"steps between scorings (default: steps / {SCORINGS})")
    p.add_argument("--teachers", nargs="+", default=["all"], help="teacher names, or 'all' (every box teacher of saggriac and the oracle)")
    p.add_argument("--workers", type=int, default=1, help="runs at a time, one process and one torch thread each")
    p.add_argument("--analyse", action="store_true", help="only recompute the tables and the figure from --out/curves.csv")
    p.add_argument("--power", action="store_true", help="print the protocol's power table and stop")
    p.add_argument("--pilot", action="store_true", help="apply the protocol's pilot rules to --out/curves.csv and stop")
    a = p.parse_args(argv)
    if a.power:
        print(power_table())
        return
    if a.pilot:
        print(pilot_rules(read_table(a.out / "curves.csv")))
        return
    if a.analyse:
        if not (a.out / "curves.csv").exists():
            p.error(f"--analyse reads {a.out / 'curves.csv'}, which does not exist")
        print(analyse(a.out))
        return
    known = teacher_names()
    teachers = known if a.teachers == ["all"] else a.teachers
    unknown = [t for t in teachers if t not in known]
    if unknown:
        p.error(f"--teachers: unknown teacher(s) {unknown}; saggriac here has {known} (or 'all')")
    every = a.every if a.every is not None else a.steps // SCORINGS
    if a.steps <= 0 or every <= 0 or a.steps % every or every % N_ENVS:
        p.error(f"--every must divide --steps and be a multiple of {N_ENVS}; got --steps {a.steps} --every {every}")
    if a.workers < 1:
        p.error(f"--workers must be an int >= 1; got {a.workers}")
    seeds = a.seeds if a.seeds is not None else design(a.out).get(a.reward, {"seeds": REPORT_SEEDS[a.reward]})["seeds"]
    threshold = THRESHOLDS[a.reward]
    a.out.mkdir(parents=True, exist_ok=True)
    curves = load_curves(a.out)
    mine = curves[curves["reward"] == a.reward]
    clash = mine[(mine["budget"] != a.steps) | (mine["threshold"] != threshold)]
    if len(clash):
        p.error(f"{a.out / 'curves.csv'} holds {a.reward} runs with budget {sorted(set(clash['budget']))} and threshold {sorted(set(clash['threshold']))}; this call has --steps {a.steps} and threshold {threshold}: the runs would not be comparable. Use another --out.")
    done = set(map(tuple, curves[KEY].drop_duplicates().itertuples(index=False, name=None))) if len(curves) else set()
    code = commit()
    joints = task_options(a.out).get("joints", "limited")
    jobs = [(a.reward, t, s, a.steps, every, threshold, code, *([joints] if joints != "limited" else [])) for s in seeds for t in teachers if (a.reward, t, s) not in done]
    print(f"{len(jobs)} runs to do, {len(seeds) * len(teachers) - len(jobs)} already in {a.out / 'curves.csv'}", file=sys.stderr)
    if a.workers == 1:
        results = map(one_run, jobs)
        pool = None
    else:
        import multiprocessing as mp

        from saggriac.runs.resources import share_cores

        pool = mp.get_context("spawn").Pool(a.workers, initializer=share_cores, initargs=(a.workers,))
        results = pool.imap_unordered(one_run, jobs)
    from saggriac.files import write_file

    try:
        for rows in tqdm(results, total=len(jobs), desc=f"{a.reward} runs"):
            curves = pd.concat([curves, pd.DataFrame(rows)], ignore_index=True) if len(curves) else pd.DataFrame(rows)
            write_file(a.out / "curves.csv", lambda tmp: curves.to_csv(tmp, index=False), what="the curves", overwrite=True)
            write_file(a.out / "runs.csv", lambda tmp: runs_table(curves).to_csv(tmp, index=False), what="the runs table", overwrite=True)
    finally:
        if pool is not None:
            pool.close()
            pool.join()
    print(analyse(a.out))


if __name__ == "__main__":
    main()
