"""Writes the checkpoints of one format for the tests (checkpoint.rs), with the core of the commit
that wrote that format, and what each run evaluates after it is resumed there (the bits of
reach_error and pred_error, one metric row per line).

    python saved_checkpoints.py FORMAT PATH_OF_THAT_COMMIT'S_CORE.so OUT_DIR

- 5: saggriac 0.5.0 (4ffeabf): a run of micro-actions and an episodic one.
- 6: saggriac 0.6.0 (164832d): runs whose goals ADR, Goal GAN and SPDL choose.
- 7: the same core as saved_teachers.py 6 (before SAGG-RIAC's mode 3 reading, #48): a run of
  SAGG-RIAC's own high level with a small tree.
"""
import sys

from old_core import bits, load

BASE = {"n_steps": 300, "n_test_goals": 5, "n_test_configs": 5, "eval_schedule": [0, 100, 200, 300]}
RUNS = {
    5: {
        "micro": {},
        "episodic": {"paradigm": "episodic", "joint_limit": 3.141592653589793, "goal_low": [-50.0, -50.0], "goal_high": [50.0, 50.0]},
    },
    6: {
        "adr": {"teacher": "adr", "teacher_params": {"step": 0.1}},
        "goal_gan": {"teacher": "goal_gan", "teacher_params": {"update_size": 10, "gan_iterations": 5, "hidden": 8}},
        "spdl": {"teacher": "spdl", "teacher_params": {"update_every": 20, "warmup": 20}},
    },
    7: {"sagg_riac": {"g_max": 12, "zeta": 8, "min_child": 2}},
}


def main():
    fmt, path, out = int(sys.argv[1]), sys.argv[2], sys.argv[3]
    core = load(path)
    print(core.__version__, core.GIT_COMMIT)
    for name, extra in RUNS[fmt].items():
        cfg = {**BASE, **extra}
        learner = core.Learner(cfg, 3, 4)
        learner.run(lambda row: row["step"] < 100)
        data = bytes(learner.checkpoint())
        resumed = core.Learner.restore(cfg, data)
        assert resumed.run(None)
        m = resumed.metrics()
        lines = [f"{bits(m['reach_error'][i])} {bits(m['pred_error'][i])}" for i in range(len(m["step"]))]
        open(f"{out}/checkpoint_v{fmt}_{name}.bin", "wb").write(data)
        open(f"{out}/checkpoint_v{fmt}_{name}.next", "w").write("\n".join(lines) + "\n")
        print(name, len(data), "bytes;", list(m["step"]), list(m["reach_error"]))


if __name__ == "__main__":
    main()
