"""saggriac's SpdlSelector beside TeachMyAgent's SPDL (SelfPacedTeacher: the alpha form of the
NeurIPS 2020 paper, the authors' code), run from the snapshot in the folder TEACHMYAGENT names.

1. One update on the same goals. Both start from the same Gaussian (2-D and 5-D, full
   covariance), are told the same 50 goals and competences (a slab: competence 1 where
   x_0 < 0.3; and every goal a success), and take one update with zeta 0.5, epsilon 0.05.
   Printed: p's means and standard deviations after it, ours (form="alpha",
   covariance="full") and TeachMyAgent's, and the largest difference.
2. Whole runs on tasks with a known answer, on [0, 1]^d from N(0.1, 0.05^2) toward
   N(0.5, 0.25^2) in every dimension, an update every 50 episodes after 50: slab (as above),
   none (competence 0: p stays), all (competence 1: p reaches the target), disc (2-D,
   competence 1 within 0.3 + episode / 4000 of the origin: a learner whose solvable set
   grows). Ours in the alpha form (full covariance, as TeachMyAgent's) and in the delta form
   (delta 0.5), TeachMyAgent's with its PercentageAlphaFunction(0, zeta). Printed per task and
   teacher: KL(p || mu) at 1,000, 2,000 and 4,000 episodes (median over seeds: a run's pace is
   heavy-tailed, some seeds stall for a while) and, for the slab, E_p[competence] =
   Phi((0.3 - m_0) / s_0) over the last 2,000 episodes (mean over seeds).

TeachMyAgent's value estimator is handed each episode's competence (its initial state is the
competence), so both see the same numbers; its step is counted in episodes.

    TEACHMYAGENT=path/to/TeachMyAgent python benchmarks/references/spdl_vs_tma.py [--seeds 8] [--zeta 0.5]
"""

import argparse
import contextlib
import io
import math
import os
import sys

# A snapshot of flowersteam/TeachMyAgent (not a package on the registries): its folder.
if not os.environ.get("TEACHMYAGENT"):
    sys.exit("Set TEACHMYAGENT to the folder of a TeachMyAgent snapshot (git clone https://github.com/flowersteam/TeachMyAgent).")
sys.path.insert(0, os.environ["TEACHMYAGENT"])
import numpy as np  # noqa: E402
import torch  # noqa: E402

import saggriac as sg  # noqa: E402
from TeachMyAgent.teachers.algos.self_paced_teacher import SelfPacedTeacher  # noqa: E402
from TeachMyAgent.teachers.utils.alpha_functions import PercentageAlphaFunction  # noqa: E402

torch.set_num_threads(1)
N, EVERY = 4000, 50
TASKS = {
    "slab": lambda g, k: float(g[0] < 0.3),
    "none": lambda g, k: 0.0,
    "all": lambda g, k: 1.0,
    "disc": lambda g, k: float(np.hypot(g[0], g[1]) < 0.3 + k / N),
}


def phi(z: float) -> float:
    return 0.5 * (1.0 + math.erf(z / math.sqrt(2.0)))


def tma_teacher(d, seed, mean, std, zeta):
    t = SelfPacedTeacher(np.zeros(d), np.ones(d), seed, 0, 1, update_frequency=EVERY, update_offset=EVERY, alpha_function=PercentageAlphaFunction(0, zeta),
                         initial_dist={"mean": np.asarray(mean, dtype=float), "variance": np.diag(np.asarray(std, dtype=float) ** 2)},
                         target_dist={"mean": np.full(d, 0.5), "variance": np.diag([0.25**2] * d)}, max_kl=0.05, discount_factor=1.0)
    t.value_estimator = lambda states: np.asarray(states, dtype=np.float64)
    return t


def tma_tell(t, g, c):
    t.record_initial_state(g, c)
    t.episodic_update(g, c, False)
    with contextlib.redirect_stdout(io.StringIO()):  # it prints at every update
        t.step_update(None, None, c, None, True)


def ours_state(t):
    r = t.regions()
    return (r["low"][0] + r["high"][0]) / 2, (r["high"][0] - r["low"][0]) / 2, float(r["interest"][0])


