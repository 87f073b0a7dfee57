"""Run directories, written so that nothing a user has is ever lost and a result is never
half-written.

- A run is written only to a path that is free, an empty folder, or (with ``overwrite``) a
  finished saggriac run holding nothing but saggriac's files. Any other file or folder is never
  touched.
- While a run is going, it holds a lock on its target (:func:`target_lock`), so two runs cannot
  write to one place; the final rename never replaces something that appeared meanwhile.
- Everything goes to a temporary sibling first, which is renamed into place when complete; a
  failure of any kind removes the temporary sibling.
- ``run.json`` (written last) records the size and SHA-256 of every table, so a damaged run is
  recognised (:func:`run_damage`) instead of read.
"""

from __future__ import annotations

import contextlib
import ctypes
import errno
import hashlib
import json
import os
import shutil
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any, Callable

import numpy as np
import pandas as pd

from ..errors import StorageError
from ..files import MAX_JSON_BYTES, fsync_path, as_path, check_seal, lock, read_bounded, seal  # noqa: F401 (as_path: runner, study and cli take it from here)

MANIFEST = "run.json"
TABLES = ("metrics", "goals", "attempts", "regions")
RUN_FILES = frozenset([MANIFEST, *(f"{t}.parquet" for t in TABLES)])
#: A table of a run saved before run.json recorded sizes: larger is not read (a 200,000-step run's
#: tables take about 1 MB).
MAX_TABLE_BYTES = 4_000_000_000
#: Checked before a run starts: a 200,000-step run directory takes about 1 MB; keep a margin.
MIN_FREE_BYTES = 20_000_000
#: A checkpoint takes three inodes: its folder, state.bin and checkpoint.json.
CHECKPOINT_INODES = 3
#: Checked before a run starts: a run takes 7 inodes (its lock, the temporary folder and its five
#: files); the margin leaves room for a recovery folder and for other writers meanwhile.
MIN_FREE_INODES = 32


def sibling(out: Path, suffix: str) -> Path:
    """``.NAME<suffix>`` beside ``out`` (its lock, temporary copy, checkpoint), for any spelling
    of ``out`` (``.``, ``..`` or a trailing slash name no folder by themselves)."""
    full = Path(os.path.abspath(out))
    if not full.name:
        raise StorageError(f"{out} is the root folder; a run needs a folder of its own.")
    return full.with_name(f".{full.name}{suffix}")


def _existing_ancestor(path: Path) -> Path:
    p = path
    while not p.exists():
        if p.parent == p:
            break
        p = p.parent
    return p


def reason(e: OSError) -> str:
    """Why a write failed, in words. "No space left on device" also means no free inode, which
    df -h does not show, and a quota may count files as well as bytes."""
    why = e.strerror or str(e)
    if e.errno == errno.ENOSPC:
        return f"{why} (no free space or no free inodes: df -h and df -i show which)"
    if e.errno == getattr(errno, "EDQUOT", None):
        return f"{why} (your quota of space or of files is used up: quota -s shows which)"
    return why


def _check_parent(parent: Path, min_free: int, min_inodes: int = 0) -> None:
    """The folder a run directory will be made in: it, or its nearest existing ancestor, must be a
    writable folder. Nothing is created here (a refused command leaves nothing behind)."""
    base = _existing_ancestor(parent)
    if not base.is_dir():
        raise StorageError(f"Cannot create the output folder {parent}: {base} is a file, not a folder.")
    if not os.access(base, os.W_OK | os.X_OK):
        raise StorageError(f"The output folder {base} is not writable.")
    free = shutil.disk_usage(base).free
    if free < min_free:
        raise StorageError(f"The disk of {base} has {free / 1e6:.1f} MB free; a run needs up to {min_free / 1e6:.0f} MB. Free some space or choose another folder.")
    if min_inodes:
        st = os.statvfs(base)
        # f_files == 0: the file system does not count inodes (some network ones do not).
        if st.f_files and st.f_favail < min_inodes:
            raise StorageError(
                f"The file system of {base} has {st.f_favail} free inodes; a run needs {min_inodes} (one per file and folder it writes: its result, its lock and any checkpoints). "
                "Delete some files there (df -i counts them) or choose another folder."
            )


