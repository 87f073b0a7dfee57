"""Sizes with no sense are refused with the rule that bounds them by what the run can use
(issue 33, item 9): evaluations beyond one per step, neighbours beyond the samples the memory can
hold, lengths beyond the diameter of the reachable ball, a mixture teacher in 10^4 dimensions."""

import time

import numpy as np
import pytest

import saggriac as sg
from saggriac.cli import main
from saggriac.errors import ParameterError


def test_n_evals_beyond_the_steps_is_refused_with_the_rule():
    with pytest.raises(ParameterError, match=r"'n_evals' parameter of Config must be an int in \[1, max\(n_steps, 100\)\] \(a run evaluates at most once per time step; n_steps = 300\)\. Got 1000000"):
        sg.Config.from_preset("exp1", n_steps=300, n_evals=1_000_000)
    # Up to one per step is taken, and short runs keep the default.
    assert len(sg.Config.from_preset("exp1", n_steps=300, n_evals=300).schedule()) == 301
    assert sg.Config.from_preset("exp1", n_steps=10).n_evals == 20


def test_n_evals_on_the_command_line_is_refused_before_any_work(tmp_path, capsys):
    t = time.perf_counter()
    assert main(["run", "--preset", "exp1", "--steps", "300", "--set", "n_evals=1000000", "--out", str(tmp_path / "r"), "--no-progress"]) != 0
    assert time.perf_counter() - t < 5
    assert "n_evals" in capsys.readouterr().err
    assert not (tmp_path / "r").exists()


@pytest.mark.parametrize("name", ["k_neighbours", "episodic_k"])
def test_neighbours_beyond_what_memory_holds_are_refused(name):
    least = 1 if name == "k_neighbours" else 2  # episodic_k: min(n_joints, 2)
    with pytest.raises(ParameterError, match=rf"'{name}' parameter of Config must be an int in \[{least}, max\(n_steps, 1000\)\] \(the memory holds at most one sample per time step; n_steps = 300\)\. Got 1000000"):
        sg.Config.from_preset("exp1", n_steps=300, **{name: 1_000_000})
    sg.Config.from_preset("exp1", n_steps=300, **{name: 1000})
    sg.Config.from_preset("exp1", n_steps=5000, **{name: 5000})


@pytest.mark.parametrize("name", ["v", "eps_max", "eval_tolerance"])
@pytest.mark.parametrize("value", [1e308, 101.0])
def test_lengths_beyond_the_reachable_ball_are_refused(name, value):
    with pytest.raises(ParameterError, match=rf"'{name}' parameter of Config must be a finite float > 0 and <= 2 \* reach, the diameter of the ball the body reaches \(reach = 50.*\)\. Got {value:g}"):
        sg.Config.from_preset("exp1", **{name: value})
    sg.Config.from_preset("exp1", **{name: 100.0})


def test_lengths_follow_a_user_body_s_reach():
    from saggriac.bodies.environments import PlanarArm

    cfg = sg.Config.from_preset("exp1", n_steps=200, n_evals=1, n_test_goals=5, n_test_configs=5, v=30.0)
    with pytest.raises(ParameterError, match=r"'v' parameter .*\(reach = 10\)\. Got 30"):
        sg.run(cfg, 0, environment=PlanarArm(arm_length=10.0))


@pytest.mark.parametrize("cls", [sg.AlpGmmSelector, sg.CovarGmmSelector])
def test_a_mixture_teacher_in_too_many_dimensions_is_refused_at_once(cls):
    t = time.perf_counter()
    with pytest.raises(ParameterError, match=r"'low/high' parameter of \w+ must be bounds of at most 100 dimensions \(each refit runs EM on full covariance matrices, whose cost grows as the cube of the dimension\)\. Got 10000 dimensions"):
        cls(np.zeros(10_000), np.ones(10_000), seed=0)
    assert time.perf_counter() - t < 2
    cls(np.zeros(100), np.ones(100), seed=0)


@pytest.mark.parametrize("name, small, rule", [
    ("k_neighbours", 0, r"an int in \[1, max\(n_steps, 1000\)\]"),
    ("episodic_k", 1, r"an int in \[2, max\(n_steps, 1000\)\]"),
    ("v", 0.0, r"a finite float > 0 and <= 2 \* reach"),
    ("eval_tolerance", float("nan"), r"a finite float > 0 and <= 2 \* reach"),
])
def test_one_rule_text_whether_too_small_or_too_large(name, small, rule):
    big = 10**7 if isinstance(small, int) else 1e300
    for value in (small, big):
        with pytest.raises(ParameterError, match=rf"'{name}' parameter of Config must be {rule}"):
            sg.Config.from_preset("exp1", n_steps=300, **{name: value})
