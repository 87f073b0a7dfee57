"""Fuzzing the public entry points' flags, step counts and paths with Hypothesis (issue 33):
any value of any type (numpy scalars of every kind, extreme but finite numbers, strings, None)
gives the behaviour of the plain value it stands for or a saggriac error naming the parameter,
and any file in a read path (a FIFO, a device, a huge sparse file, a folder, a link, text)
gives a result or a StorageError at once, never a hang, a raw traceback or a change on disk.

Examples per property: 60 in CI; ``SAGGRIAC_FUZZ_EXAMPLES=N`` raises it."""

import os
import signal
import stat

import numpy as np
import pytest

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import given  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

import saggriac as sg  # noqa: E402
from saggriac.errors import ParameterError, SaggriacError, StorageError  # noqa: E402
from tests.fuzzing import FUZZ, Counts, floats  # noqa: E402

COUNTS = Counts()
count = COUNTS.count

NUMPY_INTS = [np.int8, np.int16, np.int32, np.int64, np.uint8, np.uint16, np.uint32, np.uint64]

#: A value of any kind a user may pass: Python and numpy scalars, extreme finite numbers, text.
anything = st.one_of(
    st.booleans(),
    st.booleans().map(np.bool_),
    st.integers(-(2**70), 2**70),
    st.sampled_from(NUMPY_INTS).flatmap(lambda t: st.integers(int(np.iinfo(t).min), int(np.iinfo(t).max)).map(t)),
    floats,
    floats.map(np.float64),
    st.sampled_from([np.float32(1.0), np.float16(0.0), 1e308, -1e308, 2.0**63]),
    st.text(max_size=5),
    st.sampled_from([None, b"1", [True], (False,), {"x": 1}, object()]),
)


def _cfg():
    return sg.Config.from_preset("exp1", n_steps=600, n_evals=3, n_test_goals=5, n_test_configs=5)


def _is_bool(v) -> bool:
    return isinstance(v, (bool, np.bool_))


@pytest.fixture(scope="module")
def learner_steps():
    """Where a learner of _cfg() stops for each plain until (0 to the budget)."""
    return {}


@FUZZ
@given(until=anything, progress=anything)
def test_learner_run_takes_steps_and_flags_as_their_plain_values(until, progress, learner_steps):
    learner = sg.Learner(_cfg(), 0, threads=1)
    try:
        learner.run(until=until, progress=progress)
    except ParameterError as e:
        count("refused")
        assert e.param in ("until", "progress")
        if e.param == "progress":
            assert not _is_bool(progress)
        else:
            assert _is_bool(until) or not isinstance(until, (int, np.integer)) or until < 0
        return
    count("ran")
    assert _is_bool(progress) and not _is_bool(until) and isinstance(until, (int, np.integer)) and until >= 0
    plain = int(until)
    if plain not in learner_steps:
        ref = sg.Learner(_cfg(), 0, threads=1)
        ref.run(until=plain)
        learner_steps[plain] = ref.steps
    assert learner.steps == learner_steps[plain]


@FUZZ
@given(overwrite=anything, first=st.booleans())
def test_save_flags_keep_what_is_there(overwrite, first, tmp_path_factory):
    where = tmp_path_factory.mktemp("save")
    teacher = sg.RandomSelector([0.0], [1.0], seed=1)
    path = where / "t"
    if first:
        sg.RandomSelector([0.0], [1.0], seed=2).save(path)
    before = path.read_bytes() if first else None
    try:
        teacher.save(path, overwrite=overwrite)
    except ParameterError as e:
        count("flag refused")
        assert e.param == "overwrite" and not _is_bool(overwrite)
        assert (path.read_bytes() if first else None) == before and (first or not os.path.lexists(path))
        return
    except StorageError:
        count("kept")
        assert first and not bool(overwrite) and path.read_bytes() == before
        return
    count("saved")
    assert _is_bool(overwrite) and (bool(overwrite) or not first)
    loaded = sg.load_selector(path)
    assert isinstance(loaded, sg.RandomSelector) and path.read_bytes() == teacher_bytes(teacher)


def teacher_bytes(teacher) -> bytes:
    from saggriac.teachers import MAGIC

    return MAGIC + bytes(teacher._inner.save())


def _special(kind: str, path):
    if kind == "fifo":
        os.mkfifo(path)
    elif kind == "device":
        try:
            os.mknod(path, 0o600 | stat.S_IFCHR, os.makedev(1, 5))
        except PermissionError:
            path.symlink_to("/dev/zero")
    elif kind == "sparse":
        with open(path, "wb") as f:
            f.truncate(2**31)
    elif kind == "folder":
        path.mkdir()
    elif kind == "dangling":
        path.symlink_to(path.parent / "nowhere")
    elif kind == "text":
        path.write_bytes(b"{not json" * 3)
    elif kind == "empty":
        path.write_bytes(b"")


KINDS = ["fifo", "device", "sparse", "folder", "dangling", "text", "empty"]