def foreign_entries(out: Path) -> list[str]:
    """Names in ``out`` that a saggriac run directory does not hold."""
    return sorted(name for name in os.listdir(out) if name not in RUN_FILES)


def is_saggriac_run(out: Path) -> bool:
    """A folder saggriac wrote as a run: a manifest of ours and nothing but saggriac's files."""
    return _manifest_problem(out) is None and not foreign_entries(out)


def _manifest_problem(out: Path) -> str | None:
    """Why ``out``'s run.json does not show a run saggriac wrote, or None if it does."""
    try:
        data = json.loads(read_bounded(out / MANIFEST, "a run.json", MAX_JSON_BYTES))
    except StorageError as e:
        return f"its {MANIFEST} cannot be read ({e})"
    except OSError as e:
        return f"its {MANIFEST} cannot be read ({e.strerror or e})"
    except (ValueError, UnicodeDecodeError) as e:
        return f"its {MANIFEST} is damaged (not JSON: {e})"
    missing = sorted({"config", "seed", "version"} - set(data)) if isinstance(data, dict) else None
    if missing is None:
        return f"its {MANIFEST} is damaged (a JSON {type(data).__name__}, not an object)"
    if missing:
        return f"its {MANIFEST} lacks {', '.join(missing)}"
    return None


def _describe(names: list[str]) -> str:
    return ", ".join(names[:5]) + (f" and {len(names) - 5} more" if len(names) > 5 else "")


class RunExistsError(StorageError):
    """The target holds a finished run and overwriting was not asked for."""

    def __init__(self, out: Path):
        super().__init__(f"{out} already holds a finished run; pass overwrite=True to replace it, or choose another out_dir.")
        self.path = out


#: Longest addition to a target's name among its siblings (".NAME.checkpoint", ".NAME.XXXXXXXX.tmp").
SIBLING_EXTRA = 24


def check_output_dir(out: Path, overwrite: bool = False, min_free: int = 0, min_inodes: int = 0) -> None:
    """Refuse, before any work, a target that saggriac must not or cannot write.

    Accepted: a free path, an empty folder, and with ``overwrite`` a finished saggriac run. Pass
    ``min_free=MIN_FREE_BYTES`` and ``min_inodes=MIN_FREE_INODES`` before a run to refuse a nearly
    full disk before any work.
    """
    out = Path(out)
    try:
        _check_output_dir(out, overwrite, min_free, min_inodes)
    except StorageError:
        raise
    except OSError as e:  # a name the file system refuses, a folder that vanished meanwhile, ...
        raise StorageError(f"Cannot use {out} as a run directory: {e.strerror or e}.") from None


def _check_name(out: Path) -> None:
    base = _existing_ancestor(Path(os.path.abspath(out)).parent)
    try:
        limit = os.pathconf(base, "PC_NAME_MAX")
    except (OSError, ValueError, AttributeError):
        limit = 255
    for part in Path(os.path.abspath(out)).parts[1:]:
        if len(os.fsencode(part)) > limit:
            raise StorageError(f"The folder name {part[:40]}... in {out} is {len(os.fsencode(part))} bytes long; this file system allows {limit}.")
    name = len(os.fsencode(out.name))
    if name + SIBLING_EXTRA > limit:
        raise StorageError(f"The name of {out} is {name} bytes long; runs need at most {limit - SIBLING_EXTRA} here ({limit} allowed, minus room for the temporary folder beside it).")


