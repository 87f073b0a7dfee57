"""Every wrong value of a teacher's int parameter is told the one rule the core checks (issue
44, item 10): AdrSelector(buffer_size=-1) or 10.0 read "an int in [0, 2**63)" while
buffer_size=0 read "an int in [1, 1000000]". And check_competences refuses a range that is not
one (strings, NaN, lo > hi) as such, instead of raising ValueError or blaming a threshold."""

import inspect
import math
import re

import numpy as np
import pytest

import saggriac as sg
from saggriac.teachers import classes
from saggriac.teachers.ask_tell import DEFAULTS

WRONG = (-1, 0, 0.5, 2.0, True, np.int64(-3), 2**62, 10**30)


def _int_params():
    for kind, cls in sorted(classes().items()):
        for name, default in DEFAULTS[kind].items():
            if isinstance(default, int) and not isinstance(default, bool):
                yield pytest.param(cls, name, id=f"{cls.__name__}.{name}")


def _build(cls, name, value):
    kw = {"low": [0.0, 0.0], "high": [1.0, 1.0]} if "low" in inspect.signature(cls).parameters else {"n_tasks": 4}
    return cls(**{**kw, name: value})


def _rule(e, cls, name):
    found = re.fullmatch(rf"The '{name}' parameter of {cls.__name__} must be (.*)\. Got (.*) instead\.", str(e))
    assert found, str(e)
    return found.group(1)


@pytest.mark.parametrize("cls, name", list(_int_params()))
def test_every_wrong_value_of_an_int_parameter_is_told_one_rule(cls, name):
    rules = {}
    for value in WRONG:
        try:
            _build(cls, name, value)
        except sg.ParameterError as e:
            # numpy scalars are shown as the numbers they stand for.
            assert e.param == name and e.value == repr(value.item() if isinstance(value, np.generic) else value), (e.param, e.value)
            rules[repr(value)] = _rule(e, cls, name)
    # The float, the bool and the huge values are never taken; 0 is for some parameters.
    assert {"0.5", "2.0", "True", repr(2**62), repr(10**30), "-1"} <= set(rules), rules
    # A rule that names another parameter (SAGG-RIAC's min_child against g_max) is a second rule.
    own = {r for r in rules.values() if "g_max" not in r}
    assert len(own) == 1 and re.fullmatch(r"an int (in \[\d+, \d+\]|>= \d+)", own.pop()), rules


def test_the_examples_of_the_audit_read_the_same_rule():
    for make in (lambda v: sg.AdrSelector([0, 0], [1, 1], buffer_size=v), lambda v: sg.PlrSelector(v), lambda v: sg.DiscreteLpSelector(v)):
        for v in (-1, 10.0, True, 0):
            with pytest.raises(sg.ParameterError, match=r"must be an int in \[1, 1000000\]\. Got"):
                make(v)
    for v in (2.0, 0, 10**30):
        with pytest.raises(sg.ParameterError, match=r"'hidden' parameter of GoalGanSelector must be an int in \[1, 1024\]\. Got"):
            sg.GoalGanSelector([0, 0], [1, 1], hidden=v)
    for v in (1.5, -1, 2**62):
        with pytest.raises(sg.ParameterError, match=r"'warmup' parameter of SpdlSelector must be an int in \[0, 1000000\]\. Got"):
            sg.SpdlSelector([0, 0], [1, 1], warmup=v)
    # Right values still go through, numpy ints included.
    assert sg.AdrSelector([0, 0], [1, 1], buffer_size=np.int64(3)).dim == 2
    # A 0-d array is its value (it raised TypeError: 'float' object is not iterable), as the
    # fuzz of tests/teachers/test_new_teachers_fuzz.py found.
    assert sg.AdrSelector([0, 0], [1, 1], boundary_prob=np.array(0.5)).get_params()["boundary_prob"] == 0.5
    with pytest.raises(sg.ParameterError, match=r"'buffer_size' parameter of AdrSelector must be an int in \[1, 1000000\]\. Got 0 instead"):
        sg.AdrSelector([0, 0], [1, 1], buffer_size=np.array(0))


@pytest.mark.parametrize(
    "lo, hi, param, says",
    [
        ("a", "b", "lo", "must be a float, not NaN"),
        (0.0, "b", "hi", "must be a float, not NaN"),
        (None, 0.0, "lo", "must be a float, not NaN"),
        (True, 0.0, "lo", "must be a float, not NaN"),
        (float("nan"), 0.0, "lo", "must be a float, not NaN"),
        (-1.0, math.nan, "hi", "must be a float, not NaN"),
        (0.0, -math.inf, "lo", "must be a float <= hi"),
        (1.0, 0.0, "lo", "must be a float <= hi"),
    ],
)
def test_check_competences_refuses_a_range_that_is_not_one(lo, hi, param, says):
    for teacher in (sg.AdrSelector([0, 0], [1, 1]), sg.SpdlSelector([0, 0], [1, 1]), sg.GoalGanSelector([0, 0], [1, 1])):
        with pytest.raises(sg.ParameterError, match=rf"The '{param}' parameter of {type(teacher).__name__}.check_competences {says}") as e:
            teacher.check_competences(lo, hi, "me")
        assert e.value.param == param and "t_high" not in str(e.value)


