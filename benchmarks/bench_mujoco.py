"""Micro-actions per second on the MuJoCo Pusher's arm: through MuJoCo from Python, natively as
a chain body, and on the built-in spatial arm (issue 15, MuJoCo item 4).

    python benchmarks/bench_mujoco.py [--steps 20000] [--seed 0] [--condition sagg_riac]

All three run the `pusher` preset's configuration (the arm3d preset for the built-in arm) with
the same seed:
- "mujoco": `saggriac.bodies.mujoco_arm.pusher_arm()` passed as `environment=`; every micro-action,
  the evaluation's test reaches included, is a call into Python and `mj_kinematics`. Its
  positions are put in the preset's units (shoulder at the origin, reach 50) by a thin wrapper.
- "native": `Config.from_preset("pusher")`, the same kinematics read out of the model once
  (`saggriac.bodies.PUSHER_CHAIN`), stepped in Rust.
- "arm3d": the built-in 15-joint spatial arm.
First the body alone: micro-actions per second of `MujocoArm.step` called from Python, against
the native chain's forward kinematics in Rust on as many configurations. Then, per run, the wall time, the micro-actions executed (learning steps plus the test
reaches' steps, from run.json's profile) and their rate, and the final errors (the mujoco and
native runs see the same test set; their positions differ in the last bits, so their runs may
part after a while). Needs the MuJoCo extra. A benchmark, not a test.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import saggriac
from saggriac.bodies import PUSHER_SCALE
from saggriac.config import CONDITIONS
from saggriac.bodies.mujoco_arm import pusher_arm


class PusherInPresetUnits:
    """The MuJoCo Pusher arm with its positions in the preset's units."""

    def __init__(self) -> None:
        self.arm = pusher_arm()
        self.joint_space, self.action_space = self.arm.joint_space, self.arm.action_space
        self.task_space = saggriac.bodies.environments.Box(-1e3, 1e3, (3,))
        self.shoulder = self.arm.model.body("r_shoulder_pan_link").pos.copy()

    def _units(self, x: np.ndarray) -> np.ndarray:
        return (x - self.shoulder) * PUSHER_SCALE

    def reset(self, *, seed=None, options=None):
        theta, x = self.arm.reset(seed=seed, options=options)
        return theta, self._units(x)

    def step(self, dtheta):
        theta, x = self.arm.step(dtheta)
        return theta, self._units(x)


def measure(name: str, cfg: saggriac.Config, seed: int, environment=None) -> dict:
    t = time.perf_counter()
    r = saggriac.run(cfg, seed=seed, environment=environment, threads=1)
    wall = time.perf_counter() - t
    prof = r.manifest["profile"]
    actions = cfg.n_steps + int(prof["test_steps"])
    return {"case": name, "wall": wall, "actions": actions, "rate": actions / wall, "reach": r.final_reach_error, "pred": r.final_pred_error}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--steps", type=int, default=20_000)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--condition", default="sagg_riac", choices=CONDITIONS)
    a = p.parse_args()
    pusher = saggriac.Config.from_preset("pusher", condition=a.condition, n_steps=a.steps, n_evals=2)
    arm3d = saggriac.Config.from_preset("arm3d", condition=a.condition, n_steps=a.steps, n_evals=2)
    arm, rng = pusher_arm(), np.random.default_rng(a.seed)
    moves = rng.uniform(-0.02, 0.02, (a.steps, 7))
    arm.reset()
    t = time.perf_counter()
    for d in moves:
        arm.step(d)
    through_python = a.steps / (time.perf_counter() - t)
    thetas = np.clip(np.cumsum(moves, axis=0), -1.0, 1.0)
    t = time.perf_counter()
    saggriac._core.chain_forward(list(pusher.chain), thetas)
    in_rust = a.steps / (time.perf_counter() - t)
    print(f"body alone, {a.steps} micro-actions: MujocoArm.step from Python {through_python:,.0f}/s; native chain kinematics {in_rust:,.0f}/s ({in_rust / through_python:.0f} times)")
    rows = [measure("native", pusher, a.seed), measure("mujoco", pusher, a.seed, PusherInPresetUnits()), measure("arm3d", arm3d, a.seed)]
    print(f"{'case':8} {'wall s':>8} {'micro-actions':>14} {'per s':>10} {'final reach':>12} {'final pred':>11}")
    for r in rows:
        print(f"{r['case']:8} {r['wall']:8.2f} {r['actions']:14d} {r['rate']:10.0f} {r['reach']:12.3f} {r['pred']:11.3f}")
    native, mj = rows[0], rows[1]
    print(f"native / mujoco: {native['rate'] / mj['rate']:.1f} times the micro-actions per second")


if __name__ == "__main__":
    main()
