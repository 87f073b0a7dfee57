"""Faults from the third newcomer audit (issue 27): nothing replaced that saggriac did not write,
bounded sizes, no coercion, provenance checked. Each class of fault, not only its example."""

from __future__ import annotations

import json
import os
import socket
import stat
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import saggriac
from saggriac import Config
from saggriac.errors import InputError, ParameterError, SaggriacError, StorageError

TEACHERS = {
    "sagg_riac": lambda: saggriac.SaggRiacSelector([0.0, 0.0], [1.0, 1.0], seed=1),
    "riac": lambda: saggriac.RiacSelector([0.0, 0.0], [1.0, 1.0], seed=1),
    "alp_gmm": lambda: saggriac.AlpGmmSelector([0.0, 0.0], [1.0, 1.0], seed=1),
    "covar_gmm": lambda: saggriac.CovarGmmSelector([0.0, 0.0], [1.0, 1.0], seed=1),
    "discrete_lp": lambda: saggriac.DiscreteLpSelector(4, seed=1),
}


# -- 1. nothing replaced that saggriac did not write -------------------------------------------


def _special_files(tmp_path: Path) -> dict[str, Path]:
    out = {}
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    out["fifo"] = fifo
    sock = tmp_path / "sock"
    s = socket.socket(socket.AF_UNIX)
    s.bind(str(sock))
    s.close()  # the socket file stays
    out["socket"] = sock
    foreign = tmp_path / "notes.txt"
    foreign.write_text("a user's notes")
    out["foreign"] = foreign
    target = tmp_path / "elsewhere.bin"
    target.write_text("a user's file the link points to")
    link = tmp_path / "link.bin"
    link.symlink_to(target)
    out["link"] = link
    out["dangling"] = tmp_path / "dangling.bin"
    out["dangling"].symlink_to(tmp_path / "nowhere" / "x")
    return out


def _snapshot(p: Path):
    st = os.lstat(p)
    data = p.read_bytes() if stat.S_ISREG(st.st_mode) else None
    link = os.readlink(p) if stat.S_ISLNK(st.st_mode) else None
    return (stat.S_IFMT(st.st_mode), st.st_ino, data, link)


@pytest.mark.parametrize("kind", sorted(TEACHERS))
def test_teacher_save_replaces_only_its_own_files(tmp_path, kind):
    t = TEACHERS[kind]()
    specials = _special_files(tmp_path)
    if os.path.exists(os.devnull):
        specials["devnull"] = Path(os.devnull)
    for name, path in specials.items():
        before = _snapshot(path)
        with pytest.raises(StorageError):
            t.save(path, overwrite=True)
        assert _snapshot(path) == before, name
    # Its own file is replaced, and only with overwrite=True (a real bool).
    own = t.save(tmp_path / "t.bin")
    with pytest.raises(StorageError, match="exists"):
        t.save(own)
    for bad in ("no", 1, None, "False"):
        with pytest.raises(ParameterError, match="overwrite"):
            t.save(own, overwrite=bad)
    t.save(own, overwrite=True)
    assert type(saggriac.load_selector(own)) is type(t)
    assert sorted(p.name for p in tmp_path.iterdir() if p.name.startswith(".")) == []


def test_figures_replace_only_saggriac_figures(tmp_path):
    from saggriac import plots

    cfg = Config.from_preset("exp1")
    mine = tmp_path / "photo.png"
    mine.write_bytes(b"\x89PNG\r\n\x1a\n" + b"\0" * 64)  # someone's PNG
    before = _snapshot(mine)
    with pytest.raises(StorageError, match="not a figure saggriac wrote"):
        plots.plot_arm(cfg, mine)
    assert _snapshot(mine) == before
    fig = plots.plot_arm(cfg, tmp_path / "arm.png")
    plots.plot_arm(cfg, fig)  # its own figure is replaced
    fifo = tmp_path / "fifo.png"
    os.mkfifo(fifo)
    with pytest.raises(StorageError, match="FIFO"):
        plots.plot_arm(cfg, fifo)


# -- 2. bounded sizes: a clear error, never a panic, abort or hang ------------------------------

HUGE = [2**40, 2**62, 10**12]


