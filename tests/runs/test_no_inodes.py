"""A folder that cannot be made is a full disk too: no free inode, an inode quota, a folder made
immutable. The result is kept, a checkpoint that fails warns and the run goes on, and the
preflight counts inodes as well as bytes. From the fifth newcomer audit (issue 44, finding 1)."""

from __future__ import annotations

import errno
import os
import re
import shutil
import subprocess
from pathlib import Path

import pandas as pd
import pytest

import saggriac
from saggriac.cli import main
from saggriac.errors import StorageError
from saggriac.runs import checkpoint, runner, storage

TABLES = ("metrics", "goals", "attempts", "regions")


def tiny(**kw):
    return saggriac.Config.from_preset("exp1", **{"n_steps": 300, "n_evals": 2, "n_test_goals": 8, "n_test_configs": 8, **kw})


TINY_CLI = ["--steps", "300", "--set", "n_evals=2", "--set", "n_test_goals=8", "--set", "n_test_configs=8", "--no-progress"]
CHECKPOINTED_CLI = ["--steps", "3000", "--set", "n_evals=12", "--set", "n_test_goals=8", "--set", "n_test_configs=8", "--no-progress"]


def checkpointed():
    # Many evaluations, so that checkpoints come at several of them. The runs that count their
    # checkpoints take threads=1: with evaluations on other threads a loaded machine can let the
    # learner pass several evaluations before it sees one, and so write fewer (the same bits).
    return tiny(n_steps=3000, n_evals=12)


def same_tables(got, want):
    for t in TABLES:
        pd.testing.assert_frame_equal(getattr(got, t), getattr(want, t), check_exact=True)


def no_tmp(folder: Path):
    left = [p for p in os.listdir(folder) if p.endswith(".tmp")]
    assert not left, left


def tmpfs(tmp_path: Path, request, inodes: int) -> Path:
    """A fresh tmpfs of ``inodes`` inodes (its root takes one), unmounted when the test ends."""
    mnt = tmp_path / f"tmpfs{inodes}"
    mnt.mkdir()
    try:
        done = subprocess.run(["mount", "-t", "tmpfs", "-o", f"size=50m,nr_inodes={inodes}", "tmpfs", str(mnt)], capture_output=True, text=True)
    except OSError as e:
        pytest.skip(f"no mount command here ({e.strerror}); these tests need a small tmpfs")
    if done.returncode != 0:
        pytest.skip(f"mounting a tmpfs is not permitted here ({done.stderr.strip()}); these tests need root")

    def unmount():
        if subprocess.run(["umount", str(mnt)], capture_output=True).returncode != 0:
            subprocess.run(["umount", "-l", str(mnt)], capture_output=True)

    request.addfinalizer(unmount)
    return mnt


def use_up_inodes(folder: Path) -> None:
    """Create empty files in ``folder`` until the file system has no inode left."""
    folder.mkdir()
    for i in range(100_000):
        try:
            (folder / str(i)).touch()
        except OSError as e:
            assert e.errno == errno.ENOSPC, e
            return
    raise AssertionError("the file system never ran out of inodes")


# A real file system out of inodes ----------------------------------------------------------


def test_a_result_survives_a_folder_out_of_inodes(tmp_path, request, monkeypatch):
    mnt = tmpfs(tmp_path, request, 64)
    real = runner.write_run

    def starved(out, *a, **k):
        use_up_inodes(mnt / "fill")  # once the work is done, before the result is written
        return real(out, *a, **k)

    monkeypatch.setattr(runner, "write_run", starved)
    with pytest.raises(StorageError, match="No space left on device.*inodes.*kept in this exception's .result") as e:
        saggriac.run(tiny(), 0, out_dir=mnt / "r")
    same_tables(e.value.result, saggriac.run(tiny(), 0))
    assert not os.path.lexists(mnt / "r")
    no_tmp(mnt)


