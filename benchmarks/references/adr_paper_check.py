"""ADR against what its paper reports (Akkaya et al. 2019, Sec. 5.2): a bound grows while the
performance at it is >= t_H and shrinks while it is <= t_L. A 1-D task: competence 1 below a
frontier that moves from 0.6 to 0.9 at episode 20k, then falls back to 0.3 at 40k."""
import numpy as np
import saggriac as sg

for seed in range(3):
    t = sg.AdrSelector([0.0], [1.0], seed=seed, initial=0.1, buffer_size=10, step=0.02)
    rng = np.random.default_rng(seed)
    row = []
    for e in range(1, 60001):
        front = 0.6 if e <= 20000 else (0.9 if e <= 40000 else 0.3)
        g = t.sample()
        t.update(g, float(g[0] <= front) + 0.1 * rng.standard_normal())
        if e in (10000, 20000, 30000, 40000, 50000, 60000):
            row.append(f"{e // 1000}k: [{t.bounds[0][0]:.2f}, {t.bounds[1][0]:.2f}]")
    print(f"seed {seed}: " + "  ".join(row))
