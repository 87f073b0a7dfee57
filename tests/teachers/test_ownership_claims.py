"""The teacher claim (saggriac.teachers.ownership) is a security boundary: each attack a local user
could plant in the temporary directory (a link at a lock's name, a folder of someone else's or
open to all, a FIFO or a folder at a lock's place, a read-only or full temporary directory) leaves
every file outside saggriac's own untouched, and the user is told why the check is off instead
of getting a raw OSError. Copies of one teacher are told apart in one process and across two."""

import errno
import gc
import os
import pickle
import stat
import subprocess
import sys
import tempfile
import textwrap
import time
import warnings
from pathlib import Path

import pytest

import saggriac as sg
from saggriac.errors import ConformanceError
from saggriac.teachers import ownership
from saggriac.teachers.ownership import OwnershipWarning


@pytest.fixture
def tmpdir_(tmp_path, monkeypatch):
    """A temporary directory of this test's own, as TMPDIR is for saggriac."""
    tmp = tmp_path / "tmp"
    tmp.mkdir()
    monkeypatch.setattr(tempfile, "tempdir", str(tmp))
    monkeypatch.setenv("TMPDIR", str(tmp))
    return tmp


def _teacher(seed=0):
    return sg.RandomSelector([0.0, 0.0], [1.0, 1.0], seed=seed)


def _snapshot(root):
    """Every file and link under ``root``: kind, mode, owner, size, content (not followed)."""
    out = {}
    for dirpath, dirnames, filenames in os.walk(root):
        for name in dirnames + filenames:
            p = os.path.join(dirpath, name)
            st = os.lstat(p)
            body = os.readlink(p) if stat.S_ISLNK(st.st_mode) else Path(p).read_bytes() if stat.S_ISREG(st.st_mode) else None
            out[p] = (stat.S_IFMT(st.st_mode), stat.S_IMODE(st.st_mode), st.st_uid, st.st_size, body, st.st_mtime_ns)
    return out


def _claim_warns(teacher, match):
    with pytest.warns(OwnershipWarning, match=match) as record:
        ownership.claim(teacher, "SelectorGoals")
    assert "would learn alone while this one is told nothing" in str(record[0].message)
    assert not ownership.holds(teacher)


def _victim(tmp_path):
    victims = tmp_path / "victims"
    victims.mkdir()
    (victims / "precious.txt").write_text("precious data")
    return victims


def test_a_link_planted_at_the_lock_name_is_not_followed(tmp_path, tmpdir_):
    victims = _victim(tmp_path)
    t = _teacher()
    d = ownership.claims_dir()
    d.mkdir(mode=0o700)
    os.symlink(victims / "precious.txt", d / f"{t._identity}.lock")
    before = _snapshot(victims)
    _claim_warns(t, "is a symbolic link, not a lock file saggriac made; remove it")
    assert _snapshot(victims) == before
    assert (victims / "precious.txt").read_text() == "precious data"


def test_a_dangling_link_at_the_lock_name_creates_nothing_at_its_target(tmp_path, tmpdir_):
    t = _teacher()
    d = ownership.claims_dir()
    d.mkdir(mode=0o700)
    target = tmp_path / "victims" / "made-by-an-attacker"
    target.parent.mkdir()
    os.symlink(target, d / f"{t._identity}.lock")
    _claim_warns(t, "symbolic link")
    assert not target.exists()


def test_a_claims_folder_open_to_others_is_not_used(tmp_path, tmpdir_):
    d = ownership.claims_dir()
    d.mkdir()
    os.chmod(d, 0o777)
    _claim_warns(_teacher(), r"is open to other users \(mode 0777; saggriac makes it 0700\)")
    assert os.listdir(d) == []


