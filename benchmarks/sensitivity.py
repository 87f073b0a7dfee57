"""The pre-registered sensitivity study of docs/sensitivity.md, in one command.

    python benchmarks/sensitivity.py --out sensitivity/ [--workers N] [--seeds 15] [--experiments exp1 exp2 explauto]
    python benchmarks/sensitivity.py --out OUT --base current --conditions sagg_riac sagg_random --experiments exp1 exp2 [--previous runs.csv]

One parameter at a time around each preset's defaults, on the tuning seeds 100-114 only (seeds
0-14 are never run here). Every cell is a saggriac study in its own folder under
``OUT/<experiment>/<cell>``, so an interrupted run resumes where it stopped. When every cell is
done, the decision rule of docs/sensitivity.md is applied mechanically; if some values qualify,
their combination is run once more (``OUT/<experiment>/combined``) and checked against the
defaults. Writes ``OUT/runs.csv`` (one row per run), ``OUT/cells.csv`` (every cell, condition
and metric against its reference), ``OUT/decisions.csv``, ``OUT/results.md`` and
``OUT/sensitivity.png``.

Runs are evaluated only at step 0 and at their last step (``n_evals=1``): every metric of the
study is read at the last step, and the evaluation does not change what a run learns (the last
row is the same bits with any schedule; tests/core/test_eval_schedule.py).

Reruns (docs/sensitivity.md, "Deviations"):

- ``--base registered`` (default) starts every cell from the defaults the protocol registered,
  with the reading of eq. 2 the first study ran (``interest_divisor="window"``, the only one
  before saggriac 0.3). ``--base current`` starts from today's presets as they are.
- ``--conditions`` keeps only these conditions in every cell. A parameter cell left with no
  condition is not run, and the Holm family of an experiment is the parameter cells actually
  run. A parameter the protocol runs on more conditions than these is decided in two stages:
  if one of its values qualifies on the conditions run, its other conditions (and the reference
  cell's) are run too, into ``OUT/<experiment>/<cell>+rest``, and the rule is applied again with
  every condition before anything is decided. The combination check runs every condition, as
  registered.
- ``--previous runs.csv`` compares every cell, condition and seed with an earlier study's
  runs.csv (paired by seed): ``OUT/previous.csv`` and a section of ``OUT/results.md``.
"""

from __future__ import annotations

import argparse
import concurrent.futures as cf
import json
import math
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

import saggriac as sg
from saggriac.analysis.statistics import holm, paired
from saggriac.study import COST_HINT

TUNING_SEEDS = tuple(range(100, 115))
SAGG = ("sagg_riac", "sagg_random")
ACT = ("actuator_random", "actuator_riac")
ALL = ("sagg_riac", "sagg_random", "actuator_random", "actuator_riac")


@dataclass(frozen=True)
class Parameter:
    name: str
    default: Any  # as docs/sensitivity.md states it; checked against the preset
    values: tuple
    conditions: tuple[str, ...]


# The table of docs/sensitivity.md, in its order.
PARAMETERS = (
    Parameter("min_c", -1.0, (-0.5,), ("sagg_riac",)),
    Parameter("eps_c", -0.05, (-0.02, -0.1), ("sagg_riac",)),
    Parameter("zeta", 20, (10, 40), ("sagg_riac",)),
    Parameter("min_child", 5, (10, 15), ("sagg_riac",)),
    Parameter("eps_max", 0.25, (0.1, 0.5), SAGG),
    Parameter("timeout_in_exploration", False, (True,), SAGG),
    Parameter("timeout_factor", 2.0, (1.0, 4.0), SAGG),
    Parameter("k_neighbours", 45, (20, 90), SAGG),
    Parameter("ridge", 1e-3, (1e-4, 1e-2), SAGG),
    Parameter("explore_step", 0.01, (0.005, 0.02), SAGG),
    Parameter("max_joint_step", 0.05, (0.02, 0.1), ALL),
    Parameter("babble_step", 0.01, (0.005, 0.02), ACT),
    Parameter("actuator_candidates", 16, (4, 64), ("actuator_riac",)),
)
# Diagnostics: published, never a change of default.
DIAGNOSTICS = {"g_max=20": {"g_max": 20}, "g_max=20,min_c=-0.5": {"g_max": 20, "min_c": -0.5}}
EPISODIC = Parameter("competence", "relative", ("absolute",), SAGG)

PRIMARY = "reach_error"
SECONDARY = ("pred_error", "dx_error", "goals", "share_exploration", "share_on_reachable_goals", "reachable_goal_share_2nd_half")
MICRO_EXPERIMENTS = ("exp1", "exp2")
HARM = 0.10  # rule 2: the CI's upper end must stay below +10 % of the default's mean
ALPHA = 0.05


