"""Python environments in the Rust loop: the built-in ones conform, the checker rejects broken
ones saying what is wrong, a Python arm gives the built-in arm's trajectory, and failures inside
the loop are reported with nothing bad stored or saved."""

import math

import numpy as np
import pandas as pd
import pytest

import saggriac
from saggriac.bodies.environments import Box, PlanarArm
from saggriac.errors import ConformanceError, InputError, ParameterError
from saggriac.testing import check_environment


def small(**kw):
    return saggriac.Config.from_preset("exp1", **{"n_steps": 1500, "n_evals": 3, "n_test_goals": 10, "n_test_configs": 10, **kw})





@pytest.mark.parametrize("env", [PlanarArm(), PlanarArm(n_joints=3, joint_limit=math.pi), PlanarArm(link_lengths=[5, 3, 2, 1, 0.5] * 20, max_joint_step=0.1)])
def test_builtin_environments_conform(env):
    check_environment(env)


class Broken(PlanarArm):
    def __init__(self, flaw):
        super().__init__(n_joints=4)
        self.flaw = flaw
        self.calls = 0

    def reset(self, *, seed=None, options=None):
        theta, x = super().reset(seed=seed, options=options)
        if self.flaw == "shape":
            return theta[:2], x
        if self.flaw == "random_reset":
            self.calls += 1
            return theta, x + self.calls
        if self.flaw == "single":
            return theta
        return theta, x

    def step(self, dtheta):
        theta, x = super().step(dtheta)
        if self.flaw == "nan":
            x[0] = np.nan
        if self.flaw == "escape":
            theta = theta + 10.0
        return theta, x


@pytest.mark.parametrize(
    "flaw, message",
    [
        ("shape", r"theta returned by environment.reset\(seed=...\) must have shape \(4,\)"),
        ("random_reset", "same \\(theta, x\\) each time"),
        ("single", "must return a pair \\(theta, x\\)"),
        ("nan", "non-finite"),
        ("escape", "must stay within joint_space"),
    ],
)
def test_check_environment_rejects_broken_ones(flaw, message):
    with pytest.raises(ConformanceError, match=message):
        check_environment(Broken(flaw))


def test_check_environment_needs_the_protocol():
    with pytest.raises(ConformanceError, match="joint_space"):
        check_environment(object())
    env = PlanarArm(n_joints=3)
    env.joint_space = Box([-1, -2, -1], [1, 1, 1])
    with pytest.raises(ConformanceError, match="symmetric limit"):
        check_environment(env)


@pytest.mark.parametrize("condition", ["sagg_riac", "actuator_riac"])
def test_python_arm_gives_the_builtin_trajectory(condition):
    # Uniform test configurations: every number, bit for bit.
    cfg = small(condition=condition, test_configs="uniform")
    builtin = saggriac.run(cfg, seed=3)
    python = saggriac.run(cfg, seed=3, environment=PlanarArm())
    pd.testing.assert_frame_equal(builtin.metrics, python.metrics, check_exact=True)
    pd.testing.assert_frame_equal(builtin.goals, python.goals, check_exact=True)
    pd.testing.assert_frame_equal(builtin.regions, python.regions, check_exact=True)
    assert python.manifest["environment"] == "saggriac.bodies.environments.PlanarArm"


def test_least_norm_test_configurations_through_a_python_body():
    # The built-in arm's IK uses its Jacobian; a Python body's, finite differences through
    # placements. Same configurations up to the solver's precision, so the same errors but for
    # the last digits; learning itself is untouched.
    cfg = small(condition="sagg_riac")
    builtin = saggriac.run(cfg, seed=3)
    python = saggriac.run(cfg, seed=3, environment=PlanarArm())
    pd.testing.assert_frame_equal(builtin.goals, python.goals, check_exact=True)
    assert builtin.metrics["reach_error"].tolist() == python.metrics["reach_error"].tolist()
    for col in ("pred_error", "dx_error"):
        np.testing.assert_allclose(python.metrics[col], builtin.metrics[col], rtol=1e-5)
    for r in (builtin, python):
        assert r.manifest["test_set"]["configs"] == "ik_min_norm"
        assert r.manifest["test_set"]["unreached_goals"] == 0


def test_python_arm_in_the_episodic_paradigm():
    # Uniform test configurations: bit for bit (the IK ones differ in the last digits, see above).
    cfg = saggriac.Config.from_preset("explauto", n_steps=2000, n_evals=2, test_configs="uniform")
    builtin = saggriac.run(cfg, seed=0)
    python = saggriac.run(cfg, seed=0, environment=PlanarArm(joint_limit=math.pi))
    pd.testing.assert_frame_equal(builtin.metrics, python.metrics, check_exact=True)


class Faulty(PlanarArm):
    def __init__(self, at, kind):
        super().__init__()
        self.at, self.kind, self.n = at, kind, 0

    def step(self, dtheta):
        self.n += 1
        theta, x = super().step(dtheta)
        if self.n == self.at:
            if self.kind == "raise":
                raise RuntimeError("motor fault")
            x = np.array([np.nan, x[1]])
        return theta, x


def test_environment_exception_propagates_and_nothing_is_saved(tmp_path):
    with pytest.raises(RuntimeError, match="motor fault"):
        saggriac.run(small(), seed=0, environment=Faulty(300, "raise"), out_dir=tmp_path / "run")
    assert not (tmp_path / "run").exists()


def test_environment_nan_is_rejected_naming_the_step(tmp_path):
    with pytest.raises(InputError, match=r"x returned by environment.step\(\) must be finite; element 0 is NaN.*time step \d+"):
        saggriac.run(small(), seed=0, environment=Faulty(300, "nan"), out_dir=tmp_path / "run")
    assert not (tmp_path / "run").exists()


def test_environment_must_match_the_configuration():
    with pytest.raises(ParameterError, match="n_joints"):
        saggriac.run(small(), seed=0, environment=PlanarArm(n_joints=10))
    # The joint limit is the body's: said once, by the body (issue 32).
    assert saggriac.run(small(), seed=0, environment=PlanarArm(joint_limit=1.0)).config.joint_limit == 1.0
    with pytest.raises(ParameterError, match="link_lengths"):
        saggriac.run(small(link_lengths=(10.0,) * 5), seed=0, environment=PlanarArm())


def test_python_environment_example_runs():
    import subprocess
    import sys
    from pathlib import Path

    script = Path(__file__).resolve().parents[2] / "examples" / "python_environment.py"
    out = subprocess.run([sys.executable, str(script), "--steps", "1500"], capture_output=True, text=True, check=True).stdout
    assert "same seed, same result: True" in out
