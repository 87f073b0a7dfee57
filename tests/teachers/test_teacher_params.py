"""A teacher chosen by Config(teacher=...) takes any of its parameters through teacher_params:
the run's goals are those of the same teacher, built with those parameters, given as
goal_selector=."""

import numpy as np
import pytest

import saggriac as sg
from saggriac.seeding import selector_seed

PARAMS = {
    "riac": (sg.RiacSelector, {"max_region_size": 10, "split_attempts": 10, "p_alp": 0.5, "p_random": 0.4}),
    "alp_gmm": (sg.AlpGmmSelector, {"fit_rate": 20, "bootstrap": 20, "max_components": 4, "random_task_ratio": 0.1}),
    "covar_gmm": (sg.CovarGmmSelector, {"fit_rate": 20, "bootstrap": 20, "absolute_lp": False}),
    # A run's competences lie in [-1, 0]: thresholds there, so that bounds move.
    "adr": (sg.AdrSelector, {"t_low": -0.9, "t_high": -0.3, "buffer_size": 3, "boundary_prob": 0.8, "initial": 0.2}),
}


@pytest.mark.parametrize("teacher", sorted(PARAMS))
def test_teacher_params_reach_the_run_teacher(teacher, tmp_path):
    cls, params = PARAMS[teacher]
    cfg = sg.Config.from_preset("exp1", teacher=teacher, teacher_params=params, n_steps=5000, n_evals=1)
    tuned = sg.run(cfg, seed=5, out_dir=tmp_path / "r")
    default = sg.run(cfg.replace(teacher_params={}), seed=5)
    by_hand = sg.run(cfg.replace(teacher="own", teacher_params={}), seed=5, goal_selector=cls(cfg.goal_low, cfg.goal_high, seed=selector_seed(5), **params))
    goals = ["goal_x", "goal_y"]
    # Each goal tells the teacher up to 5 competences: 20 goals outlast every bootstrap above.
    assert len(tuned.goals) > 20
    assert np.array_equal(tuned.goals[goals].to_numpy(), by_hand.goals[goals].to_numpy())
    n = min(len(tuned.goals), len(default.goals))
    assert not np.array_equal(tuned.goals[goals].to_numpy()[:n], default.goals[goals].to_numpy()[:n])
    # Saved with the run, read back as given.
    assert dict(sg.RunResult.load(tmp_path / "r").config.teacher_params) == params


def test_teacher_params_are_checked_against_the_chosen_teacher(tmp_path):
    with pytest.raises(sg.ParameterError, match="fit_rate, max_components, random_task_ratio, bootstrap") as e:
        sg.Config(teacher="alp_gmm", teacher_params={"max_region_size": 50})
    assert e.value.param == "teacher_params"
    with pytest.raises(sg.ParameterError, match="empty with teacher 'own'"):
        sg.Config(teacher_params={"fit_rate": 50})
    with pytest.raises(sg.ParameterError, match=r"p_alp \+ p_random <= 1") as e:
        sg.Config(teacher="riac", teacher_params={"p_alp": 0.9})
    assert e.value.param == "teacher_params.p_alp"
    for bad in ({"fit_rate": 2.5}, {"fit_rate": True}, {"fit_rate": -1}, {"fit_rate": "100"}):
        with pytest.raises(sg.ParameterError, match="teacher_params"):
            sg.Config(teacher="alp_gmm", teacher_params=bad)
    with pytest.raises(sg.ParameterError, match="must be a bool"):
        sg.Config(teacher="covar_gmm", teacher_params={"absolute_lp": 1})
    # A dict in, a hashable Config, the dict back; numpy numbers become Python ones.
    cfg = sg.Config(teacher="alp_gmm", teacher_params={"fit_rate": np.int64(120), "bootstrap": 50})
    assert hash(cfg) == hash(sg.Config(teacher="alp_gmm", teacher_params={"bootstrap": 50, "fit_rate": 120}))
    assert cfg.to_dict()["teacher_params"] == {"bootstrap": 50, "fit_rate": 120}
    # From a TOML file, as a table.
    f = tmp_path / "c.toml"
    f.write_text('teacher = "riac"\n[teacher_params]\nmax_region_size = 80\n')
    assert dict(sg.Config.from_toml(f).teacher_params) == {"max_region_size": 80}