@dataclass
class Cell:
    experiment: str
    name: str  # folder name: "reference", "k_neighbours", "g_max=20", "combined"
    study: sg.Study
    kind: str  # "reference" | "parameter" | "diagnostic" | "combined"
    parameter: Parameter | None = None
    changes: dict[str, Any] = field(default_factory=dict)
    folder: str | None = None  # when not ``name``: the conditions a two-stage cell adds later

    @property
    def path(self) -> str:
        return f"{self.experiment}/{self.folder or self.name}"


STEPS: int | None = None  # --steps: a quick try of the script, never the study
BASE = "registered"  # --base
CONDITIONS: tuple[str, ...] = ALL  # --conditions
# What the first study ran without registering it: eq. 2 of a young region divided by its own
# count w (saggriac <= 0.2 had no other reading; Config.interest_divisor since 0.3).
REGISTERED_READINGS = {"interest_divisor": "window"}


def base_config(experiment: str) -> sg.Config:
    """With ``--base registered``, the preset with the defaults docs/sensitivity.md registered and
    the reading of eq. 2 the first study ran, whatever today's defaults are: the study applied its
    own decisions (babble_step, explauto's competence), and a rerun must still start from what it
    tested. With ``--base current``, today's preset as it is."""
    extra = {} if STEPS is None else {"n_steps": STEPS}
    if BASE == "current":
        return sg.Config.from_preset(experiment, n_evals=1, **extra)
    registered = {p.name: p.default for p in (*PARAMETERS, EPISODIC)}
    return sg.Config.from_preset(experiment, n_evals=1, **REGISTERED_READINGS, **registered, **extra)


def changed_since(experiments: list[str]) -> list[str]:
    """The registered defaults (and readings) that today's presets no longer have (the study's
    own decisions, or a later change), to say so before the run."""
    out = []
    registered = {**REGISTERED_READINGS, **{p.name: p.default for p in (*PARAMETERS, EPISODIC)}}
    for exp in experiments:
        now = sg.Config.from_preset(exp)
        out += [f"{exp}.{k}: registered {v!r}, now {getattr(now, k)!r}" for k, v in registered.items() if getattr(now, k) != v]
    return out


def kept(conditions: tuple[str, ...]) -> tuple[str, ...]:
    """The conditions of ``conditions`` that --conditions keeps, in the protocol's order."""
    return tuple(c for c in conditions if c in CONDITIONS)


def plan(experiments: list[str], seeds: tuple[int, ...]) -> list[Cell]:
    cells = []
    for exp in experiments:
        base = base_config(exp)
        if exp == "explauto":
            if kept(SAGG):
                cells.append(Cell(exp, "reference", sg.Study(base, kept(SAGG), seeds), "reference"))
            if kept(EPISODIC.conditions):
                cells.append(Cell(exp, EPISODIC.name, sg.Study(base, kept(EPISODIC.conditions), seeds, {EPISODIC.name: list(EPISODIC.values)}), "parameter", EPISODIC))
            continue
        cells.append(Cell(exp, "reference", sg.Study(base, kept(ALL), seeds), "reference"))
        for p in PARAMETERS:
            if kept(p.conditions):
                cells.append(Cell(exp, p.name, sg.Study(base, kept(p.conditions), seeds, {p.name: list(p.values)}), "parameter", p))
        if "sagg_riac" in CONDITIONS:
            for name, changes in DIAGNOSTICS.items():
                cells.append(Cell(exp, name, sg.Study(base.replace(**changes), ("sagg_riac",), seeds), "diagnostic", changes=changes))
    return cells


def rest_cells(cells: list[Cell], params: set[str], conditions: tuple[str, ...], seeds: tuple[int, ...]) -> list[Cell]:
    """The second stage: the conditions --conditions left out, for the cells of ``params`` and, if
    ``conditions`` needs them, the reference cells; only what ``cells`` does not hold yet."""
    have: dict[tuple[str, str], set[str]] = {}
    for c in cells:
        have.setdefault((c.experiment, c.name), set()).update(c.study.conditions)
    out = []
    for exp in dict.fromkeys(c.experiment for c in cells):
        base = base_config(exp)
        universe = SAGG if exp == "explauto" else ALL
        wanted = {p.name: p for p in ((EPISODIC,) if exp == "explauto" else PARAMETERS) if p.name in params}
        for name, p in wanted.items():
            missing = tuple(c for c in p.conditions if c not in have.get((exp, name), set()))
            if missing:
                out.append(Cell(exp, name, sg.Study(base, missing, seeds, {name: list(p.values)}), "parameter", p, folder=f"{name}+rest"))
        needed = set(conditions).union(*(p.conditions for p in wanted.values()))
        missing = tuple(c for c in universe if c in needed and c not in have.get((exp, "reference"), set()))
        if missing:
            out.append(Cell(exp, "reference", sg.Study(base, missing, seeds), "reference", folder="reference+rest"))
    return out


