# Writes a checkpoint of format 5 with the saggriac 0.5.0 core (4ffeabf), and what the run
# evaluates after it is resumed there (reach_error, pred_error bits per metric row).
import sys, importlib.util
# python checkpoints_v5.py PATH_OF_0.5.0_CORE.so OUT_DIR
spec = importlib.util.spec_from_file_location("_core", sys.argv[1])
core = importlib.util.module_from_spec(spec); spec.loader.exec_module(core)
print(core.__version__, core.GIT_COMMIT)
out = sys.argv[2]
for name, extra in (("micro", {}), ("episodic", {"paradigm": "episodic", "joint_limit": 3.141592653589793, "goal_low": [-50.0, -50.0], "goal_high": [50.0, 50.0]})):
    cfg = {"n_steps": 300, "n_test_goals": 5, "n_test_configs": 5, "eval_schedule": [0, 100, 200, 300], **extra}
    l = core.Learner(cfg, 3, 4)
    l.run(lambda row: row["step"] < 100)
    print(name, "stopped at", l.steps)
    data = bytes(l.checkpoint())
    r = core.Learner.restore(cfg, data)
    assert r.run(None)
    m = r.metrics()
    import struct
    lines = [" ".join(str(struct.unpack("<Q", struct.pack("<d", float(v)))[0]) for v in (m["reach_error"][i], m["pred_error"][i])) for i in range(len(m["step"]))]
    open(f"{out}/checkpoint_v5_{name}.bin", "wb").write(data)
    open(f"{out}/checkpoint_v5_{name}.next", "w").write("\n".join(lines) + "\n")
    print(name, len(data), "bytes;", list(m["step"]), list(m["reach_error"]))
