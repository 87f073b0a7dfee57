"""Every teacher on the progress-niche benchmark, side by side, with paired statistics.

    python benchmarks/teacher_niches.py --out niches/ [--seeds 20] [--updates 8000] [--distractors 0 4]

The learner is :class:`saggriac.teachers.progress_niches.ProgressNiches` (a chain of niches that open one
after another, noisy cells, impossible cells, and optional distractor dimensions). For every
space (number of distractors), teacher and seed, the teacher asks ``--updates`` goals one at a
time and is told the competence of each. Seed s gives the learner's noise and the teacher's
generator (two children of SeedSequence(s)), so runs with the same seed are paired. Each run is
the bench's niche task (``saggriac.bench.tasks.Niches``) played by its own loop, watched for
where each goal lands.

Writes to ``--out``: ``runs.csv`` (one row per run), ``curves.csv`` (the score every ``--every``
updates), ``comparisons.csv`` (every pair of teachers, paired t-tests, Holm within a space and a
metric), ``results.md`` and ``niches.png``; ``--report-only`` rebuilds the last three from the
first two. The decision rule is the one of docs/teachers.md.

``--extra sagg_riac_w`` adds SAGG-RIAC with saggriac 0.2's reading of eq. 2 (a region holding
fewer than zeta measurements divided by its own count, ``interest_divisor="window"``) as a row
for comparison. An extra teacher is not a contestant: the registered teachers' 15 pairs keep
their own Holm family and decide who wins, and the pairs with an extra teacher form a second
family per space and metric.
"""

from __future__ import annotations

import argparse
import itertools
import multiprocessing as mp
import time
from pathlib import Path

import numpy as np
import pandas as pd
from tqdm import tqdm

import saggriac as sg
from saggriac.analysis.statistics import holm, paired
from saggriac.bench.tasks import Niches, NichesCells
from saggriac.teachers.progress_niches import KINDS, ProgressNiches

TEACHERS = ("sagg_riac", "riac", "alp_gmm", "covar_gmm", "discrete_lp", "random")
# Rows for comparison, outside the protocol's family of 15 pairs: saggriac 0.2's SAGG-RIAC, and
# the teachers added after the protocol was written (issue 36).
EXTRA = ("sagg_riac_w", *[k for k in sg.teachers.available() if k not in TEACHERS], "plr_average")
ORDER = ("sagg_riac", "sagg_riac_w", *[k for k in sg.teachers.available() if k not in ("sagg_riac", "random")], "plr_average", "random")
NAMES = {"sagg_riac": "SAGG-RIAC", "sagg_riac_w": "SAGG-RIAC (w divisor, <= 0.2)", "riac": "RIAC", "alp_gmm": "ALP-GMM", "covar_gmm": "Covar-GMM", "discrete_lp": "discrete LP", "random": "random", "adr": "ADR", "plr": "PLR", "plr_average": "PLR (ties at their mean rank)", "spdl": "SPDL", "goal_gan": "Goal GAN"}
NAMES.update({k: k for k in sg.teachers.available() if k not in NAMES})  # a teacher without a display name here
TASK_LISTS = (*[k for k, c in sg.teachers.available().items() if "tasks" in c.spaces], "plr_average")  # given the 16 cells as a task list
METRICS = ("final", "auc", "share_noisy", "share_impossible")
SHORT = {"sagg_riac_w": "SAGG-RIAC\n(w, <= 0.2)", "covar_gmm": "Covar-\nGMM", "discrete_lp": "discrete\nLP"}


def make_teacher(name: str, env: ProgressNiches, seed: int):
    """Any registered teacher with its papers' defaults (a task-list teacher over the 16 cells),
    or a variant: saggriac 0.2's SAGG-RIAC (sagg_riac_w), PLR with ties at their mean rank."""
    if name == "sagg_riac_w":
        return sg.SaggRiacSelector(env.low.tolist(), env.high.tolist(), seed=seed, interest_divisor="window")
    if name == "plr_average":
        return sg.PlrSelector(env.n_cells, seed=seed, ties="average")
    cls = sg.teachers.available()[name]
    return cls(env.n_cells, seed=seed) if "tasks" in cls.spaces else cls(env.low.tolist(), env.high.tolist(), seed=seed)


