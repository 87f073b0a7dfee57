"""A run's checkpoint: the learner's whole state and a readable description, in a folder beside
the run's target (``<out>.checkpoint``), replaced atomically; and its reading back, checked."""

from __future__ import annotations

import contextlib
import json
import os
import shutil
from pathlib import Path
from typing import Any

import numpy as np

from .. import _core
from ..config import Config
from ..errors import ParameterError, StorageError
from ..files import MAX_JSON_BYTES, check_seal, read_bounded, seal
from ..seeding import check_seed, derive_seeds
from .storage import check_output_dir, replace_dir, sibling, target_lock

FILES = frozenset({"state.bin", "checkpoint.json"})
START_OVER = "Start the run over: run it again without --resume."


class CheckpointWarning(UserWarning):
    """A checkpoint could not be written; the run goes on and the last good checkpoint stays."""


def checkpoint_dir(out: str | Path) -> Path:
    """Where the checkpoint of the run that will be written to ``out`` is kept."""
    return sibling(Path(out), ".checkpoint")


def check_every(every: Any, owner: str) -> int:
    """``checkpoint_every`` as a plain int (a numpy one would not go into checkpoint.json)."""
    if isinstance(every, (bool, np.bool_)) or not isinstance(every, (int, np.integer)) or every < 1:
        raise ParameterError(f"The 'checkpoint_every' parameter of {owner} must be an int >= 1 (time steps). Got {every!r} instead.", "checkpoint_every", repr(every))
    return int(every)


def write_checkpoint(out: Path, state: bytes, info: dict[str, Any], config: Config, steps: int, every: int) -> None:
    """Replace the checkpoint atomically: the state and a readable description."""
    meta = {"config": config.to_dict(), "steps": steps, "checkpoint_every": every, **info, "version": _core.__version__, "git_commit": _core.GIT_COMMIT}

    def fill(tmp: Path) -> None:
        (tmp / "state.bin").write_bytes(state)
        (tmp / "checkpoint.json").write_text(json.dumps(seal(meta), indent=2, sort_keys=True))

    replace_dir(checkpoint_dir(out), fill, "the checkpoint", replace=is_checkpoint)


def save_checkpoint(out: Path, state: bytes, info: dict[str, Any], config: Config, steps: int, every: int, overwrite: bool) -> Path:
    """A learner's checkpoint for the run that is to be written to ``out`` (Learner.save_checkpoint),
    with the target checked as resume() will need it and locked while it is written."""
    # Refuse now a target that resume() could not write to.
    check_output_dir(out, overwrite)
    with target_lock(out):
        write_checkpoint(out, state, {**info, "overwrite": overwrite}, config, steps, every)
    return checkpoint_dir(out)


def is_checkpoint(path: Path) -> bool:
    """A checkpoint folder saggriac wrote (and may replace): its two files and nothing else. A
    symbolic link to one counts (a user moved the folder and linked it back); replacing or
    removing it replaces or removes the link only."""
    try:
        return path.is_dir() and set(os.listdir(path)) <= FILES and (path / "state.bin").exists()
    except OSError:
        return False


def remove_checkpoint(out: Path) -> None:
    """Remove the checkpoint of the finished run ``out``; of a link, the link only: what it points
    to is a folder the user put elsewhere, and stays theirs."""
    ck = checkpoint_dir(out)
    if not is_checkpoint(ck):
        return
    if ck.is_symlink():
        with contextlib.suppress(OSError):
            os.unlink(ck)
    else:
        shutil.rmtree(ck, ignore_errors=True)


def find_checkpoint(out: Path) -> Path:
    """The checkpoint folder of ``out``, refused with the reason if there is none to resume."""
    ck = checkpoint_dir(out)
    try:
        found = os.path.lexists(ck)
        finished = (out / "run.json").exists()
        link = os.readlink(ck) if ck.is_symlink() else None
    except OSError as e:
        raise StorageError(f"Cannot look for a checkpoint of {out}: {e.strerror or e}.") from None
    if not found:
        if finished:
            raise StorageError(f"{out} already holds a finished run; there is nothing to resume.")
        raise StorageError(f"No checkpoint for {out} (looked for {ck}). Start the run with checkpoint_every (--checkpoint-every) to be able to resume it.")
    # A link is read through: the checkpoint it points to may be intact, so it is not called damaged.
    if link is not None and not ck.exists():
        raise StorageError(f"The checkpoint {ck} is a symbolic link to {link}, which does not exist (moved or deleted, or a loop of links). Point the link at the checkpoint folder, or move the folder to {ck}, and resume again.")
    if link is not None and not ck.is_dir():
        raise StorageError(f"The checkpoint {ck} is a symbolic link to {link}, which is not a folder (saggriac writes a checkpoint as a folder holding state.bin and checkpoint.json). Point the link at that folder and resume again.")
    if not ck.is_dir():
        raise StorageError(f"The checkpoint {ck} is damaged: it is not a folder (saggriac writes a folder holding state.bin and checkpoint.json). {START_OVER}")
    for name in sorted(FILES):
        if not os.path.lexists(ck / name):
            raise StorageError(f"The checkpoint {ck} is damaged: it has no {name}. {START_OVER}")
    return ck


def read_description(ck: Path) -> tuple[Config, dict[str, Any], int]:
    """checkpoint.json: the run's configuration, its seeds and overwrite flag (``info``) and
    ``checkpoint_every``, each checked against the others before anything is resumed."""
    try:
        meta = json.loads(read_bounded(ck / "checkpoint.json", "a checkpoint.json", MAX_JSON_BYTES))
        if not isinstance(meta, dict):
            raise TypeError("not a JSON object")
        info = {k: meta[k] for k in ("seed", "learner_seed", "eval_seed", "overwrite")}
        every = meta["checkpoint_every"]
    except (OSError, ValueError, KeyError, TypeError, UnicodeDecodeError) as e:
        raise StorageError(f"The checkpoint {ck} is damaged: checkpoint.json cannot be read ({e}). {START_OVER}") from None
    check_seal(meta, ck / "checkpoint.json")
    config = Config.from_saved(meta["config"], meta.get("version"))
    try:
        seed = check_seed(info["seed"])
    except ParameterError:
        raise StorageError(f"The checkpoint {ck} is damaged: its seed {info['seed']!r} is not a seed.") from None
    if derive_seeds(seed) != (info["learner_seed"], info["eval_seed"]):
        raise StorageError(f"The checkpoint {ck} is inconsistent: its learner and evaluation seeds are not those of seed {seed}. {START_OVER}")
    if isinstance(every, bool) or not isinstance(every, int) or every < 1:
        raise StorageError(f"The checkpoint {ck} is damaged: checkpoint_every is {every!r}, not an int >= 1.")
    if not isinstance(info["overwrite"], bool):
        raise StorageError(f"The checkpoint {ck} is damaged: overwrite is {info['overwrite']!r}, not true or false.")
    return config, info, every


def read_state(ck: Path, limit: int) -> bytes:
    """state.bin, at most ``limit`` bytes."""
    try:
        return read_bounded(ck / "state.bin", "a checkpoint's state.bin", limit)
    except (OSError, StorageError) as e:
        raise StorageError(f"The checkpoint {ck} is damaged: {e} {START_OVER}") from None
