"""Nothing a user has is ever lost: targets saggriac did not write are never touched, two runs
never share a target, a computed result is never thrown away, damage is found and named."""

import json
import os
import subprocess
import sys
import time

import numpy as np
import pytest

import saggriac
from saggriac.cli import main
from saggriac.errors import InputError, ParameterError, StorageError
from saggriac.runs import runner, storage
from saggriac.runs import checkpoint_dir


def tiny(**kw):
    return saggriac.Config.from_preset("exp1", **{"n_steps": 300, "n_evals": 2, "n_test_goals": 8, "n_test_configs": 8, **kw})


TINY_CLI = ["--steps", "300", "--set", "n_evals=2", "--set", "n_test_goals=8", "--set", "n_test_configs=8", "--no-progress"]


def tree(path):
    """Every file under path with its bytes: what a user would find there."""
    return {str(p.relative_to(path)): p.read_bytes() for p in sorted(path.rglob("*")) if p.is_file()}


# 1. Data loss ------------------------------------------------------------------------------


@pytest.mark.parametrize("overwrite", [False, True])
def test_a_folder_saggriac_did_not_write_is_never_touched(tmp_path, overwrite, capsys):
    mine = tmp_path / "mydata"
    mine.mkdir()
    (mine / "notes.txt").write_text("my notes")
    before = tree(tmp_path)
    rc = main(["run", *TINY_CLI, "--out", str(mine), *(["--overwrite"] if overwrite else [])])
    assert rc == 2 and "did not write" in capsys.readouterr().err
    assert tree(tmp_path) == before
    with pytest.raises(StorageError, match="did not write"):
        saggriac.run(tiny(), 0, out_dir=mine, overwrite=overwrite)
    assert tree(tmp_path) == before and sorted(os.listdir(tmp_path)) == ["mydata"]


@pytest.mark.parametrize("overwrite", [False, True])
def test_a_regular_file_is_never_replaced(tmp_path, overwrite, capsys):
    f = tmp_path / "myfile.txt"
    f.write_text("precious")
    rc = main(["run", *TINY_CLI, "--out", str(f), *(["--overwrite"] if overwrite else [])])
    assert rc == 2 and "file that saggriac did not write" in capsys.readouterr().err
    with pytest.raises(StorageError, match="file that saggriac did not write"):
        saggriac.run(tiny(), 0, out_dir=f, overwrite=overwrite)
    assert f.read_text() == "precious" and sorted(os.listdir(tmp_path)) == ["myfile.txt"]


def test_overwrite_replaces_only_a_clean_saggriac_run(tmp_path):
    out = tmp_path / "r"
    saggriac.run(tiny(), 0, out_dir=out)
    (out / "my_analysis.ipynb").write_text("{}")
    before = tree(out)
    with pytest.raises(StorageError, match="holds files saggriac did not write .*my_analysis.ipynb"):
        saggriac.run(tiny(), 1, out_dir=out, overwrite=True)
    assert tree(out) == before
    (out / "my_analysis.ipynb").unlink()
    res = saggriac.run(tiny(), 1, out_dir=out, overwrite=True)
    assert saggriac.RunResult.load(out).seed == 1 == res.seed
    assert sorted(os.listdir(tmp_path)) == ["r"]


def test_an_empty_folder_is_used(tmp_path):
    (tmp_path / "empty").mkdir()
    saggriac.run(tiny(), 0, out_dir=tmp_path / "empty")
    assert saggriac.RunResult.load(tmp_path / "empty").seed == 0


# 2. Two runs, one target -------------------------------------------------------------------


def test_a_second_run_on_a_locked_target_is_refused(tmp_path):
    out = tmp_path / "r"
    with storage.target_lock(out):
        with pytest.raises(StorageError, match="Another saggriac run is writing to"):
            saggriac.run(tiny(), 0, out_dir=out)
    assert sorted(os.listdir(tmp_path)) == []  # the lock file goes with the lock
    saggriac.run(tiny(), 0, out_dir=out)


