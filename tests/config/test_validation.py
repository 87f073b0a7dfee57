"""Bad input is rejected with a message naming the parameter, the value and the rule."""

import os

import pytest

import saggriac
from saggriac.cli import main
from saggriac.errors import ParameterError, SaggriacError, StorageError


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"g_max": 1}, "The 'g_max' parameter of Config must be an int in [2, 1000000]. Got 1 instead."),
        ({"eps_c": -2.0}, "The 'eps_c' parameter of Config must be a float with min_c < eps_c < 0 (min_c = -1). Got -2 instead."),
        ({"v": 0.0}, "The 'v' parameter of Config must be a finite float > 0 and <= 2 * reach, the diameter of the ball the body reaches (reach = 50). Got 0 instead."),
        ({"q": 0}, "The 'q' parameter of Config must be an int >= 1. Got 0 instead."),
        ({"joint_limit": 4.0}, "The 'joint_limit' parameter of Config must be a float in (0, 3.141592653589793]. Got 4 instead."),
        ({"n_joints": "many"}, "The 'n_joints' parameter of Config must be an int >= 1. Got 'many' instead."),
        ({"condition": "best"}, "The 'condition' parameter of Config must be one of 'sagg_riac', 'sagg_random', 'actuator_random', 'actuator_riac'. Got 'best' instead."),
        ({"knn_index": "hnsw"}, "The 'knn_index' parameter of Config must be one of 'blocks', 'brute_force'. Got 'hnsw' instead."),
        ({"n_evals": 0}, "The 'n_evals' parameter of Config must be an int in [1, max(n_steps, 100)] (a run evaluates at most once per time step; n_steps = 50000). Got 0 instead."),
        # A value of the wrong type is named with the core's rule for that parameter, read as data.
        ({"g_max": "many"}, "The 'g_max' parameter of Config must be an int in [2, 1000000]. Got 'many' instead."),
        ({"eps_max": "far"}, "The 'eps_max' parameter of Config must be a finite float > 0 and <= 2 * reach, the diameter of the ball the body reaches (reach = 50). Got 'far' instead."),
        ({"competence": "best"}, "The 'competence' parameter of Config must be one of 'relative', 'absolute'. Got 'best' instead."),
        ({"paradigm": 3}, "The 'paradigm' parameter of Config must be a str. Got 3 instead."),
        ({"body": "tentacle"}, "The 'body' parameter of Config must be one of 'planar_arm', 'spatial_arm', 'chain'. Got 'tentacle' instead."),
    ],
)
def test_bad_parameter_messages(kwargs, message):
    with pytest.raises(ParameterError) as e:
        saggriac.Config(**kwargs)
    assert str(e.value) == message
    assert e.value.param == next(iter(kwargs))
    assert isinstance(e.value, SaggriacError) and isinstance(e.value, ValueError)


def test_tied_parameters_print_both_values():
    with pytest.raises(ParameterError, match=r"p_interest \+ p_global \+ p_lowest = 1 \(p_interest = 0.5, p_global = 0.2\)"):
        saggriac.Config(p_interest=0.5)
    with pytest.raises(ParameterError, match=r"steps <= n_steps \(n_steps = 100\)"):
        saggriac.Config(n_steps=100, eval_schedule=(0, 50, 200))


def test_unknown_parameter_and_preset():
    with pytest.raises(ParameterError, match="'gmax' parameter is not a parameter of Config"):
        saggriac.Config.from_preset("exp1", gmax=3)
    with pytest.raises(ParameterError, match="'preset' parameter must be one of 'exp1', 'exp2', 'explauto', 'arm3d', 'pusher'. Got 'exp3'"):
        saggriac.Config.from_preset("exp3")


@pytest.mark.parametrize(
    "text, says",
    [
        ('preset = "exp2"\ng_max = 0\n', ("key 'g_max'", "Got 0 instead")),
        # Bounds are checked as a pair; the message still names the file's key.
        ("goal_low = [10, 0]\ngoal_high = [0, 50]\n", ("key 'goal_low'", "goal_high")),
    ],
)
def test_toml_file_errors_name_file_and_key(tmp_path, text, says):
    f = tmp_path / "bad.toml"
    f.write_text(text)
    with pytest.raises(ParameterError) as e:
        saggriac.Config.from_toml(f)
    assert str(f) in str(e.value) and all(s in str(e.value) for s in says), str(e.value)


def test_a_toml_file_is_read_over_its_preset(tmp_path):
    ok = tmp_path / "ok.toml"
    ok.write_text('preset = "exp2"\nzeta = 30\n')
    cfg = saggriac.Config.from_toml(ok)
    assert (cfg.zeta, cfg.q, cfg.n_steps, cfg.goal_high) == (30, 100, 200_000, (150.0, 150.0))
    with pytest.raises(ParameterError, match="does not exist"):
        saggriac.Config.from_toml(tmp_path / "missing.toml")