def cost(cell: Cell) -> float:
    return sum(t.config["n_steps"] * COST_HINT.get(t.condition, 1.0) for t in cell.study.tasks())


def run_cells(cells: list[Cell], out: Path, workers: int) -> None:
    """Every cell's study, costliest first, ``workers`` studies at a time with one process each."""
    todo = sorted(cells, key=cost, reverse=True)
    total = sum(len(c.study.tasks()) for c in todo)
    done = 0
    t0 = time.perf_counter()

    def one(cell: Cell) -> tuple[Cell, sg.study.StudyResult, float]:
        s = time.perf_counter()
        res = sg.run_study(cell.study, out / cell.path, n_workers=1, progress=False)
        return cell, res, time.perf_counter() - s

    with cf.ThreadPoolExecutor(max_workers=workers) as pool:
        futures = [pool.submit(one, c) for c in todo]
        for fut in cf.as_completed(futures):
            cell, res, secs = fut.result()
            done += res.n_computed + res.n_skipped
            print(f"[{time.perf_counter() - t0:7.0f} s] {cell.path}: {res.n_computed} runs computed, {res.n_skipped} already there ({secs:.0f} s); {done}/{total} runs", flush=True)


def read_runs(cells: list[Cell], out: Path) -> pd.DataFrame:
    """One row per run: the cell, its changed value, the condition, the seed and every metric."""
    rows = []
    for cell in cells:
        folder = out / cell.path
        for task in cell.study.tasks():
            run_dir = folder / task.path
            manifest = json.loads((run_dir / "run.json").read_text())
            last = pd.read_parquet(run_dir / "metrics.parquet").iloc[-1]
            tb = manifest["time_budget"]
            goals = pd.read_parquet(run_dir / "goals.parquet")
            late = goals[goals["step_start"] >= manifest["config"]["n_steps"] / 2]
            reach = sg.Config.from_saved(manifest["config"]).reach
            cols = [c for c in ("goal_x", "goal_y", "goal_z") if c in goals.columns]
            inside = np.sqrt((late[cols].to_numpy(float) ** 2).sum(axis=1)) <= reach
            value = task.params[cell.parameter.name] if cell.kind == "parameter" else None
            rows.append(
                {
                    "experiment": cell.experiment,
                    "cell": cell.name,
                    "kind": cell.kind,
                    "value": json.dumps(value) if value is not None else "",
                    "condition": task.condition,
                    "seed": task.seed,
                    **{m: float(last[m]) for m in ("reach_error", "pred_error", "dx_error")},
                    "goals": tb["goals"],
                    "share_exploration": tb["share_exploration"],
                    "share_on_reachable_goals": tb.get("share_on_reachable_goals", math.nan),
                    "reachable_goal_share_2nd_half": float(inside.mean()) if len(late) else math.nan,
                    "wall_seconds": manifest["wall_seconds"],
                }
            )
    return pd.DataFrame(rows)


def _ci(d: np.ndarray) -> tuple[float, float, float, float]:
    """Mean of d, its 95 % CI and the two-sided p of a t-test against 0 (statistics.paired)."""
    d = np.asarray(d, dtype=float)
    if len(d) < 2:
        return float(d.mean()), float(d.mean()), float(d.mean()), math.nan
    r = paired(d, np.zeros_like(d))
    return r["mean_diff"], r["ci_low"], r["ci_high"], r["p_value"]


def _by_seed(runs: pd.DataFrame, exp: str, cell: str, value: str, cond: str, metric: str) -> pd.Series:
    sel = runs[(runs["experiment"] == exp) & (runs["cell"] == cell) & (runs["value"] == value) & (runs["condition"] == cond)]
    return sel.set_index("seed")[metric].sort_index()