def niche_task(distractors: int, cells: bool, seed: int) -> Niches:
    """The bench's progress-niche task (its cells as a task list if ``cells``) with ``distractors``
    distractor dimensions, its learner seeded with ``seed``."""
    base = NichesCells if cells else Niches
    return type(base.__name__, (base,), {"distractors": distractors})(seed)


def one_run(job: tuple[str, int, int, int, int]) -> tuple[dict, list[dict]]:
    """One teacher on one space, played by the bench task's own loop (``BenchTask.play``),
    watched on the way: the kind of cell each goal landed in, and the niches open at each scoring."""
    name, distractors, seed, updates, every = job
    if every < 1 or updates % every:
        raise ValueError(f"--every must divide --updates; got {every} and {updates}")
    env_seq, teacher_seq = np.random.SeedSequence(seed).spawn(2)
    cells = name in TASK_LISTS
    task = niche_task(distractors, cells, int(env_seq.generate_state(1, np.uint64)[0] >> 1))
    task.points = updates // every
    env = task.env
    teacher = make_teacher(name, env, int(teacher_seq.generate_state(1, np.uint64)[0]))
    kinds = [env.kind(c) for c in range(env.n_cells)]
    counts = dict.fromkeys(KINDS, 0)
    opened: list[int] = []

    def ask():
        goal = teacher.sample_task() if cells else teacher.sample()
        counts[kinds[goal if cells else env.cell(goal)]] += 1
        return goal

    def tell(goal, competence: float) -> None:
        teacher.update(goal, competence)
        if (sum(counts.values())) % every == 0:
            opened.append(env.unlocked)  # at the scoring that follows this update

    start = time.perf_counter()
    scored = task.play(ask, tell, updates)
    seconds = time.perf_counter() - start
    curve = [dict(teacher=name, distractors=distractors, seed=seed, update=t, mastery=m, unlocked=u) for (t, m), u in zip(scored, opened, strict=True)]
    row = dict(teacher=name, distractors=distractors, seed=seed, final=env.mastery(), auc=float(np.mean([p["mastery"] for p in curve])), unlocked=env.unlocked,
               share_noisy=counts["noisy"] / updates, share_impossible=counts["impossible"] / updates, share_niche=counts["niche"] / updates, seconds=seconds)
    return row, curve


def compare(runs: pd.DataFrame) -> pd.DataFrame:
    """Paired t-tests of every pair of teachers, per space and metric. Holm runs over the pairs of
    registered teachers (family "registered"), and apart over the pairs with an extra teacher
    (family "extra")."""
    rows = []
    for (d, metric) in itertools.product(sorted(runs.distractors.unique()), METRICS):
        sub = runs[runs.distractors == d].pivot(index="seed", columns="teacher", values=metric)
        names = [t for t in ORDER if t in sub.columns]
        blocks: dict[str, list[dict]] = {"registered": [], "extra": []}
        for a, b in itertools.combinations(names, 2):
            family = "extra" if a in EXTRA or b in EXTRA else "registered"
            blocks[family].append(dict(distractors=d, metric=metric, a=a, b=b, family=family, n=len(sub), **paired(sub[a].to_numpy(), sub[b].to_numpy())))
        for block in blocks.values():
            adj = holm([r["p_value"] for r in block]) if block else []
            for r, p in zip(block, adj):
                r["p_holm"] = p
            rows += block
    return pd.DataFrame(rows)


def winners(runs: pd.DataFrame, comps: pd.DataFrame, d: int, metric: str, higher: bool = True) -> tuple[str, list[str]]:
    """The best mean, and the teachers not distinguishable from it (Holm p >= 0.05)."""
    means = runs[(runs.distractors == d) & runs.teacher.isin(TEACHERS)].groupby("teacher")[metric].mean()
    best = means.idxmax() if higher else means.idxmin()
    c = comps[(comps.distractors == d) & (comps.metric == metric) & (comps.family == "registered") & ((comps.a == best) | (comps.b == best))]
    tied = sorted({r.a if r.b == best else r.b for r in c.itertuples() if not (r.p_holm < 0.05)})
    return best, tied