def test_the_cli_recovers_a_result_from_a_folder_out_of_inodes(tmp_path, request, monkeypatch, capsys):
    mnt = tmpfs(tmp_path, request, 64)
    monkeypatch.chdir(tmp_path)  # the recovery falls back to the current folder
    real = runner.write_run

    def starved(out, *a, **k):
        use_up_inodes(mnt / "fill")
        return real(out, *a, **k)

    monkeypatch.setattr(runner, "write_run", starved)
    rc = main(["run", *TINY_CLI, "--out", str(mnt / "r")])
    err = capsys.readouterr().err
    assert rc == 2 and "saved to" in err and "Traceback" not in err, err
    saved = [p for p in os.listdir(tmp_path) if p.startswith("r.recovered-")]
    assert len(saved) == 1 and str(tmp_path / saved[0]) in err
    same_tables(saggriac.RunResult.load(tmp_path / saved[0]), saggriac.run(tiny(), 0))
    no_tmp(mnt)


def test_a_checkpointed_run_out_of_inodes_warns_and_finishes(tmp_path, request, monkeypatch):
    mnt = tmpfs(tmp_path, request, 64)
    real = checkpoint.write_checkpoint
    calls = []

    def starving(*a, **k):
        calls.append(1)
        try:
            real(*a, **k)
        finally:
            if len(calls) == 1:
                use_up_inodes(mnt / "fill")  # after the first checkpoint
            elif len(calls) == 2:
                shutil.rmtree(mnt / "fill")  # the second failed; give the inodes back

    monkeypatch.setattr(checkpoint, "write_checkpoint", starving)
    with pytest.warns(checkpoint.CheckpointWarning, match=r"No space left on device.*last good checkpoint \(step \d+\) is kept"):
        res = saggriac.run(checkpointed(), 0, out_dir=mnt / "r", checkpoint_every=500, threads=1)
    assert res.path == mnt / "r" and len(calls) >= 3
    same_tables(res, saggriac.run(checkpointed(), 0))
    assert sorted(os.listdir(mnt)) == ["r"]


def test_the_preflight_refuses_a_folder_with_too_few_inodes(tmp_path, request):
    mnt = tmpfs(tmp_path, request, 4)
    free = os.statvfs(mnt).f_favail
    with pytest.raises(StorageError, match=rf"{re.escape(str(mnt))} has {free} free inodes; a run needs (\d+)") as e:
        saggriac.run(tiny(n_steps=50_000), 0, out_dir=mnt / "r")
    assert int(re.search(r"needs (\d+)", str(e.value))[1]) > free and "df -i" in str(e.value)
    assert os.listdir(mnt) == []


def test_the_preflight_counts_the_checkpoints_inodes(tmp_path, monkeypatch):
    need = storage.MIN_FREE_INODES + 2 * storage.CHECKPOINT_INODES
    fake = os.statvfs_result((4096, 4096, 10**6, 10**6, 10**6, 1000, need - 1, need - 1, 0, 255))
    monkeypatch.setattr(storage.os, "statvfs", lambda p: fake)
    with pytest.raises(StorageError, match=f"has {need - 1} free inodes; a run needs {need}"):
        saggriac.run(tiny(), 0, out_dir=tmp_path / "r", checkpoint_every=100)
    assert os.listdir(tmp_path) == []
    # Without checkpoints the same file system is enough.
    storage.check_output_dir(tmp_path / "r", False, 0, runner._min_inodes(None))


def test_a_file_system_that_counts_no_inodes_is_not_refused(tmp_path, monkeypatch):
    # Some network file systems report 0 inodes in all: nothing is known, nothing is refused.
    fake = os.statvfs_result((4096, 4096, 10**6, 10**6, 10**6, 0, 0, 0, 0, 255))
    monkeypatch.setattr(storage.os, "statvfs", lambda p: fake)
    res = saggriac.run(tiny(), 0, out_dir=tmp_path / "r", checkpoint_every=100)
    assert res.path == tmp_path / "r"


# The making of a temporary folder fails, whatever the reason --------------------------------

CODES = [errno.ENOSPC, errno.EDQUOT, errno.EPERM]


def refuse_mkdir(monkeypatch, pattern: str, code: int, when=lambda: True) -> None:
    """os.mkdir fails with ``code`` for temporary folders whose name matches ``pattern``."""
    real = os.mkdir

    def mkdir(path, *a, **k):
        if re.fullmatch(pattern, os.path.basename(os.fspath(path))) and when():
            raise OSError(code, os.strerror(code), os.fspath(path))
        return real(path, *a, **k)

    monkeypatch.setattr(os, "mkdir", mkdir)


