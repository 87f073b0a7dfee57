"""Messages a user can act on (issue 33, item 10): numbers printed short (1e300, not 301
digits), one rule text per parameter whatever the wrong value, the parameter that is wrong named
(not one derived from it), and a default run folder that says its teacher."""


import pytest

import saggriac as sg
from saggriac.cli import default_run_dir, main
from saggriac.errors import InputError, ParameterError


@pytest.mark.parametrize("value", [1e300, -1e300, 1e-300])
def test_floats_in_core_messages_are_printed_short(value):
    with pytest.raises(ParameterError) as e:
        sg.Config(ridge=-abs(value))
    assert len(str(e.value)) < 200 and f"{-abs(value):e}".split("e")[0].rstrip("0").rstrip(".") in str(e.value)
    with pytest.raises(ParameterError, match=r"min_c = -1e300\)\. Got -1e301 instead"):
        sg.Config(min_c=-1e300, eps_c=-1e301)


def test_a_huge_competence_is_printed_short():
    t = sg.SaggRiacSelector([0.0, 0.0], [1.0, 1.0], seed=0)
    with pytest.raises(InputError) as e:
        t.update([0.5, 0.5], 1e300)
    assert "got 1e300." in str(e.value) and len(str(e.value)) < 200


@pytest.mark.parametrize("value", [100.0, 0, True, "100", -1, 2**70])
def test_a_teacher_parameter_has_one_rule_text_whatever_the_value(value):
    with pytest.raises(ParameterError, match=r"'teacher_params.fit_rate' parameter of Config must be an int in \[2, 1000000\]\."):
        sg.Config(teacher="alp_gmm", teacher_params={"fit_rate": value})
    with pytest.raises(ParameterError, match=r"'fit_rate' parameter of AlpGmmSelector must be an int in \[2, 1000000\]\."):
        sg.AlpGmmSelector([0.0], [1.0], seed=0, fit_rate=value)


def test_a_float_teacher_parameter_has_one_rule_text():
    for value in (2.0, "0.5", True):
        with pytest.raises(ParameterError, match=r"'teacher_params.random_task_ratio' parameter of Config must be a float in \[0, 1\]\."):
            sg.Config(teacher="alp_gmm", teacher_params={"random_task_ratio": value})


def test_a_body_change_without_its_link_names_the_link():
    with pytest.raises(ParameterError, match=r"'body_change_link' parameter of Config must be given with body_change_step") as e:
        sg.Config(body_change_step=100)
    assert "18446744073709551615" not in str(e.value)
    with pytest.raises(ParameterError, match=r"'body_change_step' parameter .* given with body_change_link, body_change_length"):
        sg.Config(body_change_link=1, body_change_length=2.0)


def test_arm_length_zero_names_arm_length():
    with pytest.raises(ParameterError, match=r"'arm_length' parameter of Config") as e:
        sg.Config(arm_length=0)
    assert e.value.param == "arm_length" and "link_lengths" not in str(e.value)


def test_a_huge_n_steps_has_a_schedule_within_it():
    cfg = sg.Config(n_steps=2**63 - 1)
    s = cfg.schedule()
    assert s[0] == 0 and s[-1] == 2**63 - 1 and len(s) == 21
    # Below 2**53 the schedule is the float formula's, as before (same bits for every run).
    assert sg.Config(n_steps=50_000).schedule() == [round(i * 50_000 / 20) for i in range(21)]


def test_a_toml_file_with_a_byte_order_mark_is_read(tmp_path):
    f = tmp_path / "c.toml"
    f.write_bytes("\ufeffn_steps = 300\n".encode())
    assert sg.Config.from_toml(f).n_steps == 300


def test_teacher_params_is_a_read_only_dict_and_the_config_stays_hashable():
    cfg = sg.Config(teacher="alp_gmm", teacher_params={"fit_rate": 100, "bootstrap": 50})
    assert cfg.teacher_params == {"bootstrap": 50, "fit_rate": 100}
    assert repr(cfg.teacher_params) == "{'bootstrap': 50, 'fit_rate': 100}"
    assert cfg.teacher_params["fit_rate"] == 100
    assert hash(cfg) == hash(sg.Config(teacher="alp_gmm", teacher_params={"bootstrap": 50, "fit_rate": 100}))
    with pytest.raises(TypeError):
        cfg.teacher_params["fit_rate"] = 3
    assert sg.Config().teacher_params == {}


def test_teacher_params_as_pairs_is_refused_with_the_rule():
    with pytest.raises(ParameterError, match=r"'teacher_params' parameter of Config must be a dict of the teacher's parameters"):
        sg.Config(teacher="alp_gmm", teacher_params=[("fit_rate", 100)])


def test_a_default_folder_says_its_teacher():
    cfg = sg.Config.from_preset("exp1", teacher="alp_gmm", teacher_params={"fit_rate": 100})
    assert default_run_dir("exp1", cfg, 0).name == "exp1-sagg_riac-seed0-teacher=alp_gmm-teacher_params.fit_rate=100"
    long = sg.Config.from_preset("exp1", teacher="riac", teacher_params={"max_region_size": 80}, link_lengths=tuple([50 / 15] * 15))
    name = default_run_dir("exp1", long, 0).name
    assert name.startswith("exp1-sagg_riac-seed0-teacher=riac-teacher_params.max_region_size=80-") and "-custom-" in name and len(name) <= 120


def test_overwrite_on_a_damaged_run_json_says_what_is_wrong(tmp_path, capsys):
    out = tmp_path / "r"
    assert main(["run", "--preset", "exp1", "--steps", "200", "--set", "n_evals=1", "--out", str(out), "--no-progress"]) == 0
    (out / "run.json").write_text('{"config": {')
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    assert main(["run", "--preset", "exp1", "--steps", "200", "--set", "n_evals=1", "--out", str(out), "--no-progress", "--overwrite"]) != 0
    err = capsys.readouterr().err
    assert "run.json is damaged (not JSON" in err and "delete it yourself" in err and "not a saggriac manifest" not in err
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before


def test_a_huge_goal_is_printed_short():
    t = sg.SaggRiacSelector([0.0, 0.0], [1.0, 1.0], seed=0)
    with pytest.raises(InputError) as e:
        t.update([1e300, 0.5], -0.5)
    assert "coordinate 0 is 1e300 but the bounds are [0, 1]" in str(e.value) and len(str(e.value)) < 300