def report(runs: pd.DataFrame, comps: pd.DataFrame, args: argparse.Namespace) -> str:
    extra = f" --extra {' '.join(args.extra)}" if args.extra else ""
    out = [f"# Progress niches: {runs.seed.nunique()} seeds, {args.updates} updates\n",
           f"`python benchmarks/teacher_niches.py --out {args.out} --seeds {args.seeds} --updates {args.updates} --distractors {' '.join(map(str, args.distractors))}{extra}` (saggriac {sg.__version__})\n"]
    if args.extra:
        out.append(f"Extra rows, for comparison only: {', '.join(NAMES[t] for t in args.extra)}. They do not take part in the decision rule (who wins, who is tied): "
                   "Holm runs over the registered teachers' pairs, and apart over the pairs with an extra teacher (marked with a dagger instead of a star).\n")
    for d in sorted(runs.distractors.unique()):
        sub = runs[runs.distractors == d]
        out.append(f"\n## {2 + d}-D task space ({d} distractor dimensions)\n")
        out.append("| teacher | final score | area under the curve | niches open | goals in noisy cells | goals in impossible cells | seconds per run |")
        out.append("|---|---|---|---|---|---|---|")
        g = sub.groupby("teacher")
        for t in ORDER:
            if t not in g.groups:
                continue
            r = g.get_group(t)
            out.append(f"| {NAMES[t]} | {r.final.mean():.3f} ± {r.final.std():.3f} | {r.auc.mean():.3f} ± {r.auc.std():.3f} | {r.unlocked.mean():.1f} | "
                       f"{100 * r.share_noisy.mean():.1f} % | {100 * r.share_impossible.mean():.1f} % | {r.seconds.mean():.2f} |")
        for metric, higher in (("final", True), ("auc", True), ("share_noisy", False)):
            best, tied = winners(runs, comps, d, metric, higher)
            word = "highest" if higher else "lowest"
            tie = f"; not distinguishable from it (Holm p >= 0.05): {', '.join(NAMES[t] for t in tied)}" if tied else "; better than every other teacher (Holm p < 0.05)"
            out.append(f"\n- {metric}: {word} mean {NAMES[best]}{tie}.")
        names = [t for t in ORDER if t in set(sub.teacher)]
        for metric, label in (("final", "final score"), ("auc", "area under the curve"), ("share_noisy", "share of goals in noisy cells")):
            dagger = "; † Holm p < 0.05 in the extra family" if args.extra else ""
            out.append(f"\nPaired differences of the {label} (row minus column, mean over seeds; * Holm p < 0.05{dagger}):\n")
            c = comps[(comps.distractors == d) & (comps.metric == metric)]
            out.append("| | " + " | ".join(NAMES[t] for t in names) + " |")
            out.append("|---" * (len(names) + 1) + "|")
            for a in names:
                cells = []
                for b in names:
                    if a == b:
                        cells.append("")
                        continue
                    r = c[((c.a == a) & (c.b == b)) | ((c.a == b) & (c.b == a))].iloc[0]
                    diff = r.mean_diff if r.a == a else -r.mean_diff
                    mark = ("†" if r.family == "extra" else "*") if r.p_holm < 0.05 else ""
                    cells.append(f"{diff:+.3f}{mark}")
                out.append(f"| {NAMES[a]} | " + " | ".join(cells) + " |")
    return "\n".join(out) + "\n"


