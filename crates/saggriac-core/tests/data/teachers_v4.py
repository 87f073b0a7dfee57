# Teachers saved by the saggriac 0.6.0 core (format 4, 164832d) after 300 goals, and the 20
# goals each asks next. SPDL updates every 100 goals after 200, so its 20 next goals are drawn
# before its next update (its update rule changed in 10bb97b; its draws did not).
# python teachers_v4.py PATH_OF_THE_164832d_CORE.so OUT_DIR
# (teacher_v4_plr.bin is not this script's: it is 461215a's, a PlrSelector(5, seed=1) saved by
# the 164832d build after 10 levels drawn and told 0.3; a format-4 PLR does not continue to the
# bit, since its staleness rule changed in 961e3d0.)
import importlib.util, struct, sys
spec = importlib.util.spec_from_file_location("_core", sys.argv[1])
core = importlib.util.module_from_spec(spec); spec.loader.exec_module(core)
out = sys.argv[2]
lo, hi = [0.0, -1.0, 0.0], [1.0, 1.0, 2.0]
makers = {
    "adr": {"buffer_size": 3, "step": 0.1, "initial": 0.3, "initial_width": 0.2},
    "spdl": {"init_mean": 0.2, "init_std": 0.1},
    "goal_gan": {"update_size": 20, "gan_iterations": 10, "hidden": 8},
    "tscl": {"n_tasks": 5},
}
# Success where the scaled goal is near the low corner (a frontier for ADR, SPDL and Goal GAN);
# a task index's own share for the task-list teachers.
def told(kind, g):
    if kind in ("tscl", "plr"):
        return (g[0] + 1) / 6
    return float(g[0] + 0.5 * (g[1] + 1) + 0.25 * g[2] < 0.9)
bits = lambda v: struct.unpack("<Q", struct.pack("<d", float(v)))[0]
for kind, params in makers.items():
    a = core.AskTell(kind, lo, hi, 7, params)
    for _ in range(300):
        g, _, _ = a.sample(); a.update(g, told(kind, g))
    data = bytes(a.save())
    lines = []
    for _ in range(20):
        g, _, _ = a.sample(); lines.append(" ".join(str(bits(v)) for v in g)); a.update(g, told(kind, g))
    open(f"{out}/teacher_v4_{kind}.bin", "wb").write(data)
    open(f"{out}/teacher_v4_{kind}.next", "w").write("\n".join(lines) + "\n")
    print(kind, len(data))
