"""The binding's one type check of a run's parameters covers the elements of a list: serde would
take 1.5 for a time step and True for a length without a word (issue 45, item 2)."""

import pytest

import saggriac as sg
from saggriac import _core


@pytest.mark.parametrize(
    "key, value, rule",
    [
        ("eval_schedule", [0, 50.5, 100], "a list of ints >= 0"),
        ("eval_schedule", [0, True, 100], "a list of ints >= 0"),
        ("eval_schedule", [0, -1], "a list of ints >= 0"),
        ("link_lengths", [1.0, True], "a list of floats"),
        ("goal_low", [0.0, "a"], "a list of floats"),
    ],
)
def test_a_list_element_of_the_wrong_type_is_refused_by_the_core(key, value, rule):
    d = dict(sg.Config(n_steps=100).core_dict())
    d[key] = value
    with pytest.raises(sg.ParameterError, match=rf"^The '{key}' parameter of Config must be {rule}\. Got "):
        _core.validate_config(d)
