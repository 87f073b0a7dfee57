"""A checkpoint folder moved elsewhere and linked back resumes to the same bits; the run replaces
the link, never writes into or removes what it points to. A link to nothing, or to a file, is
named as such instead of being called damaged. From the fifth newcomer audit (issue 44,
finding 7, a regression since 4ffeabf)."""

from __future__ import annotations

import os
import warnings
from pathlib import Path

import pytest

import saggriac
from saggriac.cli import main
from saggriac.errors import StorageError
from saggriac.runs import checkpoint

CLI = ["--steps", "3000", "--set", "n_evals=12", "--set", "n_test_goals=8", "--set", "n_test_configs=8", "--no-progress", "--threads", "1"]  # one thread: the stop after the last due checkpoint is then certain
TABLES = [f"{t}.parquet" for t in ("metrics", "goals", "attempts", "regions")]


def tree(path: Path) -> dict[str, bytes]:
    return {str(p.relative_to(path)): p.read_bytes() for p in sorted(path.rglob("*")) if p.is_file()}


def interrupted(monkeypatch, every: str) -> None:
    """``saggriac run --out r`` stopped by Ctrl-C just after its first checkpoint."""
    real = checkpoint.write_checkpoint

    def then_stop(*a, **k):
        real(*a, **k)
        raise KeyboardInterrupt

    with monkeypatch.context() as m:
        m.setattr(checkpoint, "write_checkpoint", then_stop)
        assert main(["run", *CLI, "--checkpoint-every", every, "--out", "r"]) == 130


@pytest.mark.parametrize("every", ["500", "2500"])
def test_a_linked_checkpoint_resumes_to_the_same_tables(tmp_path, monkeypatch, every):
    # every=500: the resumed run writes checkpoints of its own (they replace the link);
    # every=2500: it finishes before the next one is due (the link is all there is to remove).
    monkeypatch.chdir(tmp_path)
    assert main(["run", *CLI, "--out", "plain"]) == 0
    interrupted(monkeypatch, every)
    os.rename(".r.checkpoint", "real.ckpt")  # mv .r.checkpoint real.ckpt && ln -s real.ckpt .r.checkpoint
    os.symlink("real.ckpt", ".r.checkpoint")
    kept = tree(tmp_path / "real.ckpt")
    real, written = checkpoint.write_checkpoint, []
    monkeypatch.setattr(checkpoint, "write_checkpoint", lambda *a, **k: written.append(real(*a, **k)))
    with warnings.catch_warnings():
        warnings.simplefilter("error", checkpoint.CheckpointWarning)  # replacing the link must work
        assert main(["run", "--resume", "r", "--no-progress"]) == 0
    assert bool(written) == (every == "500")
    for t in TABLES:
        assert (tmp_path / "r" / t).read_bytes() == (tmp_path / "plain" / t).read_bytes(), t
    # What the link pointed to is the user's folder now: left exactly as it was.
    assert tree(tmp_path / "real.ckpt") == kept
    assert sorted(os.listdir(tmp_path)) == ["plain", "r", "real.ckpt"]


@pytest.mark.parametrize(("target", "said"), [("elsewhere.ckpt", "which does not exist"), ("real.ckpt/state.bin", "which is not a folder")])
def test_a_broken_checkpoint_link_is_named_not_called_damaged(tmp_path, monkeypatch, target, said):
    monkeypatch.chdir(tmp_path)
    interrupted(monkeypatch, "500")
    os.rename(".r.checkpoint", "real.ckpt")
    os.symlink(target, ".r.checkpoint")
    with pytest.raises(StorageError, match=f"symbolic link to .*{target.split('/')[-1]}, {said}") as e:
        saggriac.resume("r")
    assert "damaged" not in str(e.value) and "without --resume" not in str(e.value)
    assert sorted(os.listdir("real.ckpt")) == ["checkpoint.json", "state.bin"]
    # Put right by pointing the link at the folder: the run resumes.
    os.unlink(".r.checkpoint")
    os.symlink("real.ckpt", ".r.checkpoint")
    assert saggriac.resume("r").path == Path("r")