def _check_output_dir(out: Path, overwrite: bool, min_free: int, min_inodes: int) -> None:
    _check_name(out)
    absolute = Path(os.path.abspath(out))
    here = Path.cwd()
    if absolute == Path(absolute.anchor) or absolute == here or absolute in here.parents:
        raise StorageError(f"{out} is the current folder or one of its parents; a run needs a folder of its own (for example {out / 'my-run'}).")
    if out.is_symlink():
        raise StorageError(f"{out} is a symbolic link; saggriac replaces only folders it wrote. Choose another path.")
    if out.exists():
        if not out.is_dir():
            raise StorageError(f"{out} is a file that saggriac did not write; saggriac never replaces it. Choose another path.")
        if os.path.ismount(out):
            raise StorageError(f"{out} is a mount point; a run needs a folder of its own inside it.")
        if (out / MANIFEST).exists():
            if not overwrite:
                raise RunExistsError(out)
            if not is_saggriac_run(out):
                extra = foreign_entries(out)
                if extra:
                    raise StorageError(f"{out} cannot be overwritten: it also holds files saggriac did not write ({_describe(extra)}). Move those files out, or choose another path.")
                why = _manifest_problem(out)
                raise StorageError(
                    f"{out} cannot be overwritten: {why}, so saggriac cannot tell that it wrote this folder, and replaces only runs it can tell are its own. "
                    "If the folder is a damaged run of yours, delete it yourself; or choose another path."
                )
        else:
            entries = sorted(os.listdir(out))
            if entries:
                raise StorageError(f"{out} is a folder saggriac did not write (it holds {_describe(entries)}); saggriac never writes into it, even with overwrite. Choose a new path or an empty folder.")
        if not os.access(out, os.W_OK | os.X_OK):
            raise StorageError(f"The output folder {out} is not writable.")
    _check_parent(absolute.parent, min_free, min_inodes)


@contextlib.contextmanager
def target_lock(out: Path, what: str = "run") -> Iterator[None]:
    """Hold an exclusive lock on ``out`` (through ``.NAME.lock`` beside it) for the whole run, so a
    second run on the same target is refused at once. The lock file is removed on release; the
    kernel drops the lock if the process dies."""
    out = Path(out)
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise StorageError(f"Cannot create the output folder {out.parent}: {e.strerror}.") from None
    path = sibling(out, ".lock")
    with contextlib.ExitStack() as held:
        try:
            held.enter_context(lock(path, f"Another saggriac {what} is writing to {out}; wait for it to finish (or stop it) first.", remove=True))
        except StorageError:
            raise
        except OSError as e:
            raise StorageError(f"Cannot lock {out} ({path}): {e.strerror}.") from None
        yield


def clear_stale_lock(out: Path) -> None:
    """Remove the lock file of ``out`` left by a process killed after its run finished but
    before :func:`target_lock` released it; a lock a live process holds is kept."""
    path = sibling(Path(out), ".lock")
    if not os.path.lexists(path):
        return
    # Held by a live process (a StorageError), or not ours to open: kept.
    with contextlib.suppress(OSError), lock(path, "held", remove=True):
        pass


_RENAME_NOREPLACE = 1


def _rename_noreplace(src: Path, dst: Path) -> None:
    """Rename ``src`` to ``dst``, failing with FileExistsError if ``dst`` exists (atomically where
    the kernel offers renameat2, else by a check just before the rename)."""
    libc = None
    with contextlib.suppress(OSError, AttributeError):
        libc = ctypes.CDLL(None, use_errno=True)
    fn = getattr(libc, "renameat2", None) if libc is not None else None
    if fn is not None:
        at_fdcwd = -100
        if fn(at_fdcwd, os.fsencode(src), at_fdcwd, os.fsencode(dst), _RENAME_NOREPLACE) == 0:
            return
        err = ctypes.get_errno()
        if err == errno.EEXIST:
            raise FileExistsError(err, os.strerror(err), str(dst))
        if err not in (errno.EINVAL, errno.ENOSYS, errno.ENOTSUP):
            raise OSError(err, os.strerror(err), str(dst))
    if os.path.lexists(dst):
        raise FileExistsError(errno.EEXIST, os.strerror(errno.EEXIST), str(dst))
    os.rename(src, dst)


