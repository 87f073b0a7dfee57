# Teachers saved by the saggriac 0.5.0 core (format 3, 4ffeabf) after 300 goals, and the 20
# goals each asks next (told as in tests/data's format-2 files).
import importlib.util, struct, sys
# python teachers_v3.py PATH_OF_0.5.0_CORE.so OUT_DIR
spec = importlib.util.spec_from_file_location("_core", sys.argv[1])
core = importlib.util.module_from_spec(spec); spec.loader.exec_module(core)
out = sys.argv[2]
lo, hi = [0.0, -1.0, 0.0], [1.0, 1.0, 2.0]
makers = {
    "sagg_riac": lambda: core.AskTell("sagg_riac", lo, hi, 7, g_max=12, zeta=8, min_child=2, interest_divisor="window"),
    "random": lambda: core.AskTell("random", lo, hi, 7),
    "riac": lambda: core.AskTell.riac(lo, hi, 7, 20, 10, 0.25, 1 / 6, 0.6, 0.3),
    "alp_gmm": lambda: core.AskTell.alp_gmm(lo, hi, 7, 40, 4, 0.2, 40),
    "covar_gmm": lambda: core.AskTell.covar_gmm(lo, hi, 7, 40, 4, 0.2, 40, False),
    "discrete_lp": lambda: core.AskTell.discrete_lp(5, 7, 0.2, 0.3),
}
told = lambda kind, g: (g[0] + 1) / 6 if kind == "discrete_lp" else -0.5 * g[0] - 0.25 * g[-1] * g[-1]
bits = lambda v: struct.unpack("<Q", struct.pack("<d", float(v)))[0]
for kind, make in makers.items():
    a = make()
    for _ in range(300):
        g, _, _ = a.sample(); a.update(g, told(kind, g))
    data = bytes(a.save())
    lines = []
    for _ in range(20):
        g, _, _ = a.sample(); lines.append(" ".join(str(bits(v)) for v in g)); a.update(g, told(kind, g))
    open(f"{out}/teacher_v3_{kind}.bin", "wb").write(data)
    open(f"{out}/teacher_v3_{kind}.next", "w").write("\n".join(lines) + "\n")
    print(kind, len(data))
