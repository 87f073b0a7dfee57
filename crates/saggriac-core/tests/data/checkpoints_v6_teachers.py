# Writes checkpoints of format 6 with the saggriac 0.6.0 core (164832d) of runs whose goals
# ADR, Goal GAN and SPDL choose, and what each run evaluates after it is resumed there
# (reach_error, pred_error bits per metric row).
import sys, importlib.util, struct
# python checkpoints_v6_teachers.py PATH_OF_THE_164832d_CORE.so OUT_DIR
spec = importlib.util.spec_from_file_location("_core", sys.argv[1])
core = importlib.util.module_from_spec(spec); spec.loader.exec_module(core)
out = sys.argv[2]
teachers = {"adr": {"step": 0.1}, "goal_gan": {"update_size": 10, "gan_iterations": 5, "hidden": 8}, "spdl": {"update_every": 20, "warmup": 20}}
for kind, params in teachers.items():
    cfg = {"n_steps": 300, "n_test_goals": 5, "n_test_configs": 5, "eval_schedule": [0, 100, 200, 300], "teacher": kind, "teacher_params": params}
    l = core.Learner(cfg, 3, 4)
    l.run(lambda row: row["step"] < 100)
    data = bytes(l.checkpoint())
    r = core.Learner.restore(cfg, data)
    assert r.run(None)
    m = r.metrics()
    lines = [" ".join(str(struct.unpack("<Q", struct.pack("<d", float(v)))[0]) for v in (m["reach_error"][i], m["pred_error"][i])) for i in range(len(m["step"]))]
    open(f"{out}/checkpoint_v6_{kind}.bin", "wb").write(data)
    open(f"{out}/checkpoint_v6_{kind}.next", "w").write("\n".join(lines) + "\n")
    print(kind, len(data), "bytes;", list(m["step"]), list(m["reach_error"]))
