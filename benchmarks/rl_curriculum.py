"""A deep-RL student (Stable-Baselines3's PPO) learning to reach with a teacher choosing its goals.

    python benchmarks/rl_curriculum.py --out rl_curriculum/ [--seeds 0-7] [--steps 200000] [--workers 2]

The protocol, the decision rule and the results are in docs/rl_curriculum.md. The student is PPO
(SB3's defaults, 4 environments in one process, one torch thread) on a saggriac goal arm: 3
joints, reach 1, goals in the box [-2, 2]^2, of which the arm reaches the disc of radius 1
(a fifth of the box). Every ``--every`` steps the deterministic policy is scored on the same 200
test goals, uniform in the reachable disc. A teacher (:data:`TEACHERS`) chooses the goal of
every training episode through :class:`saggriac.adapters.sb3.TeacherCallback` and is told the episode's
closeness ``max(0, 1 - final distance / reach)``. A goal counts as reached within 0.2 (the
pilot's rule moved it from 0.1, see docs/rl_curriculum.md).

Seed s gives PPO's seed, the environments' seeds and the teacher's seed (children of
SeedSequence(s)); every teacher runs with the same s, so runs are paired by seed. Each finished
run is kept in ``--out/jobs/`` and not run again; the rest of ``--out``: ``curves.csv``,
``runs.csv``, ``comparisons.csv``, ``results.md`` and ``rl_curriculum.png``.
"""

from __future__ import annotations

import argparse
import itertools
import math
import multiprocessing as mp
import time
from pathlib import Path

import numpy as np
import pandas as pd
from tqdm import tqdm

TEACHERS = ("random", "sagg_riac", "riac", "alp_gmm", "covar_gmm")
NAMES = {"random": "random", "sagg_riac": "SAGG-RIAC", "riac": "RIAC", "alp_gmm": "ALP-GMM", "covar_gmm": "Covar-GMM"}
# The task, fixed in the protocol before any run.
ENV = dict(n_joints=3, arm_length=1.0, joint_limit=math.pi, max_joint_step=0.2, goal_low=(-2.0, -2.0), goal_high=(2.0, 2.0), distance_threshold=0.2, reward_type="dense")
EPISODE_STEPS = 50
N_ENVS = 4
N_TEST = 200
TEST_SEED = 20261203  # one test set for every run


def test_goals(reach: float) -> np.ndarray:
    """N_TEST goals uniform in the disc of radius ``reach`` (the arm's reachable set), by rejection
    from the goal box."""
    rng = np.random.default_rng(TEST_SEED)
    low, high = np.asarray(ENV["goal_low"]), np.asarray(ENV["goal_high"])
    out: list[np.ndarray] = []
    while len(out) < N_TEST:
        g = rng.uniform(low, high)
        if np.linalg.norm(g) <= reach:
            out.append(g)
    return np.array(out)


def make_env():
    from gymnasium.wrappers import TimeLimit

    from saggriac.adapters.gym import GoalArmEnv

    return TimeLimit(GoalArmEnv(**ENV), EPISODE_STEPS)


def make_teacher(name: str, seed: int):
    import saggriac as sg

    low, high = list(ENV["goal_low"]), list(ENV["goal_high"])
    return {
        "random": sg.RandomSelector,
        "sagg_riac": sg.SaggRiacSelector,
        "riac": sg.RiacSelector,
        "alp_gmm": sg.AlpGmmSelector,
        "covar_gmm": sg.CovarGmmSelector,
    }[name](low, high, seed=seed)


def evaluate(model, goals: np.ndarray) -> tuple[float, float]:
    """The deterministic policy from the rest pose towards every goal at once (one batched
    forward pass per step): the share of goals within the threshold at the episode's end, and
    the mean final distance."""
    envs = [make_env().unwrapped for _ in goals]
    obs = [e.reset(options={"goal": g})[0] for e, g in zip(envs, goals)]
    info: list[dict] = []
    for _ in range(EPISODE_STEPS):
        batch = {k: np.stack([o[k] for o in obs]) for k in obs[0]}
        actions, _ = model.predict(batch, deterministic=True)
        steps = [e.step(a) for e, a in zip(envs, actions)]
        obs = [s[0] for s in steps]
        info = [s[4] for s in steps]
    return float(np.mean([i["is_success"] for i in info])), float(np.mean([i["distance"] for i in info]))


