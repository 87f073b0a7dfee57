"""A study's folder: its description (study.json), the lock one run_study holds on it, and
which runs in it are finished, damaged or left over from a killed process."""

from __future__ import annotations

import contextlib
import json
import os
import shutil
import time
import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import pandas as pd

from .. import _core
from ..config import Config
from ..errors import ParameterError, StorageError
from ..files import lock, write_file
from ..runs.result import run_stopped_early
from ..runs.storage import MANIFEST, read_manifest, run_damage
from .spec import STUDY_FORMAT, LOCK_FILE, RUNS_DIR, STUDY_FILE, Study, Task


def set_aside(run_dir: Path) -> Path:
    """Move a damaged run out of the study's way, keeping what is left of it."""
    stamp = time.strftime("%Y%m%d-%H%M%S")
    for i in range(1000):
        aside = run_dir.with_name(f".{run_dir.name}.damaged-{stamp}{'' if i == 0 else f'-{i}'}")
        if not os.path.lexists(aside):
            run_dir.rename(aside)
            return aside
    raise StorageError(f"Cannot set the damaged run {run_dir} aside: too many earlier copies beside it; delete them.")  # pragma: no cover


def _write_json_atomic(path: Path, data: dict[str, Any]) -> None:
    write_file(path, lambda tmp: tmp.write_text(json.dumps(data, indent=2, sort_keys=True)), what=path.name, overwrite=True)


@contextmanager
def folder_lock(out: Path) -> Iterator[None]:
    """Hold an exclusive lock on the study folder: a second run_study on it would delete the
    first one's temporary directories. The kernel drops the lock when the process dies."""
    with contextlib.ExitStack() as held:
        try:
            unlocked = held.enter_context(lock(out / LOCK_FILE, f"Another run_study is writing to {out}; wait for it to finish (or stop it) first."))
        except StorageError:
            raise
        except OSError as e:
            # Opening the lock file (a read-only folder): worded as resume words it, not a traceback.
            raise StorageError(f"Cannot lock {out} ({out / LOCK_FILE}): {e.strerror or e}.") from None
        if unlocked is not None:  # pragma: no cover - file systems without flock
            warnings.warn(f"Cannot lock {out} ({unlocked.strerror}); do not run two run_study on this folder at once.", RuntimeWarning, stacklevel=4)
        yield


def _describe_difference(old: dict[str, Any], new: dict[str, Any]) -> str:
    diffs = []
    for key in ("conditions", "seeds", "grid"):
        if old.get(key) != new.get(key):
            diffs.append(f"{key} {old.get(key)!r} -> {new.get(key)!r}")
    old_base, new_base = old.get("base", {}), new.get("base", {})
    for key in sorted(set(old_base) | set(new_base)):
        if key != "condition" and old_base.get(key) != new_base.get(key):
            diffs.append(f"base.{key} {old_base.get(key)!r} -> {new_base.get(key)!r}")
    return "; ".join(diffs[:6]) + ("; ..." if len(diffs) > 6 else "")


def _runs_of(study: Study) -> dict[str, tuple[int, dict[str, Any]]]:
    return {t.path: (t.seed, t.config) for t in study.tasks()}


def check_study_folder(out: Path) -> None:
    """A study goes into a new or empty folder, or a study folder; never into a user's folder."""
    try:
        _check_study_place(out)
    except StorageError:
        raise
    except OSError as e:
        raise StorageError(f"Cannot use {out} as a study folder: {e.strerror or e}.") from None


def _check_study_place(out: Path) -> None:
    if out.is_symlink() or (out.exists() and not out.is_dir()):
        raise StorageError(f"{out} is not a folder; a study needs a folder of its own. Choose another out_dir.")
    if out.is_dir() and not (out / STUDY_FILE).exists():
        entries = sorted(n for n in os.listdir(out) if n != LOCK_FILE and not (n.startswith(f".{STUDY_FILE}.") and n.endswith(".tmp")))
        if (out / RUNS_DIR).exists():
            raise StorageError(f"{out} holds a {RUNS_DIR}/ folder but no {STUDY_FILE}; it was not made by run_study. Choose another out_dir.")
        if entries:
            shown = ", ".join(entries[:5]) + (" ..." if len(entries) > 5 else "")
            raise StorageError(f"{out} is a folder run_study did not make (it holds {shown}); a study goes into a new or empty folder. Choose another out_dir.")


def check_or_write_spec(out: Path, study: Study) -> None:
    path = out / STUDY_FILE
    if path.exists():
        old = Study.load(out)
        # The same study is the same set of runs at the same places (order does not matter).
        if _runs_of(old) != _runs_of(study):
            raise StorageError(
                f"{path} holds a different study ({_describe_difference(old.to_dict(), study.to_dict())}). "
                "A folder holds one study: choose another out_dir, or delete this one to start over."
            )
        return
    if (out / RUNS_DIR).exists():
        raise StorageError(f"{out} holds a {RUNS_DIR}/ folder but no {STUDY_FILE}; it was not made by run_study. Choose another out_dir.")
    for leftover in out.glob(f".{STUDY_FILE}.*.tmp"):
        leftover.unlink(missing_ok=True)
    _write_json_atomic(path, {"format": STUDY_FORMAT, "study": study.to_dict(), "created_with": {"saggriac": _core.__version__, "git_commit": _core.GIT_COMMIT}})


def is_finished(out: Path, task: Task) -> bool | str:
    """True for a finished, intact run of this task; False for none; for a damaged one, the
    reason. Raises if a finished run is of another configuration."""
    run_dir = out / task.path
    manifest = run_dir / MANIFEST
    if not manifest.exists():
        return False
    damage = run_damage(run_dir)
    if damage is not None:
        return damage
    data = read_manifest(run_dir)
    try:
        same = data["seed"] == task.seed and Config.from_saved(data["config"], data.get("version")) == Config(**task.config)
    except (KeyError, TypeError, ParameterError, StorageError) as e:
        writer = f", written by saggriac {data['version']}" if isinstance(data.get("version"), str) else ""
        return f"{manifest} does not describe a run this version of saggriac ({_core.__version__}) can read{writer} ({e})"
    if not same:
        raise StorageError(f"{run_dir} holds a finished run of another configuration or seed; delete it to have the run redone.")
    early = run_stopped_early(data, _last_steps(run_dir))
    if early is not None:
        return early
    return True


def _last_steps(run_dir: Path) -> pd.DataFrame:
    """The step column of a run's metrics (what tells a partial run of saggriac 0.5.0)."""
    return pd.read_parquet(run_dir / "metrics.parquet", columns=["step"])


def remove_leftovers(out: Path, task: Task) -> None:
    """Remove the temporary directories that storage.write_run left when a process was killed."""
    parent = (out / task.path).parent
    try:
        names = os.listdir(parent)
    except (FileNotFoundError, NotADirectoryError):
        return
    prefix = f".{Path(task.path).name}."
    for name in names:
        if name.startswith(prefix) and name.endswith(".tmp"):
            shutil.rmtree(parent / name)