def compare_cells(runs: pd.DataFrame) -> pd.DataFrame:
    """Every (cell, value, condition, metric) against the reference cell of its experiment, paired
    by seed; Holm over every non-reference row of an experiment and metric (diagnostics and the
    combined check form their own families)."""
    rows = []
    groups = runs[runs["kind"] != "reference"][["experiment", "cell", "kind", "value", "condition"]].drop_duplicates()
    for g in groups.itertuples(index=False):
        for metric in (PRIMARY, *SECONDARY):
            v = _by_seed(runs, g.experiment, g.cell, g.value, g.condition, metric)
            d = _by_seed(runs, g.experiment, "reference", "", g.condition, metric)
            seeds = v.index.intersection(d.index)
            v, d = v.loc[seeds].to_numpy(float), d.loc[seeds].to_numpy(float)
            if np.isnan(v).all() or np.isnan(d).all():
                continue
            mean, lo, hi, p = _ci(v - d)
            ref = float(np.mean(d))
            rows.append(
                dict(experiment=g.experiment, cell=g.cell, kind=g.kind, value=g.value, condition=g.condition, metric=metric, n=len(seeds),
                     mean=float(np.mean(v)), sd=float(np.std(v, ddof=1)), ref_mean=ref, ref_sd=float(np.std(d, ddof=1)),
                     mean_diff=mean, ci_low=lo, ci_high=hi, rel_change=mean / ref if ref else math.nan, p_value=p)
            )
    table = pd.DataFrame(rows)
    table["p_holm"] = math.nan
    for _, idx in table.groupby(["experiment", "metric", "kind"]).groups.items():
        table.loc[idx, "p_holm"] = holm(table.loc[idx, "p_value"].to_numpy(float))
    return table


def decision_rows(runs: pd.DataFrame) -> pd.DataFrame:
    """The deciding statistic of every cell: per seed, the mean over the cell's conditions of
    (value - default) / default-cell mean of the primary metric; its mean, 95 % CI and t-test
    against 0, with Holm over the parameter cells of each experiment."""
    rows = []
    groups = runs[runs["kind"] != "reference"].groupby(["experiment", "cell", "kind", "value"], sort=False)
    for (exp, cell, kind, value), sel in groups:
        conds = list(dict.fromkeys(sel["condition"]))
        rel = []
        for cond in conds:
            v = _by_seed(runs, exp, cell, value, cond, PRIMARY)
            d = _by_seed(runs, exp, "reference", "", cond, PRIMARY)
            rel.append((v - d.loc[v.index]) / d.mean())
        r = pd.concat(rel, axis=1).mean(axis=1).to_numpy(float)
        mean, lo, hi, p = _ci(r)
        per_cond_hi = max(_ci(x.to_numpy(float))[2] for x in rel)
        rows.append(dict(experiment=exp, cell=cell, kind=kind, value=value, conditions=" ".join(conds), n=len(r), rel_change=mean, ci_low=lo, ci_high=hi, p_value=p, worst_condition_ci_high=per_cond_hi))
    table = pd.DataFrame(rows)
    table["p_holm"] = math.nan
    for _, idx in table.groupby(["experiment", "kind"]).groups.items():
        table.loc[idx, "p_holm"] = holm(table.loc[idx, "p_value"].to_numpy(float))
    return table


def decide(dec: pd.DataFrame, experiments: list[str]) -> tuple[pd.DataFrame, dict[str, dict[str, Any]]]:
    """docs/sensitivity.md's rule, applied mechanically. Returns the per-value verdicts and the
    changes per experiment family ("micro": exp1 and exp2; "explauto")."""
    verdicts = []
    changes: dict[str, dict[str, Any]] = {"micro": {}, "explauto": {}}
    micro = [e for e in MICRO_EXPERIMENTS if e in experiments]
    params = dec[dec["kind"] == "parameter"]
    for (cell, value), sel in params.groupby(["cell", "value"], sort=False):
        by_exp = sel.set_index("experiment")
        if cell == EPISODIC.name:
            row = by_exp.loc["explauto"]
            better = row["p_holm"] < ALPHA and row["rel_change"] < 0
            harmless = row["worst_condition_ci_high"] < HARM
            ok, why = bool(better and harmless), f"explauto: p_holm {row['p_holm']:.3g}, change {row['rel_change']:+.1%}; worst condition's CI upper {row['worst_condition_ci_high']:+.1%}"
            verdicts.append(dict(parameter=cell, value=value, qualifies=ok, score=row["rel_change"], conditions=row["conditions"], reason=why))
            continue
        if len(micro) < 2 or not set(micro) <= set(by_exp.index):
            verdicts.append(dict(parameter=cell, value=value, qualifies=False, score=math.nan, conditions=" / ".join(dict.fromkeys(sel["conditions"])), reason="needs both experiments"))
            continue
        reasons, ok = [], False
        for e, other in ((micro[0], micro[1]), (micro[1], micro[0])):
            a, b = by_exp.loc[e], by_exp.loc[other]
            better = a["p_holm"] < ALPHA and a["rel_change"] < 0
            harmless = b["ci_high"] < HARM
            reasons.append(f"{e}: change {a['rel_change']:+.1%}, p_holm {a['p_holm']:.3g}{' (better)' if better else ''}; {other} CI upper {b['ci_high']:+.1%}{' (no harm)' if harmless else ' (possible harm)'}")
            ok = ok or bool(better and harmless)
        score = float(np.mean([by_exp.loc[e, "rel_change"] for e in micro]))
        verdicts.append(dict(parameter=cell, value=value, qualifies=ok, score=score, conditions=" / ".join(dict.fromkeys(sel["conditions"])), reason="; ".join(reasons)))
    verdicts = pd.DataFrame(verdicts)
    for cell, sel in verdicts[verdicts["qualifies"]].groupby("parameter"):
        best = sel.sort_values("score").iloc[0]
        family = "explauto" if cell == EPISODIC.name else "micro"
        changes[family][cell] = json.loads(best["value"])
    return verdicts, changes


