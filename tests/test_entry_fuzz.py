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


def teardown_module():
    print(f"\n{__name__}: {dict(sorted(COUNTS.items()))}")