def figure(curves: pd.DataFrame, runs: pd.DataFrame, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    spaces = sorted(curves.distractors.unique())
    fig, axes = plt.subplots(2, len(spaces), figsize=(5.5 * len(spaces), 8), squeeze=False)
    for col, d in enumerate(spaces):
        ax = axes[0, col]
        for t in ORDER:
            c = curves[(curves.distractors == d) & (curves.teacher == t)]
            if c.empty:
                continue
            m = c.groupby("update").mastery
            x, mu, sd = m.mean().index, m.mean().to_numpy(), m.std().to_numpy()
            (line,) = ax.plot(x, mu, label=NAMES[t], **({"ls": "--", "color": "tab:blue"} if t == "sagg_riac_w" else {}))
            ax.fill_between(x, mu - sd, mu + sd, color=line.get_color(), alpha=0.15)
        ax.set_title(f"{2 + d}-D ({d} distractors): mean skill over the niches (±1 sd)")
        ax.set_xlabel("updates")
        ax.set_ylim(0, 1)
        ax.legend(fontsize=8)
        ax = axes[1, col]
        sub = runs[runs.distractors == d].groupby("teacher")[["share_niche", "share_noisy", "share_impossible"]].mean()
        names = [t for t in ORDER if t in sub.index]
        bottom = np.zeros(len(names))
        for key, colour in (("share_niche", "tab:green"), ("share_noisy", "tab:orange"), ("share_impossible", "tab:grey")):
            v = sub.loc[names, key].to_numpy()
            ax.bar([SHORT.get(t, NAMES[t]) for t in names], v, bottom=bottom, color=colour, label=key.replace("share_", "goals in ") + (" cells" if key != "share_niche" else "s"))
            bottom += v
        ax.set_title("where the goals went (mean over seeds)")
        ax.set_ylim(0, 1)
        ax.tick_params(axis="x", labelsize=8)
        ax.legend(fontsize=8, loc="lower right")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--out", type=Path, required=True)
    p.add_argument("--seeds", type=int, default=20, help="seeds 0 .. N-1")
    p.add_argument("--first-seed", type=int, default=0)
    p.add_argument("--updates", type=int, default=8000)
    p.add_argument("--every", type=int, default=250)
    p.add_argument("--distractors", type=int, nargs="+", default=[0, 4])
    p.add_argument("--teachers", nargs="+", default=list(TEACHERS), choices=TEACHERS)
    p.add_argument("--extra", nargs="*", default=[], choices=EXTRA, help="teachers added as rows for comparison, outside the decision rule")
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--report-only", action="store_true", help="rebuild comparisons.csv, results.md and niches.png from --out's runs.csv and curves.csv, running nothing (seeds, updates, distractors and extra rows read from the runs)")
    args = p.parse_args()
    if args.report_only:
        runs = pd.read_csv(args.out / "runs.csv")
        curves_df = pd.read_csv(args.out / "curves.csv")
        args.seeds, args.updates = runs.seed.nunique(), int(curves_df["update"].max())
        args.distractors = sorted(runs.distractors.unique().tolist())
        args.extra = [t for t in EXTRA if t in set(runs.teacher)]
        write_report(runs, curves_df, args)
        return
    if args.seeds < 2 or args.every < 1 or args.updates < args.every or args.updates % args.every:
        p.error(f"--seeds must be >= 2, --every >= 1 and --updates a multiple of --every; got --seeds {args.seeds}, --updates {args.updates}, --every {args.every}")
    args.out.mkdir(parents=True, exist_ok=True)
    seeds = range(args.first_seed, args.first_seed + args.seeds)
    # The costliest teachers first, so that the pool's idle tail is short.
    order = sorted([*args.teachers, *args.extra], key=lambda t: t not in ("alp_gmm", "covar_gmm"))
    jobs = [(t, d, s, args.updates, args.every) for d in sorted(args.distractors, reverse=True) for t in order for s in seeds]
    rows, curves = [], []
    with mp.get_context("spawn").Pool(args.workers) as pool:
        for row, curve in tqdm(pool.imap_unordered(one_run, jobs), total=len(jobs), desc="niche runs"):
            rows.append(row)
            curves += curve
    runs = pd.DataFrame(rows).sort_values(["distractors", "teacher", "seed"]).reset_index(drop=True)
    curves_df = pd.DataFrame(curves).sort_values(["distractors", "teacher", "seed", "update"]).reset_index(drop=True)
    runs.to_csv(args.out / "runs.csv", index=False)
    curves_df.to_csv(args.out / "curves.csv", index=False)
    write_report(runs, curves_df, args)


def write_report(runs: pd.DataFrame, curves_df: pd.DataFrame, args: argparse.Namespace) -> None:
    comps = compare(runs)
    comps.to_csv(args.out / "comparisons.csv", index=False)
    text = report(runs, comps, args)
    (args.out / "results.md").write_text(text)
    figure(curves_df, runs, args.out / "niches.png")
    print(text)


if __name__ == "__main__":
    main()