def test_two_concurrent_cli_runs_one_wins_one_is_refused(tmp_path):
    out = tmp_path / "r"
    cmd = [sys.executable, "-m", "saggriac.cli", "run", "--steps", "200000", "--set", "n_evals=3", "--set", "n_test_goals=8", "--set", "n_test_configs=8", "--no-progress", "--out", str(out)]
    first = subprocess.Popen([*cmd, "--seed", "1"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    # Wait until the first holds the lock, then start the second.
    deadline = time.time() + 60
    while not (tmp_path / ".r.lock").exists() and time.time() < deadline:
        time.sleep(0.05)
    second = subprocess.run([*cmd, "--seed", "2"], capture_output=True, text=True, timeout=300)
    out1, err1 = first.communicate(timeout=300)
    assert first.returncode == 0, err1
    assert second.returncode == 2 and "Another saggriac run is writing to" in second.stderr
    assert json.loads((out / "run.json").read_text())["seed"] == 1
    assert sorted(os.listdir(tmp_path)) == ["r"]


class _SquatterSelector:
    """A goal selector that, mid-run, makes the run's target as a user folder of its own."""

    def __init__(self, target, low, high):
        self.target, self.low, self.high = target, np.asarray(low, float), np.asarray(high, float)
        self.rng = np.random.default_rng(0)

    def sample(self):
        if not self.target.exists():
            self.target.mkdir()
            (self.target / "theirs.txt").write_text("not saggriac's")
        return self.rng.uniform(self.low, self.high)

    def update(self, goal, competence):
        return None


def test_the_final_rename_never_replaces_what_appeared_meanwhile(tmp_path):
    out = tmp_path / "r"
    cfg = tiny()
    with pytest.raises(StorageError) as e:
        saggriac.run(cfg, 0, out_dir=out, goal_selector=_SquatterSelector(out, cfg.goal_low, cfg.goal_high))
    assert (out / "theirs.txt").read_text() == "not saggriac's" and sorted(os.listdir(out)) == ["theirs.txt"]
    assert e.value.result.steps[-1] == 300  # the work is kept
    assert not [p for p in os.listdir(tmp_path) if p.endswith(".tmp")]


# 3. Mislabelled results -------------------------------------------------------------------


def test_preset_and_config_resolve_to_one_preset(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    plain = tmp_path / "plain.toml"
    plain.write_text("zeta = 25\n")
    assert main(["run", "--preset", "exp2", "--config", str(plain), *TINY_CLI]) == 0
    out = capsys.readouterr().out
    ran = [p for p in os.listdir("runs")]
    assert len(ran) == 1 and ran[0].startswith("exp2-sagg_riac-seed0-") and "zeta=25" in ran[0], ran
    manifest = json.loads((tmp_path / "runs" / ran[0] / "run.json").read_text())
    assert manifest["config"]["q"] == 100 and manifest["config"]["goal_high"] == [150.0, 150.0]  # exp2's
    assert f"results written to runs/{ran[0]}" in out

    named = tmp_path / "named.toml"
    named.write_text('preset = "exp2"\n')
    rc = main(["run", "--preset", "exp1", "--config", str(named), *TINY_CLI])
    err = capsys.readouterr().err
    assert rc == 2 and "'exp2'" in err and "'exp1'" in err and str(named) in err
    assert main(["run", "--config", str(named), *TINY_CLI, "--seed", "3"]) == 0
    assert any(p.startswith("exp2-sagg_riac-seed3-") for p in os.listdir("runs"))


def test_a_second_run_with_other_settings_gets_its_own_folder(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(["run", *TINY_CLI]) == 0
    assert main(["run", *TINY_CLI[:-1], "--set", "g_max=40", "--no-progress"]) == 0
    names = sorted(os.listdir("runs"))
    assert len(names) == 2 and any("g_max=40" in n for n in names)
    rc = main(["run", *TINY_CLI])  # the very same run again: say which flag to use, in CLI terms
    err = capsys.readouterr().err
    assert rc == 2 and "--overwrite" in err and "--out" in err and "overwrite=True" not in err


# 4. Computed, then lost --------------------------------------------------------------------


@pytest.mark.parametrize("target", [".", "..", ""])
def test_unusable_targets_are_refused_before_the_work(tmp_path, monkeypatch, capsys, target):
    work = tmp_path / "a" / "b"
    work.mkdir(parents=True)
    monkeypatch.chdir(work)
    t0 = time.perf_counter()
    rc = main(["run", "--steps", "50000", "--no-progress", "--out", target])
    assert rc == 2 and time.perf_counter() - t0 < 5
    assert "saggriac: error:" in capsys.readouterr().err
    assert tree(tmp_path) == {}
    with pytest.raises(saggriac.SaggriacError):
        saggriac.run(tiny(), 0, out_dir=target)


def test_numpy_scalars_in_config_are_their_python_values(tmp_path):
    cfg = saggriac.Config(n_steps=np.int64(300), n_evals=np.int32(2), n_test_goals=np.uint16(8), n_test_configs=8, v=np.float32(0.5), goal_high=np.array([50.0, 50.0]))
    assert type(cfg.n_steps) is int and type(cfg.v) is float and cfg.goal_high == (50.0, 50.0)
    assert cfg == tiny().replace(v=0.5)
    saggriac.run(cfg, 0, out_dir=tmp_path / "np64")
    assert json.loads((tmp_path / "np64" / "run.json").read_text())["config"]["n_steps"] == 300
    assert sorted(os.listdir(tmp_path)) == ["np64"]


def test_no_tmp_survives_any_failure_while_saving(tmp_path, monkeypatch):
    def broken(*a, **k):
        raise TypeError("not serialisable")

    monkeypatch.setattr(storage, "_digest", broken)
    with pytest.raises(TypeError):
        saggriac.run(tiny(), 0, out_dir=tmp_path / "r")
    assert sorted(os.listdir(tmp_path)) == []


def test_the_cli_saves_a_result_it_could_not_write_to_a_recovery_folder(tmp_path, monkeypatch, capsys):
    real = storage.replace_dir

    def failing(out, fill, what, replace=None):
        if what == "the run" and out.name == "r":
            raise StorageError(f"Could not write the run to {out}: Device or resource busy.")
        return real(out, fill, what, replace)

    monkeypatch.setattr(storage, "replace_dir", failing)
    rc = main(["run", *TINY_CLI, "--out", str(tmp_path / "r")])
    err = capsys.readouterr().err
    assert rc == 2 and "saved to" in err, err
    saved = [p for p in os.listdir(tmp_path) if p.startswith("r.recovered-")]
    assert len(saved) == 1 and str(tmp_path / saved[0]) in err
    assert saggriac.RunResult.load(tmp_path / saved[0]).steps[-1] == 300


def _chattr(path, flag):
    return subprocess.run(["chattr", flag, str(path)], capture_output=True).returncode == 0


def test_a_read_only_target_is_refused_before_the_work(tmp_path):
    out = tmp_path / "r"
    saggriac.run(tiny(), 0, out_dir=out)
    if os.geteuid() == 0:
        if not _chattr(out, "+i"):
            pytest.skip("running as root on a file system without chattr +i: nothing is read-only to root")
    else:
        out.chmod(0o500)
    try:
        t0 = time.perf_counter()
        with pytest.raises(StorageError, match="not writable"):
            saggriac.run(tiny(n_steps=50_000), 1, out_dir=out, overwrite=True)
        assert time.perf_counter() - t0 < 5
    finally:
        _chattr(out, "-i") if os.geteuid() == 0 else out.chmod(0o755)


# 5. Damaged runs -------------------------------------------------------------------------


def test_run_json_records_table_checksums_and_load_names_the_damage(tmp_path):
    out = tmp_path / "r"
    saggriac.run(tiny(), 0, out_dir=out)
    recorded = json.loads((out / "run.json").read_text())["tables"]
    assert set(recorded) == {"metrics.parquet", "goals.parquet", "attempts.parquet", "regions.parquet"}
    assert recorded["metrics.parquet"]["bytes"] == (out / "metrics.parquet").stat().st_size
    data = (out / "goals.parquet").read_bytes()
    (out / "goals.parquet").write_bytes(data[:100])
    with pytest.raises(StorageError, match=r"goals.parquet has 100 bytes.*truncated"):
        saggriac.RunResult.load(out)
    flipped = bytearray(data)
    flipped[len(data) // 2] ^= 0xFF
    (out / "goals.parquet").write_bytes(bytes(flipped))
    with pytest.raises(StorageError, match=r"goals.parquet does not match the SHA-256"):
        saggriac.RunResult.load(out)
    (out / "goals.parquet").unlink()
    with pytest.raises(StorageError, match=r"goals.parquet is missing"):
        saggriac.RunResult.load(out)


def test_a_study_rerun_recomputes_damaged_runs_and_says_so(tmp_path, capsys):
    study = saggriac.Study(base=tiny(), conditions=("sagg_riac", "sagg_random"), seeds=(0,))
    saggriac.run_study(study, tmp_path / "st", n_workers=1, progress=False)
    clean = tree(tmp_path / "st" / "runs")
    runs = tmp_path / "st" / "runs"
    (runs / "sagg_riac" / "seed0" / "metrics.parquet").unlink()
    with open(runs / "sagg_random" / "seed0" / "attempts.parquet", "r+b") as f:
        f.truncate(100)
    res = saggriac.run_study(study, tmp_path / "st", n_workers=1, progress=False)
    err = capsys.readouterr().err
    assert res.n_computed == 2 and set(res.repaired) == {"sagg_riac/seed0", "sagg_random/seed0"}
    assert "metrics.parquet is missing" in res.repaired["sagg_riac/seed0"] and "truncated" in res.repaired["sagg_random/seed0"]
    assert "sagg_riac/seed0 is damaged" in err and "recomputed" in err
    again = {k: v for k, v in tree(runs).items() if "damaged-" not in k}
    for name in clean:  # the recomputed tables are the very same bytes
        if name.endswith(".parquet"):
            assert again[name] == clean[name], name
    # what was left of the damaged runs is kept aside, not deleted
    assert [p for p in os.listdir(runs / "sagg_riac") if p.startswith(".seed0.damaged-")]


# 6. Checkpoints ----------------------------------------------------------------------------


def test_a_checkpoint_with_a_flipped_byte_is_refused(tmp_path, monkeypatch, capsys):
    out = tmp_path / "run"

    def interrupted(*a, **k):
        raise KeyboardInterrupt

    with monkeypatch.context() as m:
        m.setattr(runner, "write_run", interrupted)
        with pytest.raises(KeyboardInterrupt):
            saggriac.run(tiny(n_steps=2000, n_evals=8), 0, out_dir=out, checkpoint_every=500, threads=1)
    state = checkpoint_dir(out) / "state.bin"
    data = bytearray(state.read_bytes())
    data[len(data) // 2] ^= 0xFF
    state.write_bytes(bytes(data))
    with pytest.raises(InputError, match="damaged.*without --resume"):
        saggriac.resume(out)
    rc = main(["run", "--resume", str(out), "--no-progress"])
    assert rc == 2 and "checksum" in capsys.readouterr().err
    assert not out.exists()


# 7/10. Tracebacks and silent coercions ---------------------------------------------------


def test_non_utf8_toml_is_a_saggriac_error(tmp_path, capsys):
    f = tmp_path / "latin1.toml"
    f.write_bytes('zeta = 20 # caf\xe9\n'.encode("latin-1"))
    rc = main(["run", "--config", str(f), *TINY_CLI])
    err = capsys.readouterr().err
    assert rc == 2 and "not UTF-8" in err and str(f) in err


@pytest.mark.parametrize(
    "kw, text",
    [
        (dict(eval_schedule=[0, "a"]), "'eval_schedule' parameter of Config must be a list of ints"),
        (dict(eval_schedule=[0, 50.5, 100], n_steps=100), "'eval_schedule' parameter of Config must be a list of ints"),
        (dict(eval_schedule=[0, True, 100], n_steps=100), "'eval_schedule' parameter of Config must be a list of ints"),
        (dict(eps_max=True), "'eps_max' parameter of Config must be a float. Got True"),
        (dict(g_max=True), "'g_max' parameter of Config must be an int. Got True"),
        (dict(episodic_refine=1), "'episodic_refine' parameter of Config must be a bool"),
        (dict(n_steps=-5), "'n_steps' parameter of Config must be an int >= 1"),
        (dict(n_steps=0), "'n_steps' parameter of Config must be an int >= 1"),
        (dict(eval_tolerance=0.0), "'eval_tolerance' parameter of Config"),
        (dict(explore_step=0.0), "'explore_step' parameter of Config"),
        (dict(goal_low=(10.0, 0.0), goal_high=(0.0, 50.0)), "'goal_low' and 'goal_high' parameters of Config must be finite with goal_low < goal_high"),
        (dict(goal_low=(0.0, 0.0), goal_high=(0.0, 0.0)), "goal_low = [0.0, 0.0] and goal_high = [0.0, 0.0]"),
        (dict(arm_length=1e300), "'arm_length' parameter of Config must be a float in [1e-12, 1e+12]"),
        (dict(goal_high=(1e300, 50.0)), "'goal_high' parameter of Config must be at most 1e+12"),
        # A rule of the configuration, the same on every machine (no memory is read).
        (dict(n_joints=10**12), "'n_joints' parameter of Config must be an int in [1, 1000000]. Got 1000000000000"),
    ],
)
def test_bad_config_values_are_refused_in_config_terms(kw, text):
    with pytest.raises(ParameterError) as e:
        saggriac.Config(**kw)
    assert text in str(e.value)


@pytest.mark.parametrize("kw", [dict(seed=-1), dict(seed=2**70), dict(seed=1.5), dict(seed=True), dict(g_max=10**30), dict(zeta=2.0), dict(p_interest="0.7")])
def test_selector_arguments_are_checked_not_coerced(kw):
    with pytest.raises(ParameterError, match=f"'{next(iter(kw))}' parameter of SaggRiacSelector"):
        saggriac.SaggRiacSelector([0, 0], [1, 1], **kw)


def test_selector_bounds_whose_width_overflows_are_refused():
    with pytest.raises(ParameterError, match="high - low is a finite float"):
        saggriac.SaggRiacSelector([-1e308, 0], [1e308, 1])
    assert np.isfinite(saggriac.SaggRiacSelector([-1e307, 0], [1e307, 1], seed=0).sample()).all()


def test_a_run_that_cannot_fit_in_memory_is_refused_before_it_starts(tmp_path):
    cfg = saggriac.Config(n_joints=10**6, n_steps=50_000)
    t0 = time.perf_counter()
    with pytest.raises(ParameterError, match=r"would need about .* GB of memory .* more than this machine has"):
        saggriac.run(cfg, 0, out_dir=tmp_path / "big")
    assert time.perf_counter() - t0 < 5 and not (tmp_path / "big").exists()


def test_cli_flags_that_would_be_ignored_are_refused(tmp_path, capsys):
    rc = main(["reproduce", "exp1", "--conditions", "", "--out", str(tmp_path / "st")])
    assert rc == 2 and "--conditions" in capsys.readouterr().err and not (tmp_path / "st").exists()
    for extra in (["--seed", "9"], ["--preset", "exp2"], ["--overwrite"]):
        rc = main(["run", "--resume", str(tmp_path / "ck"), *extra])
        assert rc == 2 and extra[0] in capsys.readouterr().err


def test_scheduler_addresses_are_checked_before_anything_is_written(tmp_path):
    pytest.importorskip("distributed")
    study = saggriac.Study(base=tiny(), conditions=("sagg_riac",), seeds=(0,))
    t0 = time.perf_counter()
    with pytest.raises(ParameterError, match="must be an address such as"):
        saggriac.run_study(study, tmp_path / "a", backend="dask", scheduler="notanaddress", progress=False)
    with pytest.raises(ParameterError, match="no Dask scheduler answers"):
        saggriac.run_study(study, tmp_path / "b", backend="dask", scheduler="tcp://127.0.0.1:1", progress=False)
    assert time.perf_counter() - t0 < 12
    assert sorted(os.listdir(tmp_path)) == []


# 12. Small things users meet first -------------------------------------------------------


def test_version_and_help_for_every_argument(capsys):
    from saggriac.cli import build_parser

    with pytest.raises(SystemExit) as e:
        main(["--version"])
    assert e.value.code == 0 and capsys.readouterr().out.strip() == f"saggriac {saggriac.__version__}"
    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    for name, p in sub.choices.items():
        for action in p._actions:
            assert action.help, f"saggriac {name}: {action.dest} has no help text"


def test_a_refused_command_leaves_no_empty_runs_folder(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(["run", "--checkpoint-every", "0", "--no-progress"]) == 2
    assert main(["run", "--set", "g_max=0", "--no-progress"]) == 2
    assert main(["run", "--out", "deep/er/run", "--set", "n_joints=0", "--no-progress"]) == 2
    assert os.listdir(tmp_path) == []


def test_a_config_is_valid_or_not_whatever_the_machine(monkeypatch):
    """Config() reads nothing of the machine (a configuration valid here is valid on a Dask
    worker); the memory check happens where a run starts."""
    from saggriac.runs import resources

    def no_machine():
        raise AssertionError("Config() read the machine's memory")

    monkeypatch.setattr(resources, "machine_memory", no_machine)
    cfg = saggriac.Config(n_joints=10**6, n_steps=10)
    assert cfg.joints == 10**6
    with pytest.raises(AssertionError, match="read the machine's memory"):
        saggriac.run(cfg, 0)