@pytest.mark.parametrize("code", CODES, ids=errno.errorcode.get)
def test_a_result_whose_folder_cannot_be_made_is_kept(tmp_path, monkeypatch, code):
    refuse_mkdir(monkeypatch, r"\.r\.[a-z0-9_]{8}\.tmp", code)
    with pytest.raises(StorageError, match=re.escape(os.strerror(code))) as e:
        saggriac.run(tiny(), 0, out_dir=tmp_path / "r")
    same_tables(e.value.result, saggriac.run(tiny(), 0))
    assert os.listdir(tmp_path) == []


@pytest.mark.parametrize("code", CODES, ids=errno.errorcode.get)
def test_the_cli_recovers_a_result_whose_folder_cannot_be_made(tmp_path, monkeypatch, capsys, code):
    refuse_mkdir(monkeypatch, r"\.r\.[a-z0-9_]{8}\.tmp", code)
    rc = main(["run", *TINY_CLI, "--out", str(tmp_path / "r")])
    err = capsys.readouterr().err
    assert rc == 2 and "saved to" in err, err
    saved = [p for p in os.listdir(tmp_path) if p.startswith("r.recovered-")]
    assert len(saved) == 1
    same_tables(saggriac.RunResult.load(tmp_path / saved[0]), saggriac.run(tiny(), 0))


@pytest.mark.parametrize("code", CODES, ids=errno.errorcode.get)
def test_a_checkpoint_whose_folder_cannot_be_made_warns_and_the_run_finishes(tmp_path, monkeypatch, code):
    made = []
    refuse_mkdir(monkeypatch, r"\.\.r\.checkpoint\.[a-z0-9_]{8}\.tmp", code, when=lambda: made.append(1) or len(made) == 2)
    with pytest.warns(checkpoint.CheckpointWarning, match=re.escape(os.strerror(code))):
        res = saggriac.run(checkpointed(), 0, out_dir=tmp_path / "r", checkpoint_every=500, threads=1)
    assert res.path == tmp_path / "r" and len(made) >= 3
    same_tables(res, saggriac.run(checkpointed(), 0))
    assert sorted(os.listdir(tmp_path)) == ["r"]


# A folder made immutable while the run goes on ---------------------------------------------


def chattr(path: Path, flag: str) -> bool:
    try:
        return subprocess.run(["chattr", flag, str(path)], capture_output=True).returncode == 0
    except OSError:
        return False


@pytest.mark.parametrize("via", ["api", "cli"])
def test_a_folder_made_immutable_after_the_first_checkpoint(tmp_path, request, monkeypatch, capsys, via):
    folder = tmp_path / "w"
    folder.mkdir()
    if not chattr(folder, "+i"):
        pytest.skip("chattr +i is not available here (not root, or a file system without it)")
    chattr(folder, "-i")
    request.addfinalizer(lambda: chattr(folder, "-i"))
    monkeypatch.chdir(tmp_path)  # where the CLI saves what it cannot write beside the target
    real = checkpoint.write_checkpoint
    calls = []

    def then_immutable(*a, **k):
        calls.append(1)
        real(*a, **k)
        if len(calls) == 1:
            assert chattr(folder, "+i")

    monkeypatch.setattr(checkpoint, "write_checkpoint", then_immutable)
    with pytest.warns(checkpoint.CheckpointWarning, match=r"Operation not permitted.*last good checkpoint \(step \d+\) is kept"):
        if via == "api":
            with pytest.raises(StorageError) as e:
                saggriac.run(checkpointed(), 0, out_dir=folder / "r", checkpoint_every=500, threads=1)
            got = e.value.result
        else:
            rc = main(["run", *CHECKPOINTED_CLI, "--checkpoint-every", "500", "--out", str(folder / "r")])
            err = capsys.readouterr().err
            assert rc == 2 and "saved to" in err and "Traceback" not in err, err
            saved = [p for p in os.listdir(tmp_path) if p.startswith("r.recovered-")]
            assert len(saved) == 1
            got = saggriac.RunResult.load(tmp_path / saved[0])
    assert len(calls) >= 2
    same_tables(got, saggriac.run(checkpointed(), 0))
    # The last good checkpoint is still there; the lock file could not be removed either (the next
    # run clears it), and no temporary folder was left.
    assert sorted(os.listdir(folder)) == [".r.checkpoint", ".r.lock"]