@pytest.mark.parametrize(
    "make",
    [
        *(lambda v=v: saggriac.SaggRiacSelector([0.0], [1.0], zeta=v) for v in HUGE),
        *(lambda v=v: saggriac.SaggRiacSelector([0.0], [1.0], g_max=v) for v in HUGE),
        *(lambda v=v: saggriac.RiacSelector([0.0], [1.0], split_attempts=v) for v in HUGE),
        *(lambda v=v: saggriac.RiacSelector([0.0], [1.0], max_region_size=v) for v in HUGE),
        *(lambda v=v: saggriac.AlpGmmSelector([0.0], [1.0], fit_rate=v) for v in HUGE),
        *(lambda v=v: saggriac.AlpGmmSelector([0.0], [1.0], max_components=v) for v in (101, *HUGE)),
        *(lambda v=v: saggriac.CovarGmmSelector([0.0], [1.0], bootstrap=v) for v in HUGE),
        *(lambda v=v: saggriac.DiscreteLpSelector(v) for v in (2**31, *HUGE)),
        *(lambda v=v: Config(zeta=v) for v in HUGE),
        *(lambda v=v: Config(g_max=v) for v in HUGE),
    ],
)
def test_sizes_have_stated_bounds(make):
    with pytest.raises(ParameterError, match=r"must be an int in \[\d+, (\d+\]|2\*\*\d+\))"):
        make()


@pytest.mark.parametrize("n", [10**8, 2**40, 2**62])
def test_sample_batch_is_bounded(n):
    t = saggriac.SaggRiacSelector([0.0, 0.0], [1.0, 1.0])
    with pytest.raises(SaggriacError, match="n"):
        t.sample_batch(n)
    assert t.sample_batch(3).shape == (3, 2)


@pytest.mark.parametrize("kind", ["alp_gmm", "covar_gmm", "riac", "sagg_riac"])
@pytest.mark.parametrize("scale", [1e150, 1e300, -1e300])
def test_extreme_competences_are_refused_or_kept_finite(kind, scale):
    t = TEACHERS[kind]()
    rng = np.random.default_rng(0)
    for i in range(600):
        g = t.sample()
        try:
            t.update(g, scale * rng.uniform(-1, 1))
        except InputError as e:
            assert "1e100" in str(e)
            t.update(g, rng.uniform(-1, 0))
    assert np.all(np.isfinite(t.sample_batch(50)))


# -- 4. no coercion ------------------------------------------------------------------------------


@pytest.mark.parametrize("kind", sorted(set(TEACHERS) - {"discrete_lp"}))
@pytest.mark.parametrize("goal, competence", [([0.5, 0.5], "0.5"), ([0.5, 0.5], True), (["0.5", "0.5"], -0.5), ([True, False], -0.5), ([0.5, 0.5], [-0.5, -0.5]), ([0.5, 0.5], None)])
def test_teachers_refuse_strings_and_bools(kind, goal, competence):
    t = TEACHERS[kind]()
    with pytest.raises(InputError):
        t.update(goal, competence)
    assert len(t.history()["told_competence"]) == 0


@pytest.mark.parametrize("low, high", [(["0", "0"], [1, 1]), ([False, False], [True, True]), ([0, 0], "11")])
def test_bounds_refuse_strings_and_bools(low, high):
    with pytest.raises(InputError):
        saggriac.SaggRiacSelector(low, high)


# -- 3. provenance ---------------------------------------------------------------------------------


def _checkpointed(tmp_path: Path, seed: int) -> Path:
    """A run interrupted after its first checkpoint (kill -9 in a subprocess)."""
    out = tmp_path / f"run{seed}"
    code = f"""
import os, saggriac
from saggriac import runner
real = runner._write_checkpoint
def once(*a, **k):
    real(*a, **k)
    os._exit(9)
runner._write_checkpoint = once
cfg = saggriac.Config.from_preset("exp1", n_steps=3000, n_evals=3, n_test_goals=5, n_test_configs=5)
saggriac.run(cfg, seed={seed}, out_dir={str(out)!r}, checkpoint_every=1000)
"""
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert r.returncode == 9, r.stderr
    return out


def test_resume_refuses_a_state_from_another_seed(tmp_path):
    a, b = _checkpointed(tmp_path, 0), _checkpointed(tmp_path, 1)
    ca, cb = saggriac.runner.checkpoint_dir(a), saggriac.runner.checkpoint_dir(b)
    (ca / "state.bin").write_bytes((cb / "state.bin").read_bytes())
    with pytest.raises(StorageError, match="other seeds"):
        saggriac.resume(a)
    assert not a.exists()


@pytest.mark.parametrize("edit", [{"seed": 1}, {"learner_seed": 7}, {"checkpoint_every": 0}, {"overwrite": True}, {"steps": 5}])
def test_resume_refuses_an_edited_checkpoint_json(tmp_path, edit):
    out = _checkpointed(tmp_path, 0)
    f = saggriac.runner.checkpoint_dir(out) / "checkpoint.json"
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
    with pytest.raises(StorageError, match="does not know: a_parameter_from_the_future"):
        saggriac.RunResult.load(out)


