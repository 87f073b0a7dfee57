"""A body's declared reach is bounded as every length is, and checked against a quick measurement
of the body (issue 33, item 5): 1e300, 1e13 and 1e-300 are refused, a reach ten times the body's
or below its span is warned about, saying by what factor."""

import warnings

import pytest

import saggriac as sg
from saggriac.bodies.environments import PlanarArm
from saggriac.errors import ConformanceError
from saggriac.bodies.scale import ReachWarning


def small(**kw):
    return sg.Config.from_preset("exp1", **{"n_steps": 200, "n_evals": 1, "n_test_goals": 5, "n_test_configs": 5, **kw})


class Declared(PlanarArm):
    def __init__(self, reach, **kw):
        super().__init__(**kw)
        self.declared = reach

    @property
    def reach(self):
        return self.declared


@pytest.mark.parametrize("reach", [1e300, 1e13, 1e-300, 1e-13])
def test_a_declared_reach_out_of_bounds_is_refused(reach, tmp_path):
    with pytest.raises(ConformanceError, match=r"environment.reach must be a float in \[1e-12, 1e\+12\]"):
        sg.run(small(), 0, environment=Declared(reach), out_dir=tmp_path / "r")
    assert not (tmp_path / "r").exists()


def test_the_same_rule_bounds_arm_length():
    with pytest.raises(sg.ParameterError, match=r"'arm_length' parameter of Config must be a float in \[1e-12, 1e\+12\]"):
        sg.Config(arm_length=1e-300)


@pytest.mark.parametrize("reach, factor", [(500.0, "11.9"), (5.0, "8.37")])
def test_a_declared_reach_far_from_the_body_is_warned_with_the_factor(reach, factor):
    with pytest.warns(ReachWarning, match=rf"environment.reach = {reach:g} is {factor} times"):
        sg.run(small(), 0, environment=Declared(reach))


def test_a_true_declared_reach_gives_no_warning():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for env in (PlanarArm(), PlanarArm(n_joints=100), PlanarArm(joint_limit=3.14159)):
            sg.run(small(n_joints=len(env.lengths)), 0, environment=env)