def one_run(job: tuple[str, int, int, int, str]) -> str:
    name, seed, steps, every, out = job
    import torch
    from stable_baselines3 import PPO
    from stable_baselines3.common.callbacks import BaseCallback, CallbackList
    from stable_baselines3.common.vec_env import DummyVecEnv

    from saggriac.files import write_file
    from saggriac.adapters.sb3 import TeacherCallback

    torch.set_num_threads(1)
    path = Path(out) / "jobs" / f"{name}_{seed}.csv"
    model_seed, env_seed, teacher_seed = (int(s.generate_state(1)[0]) for s in np.random.SeedSequence(seed).spawn(3))
    env = DummyVecEnv([make_env] * N_ENVS)
    env.seed(env_seed)
    model = PPO("MultiInputPolicy", env, seed=model_seed, device="cpu", verbose=0)
    reach = float(env.envs[0].unwrapped.reach)
    goals = test_goals(reach)
    teacher = TeacherCallback(make_teacher(name, teacher_seed), competence=lambda info: max(0.0, 1.0 - info["distance"] / reach))
    rows: list[dict] = []
    start = time.perf_counter()

    class Score(BaseCallback):
        def _on_step(self) -> bool:
            if self.num_timesteps % every == 0:
                told = [g for g, _ in teacher.history]
                recent = np.array(told[-200:]) if told else np.zeros((0, 2))
                success, distance = evaluate(self.model, goals)
                rows.append(dict(teacher=name, seed=seed, step=self.num_timesteps, success=success, distance=distance, episodes=len(told), reachable_share=float(np.mean(np.linalg.norm(recent, axis=1) <= reach)) if len(recent) else float("nan"), seconds=time.perf_counter() - start))
            return True

    success, distance = evaluate(model, goals)
    rows.append(dict(teacher=name, seed=seed, step=0, success=success, distance=distance, episodes=0, reachable_share=float("nan"), seconds=0.0))
    model.learn(steps, callback=CallbackList([teacher, Score()]))
    write_file(path, lambda tmp: pd.DataFrame(rows).to_csv(tmp, index=False), what="a job's table", overwrite=True)
    return str(path)


def compare(runs: pd.DataFrame, metric: str, pairs: list[tuple[str, str]]) -> pd.DataFrame:
    from saggriac.analysis.statistics import holm, paired

    wide = runs.pivot(index="seed", columns="teacher", values=metric)
    rows = []
    for a, b in pairs:
        r = paired(wide[a].to_numpy(), wide[b].to_numpy())
        rows.append(dict(metric=metric, a=a, b=b, mean_a=wide[a].mean(), mean_b=wide[b].mean(), **r))
    table = pd.DataFrame(rows)
    table["p_holm"] = holm(table["p_value"].to_numpy())
    table["verdict"] = [
        ("a better" if d > 0 else "b better") if p < 0.05 else "no difference shown"
        for d, p in zip(table["mean_diff"], table["p_holm"])
    ]
    return table