def test_a_users_selector_is_told_points_of_its_box():
    """Subgoals lie between where the arm is and the goal: from a start outside the goal box
    (here the rest pose, x = 50, beyond the box's x <= 30) they leave the box. A user's selector
    is told the nearest point of its box, as the built-in teachers record it, instead of a point
    its update() may refuse (saggriac's own ask/tell teachers do)."""

    class Strict(sg.RandomSelector):
        told: list = []

        def update(self, goal, competence):
            assert np.all(goal >= self.low) and np.all(goal <= self.high), goal
            Strict.told.append(np.array(goal))
            return super().update(goal, competence)

    cfg = sg.Config.from_preset("exp1", goal_low=(0.0, -30.0), goal_high=(30.0, 30.0), n_steps=1500, n_evals=1)
    r = sg.run(cfg, seed=2, goal_selector=Strict(cfg.goal_low, cfg.goal_high, seed=0))
    # The run's own table keeps the subgoals where they were; some of them left the box.
    assert (r.attempts["target_x"] > 30.0).any()
    assert len(Strict.told) == len(r.attempts) and np.max([t[0] for t in Strict.told]) <= 30.0


def test_one_constructor_takes_a_kind_and_its_parameters():
    """The ask/tell constructor takes any teacher by kind with a dict of its parameters (those of
    _core.teacher_defaults()); wrong names, types and values are named with the class, the
    parameter, the value and the rule."""
    from saggriac import _core

    for kind, params in _core.teacher_defaults().items():
        low, high = ([], []) if kind == "discrete_lp" else ([0.0, 0.0], [1.0, 1.0])
        assert _core.AskTell(kind, low, high, 3, params).kind == kind
    with pytest.raises(sg.ParameterError, match=r"^The 'interest_divisor' parameter of SaggRiacSelector must be one of 'zeta', 'window', 'printed'. Got 'w' instead.$"):
        _core.AskTell("sagg_riac", [0.0], [1.0], 0, {"interest_divisor": "w"})
    with pytest.raises(sg.ParameterError, match=r"'params' parameter of AlpGmmSelector must be a dict of the 'alp_gmm' teacher's parameters \(those of saggriac.AlpGmmSelector: fit_rate, max_components, random_task_ratio, bootstrap\). Got a dict with key 'bogus'"):
        _core.AskTell("alp_gmm", [0.0], [1.0], 0, {"bogus": 1})
    with pytest.raises(sg.ParameterError, match=r"^The 'fit_rate' parameter of CovarGmmSelector must be an int in \[2, 1000000\]. Got -1 instead.$"):
        _core.AskTell("covar_gmm", [0.0], [1.0], 0, {"fit_rate": -1})
    kinds = ", ".join(f"'{k}'" for k in sg.teachers.available())
    with pytest.raises(sg.ParameterError, match=f"The 'kind' parameter of GoalSelector must be one of {kinds}. Got 'foo'"):
        _core.AskTell("foo", [0.0], [1.0], 0)
    # A run takes any teacher of goals in a box; the task-list teacher is refused by name.
    with pytest.raises(sg.ParameterError, match="The 'teacher' parameter of Config must be 'own' or a teacher of goals in a box"):
        sg.Config(teacher="discrete_lp")
    with pytest.raises(sg.ParameterError, match="The 'teacher' parameter of Config must be 'own' or a teacher of goals in a box"):
        sg.Config(teacher="plr")
    with pytest.raises(sg.ParameterError, match="The 'teacher' parameter of Config must be one of 'own', 'sagg_riac', 'random'"):
        sg.Config(teacher="foo")
