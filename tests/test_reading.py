"""One rule for every file saggriac reads (issue 33, item 3): a regular file (a link to one is
followed) of bounded size. A FIFO nobody writes, a character device (a copy of /dev/zero) and a
huge sparse file put where saggriac reads a selector, a run.json, a checkpoint, a study.json or
a Parquet table are refused at once with a StorageError naming the file; before, the FIFO
blocked forever and the device and the big file were read until memory ran out."""

import contextlib
import os
import shutil
import signal
import stat
from pathlib import Path

import pytest

import saggriac as sg
from saggriac.errors import StorageError



@contextlib.contextmanager
def _within(seconds: int):
    """Fail instead of hanging: every refusal here is immediate."""

    def stop(*_):
        raise TimeoutError(f"still reading after {seconds} s")

    old = signal.signal(signal.SIGALRM, stop)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)


def _put(kind: str, path: Path) -> None:
    """Replace ``path`` by a special file of ``kind``."""
    if os.path.lexists(path):
        shutil.rmtree(path) if path.is_dir() and not path.is_symlink() else path.unlink()
    if kind == "fifo":
        os.mkfifo(path)
    elif kind == "device":
        try:
            os.mknod(path, 0o600 | stat.S_IFCHR, os.makedev(1, 5))  # a copy of /dev/zero
        except PermissionError:
            path.symlink_to("/dev/zero")  # not root: a link to it
    elif kind == "big":
        with open(path, "wb") as f:
            f.truncate(1_001_000_000)  # sparse, no disk used; above the 1 GB bound of a saved teacher
    else:
        raise AssertionError(kind)


KINDS = ["fifo", "device", "big"]


def _cfg():
    return sg.Config.from_preset("exp1", n_steps=300, n_evals=2, n_test_goals=5, n_test_configs=5)


@pytest.mark.parametrize("kind", KINDS)
def test_a_selector_file(kind, tmp_path):
    path = tmp_path / "teacher"
    _put(kind, path)
    with _within(10), pytest.raises(StorageError, match=r"teacher.* (a FIFO|a character device|bytes; a saved teacher is at most)"):
        sg.load_selector(path)


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("name", ["run.json", "metrics.parquet", "regions.parquet"])
def test_a_run_file(kind, name, tmp_path):
    out = sg.run(_cfg(), 0, out_dir=tmp_path / "r").path
    _put(kind, out / name)
    with _within(10), pytest.raises(StorageError, match=f"{name}.*(FIFO|character device|regular file|bytes)"):
        sg.RunResult.load(out)
    if name == "run.json":
        # Nor is the folder taken for a run of saggriac's that overwrite may replace.
        with _within(10), pytest.raises(StorageError, match="cannot be overwritten"):
            sg.run(_cfg(), 1, out_dir=out, overwrite=True)
        assert not stat.S_ISREG(os.lstat(out / name).st_mode) or os.lstat(out / name).st_size > 1e9


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("name", ["checkpoint.json", "state.bin"])
def test_a_checkpoint_file(kind, name, tmp_path):
    learner = sg.Learner(_cfg(), 0, threads=1)
    learner.run(until=100)
    ck = learner.save_checkpoint(tmp_path / "r", 100)
    _put(kind, ck / name)
    with _within(10), pytest.raises(StorageError, match=rf"The checkpoint .* is damaged: .*({name}|checkpoint.json).*(FIFO|character device|bytes)"):
        sg.resume(tmp_path / "r")
    assert not (tmp_path / "r").exists()


@pytest.mark.parametrize("kind", KINDS)
def test_a_study_file(kind, tmp_path):
    out = tmp_path / "st"
    sg.run_study(sg.Study(base=_cfg(), conditions=("sagg_random",), seeds=(0,)), out, n_workers=1, progress=False)
    _put(kind, out / "study.json")
    with _within(10), pytest.raises(StorageError, match="study.json .*(FIFO|character device|bytes)"):
        sg.load_study(out)
    with _within(10), pytest.raises(StorageError, match="study.json"):
        sg.run_study(sg.Study(base=_cfg(), conditions=("sagg_random",), seeds=(0,)), out, n_workers=1, progress=False)


def test_a_directory_or_missing_file_is_named(tmp_path):
    (tmp_path / "d").mkdir()
    with pytest.raises(StorageError, match="is a folder; saggriac reads a saved teacher only from a regular file"):
        sg.load_selector(tmp_path / "d")
    with pytest.raises(StorageError, match="No such file"):
        sg.load_selector(tmp_path / "none")


@pytest.mark.parametrize("bad", [42, None, b"teacher", 1.5, ""])
def test_a_path_that_is_no_path_is_named(bad):
    """load_selector(42) and RunResult.load(None) raised a raw TypeError from os."""
    from saggriac.errors import ParameterError

    with pytest.raises(ParameterError, match=r"The 'path' parameter of load_selector must (be a path|name a file)"):
        sg.load_selector(bad)
    with pytest.raises(ParameterError, match=r"The 'path' parameter of RunResult.load must (be a path|name a folder)"):
        sg.RunResult.load(bad)