@pytest.mark.skipif(os.geteuid() != 0, reason="making a folder of another user needs root")
def test_a_claims_folder_of_another_user_is_not_used(tmp_path, tmpdir_):
    d = ownership.claims_dir()
    d.mkdir(mode=0o700)
    os.chown(d, 12345, 12345)
    _claim_warns(_teacher(), r"belongs to another user \(uid 12345\)")
    assert os.listdir(d) == []


def test_a_link_in_place_of_the_claims_folder_is_not_followed(tmp_path, tmpdir_):
    victims = _victim(tmp_path)
    os.symlink(victims, ownership.claims_dir())
    before = _snapshot(victims)
    _claim_warns(_teacher(), "is a symbolic link")
    assert _snapshot(victims) == before


def test_a_file_in_place_of_the_claims_folder_is_left_alone(tmp_path, tmpdir_):
    ownership.claims_dir().write_text("a user's file")
    _claim_warns(_teacher(), "is not a folder")
    assert ownership.claims_dir().read_text() == "a user's file"


@pytest.mark.parametrize("kind", ["fifo", "folder", "hard link"])
def test_something_else_at_the_lock_place_is_refused_not_used(tmp_path, tmpdir_, kind):
    victims = _victim(tmp_path)
    t = _teacher()
    d = ownership.claims_dir()
    d.mkdir(mode=0o700)
    lock = d / f"{t._identity}.lock"
    if kind == "fifo":
        os.mkfifo(lock)
        match = "is not a regular file"
    elif kind == "folder":
        lock.mkdir()
        match = "is a folder"
    else:
        os.link(victims / "precious.txt", lock)
        match = "a hard link"
    before = _snapshot(victims)
    _claim_warns(t, match)  # a FIFO must not block: the test would hang
    assert _snapshot(victims) == before


def test_a_stale_lock_file_is_replaced_never_written(tmp_path, tmpdir_):
    t = _teacher()
    d = ownership.claims_dir()
    d.mkdir(mode=0o700)
    lock = d / f"{t._identity}.lock"
    lock.write_text("999999999 1 0\n")  # left by a process that ended
    old = os.open(lock, os.O_RDONLY)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            ownership.claim(t, "SelectorGoals")
        assert ownership.holds(t)
        assert os.fstat(old).st_ino != os.stat(lock).st_ino  # a new file of its own
        assert os.pread(old, 64, 0) == b"999999999 1 0\n"  # the old one was not written
        assert lock.read_text().split() == [str(os.getpid()), str(os.getppid()), "0"]
    finally:
        os.close(old)


def test_stale_lock_files_do_not_pile_up(tmpdir_):
    d = ownership.claims_dir()
    d.mkdir(mode=0o700)
    for i in range(5):
        (d / f"{i:032x}.lock").write_text("999999999 1\n")
    (d / "notes.txt").write_text("not a lock file")
    t = _teacher()
    ownership.claim(t, "SelectorGoals")
    assert sorted(os.listdir(d)) == sorted([f"{t._identity}.lock", "notes.txt"])
    del t
    gc.collect()
    assert sorted(os.listdir(d)) == ["notes.txt"]


@pytest.mark.parametrize("code", [errno.EROFS, errno.ENOSPC, errno.EDQUOT, errno.EPERM, errno.EACCES])
def test_an_unwritable_temporary_directory_warns_instead_of_raising(tmpdir_, monkeypatch, code):
    real_open = os.open

    def failing_open(path, flags, *args, **kwargs):
        if flags & os.O_CREAT:
            raise OSError(code, os.strerror(code), str(path))
        return real_open(path, flags, *args, **kwargs)

    ownership.claims_dir().mkdir(mode=0o700)
    monkeypatch.setattr(os, "open", failing_open)
    _claim_warns(_teacher(), f"cannot be made \\({os.strerror(code)}\\)")