# -- 4. no coercion, no silently dropped flag --------------------------------------------------


def _cli(args, cwd):
    r = subprocess.run([sys.executable, "-m", "saggriac.cli", *args], capture_output=True, text=True, cwd=cwd)
    return r.returncode, r.stderr


@pytest.mark.parametrize(
    "args, says",
    [
        (["run", "--set", "n_steps=500", "--steps", "300"], "--steps and --set n_steps"),
        (["run", "--set", "condition=sagg_riac", "--condition", "sagg_random"], "--condition and --set condition"),
        (["run", "--set", "zeta=10", "--set", "zeta=12"], "given twice"),
        (["run", "--out", ""], "--out"),
        (["reproduce", "exp1", "--out", ""], "--out"),
        (["reproduce", "exp1", "--seeds", "1000000000"], "seeds"),
        (["run", "--config", "/dev/zero"], "not a regular file"),
    ],
)
def test_cli_refuses_conflicts_and_unbounded_inputs(tmp_path, args, says):
    rc, err = _cli(args, tmp_path)
    assert rc != 0 and says in err, err
    assert "Traceback" not in err
    assert list(tmp_path.iterdir()) == []


def test_config_file_size_is_bounded(tmp_path):
    big = tmp_path / "big.toml"
    big.write_text("# " + "x" * 2_000_000 + "\nzeta = 20\n")
    with pytest.raises(ParameterError, match="larger than"):
        Config.from_toml(big)


def test_a_teacher_in_config_and_a_goal_selector_conflict():
    cfg = Config.from_preset("exp1", n_steps=200, n_evals=1, teacher="riac")
    sel = saggriac.RiacSelector(cfg.goal_low, cfg.goal_high)
    with pytest.raises(ParameterError, match="teacher='riac'"):
        saggriac.run(cfg, 0, goal_selector=sel)


@pytest.mark.parametrize("bad", [[np.nan, 0.0], ["1", "2"], [True, False]])
def test_competence_refuses_nonsense_positions(bad):
    with pytest.raises(InputError):
        saggriac.competence(bad, [1.0, 1.0], [0.0, 0.0])


# -- 5. bodies check their inputs ---------------------------------------------------------------


@pytest.mark.parametrize("make", [lambda: saggriac.environments.PlanarArm(), lambda: saggriac.environments.SpatialArm(n_joints=6), lambda: saggriac.environments.PlanarArm(link_lengths=[1.0, 2.0])])
@pytest.mark.parametrize("action", ["short", "long", "nan", "inf", "strings", "bools"])
def test_python_arms_refuse_bad_actions_and_keep_their_state(make, action):
    arm = make()
    n = len(arm.theta)
    arm.reset(options={"theta": np.full(n, 0.1)})
    before = (arm.theta.copy(), arm.forward(arm.theta))
    value = {"short": np.zeros(max(1, n - 1)), "long": np.zeros(n + 3), "nan": np.full(n, np.nan), "inf": np.full(n, np.inf), "strings": ["0.1"] * n, "bools": [True] * n}[action]
    with pytest.raises(InputError, match=f"{n} finite floats"):
        arm.step(value)
    with pytest.raises(InputError):
        arm.reset(options={"theta": value})
    np.testing.assert_array_equal(arm.theta, before[0])
    theta, x = arm.step(np.zeros(n))
    np.testing.assert_array_equal(x, before[1])


@pytest.mark.parametrize("kw", [dict(n_joints=0), dict(n_joints=2.5), dict(arm_length=-1.0), dict(arm_length=float("nan")), dict(link_lengths=[]), dict(link_lengths=[1.0, -1.0]), dict(joint_limit=0.0), dict(max_joint_step=float("inf"))])
def test_python_arms_check_their_parameters(kw):
    with pytest.raises(ParameterError):
        saggriac.environments.PlanarArm(**kw)


def test_mujoco_arm_refuses_duplicate_joints_and_bad_actions():
    mj = pytest.importorskip("saggriac.mujoco_arm")
    with pytest.raises(ParameterError, match="more than once"):
        mj.MujocoArm(mj.pusher_model_path(), [mj.PUSHER_JOINTS[0], mj.PUSHER_JOINTS[1], mj.PUSHER_JOINTS[0]], "tips_arm")
    arm = mj.pusher_arm()
    with pytest.raises(InputError, match="7 finite floats"):
        arm.step(np.zeros(3))
    assert arm.step(np.zeros(7))[0].shape == (7,)