def report(out: Path, curves: pd.DataFrame) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    last = curves["step"].max()
    final = curves[curves["step"] == last].set_index(["teacher", "seed"])
    auc = curves[curves["step"] > 0].groupby(["teacher", "seed"])["success"].mean().rename("auc")
    focus = curves[curves["step"] > 0].groupby(["teacher", "seed"])["reachable_share"].mean().rename("reachable_share")
    runs = pd.concat([final["success"].rename("final"), final["distance"].rename("final_distance"), auc, focus, final["seconds"]], axis=1).reset_index()
    runs.to_csv(out / "runs.csv", index=False)
    primary = compare(runs, "final", [(t, "random") for t in TEACHERS if t != "random"])
    secondary = pd.concat([compare(runs, "auc", [(t, "random") for t in TEACHERS if t != "random"]), compare(runs, "final", list(itertools.combinations(TEACHERS, 2)))])
    comparisons = pd.concat([primary.assign(family="primary"), secondary.assign(family="secondary")])
    comparisons.to_csv(out / "comparisons.csv", index=False)

    lines = [f"# RL curriculum: {runs['seed'].nunique()} seeds, {last} steps", "", "| teacher | final success | AUC | final distance | goals in reach | seconds |", "|---|---|---|---|---|---|"]
    for t in TEACHERS:
        r = runs[runs["teacher"] == t]
        if len(r):
            lines.append(f"| {NAMES[t]} | {r['final'].mean():.3f} ± {r['final'].std(ddof=1):.3f} | {r['auc'].mean():.3f} | {r['final_distance'].mean():.3f} | {r['reachable_share'].mean():.2f} | {r['seconds'].mean():.0f} |")
    for fam, table in (("primary: final success, each teacher against random (Holm over 4)", primary), ("secondary", secondary)):
        lines += ["", f"## {fam}", "", "| metric | a | b | mean a - b | 95 % CI | t | p | p (Holm) | d_z | verdict |", "|---|---|---|---|---|---|---|---|---|---|"]
        for _, r in table.iterrows():
            lines.append(f"| {r['metric']} | {NAMES[r['a']]} | {NAMES[r['b']]} | {r['mean_diff']:+.3f} | [{r['ci_low']:+.3f}, {r['ci_high']:+.3f}] | {r['statistic']:.2f} | {r['p_value']:.3g} | {r['p_holm']:.3g} | {r['effect']:.2f} | {r['verdict']} |")
    (out / "results.md").write_text("\n".join(lines) + "\n")

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4))
    for t in TEACHERS:
        c = curves[curves["teacher"] == t].groupby("step")["success"]
        m, s, n = c.mean(), c.std(ddof=1), c.count()
        ax.plot(m.index, m.values, label=NAMES[t])
        ax.fill_between(m.index, m - s / np.sqrt(n), m + s / np.sqrt(n), alpha=0.2)
        f = curves[(curves["teacher"] == t) & (curves["step"] > 0)].groupby("step")["reachable_share"].mean()
        bx.plot(f.index, f.values, label=NAMES[t])
    ax.set(xlabel="environment steps", ylabel="success on reachable test goals", title="PPO student (mean ± s.e. over seeds)")
    bx.set(xlabel="environment steps", ylabel="share of the last 200 goals in reach", title="Teachers' focus (a fifth of the box is in reach)")
    ax.legend()
    fig.tight_layout()
    fig.savefig(out / "rl_curriculum.png", dpi=120)


def seeds_arg(text: str) -> list[int]:
    if "-" in text:
        a, b = text.split("-")
        return list(range(int(a), int(b) + 1))
    return [int(s) for s in text.split(",")]


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", type=Path, required=True)
    p.add_argument("--seeds", type=seeds_arg, default=seeds_arg("0-7"), help="report seeds: 0-7; tuning seeds: 100-114")
    p.add_argument("--steps", type=int, default=200_000, help="environment steps per run")
    p.add_argument("--every", type=int, default=20_000, help="steps between scorings on the test goals")
    p.add_argument("--teachers", nargs="+", choices=TEACHERS, default=list(TEACHERS))
    p.add_argument("--workers", type=int, default=2)
    a = p.parse_args()
    if a.every <= 0 or a.steps % a.every or a.every % N_ENVS:
        p.error(f"--every must divide --steps and be a multiple of {N_ENVS}; got --steps {a.steps} --every {a.every}")
    (a.out / "jobs").mkdir(parents=True, exist_ok=True)
    jobs = [(t, s, a.steps, a.every, str(a.out)) for s in a.seeds for t in a.teachers if not (a.out / "jobs" / f"{t}_{s}.csv").exists()]
    with mp.get_context("spawn").Pool(a.workers) as pool:
        for _ in tqdm(pool.imap_unordered(one_run, jobs), total=len(jobs), desc="runs"):
            pass
    curves = pd.concat([pd.read_csv(a.out / "jobs" / f"{t}_{s}.csv") for s in a.seeds for t in a.teachers])
    curves.to_csv(a.out / "curves.csv", index=False)
    if set(a.teachers) == set(TEACHERS) and len(a.seeds) > 1:
        report(a.out, curves)
        print((a.out / "results.md").read_text())


if __name__ == "__main__":
    main()