def test_check_competences_still_tells_the_thresholds():
    with pytest.raises(sg.ParameterError, match=r"'t_high' parameter of AdrSelector must be a float <= 0"):
        sg.AdrSelector([0, 0], [1, 1]).check_competences(-1.0, 0.0, "me")
    sg.AdrSelector([0, 0], [1, 1]).check_competences(np.float32(0.0), 1, "me")  # the papers' range, numpy and int
    sg.AdrSelector([0, 0], [1, 1], t_low=-0.9, t_high=-0.3).check_competences(-math.inf, 0.0, "distances")  # TeacherCallback's distances
    with pytest.raises(sg.ParameterError, match=r"'whence' parameter of AdrSelector.check_competences must be a str"):
        sg.AdrSelector([0, 0], [1, 1]).check_competences(0.0, 1.0, 3)


def _bad_values(rule: str) -> list:
    """Values the rule ``rule`` (as a message states it) refuses: out of range and of other types."""
    other = ["x", None, [1]]
    if found := re.fullmatch(r"an int in \[(\d+), (\d+)\]", rule):
        lo, hi = int(found.group(1)), int(found.group(2))
        return [*([lo - 1] if lo > 0 else [-1]), hi + 1, 0.5, float(lo + 1), True, *other]
    if found := re.fullmatch(r"a float in ([\[(])([-\d.e]+), ([-\d.e]+)([\])])(?: \(.*\))?", rule):
        lo, hi = float(found.group(2)), float(found.group(3))
        return [lo - 1e-3 if found.group(1) == "[" else lo, hi + 1e-3 if found.group(4) == "]" else hi, math.nan, math.inf, True, *other]
    if found := re.fullmatch(r"a finite float (>=|>) ([-\d.e]+)", rule):
        lo = float(found.group(2))
        return [lo - 1 if found.group(1) == ">=" else lo, math.nan, math.inf, True, *other]
    if rule == "a finite float with |value| <= 1e100":
        return [1e101, -math.inf, math.nan, True, *other]
    if rule == "a bool":
        return [1, 0.0, "true", *other[1:]]
    if rule.startswith("one of "):
        return ["no such choice", 1, True, *other[1:]]
    raise AssertionError(f"a rule the test does not know: {rule!r}")


def _told(make, name):
    with pytest.raises(sg.ParameterError) as e:
        make()
    found = re.fullmatch(rf"The '(?:teacher_params\.)?{name}' parameter of (\w+) must be (.*)\. Got .* instead\.", str(e.value), re.DOTALL)
    assert found, str(e.value)
    return found.group(2)


def _every_parameter():
    for kind, cls in sg.teachers.available().items():
        for name in DEFAULTS[kind]:
            if name != "n_tasks":
                yield pytest.param(kind, cls, name, id=f"{kind}.{name}")


@pytest.mark.parametrize("kind, cls, name", list(_every_parameter()))
def test_one_bad_value_is_told_its_rule_by_every_route(kind, cls, name, tmp_path):
    """The core states each parameter's rule once (config/teachers/<name>.rs); every value it
    refuses, of any type, is told that text by the selector, and for a teacher a run can take,
    by Config, a TOML file and --set (issue 45, item 2)."""
    from saggriac.cli import parse_overrides

    rule = sg._core.teacher_param_rule(kind, name)
    assert rule, (kind, name)
    # A parameter the class also takes per dimension (issue 46, item 3) is told, for a list, the
    # same rule as a list states it: each value in a list of the box's length meets it.
    per_dimension = sg._core.teacher_per_dimension()[kind].get(name) == "vector"
    bad = _bad_values(rule)
    if per_dimension:
        bad += [[DEFAULTS[kind][name], v] for v in bad if isinstance(v, float)]
    for value in bad:
        told = rule + ", or a list of such floats, one per dimension of the box" if per_dimension and isinstance(value, list) else rule
        assert _told(lambda: sg.testing.example_teacher(cls, **{name: value}), name) == told, (name, value)
        if "box" not in cls.spaces or kind == "sagg_riac":
            continue  # a run takes teachers of a box; SAGG-RIAC's own parameters are Config's
        assert _told(lambda: sg.Config(teacher=kind, teacher_params={name: value}), name) == rule, (name, value)
        if value is None or isinstance(value, list):
            continue  # TOML has no null; a list is a list
        toml = tmp_path / "c.toml"
        shown = "nan" if isinstance(value, float) and math.isnan(value) else ("inf" if value == math.inf else ("-inf" if value == -math.inf else repr(value).lower() if isinstance(value, bool) else (f'"{value}"' if isinstance(value, str) else repr(value))))
        toml.write_text(f'teacher = "{kind}"\n[teacher_params]\n{name} = {shown}\n')
        assert _told(lambda: sg.Config.from_toml(toml), name) == rule, (name, value)
        overrides = parse_overrides([f"teacher={kind}", f"teacher_params.{name}={shown}"])
        assert _told(lambda: sg.Config.from_preset("exp1", **overrides), name) == rule, (name, value)