def replace_dir(out: Path, fill: Callable[[Path], None], what: str, replace: Callable[[Path], bool] | None = None) -> Path:
    """Make ``out`` hold exactly what ``fill`` writes into a fresh directory, atomically: it is
    filled as a temporary sibling, every file is flushed, then it is renamed into place.

    An existing ``out`` is replaced only if ``replace(out)`` says so (by default: never, except an
    empty folder); a symbolic link is replaced itself, what it points to is never touched. A
    failure of any kind leaves ``out`` as it was and no temporary sibling; an OSError, making the
    temporary folder included, becomes a StorageError."""
    old = sibling(out, ".old")
    tmp: Path | None = None
    try:
        # Within the try: no free inode, a quota or an immutable folder fail here, and are a full
        # disk like any other to the callers that keep the result or skip the checkpoint.
        tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}.", suffix=".tmp", dir=out.parent))
        tmp.chmod(0o755)  # mkdtemp makes it private; results are meant to be shared
        fill(tmp)
        for f in tmp.iterdir():
            fsync_path(f)
        if out.is_dir() and not out.is_symlink() and not os.listdir(out):
            os.rename(tmp, out)  # over an empty folder only: fails if anything appeared in it
        elif os.path.lexists(out):
            if replace is None or not replace(out):
                raise FileExistsError(errno.EEXIST, "it appeared while the run was going and is not a run saggriac may replace", str(out))
            if os.path.lexists(old):
                _remove(old)
            _rename_noreplace(out, old)
            _rename_noreplace(tmp, out)
            with contextlib.suppress(OSError):
                _remove(old)
        else:
            _rename_noreplace(tmp, out)
        fsync_path(out.parent)
    except OSError as e:
        if tmp is not None:
            shutil.rmtree(tmp, ignore_errors=True)
        raise StorageError(f"Could not write {what} to {out}: {reason(e)}.") from None
    except BaseException:
        if tmp is not None:
            shutil.rmtree(tmp, ignore_errors=True)
        raise
    return out


def _remove(path: Path) -> None:
    """Remove a folder saggriac replaced; a symbolic link goes, never what it points to."""
    if path.is_symlink() or not path.is_dir():
        os.unlink(path)
    else:
        shutil.rmtree(path)


def _digest(path: Path) -> dict[str, Any]:
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return {"bytes": path.stat().st_size, "sha256": h.hexdigest()}


def write_run(out: Path, manifest: dict[str, Any], tables: dict[str, pd.DataFrame], overwrite: bool = False) -> Path:
    """Write a run directory atomically; a directory with a manifest is always complete. The
    manifest gets the size and SHA-256 of every table (``manifest["tables"]``)."""
    out = Path(out)
    old = sibling(out, ".old")
    if not os.path.lexists(out) and is_saggriac_run(old):
        # A previous overwrite was killed between its two renames: put the finished run back.
        old.rename(out)
    check_output_dir(out, overwrite)

    def fill(tmp: Path) -> None:
        digests = {}
        for name, df in tables.items():
            df.to_parquet(tmp / f"{name}.parquet", index=False)
            digests[f"{name}.parquet"] = _digest(tmp / f"{name}.parquet")
        manifest["tables"] = digests
        (tmp / MANIFEST).write_text(json.dumps(seal(manifest), indent=2, sort_keys=True))

    return replace_dir(out, fill, "the run", replace=lambda p: overwrite and (p / MANIFEST).exists() and is_saggriac_run(p))


def read_manifest(path: Path) -> dict[str, Any]:
    """run.json of the run at ``path``, checked against its checksum."""
    return _read_manifest(path)