class _IgnoresPlacement(saggriac.environments.PlanarArm):
    def reset(self, *, seed=None, options=None):
        return super().reset(seed=seed)


class _ClaimsPlacement(saggriac.environments.PlanarArm):
    def reset(self, *, seed=None, options=None):
        theta, x = super().reset(seed=seed)
        return (np.asarray(options["theta"], dtype=float) if options else theta), x


@pytest.mark.parametrize("env", [_IgnoresPlacement, _ClaimsPlacement])
def test_run_refuses_a_body_that_ignores_placement(env, tmp_path):
    cfg = Config.from_preset("exp1", n_steps=200, n_evals=1, n_test_goals=3, n_test_configs=3)
    with pytest.raises(saggriac.errors.ConformanceError, match="options=\\{'theta'"):
        saggriac.run(cfg, 0, environment=env(), out_dir=tmp_path / "r")
    assert not (tmp_path / "r").exists()


# -- 6. disks fill, work survives ------------------------------------------------------------


def test_the_free_space_check_counts_the_checkpoints(tmp_path, monkeypatch):
    from saggriac import resources, storage

    cfg = Config.from_preset("exp2", n_evals=1)
    need = 2 * resources.checkpoint_bytes(cfg)
    assert need > 50e6  # exp2's state grows past 20 MB (audit: 22 MB at 81k steps)
    free = storage.MIN_FREE_BYTES + need // 2
    monkeypatch.setattr(storage.shutil, "disk_usage", lambda p: type("U", (), {"free": free})())
    with pytest.raises(StorageError, match="MB free"):
        saggriac.run(cfg, 0, out_dir=tmp_path / "r", checkpoint_every=50_000)
    # Without checkpoints the same disk is enough to start.
    storage.check_output_dir(tmp_path / "r", False, saggriac.runner._min_free(cfg, None))


def test_a_failed_checkpoint_write_warns_and_the_run_finishes(tmp_path, monkeypatch):
    from saggriac import runner

    real = runner._write_checkpoint
    calls = []

    def flaky(*a, **k):
        calls.append(1)
        if len(calls) == 2:
            raise StorageError("No space left on device (simulated)")
        real(*a, **k)

    monkeypatch.setattr(runner, "_write_checkpoint", flaky)
    # Checkpoints are written at evaluations, between goal attempts: many evaluations, many chances.
    cfg = Config.from_preset("exp1", n_steps=6000, n_evals=24, n_test_goals=5, n_test_configs=5)
    with pytest.warns(runner.CheckpointWarning, match=r"last good checkpoint \(step \d+\) is kept"):
        res = saggriac.run(cfg, 0, out_dir=tmp_path / "r", checkpoint_every=250)
    plain = saggriac.run(cfg, 0)
    assert res.path is not None and len(calls) >= 3  # and later checkpoints were written again
    np.testing.assert_array_equal(res.metrics["reach_error"], plain.metrics["reach_error"])


def test_a_study_run_that_cannot_be_written_says_where_it_went(tmp_path, monkeypatch):
    from saggriac import study as study_mod
    from saggriac.study import spec

    real = spec.run

    def unwritable(cfg, seed, out_dir, **kw):
        res = real(cfg, seed=seed, **kw)
        e = StorageError(f"Cannot write the run to {out_dir}: No space left on device (simulated).")
        e.result = res
        raise e

    monkeypatch.setattr(spec, "run", unwritable)
    cfg = Config.from_preset("exp1", n_steps=300, n_evals=1, n_test_goals=3, n_test_configs=3)
    task = study_mod.Study(cfg, "sagg_riac", (0,)).tasks()[0]
    with pytest.raises(StorageError, match="saved to (.*recovered-[^ ]*)") as e:
        study_mod.run_task(task, tmp_path / "st")
    place = Path(str(e.value).split("saved to ")[1].split(" instead")[0])
    assert saggriac.RunResult.load(place).seed == 0


def test_goal_env_refuses_a_goal_outside_its_box():
    gym = pytest.importorskip("gymnasium")
    import saggriac.gym  # noqa: F401 (registers the environments)

    env = gym.make("saggriac/PlanarArmExp1-v0")
    with pytest.raises(InputError, match="outside the environment's goal box"):
        env.reset(options={"goal": [1e6, 1e6]})
    obs, _ = env.reset(options={"goal": [10.0, 10.0]})
    assert env.observation_space.contains(obs)
