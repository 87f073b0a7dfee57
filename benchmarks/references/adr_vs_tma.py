"""ADR (saggriac) beside TeachMyAgent's ADR (a snapshot, from the folder TEACHMYAGENT names with gym
shimmed by gymnasium) on the same task and competences: a 2-D box [0, 1]^2 whose learnable part
is x <= 0.7 and y <= 0.8 (competence 1 there, 0 elsewhere, plus noise of sd 0.1); the same
parameters: p_b = 0.5, m = 10, t_L = 0.2, t_H = 0.8, step 0.05 (width 1, so the same absolute
step), initial value the box's centre. Reported: the bounds after 5k, 20k, 50k episodes over 10
seeds, and the share of episodes whose competence reached a buffer."""
import sys
import os

# A snapshot of flowersteam/TeachMyAgent (not a package on the registries): its folder.
if not os.environ.get("TEACHMYAGENT"):
    sys.exit("Set TEACHMYAGENT to the folder of a TeachMyAgent snapshot (git clone https://github.com/flowersteam/TeachMyAgent).")
sys.path.insert(0, os.environ["TEACHMYAGENT"])
import numpy as np
import saggriac as sg
from TeachMyAgent.teachers.algos.adr import ADR

LEARN = np.array([0.7, 0.8])

def perf(task, rng):
    ok = np.all(np.asarray(task, dtype=np.float64) <= LEARN + 1e-6)
    return float(ok) + 0.1 * rng.standard_normal()

def run_ours(seed, episodes):
    t = sg.AdrSelector([0, 0], [1, 1], seed=seed, boundary_prob=0.5, buffer_size=10, t_low=0.2, t_high=0.8, step=0.05)
    rng = np.random.default_rng(1000 + seed)
    snaps, credited = {}, 0
    for e in range(1, episodes + 1):
        g = t.sample()
        credited += t.update(g, perf(g, rng)) is not None
        if e in CHECK:
            lo, hi = t.bounds
            snaps[e] = np.concatenate([lo, hi])
    return snaps, credited / episodes

def run_tma(seed, episodes):
    t = ADR([0, 0], [1, 1], seed=seed + 1, env_reward_lb=0, env_reward_ub=1, step_size=0.05, max_reward_thr=0.8, min_reward_thr=0.2,
            initial_dist={"mean": np.array([0.5, 0.5]), "variance": np.diag([1e-6, 1e-6])}, boundary_sampling_p=0.5, queue_len=10)
    rng = np.random.default_rng(1000 + seed)
    snaps, credited = {}, 0
    for e in range(1, episodes + 1):
        g = t.sample_task()
        on_bound = any(g[i] == t.cur_mins[i] or g[i] == t.cur_maxs[i] for i in range(2))
        credited += on_bound
        t.episodic_update(g, perf(g, rng), False)
        if e in CHECK:
            snaps[e] = np.concatenate([t.cur_mins, t.cur_maxs]).astype(np.float64)
    return snaps, credited / episodes

CHECK = (5000, 20000, 50000)
if __name__ == "__main__":
    seeds = range(10)
    for name, fn in (("saggriac", run_ours), ("TeachMyAgent", run_tma)):
        res = [fn(s, max(CHECK)) for s in seeds]
        for e in CHECK:
            b = np.array([r[0][e] for r in res])
            m, sd = b.mean(0), b.std(0)
            print(f"{name:12s} after {e:6d}: phi_L = ({m[0]:.3f}±{sd[0]:.3f}, {m[1]:.3f}±{sd[1]:.3f})  phi_H = ({m[2]:.3f}±{sd[2]:.3f}, {m[3]:.3f}±{sd[3]:.3f})")
        print(f"{name:12s} share of episodes put in a buffer: {np.mean([r[1] for r in res]):.3f}")
