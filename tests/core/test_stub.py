"""The checked-in type stub describes the compiled module."""

import ast
from pathlib import Path

import saggriac
from saggriac import _core


def _stub_names():
    stub = Path(saggriac.__file__).with_name("_core.pyi")
    tree = ast.parse(stub.read_text())
    top, methods = set(), set()
    for node in tree.body:
        if isinstance(node, ast.FunctionDef):
            top.add(node.name)
        elif isinstance(node, ast.AnnAssign):
            top.add(node.target.id)
        elif isinstance(node, ast.ClassDef):
            top.add(node.name)
            methods |= {f"{node.name}.{m.name}" for m in node.body if isinstance(m, ast.FunctionDef) and not m.name.startswith("__")}
    return top, methods


def test_stub_matches_module():
    top, methods = _stub_names()
    public = {n for n in dir(_core) if not n.startswith("_")} | {"__version__"}
    assert top == public
    actual = {f"{c}.{n}" for c in ("Learner", "AskTell") for n in dir(getattr(_core, c)) if not n.startswith("_")}
    assert methods == actual


def test_config_keys_match():
    cfg = saggriac.Config()
    assert set(cfg.core_dict()) == set(_core.CONFIG_KEYS)


def test_python_defaults_are_the_cores():
    """Config()'s defaults build exactly the core's default configuration (the evaluation
    schedule, which Python derives from n_evals, given to both); so a default changed on one
    side only fails here. The same for each preset against its own keys."""
    schedule = saggriac.Config().schedule()
    assert _core.config_debug(saggriac.Config().core_dict()) == _core.config_debug({"eval_schedule": schedule})
    for name, keys in saggriac.config.PRESETS.items():
        cfg = saggriac.Config.from_preset(name)
        given = {k: cfg.core_dict()[k] for k in keys} | {"eval_schedule": cfg.schedule()}
        assert _core.config_debug(cfg.core_dict()) == _core.config_debug(given), name


def test_each_default_is_declared_once_by_the_core():
    """Config's defaults and the teachers' are read from the core: a default written again on
    the Python side (and so able to drift) fails here. The exceptions are Python's own: lengths
    that follow the body (None; the core's value is the default arm's reach over the divisor),
    the schedule derived from n_evals, and teacher_params (empty: the teacher's defaults)."""
    import dataclasses
    import inspect

    core = _core.config_defaults()
    assert set(core) == set(_core.CONFIG_KEYS)
    own = {"v", "eps_max", "eval_tolerance", "eval_schedule", "teacher_params", "n_evals"}
    for f in dataclasses.fields(saggriac.Config):
        if f.name in own:
            continue
        want = tuple(core[f.name]) if isinstance(core[f.name], list) else core[f.name]
        assert f.default == want and type(f.default) is type(want), f.name
    reach = saggriac.Config().reach
    for name, divisor in saggriac.config.LENGTH_DIVISORS.items():
        assert reach / divisor == core[name], name
    # Each teacher's class takes exactly the core's parameters of its kind, with the core's
    # defaults (a parameter without a default, such as n_tasks, is required), and one class
    # stands for each teacher the core declares.
    from saggriac.teachers import classes

    _CLASSES = classes()

    teachers = _core.teacher_defaults()
    per_dimension = _core.teacher_per_dimension()
    assert set(_CLASSES) == set(teachers) == set(per_dimension)
    for kind, cls in _CLASSES.items():
        sig = inspect.signature(cls).parameters
        # A matrix taken per dimension (SPDL's covariances) has no single number: None, not given.
        matrices = {n for n, shape in per_dimension[kind].items() if shape == "matrix"}
        assert set(sig) - {"low", "high", "seed"} == set(teachers[kind]) | matrices, kind
        assert all(sig[n].default is None for n in matrices), kind
        assert {n for n, shape in per_dimension[kind].items() if shape == "vector"} <= set(teachers[kind]), kind
        given = {k: p.default for k, p in sig.items() if k in teachers[kind] and p.default is not p.empty}
        assert given == {k: teachers[kind][k] for k in given} and len(given) >= len(teachers[kind]) - 1, kind
    # The registry names each class and its goal space as the Python classes are, in order.
    from saggriac.teachers import available

    assert [(k, c.__name__, c.spaces) for k, c in available().items()] == [(k, cls, (space,)) for k, cls, space in _core.teacher_registry()]
    # SAGG-RIAC's own high level in a run and on its own: the same defaults.
    assert teachers["sagg_riac"] == {k: core[k] for k in teachers["sagg_riac"]}