def _read_manifest(path: Path) -> dict[str, Any]:
    try:
        manifest = json.loads(read_bounded(path / MANIFEST, "a run.json", MAX_JSON_BYTES))
    except StorageError as e:
        raise StorageError(f"{path / MANIFEST} is damaged: {e}") from None
    except (FileNotFoundError, NotADirectoryError):
        raise StorageError(f"{path} is not a finished run directory (no {MANIFEST}).") from None
    except IsADirectoryError:
        raise StorageError(f"{path / MANIFEST} is damaged: it is a folder, not a file.") from None
    except OSError as e:
        raise StorageError(f"Cannot read {path / MANIFEST}: {e.strerror or e}.") from None
    except (ValueError, UnicodeDecodeError) as e:
        raise StorageError(f"{path / MANIFEST} is damaged: it cannot be read as JSON ({e}).") from None
    if not isinstance(manifest, dict) or not {"config", "seed"} <= set(manifest):
        raise StorageError(f"{path / MANIFEST} is damaged: it is not a saggriac manifest (no config and seed).")
    check_seal(manifest, path / MANIFEST)
    return manifest


def run_damage(path: Path) -> str | None:
    """Why the finished run at ``path`` cannot be trusted (a missing, truncated or changed table,
    an unreadable manifest), or None if every table matches what ``run.json`` records."""
    try:
        manifest = _read_manifest(path)
    except StorageError as e:
        return str(e)
    recorded = manifest.get("tables")
    for t in TABLES:
        f = path / f"{t}.parquet"
        if not os.path.lexists(f):
            return f"{f} is missing"
        if f.is_symlink() or not f.is_file():
            return f"{f} is not a regular file"
        if recorded is None:  # written before checksums were recorded: it must at least parse
            if f.stat().st_size > MAX_TABLE_BYTES:
                return f"{f} is {f.stat().st_size:,} bytes, more than a table of saggriac holds ({MAX_TABLE_BYTES:,})"
            try:
                pd.read_parquet(f)
            except Exception as e:  # pyarrow raises several types for a damaged file
                return f"{f} cannot be read ({e})"
            continue
        want = recorded.get(f.name)
        if not isinstance(want, dict):
            return f"{path / MANIFEST} records no checksum for {f.name}"
        try:
            # The size first: a huge file put in a table's place is not read through.
            size = f.stat().st_size
            if size != want.get("bytes"):
                return f"{f} has {size} bytes, {MANIFEST} records {want.get('bytes')} (truncated or changed)"
            got = _digest(f)
        except OSError as e:
            return f"{f} cannot be read ({e.strerror or e})"
        if got["bytes"] != want.get("bytes"):
            return f"{f} has {got['bytes']} bytes, {MANIFEST} records {want.get('bytes')} (truncated or changed)"
        if got["sha256"] != want.get("sha256"):
            return f"{f} does not match the SHA-256 {MANIFEST} records (changed or damaged)"
    return None


def signed_integers(frame: pd.DataFrame) -> pd.DataFrame:
    """``frame`` with every unsigned integer column as int64, in place: what the tables of runs
    written before saggriac 0.4 held unsigned (the core now hands out int64), so that steps and
    counts users subtract (``step_end - step_start``) do not wrap around. Counters stay far
    below 2**63."""
    for c in frame.columns:
        if frame[c].dtype.kind == "u":
            frame[c] = frame[c].astype(np.int64)
    return frame


def read_run(path: Path) -> tuple[dict[str, Any], dict[str, pd.DataFrame]]:
    """The manifest and tables of a finished run, after checking every table against run.json."""
    path = Path(path)
    manifest = _read_manifest(path)
    damage = run_damage(path)
    if damage is not None:
        raise StorageError(f"{path} is damaged: {damage}.")
    try:
        # Runs written before saggriac 0.4 hold unsigned counters.
        tables = {name: signed_integers(pd.read_parquet(path / f"{name}.parquet")) for name in TABLES}
    except Exception as e:  # a change that kept size and checksum cannot happen; stay clear anyway
        raise StorageError(f"{path} is damaged: a table cannot be read ({e}).") from None
    return manifest, tables
