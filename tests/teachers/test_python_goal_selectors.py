"""Python goal selectors in the Rust loop: the built-in ones conform, the checker rejects a
broken one, a Python selector drives the loop, and its exceptions propagate."""

import numpy as np
import pytest

import saggriac
from saggriac.errors import ConformanceError, ParameterError
from saggriac.testing import check_goal_selector


def small(**kw):
    return saggriac.Config.from_preset("exp1", **{"n_steps": 1500, "n_evals": 3, "n_test_goals": 10, "n_test_configs": 10, **kw})


@pytest.mark.parametrize("make", [lambda: saggriac.SaggRiacSelector([0, -50], [50, 50], seed=1), lambda: saggriac.RandomSelector([-1, -1, -1], [1, 1, 1], seed=2)])
def test_builtin_goal_selectors_conform(make):
    check_goal_selector(make())


class BadSelector:
    def __init__(self, flaw):
        self.low, self.high, self.flaw = np.array([0.0, 0.0]), np.array([1.0, 1.0]), flaw

    def sample(self):
        return np.array([2.0, 0.5]) if self.flaw == "outside" else np.array([0.5])

    def update(self, goal, competence):
        pass


def test_check_goal_selector_rejects_broken_ones():
    with pytest.raises(ConformanceError, match="within \\[low, high\\]"):
        check_goal_selector(BadSelector("outside"))
    with pytest.raises(ConformanceError, match="shape \\(2,\\)"):
        check_goal_selector(BadSelector("short"))
    with pytest.raises(ConformanceError, match="'update' method"):
        check_goal_selector(type("NoUpdate", (), {"low": [0.0], "high": [1.0], "sample": lambda self: [0.5]})())


class GridGoals:
    """Goals from a fixed list, in turn; remembers what it was told."""

    def __init__(self):
        self.low, self.high = np.array([0.0, -50.0]), np.array([50.0, 50.0])
        self.goals = [np.array([30.0 + i, 10.0 * (i % 3 - 1)]) for i in range(10)]
        self.i, self.told = 0, []

    def sample(self):
        g = self.goals[self.i % len(self.goals)]
        self.i += 1
        return g

    def update(self, goal, competence):
        self.told.append((np.array(goal), competence))


def test_python_goal_selector_drives_the_loop():
    sel = GridGoals()
    res = saggriac.run(small(), seed=0, goal_selector=sel)
    g = res.goals
    assert len(g) == sel.i  # every sampled goal was attempted
    assert np.allclose(g[["goal_x", "goal_y"]].to_numpy(), np.array(sel.goals * 100)[: len(g)])
    assert (g["mode"] == 5).all()
    # One update per subgoal, with the paper's competence range.
    assert len(sel.told) == len(res.attempts)
    assert all(-1.0 <= c <= 0.0 for _, c in sel.told)


def test_goal_selector_needs_a_sagg_condition_and_the_goal_space():
    with pytest.raises(ParameterError, match="condition"):
        saggriac.run(small(condition="actuator_random"), seed=0, goal_selector=GridGoals())
    with pytest.raises(ParameterError, match="goal_low"):
        saggriac.run(small(goal_low=(0.0, -40.0)), seed=0, goal_selector=GridGoals())


def test_goal_selector_exception_propagates():
    class Raising(GridGoals):
        def update(self, goal, competence):
            raise KeyError("teacher broke")

    with pytest.raises(KeyError, match="teacher broke"):
        saggriac.run(small(), seed=0, goal_selector=Raising())
