"""saggriac's SpdlSelector (delta form, Klink et al. JMLR 2021) beside TeachMyAgent's SPDL
(alpha form, NeurIPS 2020, taken from the authors' code), run from the snapshot in
the folder TEACHMYAGENT names, on the same task and competences: [0, 1]^2, competence 1 when the goal
lies in a disc around the origin of radius 0.3 + episode / 4000 (a learner whose solvable set
grows with practice), else 0. Both start at N(0.1, 0.05^2) per dimension, aim at N(0.5, 0.25^2),
update every 50 episodes after 50, KL step 0.05. TMA's value estimator is handed the
competence of each episode (through record_initial_state), as ours is told it; its alpha is
TeachMyAgent's PercentageAlphaFunction(offset 0, zeta), with TeachMyAgent's default zeta 0.05 and 0.5. Reported: KL(p || mu) and p's mean
every 500 episodes, mean over 5 seeds."""
import sys
import os

# A snapshot of flowersteam/TeachMyAgent (not a package on the registries): its folder.
if not os.environ.get("TEACHMYAGENT"):
    sys.exit("Set TEACHMYAGENT to the folder of a TeachMyAgent snapshot (git clone https://github.com/flowersteam/TeachMyAgent).")
sys.path.insert(0, os.environ["TEACHMYAGENT"])
import numpy as np
import torch
import saggriac as sg
from TeachMyAgent.teachers.algos.self_paced_teacher import SelfPacedTeacher
from TeachMyAgent.teachers.utils.alpha_functions import PercentageAlphaFunction

N, EVERY, SEEDS = 4000, 500, 5
torch.set_num_threads(1)

def comp(g, k):
    return float(np.hypot(*g) < 0.3 + k / N)

def kl_diag(m, s, mt=0.5, st=0.25):
    return float(np.sum(np.log(st / s) + (s**2 + (m - mt) ** 2) / (2 * st**2) - 0.5))

def ours(seed):
    t = sg.SpdlSelector([0.0, 0.0], [1.0, 1.0], seed=seed, init_mean=0.1, init_std=0.05, update_every=50, warmup=50)
    out = []
    for k in range(N):
        g = t.sample()
        t.update(g, comp(g, k))
        if (k + 1) % EVERY == 0:
            r = t.regions()
            m, s = (r["low"][0] + r["high"][0]) / 2, (r["high"][0] - r["low"][0]) / 2
            out.append((float(r["interest"][0]), *m, *s))
    return out

def tma(seed, zeta):
    t = SelfPacedTeacher([0.0, 0.0], [1.0, 1.0], seed, 0, 1, update_frequency=50, update_offset=50, alpha_function=PercentageAlphaFunction(0, zeta),
                         initial_dist={"mean": np.array([0.1, 0.1]), "variance": np.diag([0.05**2] * 2)},
                         target_dist={"mean": np.array([0.5, 0.5]), "variance": np.diag([0.25**2] * 2)}, max_kl=0.05, discount_factor=1.0)
    t.value_estimator = lambda states: np.asarray(states, dtype=np.float64)
    out = []
    for k in range(N):
        g = np.asarray(t.sample_task(), dtype=np.float64)
        c = comp(g, k)
        t.record_initial_state(g, c)
        t.episodic_update(g, c, False)
        t.step_update(None, None, c, None, True)
        if (k + 1) % EVERY == 0:
            m = t.context_dist.mean()
            s = np.sqrt(np.diag(t.context_dist.covariance_matrix()))
            out.append((float(t.target_context_kl()), *m, *s))
    return out

if __name__ == "__main__":
    rows = {"saggriac (delta 0.5)": np.array([ours(s) for s in range(SEEDS)]).mean(0)}
    for zeta in (0.05, 0.5):
        rows[f"TeachMyAgent (zeta {zeta})"] = np.array([tma(s, zeta) for s in range(SEEDS)]).mean(0)
    print("| episodes | " + " | ".join(f"{n}: KL, mean, sd" for n in rows) + " |")
    print("|---|" + "---|" * len(rows))
    for i in range(N // EVERY):
        f = lambda r: f"{r[0]:.3f}, ({r[1]:.2f}, {r[2]:.2f}), ({r[3]:.2f}, {r[4]:.2f})"
        print(f"| {(i + 1) * EVERY} | " + " | ".join(f(v[i]) for v in rows.values()) + " |")