def test_a_temporary_directory_where_no_folder_can_be_made_warns(tmpdir_, monkeypatch):
    def failing_mkdir(path, mode=0o777, **kwargs):
        raise OSError(errno.EROFS, os.strerror(errno.EROFS), str(path))

    monkeypatch.setattr(os, "mkdir", failing_mkdir)
    _claim_warns(_teacher(), r"folder .* cannot be made \(Read-only file system\); point TMPDIR at a writable folder")


def test_the_warning_is_given_once_per_teacher(tmpdir_):
    ownership.claims_dir().mkdir(mode=0o777)
    os.chmod(ownership.claims_dir(), 0o777)
    t = _teacher()
    _claim_warns(t, "open to other users")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ownership.claim(t, "SelectorGoals")  # each reset claims again: no second warning


def _mount(tmp_path, name, options):
    point = tmp_path / name
    point.mkdir()
    r = subprocess.run(["mount", "-t", "tmpfs", "-o", options, "tmpfs", str(point)], capture_output=True)
    if r.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs here ({r.stderr.decode().strip()})")
    return point


@pytest.fixture
def mounts(tmp_path):
    made = []
    yield lambda name, options: made.append(_mount(tmp_path, name, options)) or made[-1]
    for point in reversed(made):
        subprocess.run(["umount", "-l", str(point)], check=False)


@pytest.mark.parametrize("with_folder", [True, False])
def test_a_read_only_temporary_directory_warns(tmp_path, monkeypatch, mounts, with_folder):
    tmp = mounts("ro", "size=1m")
    if with_folder:
        (tmp / f"saggriac-teachers-{os.getuid()}").mkdir(mode=0o700)
    subprocess.run(["mount", "-o", "remount,ro", str(tmp)], check=True)
    monkeypatch.setattr(tempfile, "tempdir", str(tmp))
    _claim_warns(_teacher(), r"cannot be made \(Read-only file system\)")


def test_a_temporary_directory_without_free_inodes_warns(tmp_path, monkeypatch, mounts):
    tmp = mounts("noinodes", "size=1m,nr_inodes=3")
    (tmp / f"saggriac-teachers-{os.getuid()}").mkdir(mode=0o700)
    i = 0
    while True:
        try:
            (tmp / f"f{i}").touch()
        except OSError:
            break
        i += 1
    monkeypatch.setattr(tempfile, "tempdir", str(tmp))
    _claim_warns(_teacher(), r"cannot be made \(No space left on device\)")


def test_a_temporary_directory_without_free_bytes_still_claims(tmp_path, monkeypatch, mounts):
    tmp = mounts("nobytes", "size=64k")
    (tmp / f"saggriac-teachers-{os.getuid()}").mkdir(mode=0o700)
    fd = os.open(tmp / "filler", os.O_WRONLY | os.O_CREAT, 0o600)
    try:
        while os.write(fd, b"\0" * 4096):
            pass
    except OSError:
        pass
    finally:
        os.close(fd)
    monkeypatch.setattr(tempfile, "tempdir", str(tmp))
    t = _teacher()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ownership.claim(t, "SelectorGoals")
    assert ownership.holds(t)  # an empty lock file needs no block: the claim holds


def test_two_copies_in_one_process_are_told_apart(tmpdir_):
    blob = pickle.dumps(_teacher(seed=1))
    c1, c2 = pickle.loads(blob), pickle.loads(blob)
    ownership.claim(c1, "SelectorGoals")
    ownership.claim(c1, "SelectorGoals")  # the same object again: fine
    with pytest.raises(ConformanceError, match="another copy of the same teacher in this process"):
        ownership.claim(c2, "SelectorGoals")
    lock = ownership.claims_dir() / f"{c1._identity}.lock"
    del c1
    gc.collect()  # the copy that held it is gone: the claim is released, not handed on silently
    assert not lock.exists() and not ownership.holds(c2)
    ownership.claim(c2, "SelectorGoals")
    assert ownership.holds(c2)


