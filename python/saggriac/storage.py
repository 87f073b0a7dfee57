"""Run directories, written so that a result is never half-written: everything goes to a
temporary sibling directory first, which is renamed into place only when complete."""

from __future__ import annotations

import json
import os
import shutil
import tempfile
from pathlib import Path
from typing import Any, Callable

import pandas as pd

from .errors import StorageError

MANIFEST = "run.json"
TABLES = ("metrics", "goals", "attempts", "regions")
#: Checked before a run starts: a 200,000-step run directory takes about 1 MB; keep a margin.
MIN_FREE_BYTES = 20_000_000


def _check_writable(parent: Path, min_free: int) -> None:
    try:
        parent.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise StorageError(f"Cannot create the output folder {parent}: {e.strerror}.") from None
    if not os.access(parent, os.W_OK):
        raise StorageError(f"The output folder {parent} is not writable.")
    free = shutil.disk_usage(parent).free
    if free < min_free:
        raise StorageError(f"The disk of {parent} has {free / 1e6:.1f} MB free; a run needs up to {min_free / 1e6:.0f} MB. Free some space or choose another folder.")


def check_output_dir(out: Path, overwrite: bool = False, min_free: int = 0) -> None:
    """Fail if `out` cannot be written or already holds a finished run.

    Before a run, pass `min_free=MIN_FREE_BYTES` to refuse a nearly full disk before any work;
    a finished result is then written with no such rule (a real lack of space still raises).
    """
    if (out / MANIFEST).exists() and not overwrite:
        raise StorageError(f"{out} already holds a finished run; pass overwrite=True (--overwrite) to replace it.")
    _check_writable(out.parent, min_free)


def _fsync(path: Path) -> None:
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def replace_dir(out: Path, fill: Callable[[Path], None], what: str) -> Path:
    """Make ``out`` hold exactly what ``fill`` writes into a fresh directory, atomically: it is
    filled as a temporary sibling, every file is flushed, then it is renamed into place (over a
    previous ``out``, moved aside first). A failure leaves the previous ``out`` as it was."""
    old = out.with_name(f".{out.name}.old")
    tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}.", suffix=".tmp", dir=out.parent))
    try:
        tmp.chmod(0o755)  # mkdtemp makes it private; results are meant to be shared
        fill(tmp)
        for f in tmp.iterdir():
            _fsync(f)
        if out.exists():
            shutil.rmtree(old, ignore_errors=True)
            out.rename(old)
            tmp.rename(out)
            shutil.rmtree(old, ignore_errors=True)
        else:
            tmp.rename(out)
        _fsync(out.parent)
    except OSError as e:
        shutil.rmtree(tmp, ignore_errors=True)
        raise StorageError(f"Could not write {what} to {out}: {e}") from None
    return out


def write_run(out: Path, manifest: dict[str, Any], tables: dict[str, pd.DataFrame], overwrite: bool = False) -> Path:
    """Write a run directory atomically; a directory with a manifest is always complete."""
    old = out.with_name(f".{out.name}.old")
    if not out.exists() and (old / MANIFEST).exists():
        # A previous overwrite was killed between its two renames: put the finished run back.
        old.rename(out)
    check_output_dir(out, overwrite)

    def fill(tmp: Path) -> None:
        for name, df in tables.items():
            df.to_parquet(tmp / f"{name}.parquet", index=False)
        (tmp / MANIFEST).write_text(json.dumps(manifest, indent=2, sort_keys=True))

    return replace_dir(out, fill, "the run")


def read_run(path: Path) -> tuple[dict[str, Any], dict[str, pd.DataFrame]]:
    path = Path(path)
    if not (path / MANIFEST).exists():
        raise StorageError(f"{path} is not a finished run directory (no {MANIFEST}).")
    with open(path / MANIFEST) as f:
        manifest = json.load(f)
    missing = [name for name in TABLES if not (path / f"{name}.parquet").exists()]
    if missing:
        raise StorageError(f"{path} is damaged: {', '.join(m + '.parquet' for m in missing)} missing although {MANIFEST} is there.")
    tables = {name: pd.read_parquet(path / f"{name}.parquet") for name in TABLES}
    return manifest, tables