def tma_state(t):
    return t.context_dist.mean(), np.sqrt(np.diag(t.context_dist.covariance_matrix())), float(t.target_context_kl())


def one_update(zeta):
    print("## One update on the same 50 goals (alpha form, full covariance)\n")
    print("| task | d | ours: means; sds | TeachMyAgent: means; sds | largest difference |")
    print("|---|---|---|---|---|")
    rng = np.random.default_rng(0)
    for d in (2, 5):
        mean, std = np.linspace(0.3, 0.1, d), np.linspace(0.1, 0.05, d)
        goals = np.clip(mean + std * rng.standard_normal((EVERY, d)), 0, 1)
        for task in ("slab", "all"):
            c = [TASKS[task](g, 0) for g in goals]
            a = sg.SpdlSelector(np.zeros(d), np.ones(d), init_mean=list(mean), init_std=list(std), update_every=EVERY, warmup=EVERY, form="alpha", covariance="full", alpha_zeta=zeta)
            b = tma_teacher(d, 1, mean, std, zeta)
            for g, ci in zip(goals, c):
                a.update(g, ci)
                tma_tell(b, g, ci)
            (ma, sa, _), (mb, sb, _) = ours_state(a), tma_state(b)
            show = lambda m, s: ", ".join(f"{v:.4f}" for v in m) + "; " + ", ".join(f"{v:.4f}" for v in s)
            print(f"| {task} | {d} | {show(ma, sa)} | {show(mb, sb)} | {max(np.abs(ma - mb).max(), np.abs(sa - sb).max()):.1e} |")


def run(who, task, d, seed, zeta):
    if who == "tma":
        t = tma_teacher(d, seed + 1, np.full(d, 0.1), np.full(d, 0.05), zeta)
    else:
        form = {"form": "alpha", "covariance": "full", "alpha_zeta": zeta} if who == "alpha" else {}
        t = sg.SpdlSelector(np.zeros(d), np.ones(d), seed=seed, init_mean=0.1, init_std=0.05, update_every=EVERY, warmup=EVERY, **form)
    kls, e = [], []
    for k in range(N):
        g = np.asarray(t.sample_task(), dtype=np.float64) if who == "tma" else t.sample()
        c = TASKS[task](g, k)
        if who == "tma":
            tma_tell(t, g, c)
        else:
            t.update(g, c)
        if (k + 1) % EVERY == 0:
            m, s, kl = tma_state(t) if who == "tma" else ours_state(t)
            if k + 1 in (1000, 2000, 4000):
                kls.append(kl)
            if k >= N - 2000:
                e.append(phi((0.3 - m[0]) / s[0]))
    return kls, float(np.mean(e))


def runs(seeds, zeta):
    print(f"\n## Whole runs: KL(p || mu) at 1,000 / 2,000 / 4,000 episodes (median of {seeds} seeds); slab: E_p[competence] over the last 2,000 (mean)\n")
    names = {"alpha": f"ours, alpha (zeta {zeta})", "tma": f"TeachMyAgent (zeta {zeta})", "delta": "ours, delta (0.5)"}
    print("| task | d | " + " | ".join(names.values()) + " |")
    print("|---|---|" + "---|" * len(names))
    for task, d in (("slab", 2), ("slab", 5), ("none", 2), ("all", 2), ("all", 5), ("disc", 2)):
        cells = []
        for who in names:
            out = [run(who, task, d, s, zeta) for s in range(seeds)]
            kl = np.median(np.array([o[0] for o in out]), axis=0)
            cell = " / ".join(f"{v:.3f}" for v in kl)
            if task == "slab":
                cell += f"; E_p {np.mean([o[1] for o in out]):.3f}"
            cells.append(cell)
        print(f"| {task} | {d} | " + " | ".join(cells) + " |", flush=True)


if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--seeds", type=int, default=8)
    p.add_argument("--zeta", type=float, default=0.5)
    a = p.parse_args()
    one_update(a.zeta)
    runs(a.seeds, a.zeta)