HOLDER = """
import os, pickle, sys, time, tempfile
tempfile.tempdir = sys.argv[2]
from saggriac.teachers import ownership
t = pickle.load(open(sys.argv[1], "rb"))
ownership.claim(t, "SelectorGoals")
print(os.getpid(), flush=True)
time.sleep(60)
"""


def test_two_jobs_loading_one_saved_teacher_are_told_so(tmp_path, tmpdir_):
    saved = tmp_path / "t.pkl"
    saved.write_bytes(pickle.dumps(_teacher(seed=2)))
    # Started from a shell that exits at once, as a second job would be: no child of this one.
    shell = subprocess.Popen(["sh", "-c", '"$@" &', "sh", sys.executable, "-c", textwrap.dedent(HOLDER), str(saved), str(tmpdir_)], stdout=subprocess.PIPE, text=True)
    pid = int(shell.stdout.readline())
    shell.stdout.close()
    shell.wait()
    try:
        with pytest.raises(ConformanceError) as err:
            ownership.claim(pickle.loads(saved.read_bytes()), "SelectorGoals")
        message = str(err.value)
        assert f"another process (pid {pid}), no worker of this one: two jobs each loaded the same saved teacher" in message
        assert "saggriac.load_selector(path)" in message and "allow_copy=True" in message
    finally:
        os.kill(pid, 9)
    for _ in range(500):  # the job ended: its claim goes with it
        t = pickle.loads(saved.read_bytes())
        try:
            ownership.claim(t, "SelectorGoals")
            break
        except ConformanceError:
            time.sleep(0.01)
    assert ownership.holds(t)


FOLDERS = ["missing", "private", "open to all", "link", "file", "another user's"]
LOCKS = ["missing", "stale", "link", "dangling link", "fifo", "folder", "hard link", "another user's"]


# A lock file needs a claims folder to be in.
STATES = [(f, l) for f in FOLDERS for l in LOCKS if l == "missing" or f in ("private", "open to all", "another user's")]


@pytest.mark.parametrize(("folder", "lock"), STATES)
def test_every_state_of_the_claims_folder_gives_a_claim_or_a_warning_and_touches_nothing(tmp_path, tmpdir_, folder, lock):
    """The claim's file-system fuzz: each state a folder and a lock file can be in, combined."""
    if "another user's" in (folder, lock) and os.geteuid() != 0:
        pytest.skip("making a file of another user needs root")
    victims = _victim(tmp_path)
    t = _teacher()
    d = ownership.claims_dir()
    if folder == "link":
        os.symlink(victims, d)
    elif folder == "file":
        d.write_text("a user's file")
    elif folder != "missing":
        d.mkdir(mode=0o700)
        if folder == "open to all":
            os.chmod(d, 0o777)
        elif folder == "another user's":
            os.chown(d, 12345, 12345)
    if lock != "missing":
        path = d / f"{t._identity}.lock"
        if lock == "stale":
            path.write_text("999999999 1 0\n")
        elif lock == "link":
            os.symlink(victims / "precious.txt", path)
        elif lock == "dangling link":
            os.symlink(victims / "made-by-an-attacker", path)
        elif lock == "fifo":
            os.mkfifo(path)
        elif lock == "folder":
            path.mkdir()
        elif lock == "hard link":
            os.link(victims / "precious.txt", path)
        else:
            path.write_text("")
            os.chown(path, 12345, 12345)
    before = _snapshot(victims)
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        ownership.claim(t, "SelectorGoals")
    warned = [w for w in seen if issubclass(w.category, OwnershipWarning)]
    assert len(seen) == len(warned)  # nothing else: no ResourceWarning, no raw error
    has_lock = folder in ("private", "open to all", "another user's")
    safe = folder in ("missing", "private") and (not has_lock or lock in ("missing", "stale"))
    assert ownership.holds(t) == safe and len(warned) == (0 if safe else 1), (seen, folder, lock)
    assert _snapshot(victims) == before
    assert not (victims / "made-by-an-attacker").exists()
