"""Checkpoint and resume of a single run: an interrupted run continues to the same result."""

import json
import signal
import subprocess
import sys
import time

import pandas as pd
import pytest

import saggriac
from saggriac import _core
from saggriac.bodies.environments import PlanarArm
from saggriac.errors import ParameterError, StorageError
from saggriac.runs import checkpoint_dir


def cfg_for(**kw):
    return saggriac.Config.from_preset("exp1", **{"n_steps": 3000, "n_evals": 10, "n_test_goals": 10, "n_test_configs": 10, **kw})


def frames(res):
    return [res.metrics, res.goals, res.attempts, res.regions]


@pytest.mark.parametrize(
    "kw",
    [dict(), dict(condition="actuator_riac"), dict(paradigm="episodic", motor_noise=0.01, body_change_step=1500, body_change_link=2, body_change_length=5.0)],
)
def test_restore_at_every_evaluation_gives_the_uninterrupted_run(kw):
    cfg = cfg_for(**kw)
    ref = saggriac.run(cfg, seed=7)
    seeds = saggriac.seeding.derive_seeds(7)
    learner = _core.Learner(cfg.core_dict(), *seeds)
    restores = 0
    while not learner.run(lambda row: False):
        state = learner.checkpoint()
        learner = _core.Learner.restore(cfg.core_dict(), state)
        restores += 1
    assert restores >= 5
    pd.testing.assert_frame_equal(pd.DataFrame(learner.metrics()), ref.metrics, check_exact=True)
    got = saggriac.runs.learner._xy_columns(learner.goals())
    pd.testing.assert_frame_equal(got, ref.goals, check_exact=True)


def test_checkpointed_run_equals_the_plain_run_and_cleans_up(tmp_path):
    cfg = cfg_for()
    ref = saggriac.run(cfg, seed=1)
    res = saggriac.run(cfg, seed=1, out_dir=tmp_path / "run", checkpoint_every=700)
    for a, b in zip(frames(res), frames(ref)):
        pd.testing.assert_frame_equal(a, b, check_exact=True)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run"]  # no checkpoint left behind


def test_sigkill_then_resume_from_the_command_line(tmp_path):
    out = tmp_path / "run"
    args = ["--preset", "exp1", "--seed", "2", "--steps", "6000", "--set", "n_evals=12", "--set", "n_test_goals=10", "--set", "n_test_configs=10"]
    cmd = [sys.executable, "-m", "saggriac.cli", "run", *args, "--out", str(out), "--no-progress", "--checkpoint-every", "1000"]
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    meta = checkpoint_dir(out) / "checkpoint.json"
    deadline = time.time() + 120
    while time.time() < deadline:
        if meta.exists() and json.loads(meta.read_text())["steps"] >= 2000:
            break
        if proc.poll() is not None:
            pytest.fail(f"the run ended (exit {proc.returncode}) before it could be killed")
        time.sleep(0.05)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    assert not (out / "run.json").exists()
    killed_at = json.loads(meta.read_text())["steps"]
    assert 2000 <= killed_at < 6000
    done = subprocess.run([sys.executable, "-m", "saggriac.cli", "run", "--resume", str(out), "--no-progress"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert f"resumed at step {killed_at}" in done.stdout
    resumed = saggriac.RunResult.load(out)
    plain = saggriac.run(saggriac.Config.from_preset("exp1", n_steps=6000, n_evals=12, n_test_goals=10, n_test_configs=10), seed=2)
    for a, b in zip(frames(resumed), frames(plain)):
        pd.testing.assert_frame_equal(a, b, check_exact=True)
    assert resumed.manifest["resumed_at_step"] == killed_at
    assert not checkpoint_dir(out).exists()


def test_resume_and_checkpoint_errors(tmp_path, capsys):
    with pytest.raises(StorageError, match="No checkpoint"):
        saggriac.resume(tmp_path / "nothing")
    with pytest.raises(ParameterError, match="needs out_dir"):
        saggriac.run(cfg_for(), seed=0, checkpoint_every=100)
    with pytest.raises(ParameterError, match="checkpoint_every"):
        saggriac.run(cfg_for(), seed=0, out_dir=tmp_path / "r", checkpoint_every=0)
    with pytest.raises(ParameterError, match="user's environment"):
        saggriac.run(cfg_for(), seed=0, out_dir=tmp_path / "r", checkpoint_every=100, environment=PlanarArm())
    # A damaged checkpoint is refused with a clear message, and nothing is written.
    ck = checkpoint_dir(tmp_path / "bad")
    ck.mkdir()
    ls, es = saggriac.seeding.derive_seeds(0)
    meta = {"config": cfg_for().to_dict(), "seed": 0, "learner_seed": ls, "eval_seed": es, "overwrite": False, "checkpoint_every": 100, "steps": 100, "version": saggriac.__version__}
    (ck / "checkpoint.json").write_text(json.dumps(saggriac.files.seal(meta)))
    (ck / "state.bin").write_bytes(b"\x00\x01garbage")
    with pytest.raises(saggriac.InputError, match="damaged"):
        saggriac.resume(tmp_path / "bad")
    assert not (tmp_path / "bad").exists()
    from saggriac.cli import main

    assert main(["run", "--resume", str(tmp_path / "bad"), "--steps", "10"]) == 2
    assert "drop --steps" in capsys.readouterr().err
