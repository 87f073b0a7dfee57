"""A study folder that cannot be written (issue 44, item 9): `saggriac reproduce` rerun on a
finished study in a read-only folder printed a traceback ending in OSError [Errno 30] from the
study's lock; it is now worded as `resume` words its own ("Cannot lock ...: Read-only file
system"), with exit status 2."""

import errno
import subprocess
from contextlib import contextmanager

import pytest

import saggriac as sg
import saggriac.study.folder as folder
from saggriac.cli import main
from saggriac.errors import StorageError

ARGS = ["exp1", "--seeds", "2", "--steps", "300", "--conditions", "sagg_riac,sagg_random", "--workers", "1", "--no-progress"]


@pytest.fixture
def read_only_mount():
    """Make a folder read-only for root too: a bind mount of it on itself, remounted ro."""
    mounted = []

    def make(point):
        done = subprocess.run(["mount", "--bind", str(point), str(point)], capture_output=True, text=True)
        if done.returncode:
            pytest.skip(f"cannot bind-mount here ({done.stderr.strip() or done.returncode}): a read-only folder needs a mount for root")
        mounted.append(point)
        done = subprocess.run(["mount", "-o", "remount,ro,bind", str(point)], capture_output=True, text=True)
        if done.returncode:
            pytest.skip(f"cannot remount read-only here ({done.stderr.strip() or done.returncode})")

    yield make
    for point in reversed(mounted):
        subprocess.run(["umount", "-l", str(point)], check=False)


def test_reproduce_rerun_in_a_read_only_folder_is_worded(tmp_path, read_only_mount, capsys):
    ro = tmp_path / "ro"
    ro.mkdir()
    out = ro / "st"
    assert main(["reproduce", *ARGS, "--out", str(out)]) == 0
    capsys.readouterr()
    read_only_mount(ro)
    with pytest.raises(OSError):
        (ro / "probe").touch()  # the mount holds, for root too
    assert main(["reproduce", *ARGS, "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert f"saggriac: error: Cannot lock {out} ({out / '.lock'}): Read-only file system." in err
    assert "Traceback" not in err


def test_a_lock_file_that_cannot_be_opened_is_a_storage_error(tmp_path, monkeypatch):
    """The same refusal wherever the mount above is not permitted."""

    @contextmanager
    def refused(path, busy, **kw):
        raise OSError(errno.EROFS, "Read-only file system", str(path))
        yield  # pragma: no cover

    monkeypatch.setattr(folder, "lock", refused)
    out = tmp_path / "st"
    study = sg.Study(sg.Config.from_preset("exp1", n_steps=300, n_evals=1), ("sagg_riac",), (0,))
    with pytest.raises(StorageError, match=rf"^Cannot lock {out} \({out}/.lock\): Read-only file system\.$"):
        sg.run_study(study, out, progress=False)


def test_a_busy_study_is_still_told_as_busy(tmp_path):
    out = tmp_path / "st"
    out.mkdir()
    study = sg.Study(sg.Config.from_preset("exp1", n_steps=300, n_evals=1), ("sagg_riac",), (0,))
    with folder.folder_lock(out):
        with pytest.raises(StorageError, match="Another run_study is writing to"):
            sg.run_study(study, out, progress=False)
