"""SPDL on tasks whose answer is known (issue 46): on [0, 1]^d, from N(0.1, 0.05^2) toward the
target N(0.5, 0.25^2) in every dimension, delta 0.5, epsilon 0.05, one update every 50 or 100
goals after as many.

- slab: competence 1 where x_0 < 0.3, else 0. The delta problem's optimum puts x_0 at
  N(0.3, 0.25^2), where E_p[competence] = Phi((0.3 - m_0) / s_0) = delta, and the other
  dimensions at the target.
- none: competence 0 everywhere; p stays where it started.
- all: competence 1 everywhere; p reaches the target.

Printed per task: E_p[competence] in closed form averaged over the updates of the last half of
the run, then over seeds (the slab's known answer is delta); p's x_0 mean and sd at the end; and
KL(p || mu) at the end (0 for "all", its start for "none").

    python benchmarks/references/spdl_known_optima.py [--seeds 5] [--goals 6000] [--form delta] [--covariance diagonal]

``--form alpha`` runs the NeurIPS paper's form instead (its answer on the slab is not delta: alpha
trades competence against KL to the target; benchmarks/references/spdl_vs_tma.py sets it beside
TeachMyAgent's).
"""

import argparse
import math

import numpy as np

import saggriac as sg

TASKS = {
    "slab": lambda g: float(g[0] < 0.3),
    "none": lambda g: 0.0,
    "all": lambda g: 1.0,
}


def phi(z: float) -> float:
    return 0.5 * (1.0 + math.erf(z / math.sqrt(2.0)))


def run(task: str, d: int, every: int, seed: int, goals: int, **form: str) -> tuple[float, float, float, float]:
    t = sg.SpdlSelector(np.zeros(d), np.ones(d), seed=seed, init_mean=0.1, init_std=0.05, update_every=every, warmup=every, **form)
    told, e = TASKS[task], []
    for k in range(goals):
        g = t.sample()
        t.update(g, told(g))
        if k >= goals // 2 and (k + 1) % every == 0:
            r = t.regions()
            m, s = (r["low"][0, 0] + r["high"][0, 0]) / 2, (r["high"][0, 0] - r["low"][0, 0]) / 2
            e.append(phi((0.3 - m) / s))
    r = t.regions()
    m, s = (r["low"][0, 0] + r["high"][0, 0]) / 2, (r["high"][0, 0] - r["low"][0, 0]) / 2
    return float(np.mean(e)), float(m), float(s), float(r["interest"][0])


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--seeds", type=int, default=5)
    p.add_argument("--goals", type=int, default=6000)
    p.add_argument("--form", default="delta", choices=["delta", "alpha"])
    p.add_argument("--covariance", default="diagonal", choices=["diagonal", "full"])
    a = p.parse_args()
    form = {"form": a.form, "covariance": a.covariance}
    print("| task | d | update every | E_p[competence] (slab: delta = 0.5) | per seed | x_0 mean, sd | KL(p \\|\\| mu) |")
    print("|---|---|---|---|---|---|---|")
    for task in TASKS:
        for d in (2, 5):
            for every in (50, 100):
                rows = np.array([run(task, d, every, s, a.goals, **form) for s in range(a.seeds)])
                e = rows[:, 0]
                per = ", ".join(f"{v:.3f}" for v in e) if task == "slab" else "-"
                shown = f"{e.mean():.3f}" if task == "slab" else "-"
                print(f"| {task} | {d} | {every} | {shown} | {per} | {rows[:, 1].mean():.3f}, {rows[:, 2].mean():.3f} | {rows[:, 3].mean():.4f} |", flush=True)


if __name__ == "__main__":
    main()
