"""PLR (saggriac) beside Syllabus's PLR TaskSampler (syllabus-rl 0.7) on the same level list and
the same told scores. Distribution: both are driven through the same level sequence (ours draws;
Syllabus's state is forced to the same draws and scores); at checkpoints, Syllabus's
sample_weights() is compared with the empirical distribution of one draw from each of M copies
of our teacher. Speed: sample + update, interleaved blocks in one sitting."""
import time
import numpy as np
import saggriac as sg
from syllabus.curricula.plr.task_sampler import TaskSampler

def syllabus_sampler(n):
    return TaskSampler(tasks=list(range(n)), num_steps=1, num_actors=1, strategy="value_l1", replay_schedule="fixed",
                       score_transform="rank", temperature=0.1, rho=1.0, replay_prob=0.5, alpha=1.0,
                       staleness_coef=0.1, staleness_transform="power", staleness_temperature=1.0)

def ours(n, seed):
    # Syllabus with rho=1.0 and the fixed schedule: every level once, then only replays = ours "fixed", replay_prob=0.
    return sg.PlrSelector(n, seed=seed, score="told", replay_schedule="fixed", replay_prob=0.0)

def visits(kind, n, draws, seed, level_score):
    """Each implementation samples on its own; every draw is told its level's score (fixed per
    level, so ranks are fixed): the share of draws per level after the unseen phase."""
    if kind == "ours":
        t = ours(n, seed)
        draw, tell = t.sample_task, t.update
    else:
        np.random.seed(seed)  # Syllabus draws from numpy's global generator
        t = syllabus_sampler(n)
        draw, tell = t.sample, (lambda k, sc: t.update_task_score(0, k, sc, sc, 1, running_mean=True))
    out = []
    for i in range(draws):
        k = draw()
        tell(k, float(level_score[k]))
        if i >= n:
            out.append(k)
    return np.bincount(out, minlength=n) / len(out)

def distribution_check(n=20, draws=3000, seeds=20):
    level_score = np.random.default_rng(0).uniform(0, 1, n)
    by_rank = np.argsort(-level_score)
    f = {k: np.array([visits(k, n, draws, s, level_score) for s in range(seeds)]) for k in ("ours", "syllabus")}
    mo, ms = f["ours"].mean(0), f["syllabus"].mean(0)
    half = lambda a: 0.5 * np.abs(a[: seeds // 2].mean(0) - a[seeds // 2 :].mean(0)).sum()
    return by_rank, mo, ms, 0.5 * np.abs(mo - ms).sum(), half(f["ours"]), half(f["syllabus"])

def timing(n, reps=5, block=4000, seed=1):
    rng = np.random.default_rng(seed)
    scores = rng.uniform(0, 1, 200_000)
    res = {"ours": [], "syllabus": []}
    t, s = ours(n, seed), syllabus_sampler(n)
    # Warm both past the unseen phase.
    for i in range(n):
        k = t.sample_task(); t.update(k, scores[i])
        k = s.sample(); s.update_task_score(0, k, scores[i], scores[i], 1, running_mean=True)
    j = n
    for _ in range(reps):
        a = time.perf_counter()
        for i in range(block):
            k = t.sample_task(); t.update(k, scores[j + i])
        res["ours"].append((time.perf_counter() - a) / block * 1e6)
        a = time.perf_counter()
        for i in range(block // 10):
            k = s.sample(); s.update_task_score(0, k, scores[j + i], scores[j + i], 1, running_mean=True)
        res["syllabus"].append((time.perf_counter() - a) / (block // 10) * 1e6)
        j += block
    return {k: float(np.median(v)) for k, v in res.items()}

if __name__ == "__main__":
    by_rank, mo, ms, tv, ho, hs = distribution_check()
    print("share of replays per level, levels by rank of score (20 levels, 3000 draws, 20 seeds each)")
    print("rank      " + " ".join(f"{r + 1:6d}" for r in range(len(by_rank))))
    print("ours      " + " ".join(f"{mo[i]:6.4f}" for i in by_rank))
    print("Syllabus  " + " ".join(f"{ms[i]:6.4f}" for i in by_rank))
    print(f"TV(ours, Syllabus) = {tv:.4f}; between halves of the seeds: ours {ho:.4f}, Syllabus {hs:.4f}")
    print("time per sample + update (us, median of 5 interleaved blocks)")
    for n in (10, 100, 1000):
        r = timing(n)
        print(f"n = {n:5d}: ours {r['ours']:.2f} us, Syllabus {r['syllabus']:.1f} us, ratio {r['syllabus'] / r['ours']:.0f}x")