@FUZZ
@given(kind=st.sampled_from(KINDS), where=st.sampled_from(["selector", "run.json", "metrics.parquet", "study.json", "checkpoint.json", "state.bin"]))
def test_any_file_where_saggriac_reads_is_refused_at_once(kind, where, tmp_path_factory):
    count(f"{where}:{kind}")
    d = tmp_path_factory.mktemp("read")
    if where == "selector":
        target, call = d / "t", lambda: sg.load_selector(d / "t")
    elif where in ("run.json", "metrics.parquet"):
        out = sg.run(_cfg(), 0, out_dir=d / "r").path
        target, call = out / where, lambda: sg.RunResult.load(out)
        os.unlink(target)
    elif where == "study.json":
        (d / "st").mkdir()
        target, call = d / "st" / "study.json", lambda: sg.load_study(d / "st")
    else:
        learner = sg.Learner(_cfg(), 0, threads=1)
        learner.run(until=100)
        ck = learner.save_checkpoint(d / "r", 100)
        target, call = ck / where, lambda: sg.resume(d / "r")
        os.unlink(target)
    _special(kind, target)
    before = os.lstat(target)

    def stop(*_):
        raise TimeoutError("a read did not return within 10 s")

    old = signal.signal(signal.SIGALRM, stop)
    signal.alarm(10)
    try:
        with pytest.raises(SaggriacError):
            call()
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)
    after = os.lstat(target)
    assert (stat.S_IFMT(after.st_mode), after.st_ino, after.st_size) == (stat.S_IFMT(before.st_mode), before.st_ino, before.st_size)


#: Config parameters with a size bound (issue 33, item 9) and the bound a value must keep.
SIZES = {
    "n_evals": lambda v, c: 1 <= v <= max(c.n_steps, 100),
    "k_neighbours": lambda v, c: 1 <= v <= max(c.n_steps, 1000),
    "episodic_k": lambda v, c: v <= max(c.n_steps, 1000),
    "v": lambda v, c: 0 < v <= 2 * c.reach,
    "eps_max": lambda v, c: 0 < v <= 2 * c.reach,
    "eval_tolerance": lambda v, c: 0 < v <= 2 * c.reach,
    "arm_length": lambda v, c: 1e-12 <= v <= 1e12,
}


@FUZZ
@given(name=st.sampled_from(sorted(SIZES)), value=anything, n_steps=st.sampled_from([1, 300, 50_000]))
def test_config_sizes_are_bounded_by_what_the_run_can_use(name, value, n_steps):
    try:
        cfg = sg.Config(n_steps=n_steps, **{name: value})
    except ParameterError as e:
        count(f"{name} refused")
        assert e.param == name, str(e)
        # Numbers are printed short: no 300-digit integer for 1e300.
        assert len(str(e)) < 600, str(e)
        return
    count(f"{name} taken")
    got = getattr(cfg, name)
    if value is None and name in ("v", "eps_max", "eval_tolerance"):
        return  # None: follow the body's reach
    assert not _is_bool(value) and isinstance(got, (int, float)) and SIZES[name](got, cfg)


@FUZZ
@given(name=st.sampled_from(["fit_rate", "max_components", "bootstrap", "random_task_ratio"]), value=anything)
def test_a_teacher_parameter_is_told_one_rule_whatever_the_value(name, value):
    from saggriac import _core

    try:
        sg.Config(teacher="alp_gmm", teacher_params={name: value})
    except ParameterError as e:
        count(f"teacher_params.{name} refused")
        assert f"'teacher_params.{name}' parameter of Config must be {_core.teacher_param_rule('alp_gmm', name)}" in str(e) or "<= fit_rate" in str(e), str(e)
        assert len(str(e)) < 600
        return
    count(f"teacher_params.{name} taken")
    assert not _is_bool(value) and isinstance(value, (int, float, np.integer, np.floating))


#: Elements of an action or a placement: numbers of every numpy type, extremes, text, bools.
elements = st.one_of(floats, st.floats(width=32).map(np.float32), st.sampled_from([np.float32("inf"), np.float16(1.0)]), st.integers(-(2**31), 2**31), st.booleans(), st.sampled_from(["0.01", "", None, np.True_, np.int8(1)]))


@FUZZ
@given(action=st.lists(elements, min_size=14, max_size=16), theta=st.lists(elements, min_size=15, max_size=15))
def test_gymnasium_actions_and_placements_are_numbers_or_refused(action, theta):
    from saggriac.errors import InputError
    from saggriac.adapters.gym import GoalArmEnv

    env = GoalArmEnv()
    env.reset(seed=0)

    def plain(values):
        return len(values) == 15 and all(not isinstance(v, (bool, np.bool_, str)) and v is not None and np.isfinite(float(v)) for v in values)

    before = env._theta.copy()
    try:
        env.step(action)
        count("step taken")
        assert plain(action)
    except InputError:
        count("step refused")
        assert not plain(action)
        np.testing.assert_array_equal(env._theta, before)
    try:
        env.reset(seed=0, options={"theta": theta})
        count("reset taken")
        assert plain(theta) and all(abs(float(v)) <= env.arm.joint_limit * (1 + 1e-6) + 1e-12 for v in theta)
    except InputError:
        count("reset refused")
        assert not plain(theta) or any(abs(float(v)) > env.arm.joint_limit for v in theta)


@FUZZ
@given(reach=anything)
def test_a_declared_reach_is_within_the_length_bounds_or_refused(reach):
    from saggriac.errors import ConformanceError
    from saggriac.bodies.scale import declared_reach

    class Body:
        pass

    body = Body()
    body.reach = reach
    try:
        got = declared_reach(body)
    except ConformanceError as e:
        count("reach refused")
        assert "environment.reach must be a float in [1e-12, 1e+12]" in str(e)
        return
    count("reach taken")
    assert got is None and reach is None or 1e-12 <= got <= 1e12


def teardown_module():
    print(f"\n{__name__}: {dict(sorted(COUNTS.items()))}")
