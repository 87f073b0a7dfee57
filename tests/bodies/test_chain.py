"""The chain body (body="chain") and the pusher preset, which need no MuJoCo at run time."""

import subprocess
import sys

import numpy as np
import pytest

import saggriac as sg
from saggriac.bodies import PUSHER_CHAIN
from saggriac.bodies.reachable import ReachableSet


def test_the_pusher_preset_learns_from_one_command(tmp_path):
    out = tmp_path / "run"
    done = subprocess.run([sys.executable, "-m", "saggriac.cli", "run", "--no-progress", "--preset", "pusher", "--steps", "3000", "--out", str(out)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    res = sg.RunResult.load(out)
    assert res.config.body == "chain" and res.config.joints == 7
    assert res.reach_error[-1] < 0.5 * res.reach_error[0]
    # Every test goal is reachable and the least-norm configurations reach them.
    assert res.manifest["test_set"]["unreached_goals"] == 0


def test_chain_kinematics_against_a_brute_force_product_of_transforms():
    # Rebuild the forward kinematics with 4x4 homogeneous matrices, joint by joint.
    def rot(axis, a):
        axis = np.asarray(axis, float) / np.linalg.norm(axis)
        k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
        return np.eye(3) + np.sin(a) * k + (1 - np.cos(a)) * k @ k

    def quat(q):
        w, x, y, z = np.asarray(q) / np.linalg.norm(q)
        return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])

    def homog(r, p):
        t = np.eye(4)
        t[:3, :3], t[:3, 3] = r, p
        return t

    c = np.asarray(PUSHER_CHAIN)
    rng = np.random.default_rng(2)
    for theta in rng.uniform(-1, 1, (50, 7)):
        t = np.eye(4)
        for j in range(7):
            row = c[15 * j : 15 * (j + 1)]
            lo, hi = row[13], row[14]
            anchor = row[7:10]
            t = t @ homog(quat(row[3:7]), row[:3]) @ homog(np.eye(3), anchor) @ homog(rot(row[10:13], (lo + hi) / 2 + (hi - lo) / 2 * theta[j]), np.zeros(3)) @ homog(np.eye(3), -anchor)
        tip = (t @ np.append(c[-3:], 1.0))[:3]
        assert np.allclose(sg._core.chain_forward(list(PUSHER_CHAIN), theta[None, :])[0], tip, atol=1e-10)


def test_reachable_set_of_a_chain():
    cfg = sg.Config.from_preset("pusher")
    reach = ReachableSet(cfg)
    # Positions the arm takes are inside (but for thin parts the sample misses: module docstring);
    # points beyond its reach around the shoulder are not.
    cloud = sg._core.chain_cloud(list(cfg.chain), 1.0, 20000, 99)
    assert reach.contains(cloud).mean() > 0.998
    rng = np.random.default_rng(0)
    far = rng.normal(size=(2000, 3))
    far = far / np.linalg.norm(far, axis=1, keepdims=True) * rng.uniform(cfg.reach + 3.0, 60.0, (2000, 1))
    assert not reach.contains(far).any()
    # The built-in arms keep their ball.
    ball = ReachableSet(sg.Config())
    assert ball.contains([[30.0, 30.0]]).tolist() == [True] and ball.contains([[40.0, 40.0]]).tolist() == [False]


def test_chain_runs_are_deterministic_and_checkpoint(tmp_path):
    cfg = sg.Config.from_preset("pusher", n_steps=2000, n_evals=2)
    a, b = sg.run(cfg, seed=3), sg.run(cfg, seed=3)
    assert a.attempts.equals(b.attempts) and np.array_equal(a.reach_error, b.reach_error)
    c = sg.run(cfg, seed=3, out_dir=tmp_path / "c", checkpoint_every=700)
    assert c.attempts.equals(a.attempts)


@pytest.mark.parametrize(
    "kwargs, param, words",
    [
        (dict(body="chain"), "chain", "saggriac.bodies.mujoco_arm"),
        (dict(chain=PUSHER_CHAIN), "chain", "unless body is 'chain'"),
        (dict(body="chain", chain=PUSHER_CHAIN[:20]), "chain", "15 n + 3"),
        (dict(body="chain", chain=PUSHER_CHAIN, joint_limit=1.5, goal_low=(-60.0,) * 3, goal_high=(60.0,) * 3), "joint_limit", "(0, 1]"),
        (dict(body="chain", chain=PUSHER_CHAIN, link_lengths=(1.0,) * 7, joint_limit=1.0, goal_low=(-60.0,) * 3, goal_high=(60.0,) * 3), "link_lengths", "chain"),
        (dict(body="chain", chain=PUSHER_CHAIN, joint_limit=1.0, goal_low=(-60.0,) * 3, goal_high=(60.0,) * 3, body_change_step=10, body_change_link=0, body_change_length=3.0), "body_change_step", "chain"),
        (dict(body="chain", chain=PUSHER_CHAIN[:13] + (2.0, 2.0) + PUSHER_CHAIN[15:], joint_limit=1.0), "chain", "low < high"),
        (dict(body="chain", chain=("a",) * 18), "chain", "list of floats"),
    ],
)
def test_bad_chain_configurations_are_named(kwargs, param, words):
    with pytest.raises(sg.ParameterError) as e:
        sg.Config(**kwargs)
    assert e.value.param == param and words in str(e.value), str(e.value)


def test_a_goal_box_away_from_the_chain_is_refused():
    cfg = sg.Config.from_preset("pusher", goal_low=(100.0, 100.0, 100.0), goal_high=(120.0, 120.0, 120.0), n_steps=100, n_evals=1)
    with pytest.raises(sg.ParameterError) as e:
        sg.run(cfg)
    assert "reachable set" in str(e.value)
