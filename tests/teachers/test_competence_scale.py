"""Thresholds a teacher compares told competences with (ADR's t_low / t_high, SPDL's delta, Goal
GAN's success_threshold) are written for a success rate in [0, 1]; a run tells competences in
[min_c, 0]. A teacher chosen through Config takes its defaults on the run's scale, and a
threshold no told competence can meet is refused by name, wherever the range is known (a run,
TeacherCallback, SelectorCurriculum): before, Config(teacher="adr") kept its single initial goal
for the whole run without a word."""

import numpy as np
import pytest

import saggriac as sg


def test_adr_chosen_through_config_moves_its_bounds_with_its_defaults():
    cfg = sg.Config.from_preset("exp1", teacher="adr", n_steps=6000, n_evals=1)
    goals = sg.run(cfg, seed=1).goals[["goal_x", "goal_y"]].to_numpy()
    centre = (np.asarray(cfg.goal_low) + np.asarray(cfg.goal_high)) / 2
    # ADR starts from the single goal at the box's centre: other goals mean its bounds grew.
    assert np.array_equal(goals[0], centre)
    assert len(np.unique(goals, axis=0)) > 10
    assert np.abs(goals - centre).max() > 1.0


CLASSES = {"adr": sg.AdrSelector, "spdl": sg.SpdlSelector, "goal_gan": sg.GoalGanSelector}
THRESHOLDS = ("t_low", "t_high", "delta", "success_threshold")


@pytest.mark.parametrize("teacher", sorted(CLASSES))
@pytest.mark.parametrize("min_c", [-1.0, -2.0])
def test_config_defaults_are_the_papers_on_the_runs_scale(teacher, min_c):
    """The paper's value v, for [0, 1], becomes min_c + v (0 - min_c): the run's goals are those
    of the class built with those thresholds by hand."""
    paper = {p: v for p, v in sg._core.teacher_defaults()[teacher].items() if p in THRESHOLDS}
    scaled = {p: min_c + v * (0.0 - min_c) for p, v in paper.items()}
    assert all(min_c < v < 0 for v in scaled.values())
    if teacher == "adr" and min_c == -1.0:
        assert scaled == pytest.approx({"t_low": -0.8, "t_high": -0.2})
    cfg = sg.Config.from_preset("exp1", teacher=teacher, min_c=min_c, n_steps=3000, n_evals=1)
    chosen = sg.run(cfg, seed=2)
    by_hand = sg.run(cfg.replace(teacher="own"), seed=2, goal_selector=CLASSES[teacher](cfg.goal_low, cfg.goal_high, seed=sg.seeding.selector_seed(2), **scaled))
    goals = ["goal_x", "goal_y"]
    assert len(chosen.goals) > 20
    assert np.array_equal(chosen.goals[goals].to_numpy(), by_hand.goals[goals].to_numpy())


@pytest.mark.parametrize(
    "teacher, params, param, rule",
    [
        ("adr", {"t_high": 0.8}, "t_high", "a float <= 0"),
        ("adr", {"t_low": -1.5, "t_high": -0.2}, "t_low", "a float >= -1"),
        ("spdl", {"delta": 0.5}, "delta", r"a float in \[-1, 0\]"),
        ("spdl", {"delta": -1.5}, "delta", r"a float in \[-1, 0\]"),
        ("goal_gan", {"success_threshold": 0.5}, "success_threshold", r"a float in \(-1, 0\]"),
        ("goal_gan", {"success_threshold": -1.0}, "success_threshold", r"a float in \(-1, 0\]"),
    ],
)
def test_thresholds_a_run_cannot_meet_are_refused_by_name(teacher, params, param, rule):
    with pytest.raises(sg.ParameterError, match=rf"^The 'teacher_params.{param}' parameter of Config must be {rule} \(the competences a run tells \(min_c to 0\) lie in \[-1, 0\]") as e:
        sg.Config.from_preset("exp1", teacher=teacher, teacher_params=params)
    assert e.value.param == f"teacher_params.{param}"


def test_a_goal_selector_given_to_a_run_is_checked_against_its_competences():
    cfg = sg.Config.from_preset("exp1", n_steps=500, n_evals=1)
    # AdrSelector's own defaults are for [0, 1]: in a run its bounds could never grow.
    with pytest.raises(sg.ParameterError, match=r"^The 't_high' parameter of AdrSelector must be a float <= 0 \(the competences a run tells") as e:
        sg.run(cfg, seed=0, goal_selector=sg.AdrSelector(cfg.goal_low, cfg.goal_high))
    assert e.value.param == "t_high"
    sg.run(cfg, seed=0, goal_selector=sg.AdrSelector(cfg.goal_low, cfg.goal_high, t_low=-0.8, t_high=-0.2))


def test_goal_gan_refuses_rates_no_goal_can_have():
    """With 2 rollouts a goal's success rate is 0, 0.5 or 1: [0.6, 0.9] holds none."""
    with pytest.raises(sg.ParameterError, match=r"^The 'r_max' parameter of GoalGanSelector must be a float such that \[r_min, r_max\] holds a success rate k / n_rollouts \(r_min = 0.6, n_rollouts = 2\). Got 0.9 instead.$"):
        sg.GoalGanSelector([0.0], [1.0], r_min=0.6, r_max=0.9)
    assert sg.GoalGanSelector([0.0], [1.0], r_min=0.6, r_max=0.9, n_rollouts=3).dim == 1


def test_adapters_check_the_competences_they_tell():
    pytest.importorskip("stable_baselines3")
    from saggriac.adapters.sb3 import TeacherCallback

    # competence="distance" tells -distance <= 0: ADR's default t_high 0.8 is never met.
    with pytest.raises(sg.ParameterError, match=r"^The 't_high' parameter of AdrSelector must be a float <= 0 \(the competences TeacherCallback\(competence='distance'\) tells lie in \[-inf, 0\]"):
        TeacherCallback(sg.AdrSelector([0.0], [1.0]), competence="distance")
    with pytest.raises(sg.ParameterError, match=r"^The 'delta' parameter of SpdlSelector must be a float in \[0, 1\] \(the competences TeacherCallback\(competence='success'\) tells"):
        TeacherCallback(sg.SpdlSelector([0.0], [1.0], delta=-0.5), competence="success")
    # The defaults suit success; a failed check claims nothing, so the teacher can still be used.
    t = sg.AdrSelector([0.0], [1.0])
    with pytest.raises(sg.ParameterError):
        TeacherCallback(t, competence="distance")
    assert TeacherCallback(t, competence="success").teacher is t


def test_syllabus_checks_task_progress():
    pytest.importorskip("syllabus")
    import gymnasium
    from syllabus.task_space import BoxTaskSpace

    from saggriac.adapters.syllabus import SelectorCurriculum

    space = BoxTaskSpace(gymnasium.spaces.Box(np.float32([0.0]), np.float32([1.0]), dtype=np.float32))
    with pytest.raises(sg.ParameterError, match=r"^The 'success_threshold' parameter of GoalGanSelector must be a float in \(0, 1\] \(the competences SelectorCurriculum\(competence='progress'\) tells lie in \[0, 1\]"):
        SelectorCurriculum(space, sg.GoalGanSelector([0.0], [1.0], success_threshold=-0.5))
    assert SelectorCurriculum(space, sg.GoalGanSelector([0.0], [1.0])).told == 0
