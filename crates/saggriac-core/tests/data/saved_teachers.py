"""Writes the saved teachers of one format for the tests (ask_tell.rs), with the core of the
commit that wrote that format: each teacher after some goals, and the 20 goals it asks next
(each coordinate's bits, one goal per line).

    python saved_teachers.py FORMAT PATH_OF_THAT_COMMIT'S_CORE.so OUT_DIR

- 3: saggriac 0.5.0 (4ffeabf), the six teachers of 0.5, 300 goals, told as the format-2 files.
- 4: saggriac 0.6.0 (164832d), ADR, SPDL, Goal GAN, TSCL, 300 goals. SPDL updates every 100
  goals after 200, so its 20 next goals are drawn before its next update (its update rule
  changed in 10bb97b; its draws did not). teacher_v4_plr.bin is not this script's: it is
  461215a's, a PlrSelector(5, seed=1) saved by the 164832d build after 10 levels drawn and told
  0.3; a format-4 PLR does not continue to the bit, since its staleness rule changed in 961e3d0.
- 5: the core of 02d4afe (PLR's parameters with ties; SPDL's and Goal GAN's before #46, no
  parameters per dimension), ADR, SPDL, Goal GAN, TSCL, PLR, 290 goals. SPDL updates every 20
  goals here, so its next goals cross an update (at 300).
- 6: the core /work/main had installed on 2026-12-07 (saggriac 0.6.0, its GIT_COMMIT 7261afc with
  uncommitted changes; the core crate as at 82c65aa), before SAGG-RIAC's mode 3 reading (#48):
  SAGG-RIAC, 290 goals.
"""
import sys

from old_core import bits, load

LO, HI = [0.0, -1.0, 0.0], [1.0, 1.0, 2.0]
GOALS = {3: 300, 4: 300, 5: 290, 6: 290}
PARAMS = {
    4: {
        "adr": {"buffer_size": 3, "step": 0.1, "initial": 0.3, "initial_width": 0.2},
        "spdl": {"init_mean": 0.2, "init_std": 0.1},
        "goal_gan": {"update_size": 20, "gan_iterations": 10, "hidden": 8},
        "tscl": {"n_tasks": 5},
    },
    5: {
        "adr": {"buffer_size": 3, "step": 0.1, "initial": 0.3, "initial_width": 0.2},
        "spdl": {"init_mean": 0.2, "init_std": 0.1, "update_every": 20, "warmup": 20},
        "goal_gan": {"update_size": 20, "gan_iterations": 10, "hidden": 8},
        "tscl": {"n_tasks": 5},
        "plr": {"n_tasks": 5},
    },
    6: {"sagg_riac": {"g_max": 12, "zeta": 8, "min_child": 2}},
}


def makers(fmt, core):
    """kind -> a function making the teacher, in the API of the format's core."""
    if fmt == 3:
        return {
            "sagg_riac": lambda: core.AskTell("sagg_riac", LO, HI, 7, g_max=12, zeta=8, min_child=2, interest_divisor="window"),
            "random": lambda: core.AskTell("random", LO, HI, 7),
            "riac": lambda: core.AskTell.riac(LO, HI, 7, 20, 10, 0.25, 1 / 6, 0.6, 0.3),
            "alp_gmm": lambda: core.AskTell.alp_gmm(LO, HI, 7, 40, 4, 0.2, 40),
            "covar_gmm": lambda: core.AskTell.covar_gmm(LO, HI, 7, 40, 4, 0.2, 40, False),
            "discrete_lp": lambda: core.AskTell.discrete_lp(5, 7, 0.2, 0.3),
        }
    return {kind: (lambda kind=kind, params=params: core.AskTell(kind, LO, HI, 7, params)) for kind, params in PARAMS[fmt].items()}


def told(fmt, kind, g):
    """The competence told for goal g: a task index's own share for the task-list teachers; in
    format 3 a smooth slope, from format 4 success near the box's low corner (a frontier for ADR,
    SPDL and Goal GAN)."""
    if kind in ("discrete_lp", "tscl", "plr"):
        return (g[0] + 1) / 6
    if fmt == 3:
        return -0.5 * g[0] - 0.25 * g[-1] * g[-1]
    return float(g[0] + 0.5 * (g[1] + 1) + 0.25 * g[2] < 0.9)


def main():
    fmt, path, out = int(sys.argv[1]), sys.argv[2], sys.argv[3]
    core = load(path)
    for kind, make in makers(fmt, core).items():
        a = make()
        for _ in range(GOALS[fmt]):
            g, _, _ = a.sample()
            a.update(g, told(fmt, kind, g))
        data = bytes(a.save())
        assert data[0] == fmt, (kind, data[:4])
        lines = []
        for _ in range(20):
            g, _, _ = a.sample()
            lines.append(" ".join(str(bits(v)) for v in g))
            a.update(g, told(fmt, kind, g))
        open(f"{out}/teacher_v{fmt}_{kind}.bin", "wb").write(data)
        open(f"{out}/teacher_v{fmt}_{kind}.next", "w").write("\n".join(lines) + "\n")
        print(kind, len(data))


if __name__ == "__main__":
    main()
