"""The paper's reaching controller with a perfect model: how close can it get at all?

    python benchmarks/oracle_reach.py PRESET [--seeds 0-14]

For each seed, the test goals of the run's evaluation (the same ones, from the same seed) are
reached as the evaluation's test reaches do (evaluation/micro.rs: from rest for even goals and
from the previous end for odd ones, steps of length v towards the goal, dtheta = J+ dx scaled to
max_joint_step and clipped to the joint limits, stopping at eval_tolerance, after
eval_patience steps without progress, or at the timeout), but with the body's true Jacobian
(central differences of its exact forward kinematics) in place of the learnt local model. Its
error is a floor of what learning can reach with this controller; what stays above it is the
controller's (greedy straight-line steps stall at joint limits and around holes of the reachable
set), not the model's. Prints the mean error per seed and over the seeds. A diagnostic, not a test.
"""

from __future__ import annotations

import argparse

import numpy as np

import saggriac
from saggriac import _core
from saggriac.bodies.environments import PlanarArm, SpatialArm


def forward_of(cfg: saggriac.Config):
    if cfg.chain is not None:
        chain = list(cfg.chain)
        return lambda thetas: _core.chain_forward(chain, np.atleast_2d(thetas))
    body = {"planar_arm": PlanarArm, "spatial_arm": SpatialArm}[cfg.body](n_joints=cfg.n_joints, arm_length=cfg.arm_length, link_lengths=cfg.link_lengths, joint_limit=cfg.joint_limit)
    return lambda thetas: np.array([body.forward(t) for t in np.atleast_2d(thetas)])


def oracle_errors(cfg: saggriac.Config, goals: np.ndarray) -> np.ndarray:
    fk = forward_of(cfg)
    n, m, lim, h = cfg.joints, goals.shape[1], cfg.joint_limit, 1e-6
    eye = np.eye(n) * h
    theta = np.zeros(n)
    errors = []
    lengths = cfg.lengths()  # v and eval_tolerance as the run uses them (they follow the reach)
    v, tolerance = lengths["v"], lengths["eval_tolerance"]
    for i, g in enumerate(goals):
        if i % 2 == 0:
            theta = np.zeros(n)
        x = fk(theta)[0][:m]
        d0 = np.linalg.norm(g - x)
        best, since = d0, 0
        for _ in range(int(np.ceil(cfg.eval_timeout_factor * d0 / v)) + cfg.eval_timeout_min):
            d = np.linalg.norm(g - x)
            if d <= tolerance:
                break
            dx = (g - x) * min(v, d) / d
            pts = fk(np.vstack([theta + eye, theta - eye]))[:, :m]
            jac = ((pts[:n] - pts[n:]) / (2 * h)).T
            dtheta = np.linalg.pinv(jac, rcond=cfg.pinv_rcond) @ dx
            big = np.abs(dtheta).max()
            if big > cfg.max_joint_step:
                dtheta *= cfg.max_joint_step / big
            theta = np.clip(theta + dtheta, -lim, lim)
            x = fk(theta)[0][:m]
            dn = np.linalg.norm(g - x)
            if dn < best:
                best, since = dn, 0
            else:
                since += 1
                if since >= cfg.eval_patience:
                    break
        errors.append(np.linalg.norm(g - x))
    return np.array(errors)


def seeds_arg(s: str) -> list[int]:
    lo, _, hi = s.partition("-")
    return list(range(int(lo), int(hi or lo) + 1))


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("preset", choices=sorted(saggriac.config.PRESETS))
    p.add_argument("--seeds", type=seeds_arg, default=seeds_arg("0-14"))
    a = p.parse_args()
    cfg = saggriac.Config.from_preset(a.preset)
    means = []
    for seed in a.seeds:
        goals = np.asarray(saggriac.Learner(cfg, seed).test_set()["goals"], float)
        e = oracle_errors(cfg, goals)
        means.append(e.mean())
        print(f"seed {seed:3d}: mean {e.mean():7.3f}  median {np.median(e):7.3f}  goals within 1 unit {np.mean(e <= 1.0):5.0%}")
    print(f"{a.preset}: the controller with a perfect model reaches a mean error of {np.mean(means):.3f} (sd {np.std(means, ddof=1) if len(means) > 1 else 0:.3f} over {len(means)} seeds)")


if __name__ == "__main__":
    main()
