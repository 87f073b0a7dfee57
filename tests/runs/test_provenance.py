"""A run's provenance is checked: a checkpoint of another seed or an edited checkpoint.json
is not resumed, an edited run.json is not trusted, a run.json of another version says so. From the third newcomer audit (issue 27)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

import saggriac
from saggriac import Config
from saggriac.errors import StorageError


def _checkpointed(tmp_path: Path, seed: int) -> Path:
    """A run interrupted after its first checkpoint (kill -9 in a subprocess)."""
    out = tmp_path / f"run{seed}"
    code = f"""
import os, saggriac
from saggriac.runs import checkpoint
real = checkpoint.write_checkpoint
def once(*a, **k):
    real(*a, **k)
    os._exit(9)
checkpoint.write_checkpoint = once
cfg = saggriac.Config.from_preset("exp1", n_steps=3000, n_evals=3, n_test_goals=5, n_test_configs=5)
saggriac.run(cfg, seed={seed}, out_dir={str(out)!r}, checkpoint_every=1000, threads=1)
"""
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert r.returncode == 9, r.stderr
    return out


def test_resume_refuses_a_state_from_another_seed(tmp_path):
    a, b = _checkpointed(tmp_path, 0), _checkpointed(tmp_path, 1)
    ca, cb = saggriac.runs.checkpoint_dir(a), saggriac.runs.checkpoint_dir(b)
    (ca / "state.bin").write_bytes((cb / "state.bin").read_bytes())
    with pytest.raises(StorageError, match="other seeds"):
        saggriac.resume(a)
    assert not a.exists()


@pytest.mark.parametrize("edit", [{"seed": 1}, {"learner_seed": 7}, {"checkpoint_every": 0}, {"overwrite": True}, {"steps": 5}])
def test_resume_refuses_an_edited_checkpoint_json(tmp_path, edit):
    out = _checkpointed(tmp_path, 0)
    f = saggriac.runs.checkpoint_dir(out) / "checkpoint.json"
    meta = json.loads(f.read_text())
    meta.update(edit)
    f.write_text(json.dumps(meta))
    with pytest.raises(StorageError, match="changed or damaged"):
        saggriac.resume(out)


def _finished(tmp_path: Path) -> Path:
    cfg = Config.from_preset("exp1", n_steps=500, n_evals=1, n_test_goals=5, n_test_configs=5)
    return saggriac.run(cfg, seed=0, out_dir=tmp_path / "done").path


@pytest.mark.parametrize("change", ["seed", "g_max", "tables", "checksum"])
def test_an_edited_run_json_is_not_trusted(tmp_path, change):
    out = _finished(tmp_path)
    f = out / "run.json"
    text = f.read_text()
    edited = {
        "seed": lambda t: t.replace('"seed": 0', '"seed": 1', 1),
        "g_max": lambda t: t.replace('"g_max": 50', '"g_max": 45', 1),
        "tables": lambda t: t.replace('"tables"', '"tablds"', 1),
        "checksum": lambda t: t.replace('"checksum"', '"checksuk"', 1),
    }[change](text)
    assert edited != text
    f.write_text(edited)
    with pytest.raises(StorageError, match="changed or damaged"):
        saggriac.RunResult.load(out)


def test_a_run_json_from_another_version_gets_a_clear_error(tmp_path):
    out = _finished(tmp_path)
    f = out / "run.json"
    manifest = json.loads(f.read_text())
    manifest["config"]["a_parameter_from_the_future"] = 1
    manifest["version"] = "9.0.0"
    f.write_text(json.dumps(saggriac.files.seal(manifest)))
    with pytest.raises(StorageError, match=r"does not know: a_parameter_from_the_future\. It was written by saggriac 9\.0\.0; read it with that version"):
        saggriac.RunResult.load(out)