def combined_cells(changes: dict[str, dict[str, Any]], experiments: list[str], seeds: tuple[int, ...]) -> list[Cell]:
    cells = []
    for exp in experiments:
        ch = changes["explauto" if exp == "explauto" else "micro"]
        if ch:
            conds = SAGG if exp == "explauto" else ALL  # every condition, as registered, whatever --conditions says
            cells.append(Cell(exp, "combined", sg.Study(base_config(exp).replace(**ch), conds, seeds), "combined", changes=ch))
    return cells


def figure(dec: pd.DataFrame, cells_table: pd.DataFrame, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    exps = list(dict.fromkeys(dec["experiment"]))
    heights = [max(2.0, 0.28 * (dec["experiment"] == e).sum() + 1.0) for e in exps]
    fig, axes = plt.subplots(len(exps), 1, figsize=(8.5, sum(heights)), gridspec_kw={"height_ratios": heights}, squeeze=False)
    colours = {"sagg_riac": "tab:red", "sagg_random": "tab:blue", "actuator_random": "tab:green", "actuator_riac": "tab:purple"}
    for ax, exp in zip(axes[:, 0], exps):
        d = dec[dec["experiment"] == exp].reset_index(drop=True)
        y = np.arange(len(d))[::-1]
        for i, row in d.iterrows():
            colour = "grey" if row["kind"] == "diagnostic" else ("black" if row["kind"] == "parameter" else "tab:orange")
            ax.errorbar(row["rel_change"] * 100, y[i], xerr=[[100 * (row["rel_change"] - row["ci_low"])], [100 * (row["ci_high"] - row["rel_change"])]], fmt="o", color=colour, ms=4, capsize=2)
            if row["kind"] == "parameter" and row["p_holm"] < ALPHA:
                ax.text(100 * row["ci_high"], y[i], "  *", va="center", fontsize=9)
            per = cells_table[(cells_table["experiment"] == exp) & (cells_table["cell"] == row["cell"]) & (cells_table["value"] == row["value"]) & (cells_table["metric"] == PRIMARY)]
            for _, c in per.iterrows():
                ax.plot(100 * c["rel_change"], y[i] - 0.22, "|", color=colours.get(c["condition"], "k"), ms=6, mew=1.5)
        labels = [f"{r['cell']}={json.loads(r['value'])}" if r["value"] else f"{r['cell']} ({r['kind']})" for _, r in d.iterrows()]
        ax.set_yticks(y, labels, fontsize=8)
        ax.set_ylim(-0.7, len(d) - 0.3)
        ax.axvline(0, color="k", lw=0.8)
        ax.axvline(100 * HARM, color="k", lw=0.6, ls=":")
        ax.set_title(f"{exp}: change of the final reaching error against the defaults (mean over seeds, 95 % CI)", fontsize=9)
        ax.set_xlabel("relative change (%); * Holm p < 0.05; ticks: per condition", fontsize=8)
    handles = [plt.Line2D([], [], color=c, marker="|", ls="", ms=8, mew=1.5, label=k) for k, c in colours.items()]
    axes[0, 0].legend(handles=handles, fontsize=7, loc="lower right")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def _fmt(x: float, pct: bool = False) -> str:
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "-"
    return f"{x:+.1%}" if pct else f"{x:.3g}"


def markdown(dec: pd.DataFrame, table: pd.DataFrame, verdicts: pd.DataFrame, changes: dict[str, dict[str, Any]], runs: pd.DataFrame, command: str) -> str:
    out = [f"Made by `{command}` (saggriac {sg.__version__}, seeds {runs['seed'].min()}-{runs['seed'].max()}, {len(runs)} runs).", ""]
    if BASE == "current":
        out += ["Base: today's presets as they are (`--base current`).", ""]
    else:
        out += [f"Base: the registered defaults, with {', '.join(f'{k}={v!r}' for k, v in REGISTERED_READINGS.items())} (`--base registered`).", ""]
    if CONDITIONS != ALL:
        out += [f"Conditions kept (`--conditions`): {', '.join(CONDITIONS)}; cells left with no condition are not run.", ""]
    fam = dec[dec["kind"] == "parameter"].groupby("experiment", sort=False)
    out += ["Holm families: " + "; ".join(f"{exp}, the {len(sel)} parameter cells run ({', '.join(dict.fromkeys(sel['cell']))})" for exp, sel in fam) + "; the diagnostics of each experiment apart.", ""]
    out += ["### Deciding statistic per cell", "", "Relative change of the final reaching error, mean over the cell's conditions of (value - default) / default mean, per seed; mean over seeds, 95 % CI, two-sided t-test, Holm over the parameter cells of the experiment.", ""]
    out += ["| experiment | cell | value | conditions | change | 95 % CI | p | p Holm |", "|---|---|---|---|---|---|---|---|"]
    for _, r in dec.iterrows():
        value = json.loads(r["value"]) if r["value"] else ""
        out.append(f"| {r['experiment']} | {r['cell']}{' (diagnostic)' if r['kind'] == 'diagnostic' else ''} | {value} | {r['conditions']} | {_fmt(r['rel_change'], True)} | [{_fmt(r['ci_low'], True)}, {_fmt(r['ci_high'], True)}] | {_fmt(r['p_value'])} | {_fmt(r['p_holm'])} |")
    out += ["", "### Verdicts", "", "| parameter | value | decided on | qualifies | mean change over experiments | why |", "|---|---|---|---|---|---|"]
    for _, v in verdicts.iterrows():
        out.append(f"| {v['parameter']} | {json.loads(v['value'])} | {v['conditions']} | {'yes' if v['qualifies'] else 'no'} | {_fmt(v['score'], True)} | {v['reason']} |")
    out += ["", f"Changes the rule selects: micro-action presets {changes['micro'] or 'none'}; explauto {changes['explauto'] or 'none'}.", ""]
    out += ["### Every cell and condition, final reaching error", "", "| experiment | cell | value | condition | mean ± sd | default mean ± sd | difference [95 % CI] | p | p Holm |", "|---|---|---|---|---|---|---|---|---|"]
    for _, r in table[table["metric"] == PRIMARY].iterrows():
        value = json.loads(r["value"]) if r["value"] else ""
        out.append(f"| {r['experiment']} | {r['cell']} | {value} | {r['condition']} | {r['mean']:.3g} ± {r['sd']:.2g} | {r['ref_mean']:.3g} ± {r['ref_sd']:.2g} | {r['mean_diff']:+.3g} [{r['ci_low']:+.3g}, {r['ci_high']:+.3g}] | {_fmt(r['p_value'])} | {_fmt(r['p_holm'])} |")
    out += ["", "### Secondary metrics (never decide)", "", "Mean over seeds, and in brackets the relative change against the default cell; `*` marks Holm p < 0.05 (Holm over the cells of an experiment, per metric).", ""]
    out += ["| experiment | cell | value | condition | " + " | ".join(SECONDARY) + " |", "|---|---|---|---|" + "---|" * len(SECONDARY)]
    sec = table[table["metric"].isin(SECONDARY)]
    for (exp, cell, value, cond), sel in sec.groupby(["experiment", "cell", "value", "condition"], sort=False):
        by = sel.set_index("metric")
        cols = []
        for m in SECONDARY:
            if m not in by.index:
                cols.append("-")
                continue
            r = by.loc[m]
            star = "*" if r["p_holm"] < ALPHA else ""
            cols.append(f"{r['mean']:.3g} ({_fmt(r['rel_change'], True)}){star}")
        out.append(f"| {exp} | {cell} | {json.loads(value) if value else ''} | {cond} | " + " | ".join(cols) + " |")
    ref = runs[runs["kind"] == "reference"].groupby(["experiment", "condition"], sort=False)[[PRIMARY, *SECONDARY]].mean()
    out += ["", "### The reference cells (defaults)", "", "| experiment | condition | " + " | ".join((PRIMARY, *SECONDARY)) + " |", "|---|---|" + "---|" * (1 + len(SECONDARY))]
    for (exp, cond), r in ref.iterrows():
        out.append(f"| {exp} | {cond} | " + " | ".join(_fmt(float(r[m])) for m in (PRIMARY, *SECONDARY)) + " |")
    return "\n".join(out) + "\n"


def combined_check(dec: pd.DataFrame) -> list[str]:
    lines = []
    for _, r in dec[dec["kind"] == "combined"].iterrows():
        worse = r["p_value"] < ALPHA and r["rel_change"] > 0
        lines.append(f"{r['experiment']}: combined change {r['rel_change']:+.1%} [{r['ci_low']:+.1%}, {r['ci_high']:+.1%}], p {r['p_value']:.3g}: {'WORSE, the old defaults stay' if worse else 'not worse'}")
    return lines


SAME_BITS = ("reach_error", "pred_error", "dx_error", "goals", "share_exploration")
AGAINST_PREVIOUS = ("reach_error", "reachable_goal_share_2nd_half", "goals")


def against_previous(runs: pd.DataFrame, path: Path) -> pd.DataFrame:
    """Every (cell, value, condition) this study shares with an earlier study's runs.csv, paired by
    seed: mean before and now, the difference now - before with its 95 % CI and p, and how many
    seeds gave exactly the same run (every metric in SAME_BITS equal)."""
    prev = pd.read_csv(path, dtype={"value": str})
    prev["value"] = prev["value"].fillna("")
    keys = ["experiment", "cell", "value", "condition", "seed"]
    # A combined cell holds whatever changes its study's rule chose, so it is not compared.
    both = runs[runs["kind"] != "combined"].merge(prev[prev["kind"] != "combined"], on=keys, suffixes=("", "_before"))
    rows = []
    for (exp, cell, value, cond), sel in both.groupby(["experiment", "cell", "value", "condition"], sort=False):
        same = np.ones(len(sel), dtype=bool)
        for m in SAME_BITS:
            same &= (sel[m].to_numpy(float) == sel[f"{m}_before"].to_numpy(float)) | (sel[m].isna() & sel[f"{m}_before"].isna()).to_numpy()
        for metric in AGAINST_PREVIOUS:
            now, before = sel[metric].to_numpy(float), sel[f"{metric}_before"].to_numpy(float)
            if np.isnan(now).all() or np.isnan(before).all():
                continue
            if np.array_equal(now, before):
                mean = lo = hi = 0.0
                pv = math.nan
            else:
                mean, lo, hi, pv = _ci(now - before)
            rows.append(dict(experiment=exp, cell=cell, value=value, condition=cond, metric=metric, n=len(sel), before=float(np.mean(before)), now=float(np.mean(now)),
                             mean_diff=mean, ci_low=lo, ci_high=hi, p_value=pv, same_runs=int(same.sum())))
    return pd.DataFrame(rows)


def previous_markdown(prev: pd.DataFrame, path: Path) -> str:
    out = ["", f"### Against the earlier study ({path}, the same seeds)", "",
           "Paired by seed: the earlier study's mean, this one's, and the difference (now - before) with its 95 % CI and two-sided p (none when every run is the same). "
           "\"Same runs\" counts the seeds whose run is the same bits in both (every one of " + ", ".join(SAME_BITS) + " equal).", "",
           "| experiment | cell | value | condition | final reaching error: before -> now | difference [95 % CI], p | 2nd-half reachable share: before -> now | difference [95 % CI], p | same runs |",
           "|---|---|---|---|---|---|---|---|---|"]
    for (exp, cell, value, cond), sel in prev.groupby(["experiment", "cell", "value", "condition"], sort=False):
        by = sel.set_index("metric")
        cols = []
        for m in ("reach_error", "reachable_goal_share_2nd_half"):
            if m not in by.index:
                cols += ["-", "-"]
                continue
            r = by.loc[m]
            cols += [f"{r['before']:.3g} -> {r['now']:.3g}", f"{r['mean_diff']:+.3g} [{r['ci_low']:+.3g}, {r['ci_high']:+.3g}], p {_fmt(r['p_value'])}"]
        first = by.iloc[0]
        out.append(f"| {exp} | {cell} | {json.loads(value) if value else ''} | {cond} | " + " | ".join(cols) + f" | {first['same_runs']}/{first['n']} |")
    return "\n".join(out) + "\n"


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", required=True, help="study folders and results go here (resumable)")
    p.add_argument("--experiments", nargs="+", default=["exp1", "exp2", "explauto"], choices=["exp1", "exp2", "explauto"])
    p.add_argument("--seeds", type=int, default=15, help="how many tuning seeds, from 100 (default 15: 100-114)")
    p.add_argument("--workers", type=int, default=None, help="studies run at once, one process each (default: the usable cores)")
    p.add_argument("--steps", type=int, default=None, help="override every preset's n_steps: only to try the script quickly, never for the study")
    p.add_argument("--base", choices=["registered", "current"], default="registered", help="registered (default): the protocol's defaults and the first study's reading of eq. 2; current: today's presets")
    p.add_argument("--conditions", nargs="+", choices=list(ALL), default=list(ALL), help="keep only these conditions in every cell (see the module docstring for what is run later)")
    p.add_argument("--previous", type=Path, default=None, help="an earlier study's runs.csv to compare every shared cell with, paired by seed")
    a = p.parse_args()
    global STEPS, BASE, CONDITIONS
    STEPS, BASE = a.steps, a.base
    CONDITIONS = tuple(c for c in ALL if c in a.conditions)
    if not 1 <= a.seeds <= len(TUNING_SEEDS):
        p.error(f"--seeds must be between 1 and {len(TUNING_SEEDS)} (the tuning seeds 100-114). Got {a.seeds}.")
    seeds = TUNING_SEEDS[: a.seeds]
    out = Path(a.out)
    workers = a.workers or sg.study.default_workers()
    command = "python benchmarks/sensitivity.py " + " ".join(sys.argv[1:])
    cells = plan(a.experiments, seeds)
    for line in changed_since(a.experiments):
        start = "today's presets" if BASE == "current" else "the registered defaults"
        print(f"sensitivity: the study starts from {start}; {line}", flush=True)
    print(f"sensitivity: {len(cells)} cells, {sum(len(c.study.tasks()) for c in cells)} runs on seeds {seeds[0]}-{seeds[-1]}, conditions {', '.join(CONDITIONS)}, {workers} at a time, into {out}", flush=True)
    run_cells(cells, out, workers)
    runs = read_runs(cells, out)
    dec = decision_rows(runs)
    verdicts, changes = decide(dec, a.experiments)
    # Second stage: a parameter decided on fewer conditions than the protocol runs it on, with a
    # value that qualifies there, gets its other conditions before anything is decided.
    partial = {p.name for p in (*PARAMETERS, EPISODIC) if kept(p.conditions) and kept(p.conditions) != p.conditions}
    second = set(verdicts.loc[verdicts["qualifies"] & verdicts["parameter"].isin(partial), "parameter"])
    if second:
        more = rest_cells(cells, second, (), seeds)
        print(f"sensitivity: {', '.join(sorted(second))} qualifies on {', '.join(CONDITIONS)}; running its other conditions before deciding ({sum(len(c.study.tasks()) for c in more)} runs)", flush=True)
        run_cells(more, out, workers)
        cells += more
        runs = read_runs(cells, out)
        dec = decision_rows(runs)
        verdicts, changes = decide(dec, a.experiments)
    else:
        print(f"sensitivity: no parameter decided on fewer conditions than registered ({', '.join(sorted(partial)) or 'none'}) qualifies there; nothing more to run before deciding", flush=True)
    extra = combined_cells(changes, a.experiments, seeds)
    if extra:
        extra = rest_cells(cells, set(), ALL, seeds) + extra  # the combination check compares every condition with the defaults
        print(f"sensitivity: qualifying changes {changes}; checking their combination", flush=True)
        run_cells(extra, out, workers)
        runs = read_runs(cells + extra, out)
        dec = decision_rows(runs)
    table = compare_cells(runs)
    out.mkdir(parents=True, exist_ok=True)
    runs.to_csv(out / "runs.csv", index=False)
    table.to_csv(out / "cells.csv", index=False)
    dec.to_csv(out / "decisions.csv", index=False)
    verdicts.to_csv(out / "verdicts.csv", index=False)
    text = markdown(dec[dec["kind"] != "combined"], table[table["kind"] != "combined"], verdicts, changes, runs, command)
    checks = combined_check(dec)
    if checks:
        text += "\n### Combined check\n\n" + "\n".join(f"- {c}" for c in checks) + "\n"
    if a.previous is not None:
        prev = against_previous(runs, a.previous)
        prev.to_csv(out / "previous.csv", index=False)
        text += previous_markdown(prev, a.previous)
    (out / "results.md").write_text(text)
    figure(dec, table, out / "sensitivity.png")
    print(f"\nverdicts:\n{verdicts.to_string(index=False)}\n\nchanges: {changes}")
    for c in checks:
        print(c)
    print(f"\nwrote {out / 'results.md'}, {out / 'sensitivity.png'}, runs.csv, cells.csv, decisions.csv, verdicts.csv")
    return 0


if __name__ == "__main__":
    sys.exit(main())
