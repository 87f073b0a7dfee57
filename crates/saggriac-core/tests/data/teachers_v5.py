# Teachers saved by the saggriac core of 02d4afe (format 5: PLR's parameters with ties; SPDL's
# and Goal GAN's before #46, no parameters per dimension) after 290 goals, and the 20 goals each
# asks next. SPDL updates every 20 goals here, so its next goals cross an update (at 300).
# python teachers_v5.py PATH_OF_THE_02d4afe_CORE.so OUT_DIR
import importlib.util, struct, sys
spec = importlib.util.spec_from_file_location("_core", sys.argv[1])
core = importlib.util.module_from_spec(spec); spec.loader.exec_module(core)
out = sys.argv[2]
lo, hi = [0.0, -1.0, 0.0], [1.0, 1.0, 2.0]
makers = {
    "adr": {"buffer_size": 3, "step": 0.1, "initial": 0.3, "initial_width": 0.2},
    "spdl": {"init_mean": 0.2, "init_std": 0.1, "update_every": 20, "warmup": 20},
    "goal_gan": {"update_size": 20, "gan_iterations": 10, "hidden": 8},
    "tscl": {"n_tasks": 5},
    "plr": {"n_tasks": 5},
}
# The competences of teachers_v4.py: success near the low corner of the box; a task index's own
# share for the task-list teachers.
def told(kind, g):
    if kind in ("tscl", "plr"):
        return (g[0] + 1) / 6
    return float(g[0] + 0.5 * (g[1] + 1) + 0.25 * g[2] < 0.9)
bits = lambda v: struct.unpack("<Q", struct.pack("<d", float(v)))[0]
for kind, params in makers.items():
    a = core.AskTell(kind, lo, hi, 7, params)
    for _ in range(290):
        g, _, _ = a.sample(); a.update(g, told(kind, g))
    data = bytes(a.save())
    assert int.from_bytes(data[:1], "little") == 5, data[:4]
    lines = []
    for _ in range(20):
        g, _, _ = a.sample(); lines.append(" ".join(str(bits(v)) for v in g)); a.update(g, told(kind, g))
    open(f"{out}/teacher_v5_{kind}.bin", "wb").write(data)
    open(f"{out}/teacher_v5_{kind}.next", "w").write("\n".join(lines) + "\n")
    print(kind, len(data))