def test_bad_seed():
    with pytest.raises(ParameterError, match="The 'seed' parameter must be an int in"):
        saggriac.run(saggriac.Config(n_steps=10), seed=-1)


def test_existing_run_is_not_overwritten(small_config, tmp_path):
    cfg = small_config.replace(n_steps=300, n_evals=2)
    saggriac.run(cfg, seed=0, out_dir=tmp_path / "r")
    before = (tmp_path / "r" / "metrics.parquet").read_bytes()
    with pytest.raises(StorageError, match="already holds a finished run"):
        saggriac.run(cfg, seed=1, out_dir=tmp_path / "r")
    assert (tmp_path / "r" / "metrics.parquet").read_bytes() == before
    saggriac.run(cfg, seed=1, out_dir=tmp_path / "r", overwrite=True)
    assert (tmp_path / "r" / "metrics.parquet").read_bytes() != before


@pytest.mark.skipif(os.geteuid() == 0, reason="root can write anywhere")
def test_unwritable_output_fails_before_work(small_config, tmp_path):  # pragma: no cover - not as root
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o500)
    with pytest.raises(StorageError, match="not writable"):
        saggriac.run(small_config, seed=0, out_dir=ro / "run")


def test_output_under_a_file_fails_before_work(small_config, tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    with pytest.raises(StorageError, match="Cannot create the output folder"):
        saggriac.run(small_config, seed=0, out_dir=blocker / "sub" / "run")


def test_cli_run_and_errors(tmp_path, capsys):
    rc = main(["run", "--preset", "exp1", "--seed", "2", "--steps", "1500", "--set", "n_test_goals=10", "--set", "n_test_configs=10", "--out", str(tmp_path / "c"), "--no-progress"])
    out = capsys.readouterr().out
    assert rc == 0
    assert "reaching error: start" in out and "results written to" in out
    assert (tmp_path / "c" / "run.json").exists()
    rc = main(["run", "--steps", "100", "--set", "g_max=0", "--no-progress", "--out", str(tmp_path / "d")])
    err = capsys.readouterr().err
    assert rc == 2 and "The 'g_max' parameter of Config must be an int in [2, 1000000]. Got 0 instead." in err
    assert not (tmp_path / "d").exists()


def test_full_disk_after_the_work_keeps_the_result(small_config, tmp_path, monkeypatch):
    import errno

    import pandas as pd

    def no_space(self, *a, **k):
        raise OSError(errno.ENOSPC, "No space left on device")

    cfg = small_config.replace(n_steps=500)
    with monkeypatch.context() as m:
        m.setattr(pd.DataFrame, "to_parquet", no_space)
        with pytest.raises(saggriac.StorageError, match="No space left on device.*\\.result") as info:
            saggriac.run(cfg, seed=0, out_dir=tmp_path / "run")
    # Nothing half-written stands, and the work is still there to save elsewhere.
    assert sorted(p.name for p in tmp_path.iterdir()) == []
    kept = info.value.result
    assert kept.steps[-1] == 500
    kept.save(tmp_path / "elsewhere")
    loaded = saggriac.RunResult.load(tmp_path / "elsewhere")
    pd.testing.assert_frame_equal(loaded.metrics, kept.metrics)


def test_too_little_free_space_fails_before_work(small_config, tmp_path, monkeypatch):
    import shutil
    import time
    from collections import namedtuple

    usage = namedtuple("usage", "total used free")
    monkeypatch.setattr(shutil, "disk_usage", lambda p: usage(10**9, 10**9 - 10**5, 10**5))
    t0 = time.perf_counter()
    with pytest.raises(saggriac.StorageError, match="0.1 MB free"):
        saggriac.run(small_config.replace(n_steps=50_000), seed=0, out_dir=tmp_path / "run")
    assert time.perf_counter() - t0 < 2.0  # refused before the 50,000 steps, not after


def test_a_finished_result_saves_on_a_nearly_full_disk(small_config, tmp_path, monkeypatch):
    # The free-space rule guards the start of a run; a run directory (about 1 MB) that is already
    # computed must still be saved when less than that margin is left.
    import shutil
    from collections import namedtuple

    import pandas as pd

    res = saggriac.run(small_config, seed=0)
    usage = namedtuple("usage", "total used free")
    monkeypatch.setattr(shutil, "disk_usage", lambda p: usage(10**9, 10**9 - 10**7, 10**7))
    res.save(tmp_path / "kept")
    loaded = saggriac.RunResult.load(tmp_path / "kept")
    pd.testing.assert_frame_equal(loaded.metrics, res.metrics)
