"""Studies: many runs through a process pool or Dask, resumable, loaded as one tidy frame."""

import hashlib
import json
import os
import pickle
import shutil
import signal
import subprocess
import sys
import time

import pandas as pd
import pytest

import saggriac
from saggriac import Config, Study, load_study, run_study
from saggriac.study import IncompleteStudyWarning
from saggriac.errors import ParameterError, SaggriacError, StorageError
from saggriac.study import METRICS, StudyError, run_task

TABLES = ("metrics", "goals", "attempts", "regions")
RUNS = ["sagg_random/seed0", "sagg_random/seed1", "sagg_riac/seed0", "sagg_riac/seed1"]


@pytest.fixture(scope="session")
def tiny():
    return Config.from_preset("exp1", n_steps=1500, n_test_goals=10, n_test_configs=10, n_evals=5)


@pytest.fixture(scope="session")
def study(tiny):
    return Study(tiny, ("sagg_riac", "sagg_random"), (0, 1))


@pytest.fixture(scope="session")
def finished(study, tmp_path_factory):
    """The 2 x 2 study, computed once by the local pool; tests work on copies."""
    out = tmp_path_factory.mktemp("local") / "study"
    res = run_study(study, out, n_workers=2, progress=False)
    return out, res


def _copy(src, dst):
    shutil.copytree(src, dst)
    return dst


def _finished_runs(out):
    return sorted(str(p.parent.relative_to(out / "runs")) for p in out.glob("runs/*/seed*/run.json"))


def _fingerprints(out, runs):
    """sha256, inode and mtime of every file of the given runs: equal means untouched."""
    fp = {}
    for run in runs:
        for f in sorted((out / "runs" / run).iterdir()):
            st = f.stat()
            fp[str(f)] = (hashlib.sha256(f.read_bytes()).hexdigest(), st.st_ino, st.st_mtime_ns)
    return fp


def _leftovers(out):
    return sorted(p.name for p in out.glob("runs/*/.*"))


def _assert_same_tables(a, b):
    for name in TABLES:
        pd.testing.assert_frame_equal(pd.read_parquet(a / f"{name}.parquet"), pd.read_parquet(b / f"{name}.parquet"), check_exact=True)


def test_study_writes_one_run_directory_per_task(finished, study):
    out, res = finished
    assert (res.n_computed, res.n_skipped, res.path) == (4, 0, out.resolve())
    assert _finished_runs(out) == RUNS
    for run in RUNS:
        assert sorted(p.name for p in (out / "runs" / run).iterdir()) == sorted([*(f"{t}.parquet" for t in TABLES), "run.json"])
    spec = json.loads((out / "study.json").read_text())["study"]
    assert spec["conditions"] == ["sagg_riac", "sagg_random"] and spec["seeds"] == [0, 1] and spec["grid"] == {}
    assert Study.load(out) == study
    # Each run is the same as a run of saggriac.run in this process.
    cfg = study.base.replace(condition="sagg_random")
    here = saggriac.run(cfg, seed=1)
    pd.testing.assert_frame_equal(saggriac.RunResult.load(out / "runs/sagg_random/seed1").metrics, here.metrics, check_exact=True)


def test_local_pool_and_dask_local_cluster_give_identical_runs(finished, study, tmp_path):
    local, _ = finished
    res = run_study(study, tmp_path / "dask", backend="dask", n_workers=2, progress=False)
    assert (res.n_computed, res.n_skipped) == (4, 0)
    assert _finished_runs(tmp_path / "dask") == RUNS
    for run in RUNS:
        _assert_same_tables(local / "runs" / run, tmp_path / "dask" / "runs" / run)


def test_dask_on_a_given_scheduler_address_client_or_cluster(tiny, tmp_path):
    from dask.distributed import Client

    from saggriac.study import local_cluster

    st = Study(tiny.replace(n_steps=600, n_evals=2), "sagg_riac", (4,), grid={"g_max": [20, 40]})
    with local_cluster(1) as cluster:
        a = run_study(st, tmp_path / "a", backend="dask", scheduler=cluster.scheduler_address, progress=False)
        b = run_study(st, tmp_path / "b", backend="dask", scheduler=cluster, progress=False)
        with Client(cluster, set_as_default=False) as client:
            c = run_study(st, tmp_path / "c", backend="dask", scheduler=client, progress=False)
            assert client.submit(sum, [1, 2]).result() == 3  # the caller's client is left open
    assert a.n_computed == b.n_computed == c.n_computed == 2
    for run in ("sagg_riac__g_max=20/seed4", "sagg_riac__g_max=40/seed4"):
        _assert_same_tables(tmp_path / "a/runs" / run, tmp_path / "b/runs" / run)
        _assert_same_tables(tmp_path / "a/runs" / run, tmp_path / "c/runs" / run)


def test_resume_computes_only_the_missing_run_and_touches_nothing_else(finished, study, tmp_path):
    out = _copy(finished[0], tmp_path / "study")
    shutil.rmtree(out / "runs/sagg_random/seed1")
    kept = [r for r in RUNS if r != "sagg_random/seed1"]
    before = _fingerprints(out, kept)
    spec_before = (out / "study.json").read_bytes()
    res = run_study(study, out, n_workers=2, progress=False)
    assert (res.n_computed, res.n_skipped) == (1, 3)
    assert _fingerprints(out, kept) == before
    assert (out / "study.json").read_bytes() == spec_before
    _assert_same_tables(out / "runs/sagg_random/seed1", finished[0] / "runs/sagg_random/seed1")
    # A finished study starts no worker and changes nothing.
    before = _fingerprints(out, RUNS)
    res = run_study(study, out, backend="dask", progress=False)
    assert (res.n_computed, res.n_skipped) == (0, 4)
    assert _fingerprints(out, RUNS) == before


def test_run_killed_while_writing_is_redone_and_never_read(finished, study, tmp_path):
    out = _copy(finished[0], tmp_path / "study")
    full = load_study(out)
    # What a process killed inside storage.write_run leaves: a temporary sibling, no final directory.
    shutil.rmtree(out / "runs/sagg_riac/seed0")
    partial = out / "runs/sagg_riac/.seed0.k1ll3d_.tmp"
    partial.mkdir()
    data = (finished[0] / "runs/sagg_riac/seed0/metrics.parquet").read_bytes()
    (partial / "metrics.parquet").write_bytes(data[: len(data) // 2])
    # A final directory without run.json (not finished) is not read either.
    stale = out / "runs/sagg_random/seed1"
    (stale / "run.json").unlink()
    (stale / "metrics.parquet").write_bytes(data[: len(data) // 3])
    with pytest.warns(IncompleteStudyWarning, match=r"2 of 4 runs .* left out: runs/sagg_riac/seed0 \(not finished: no run.json\); runs/sagg_random/seed1"):
        frame = load_study(out)
    assert len(frame) == 2 * len(METRICS) * 6
    assert set(zip(frame["condition"], frame["seed"])) == {("sagg_riac", 1), ("sagg_random", 0)}
    kept = ["sagg_random/seed0", "sagg_riac/seed1"]
    before = _fingerprints(out, kept)
    res = run_study(study, out, n_workers=2, progress=False)
    assert (res.n_computed, res.n_skipped) == (2, 2)
    # The killed write's temporary folder is gone; the final folder without run.json is kept
    # aside (saggriac never deletes what it cannot vouch for) and the run is redone.
    (aside,) = _leftovers(out)
    assert aside.startswith(".seed1.damaged-") and list(res.repaired) == ["sagg_random/seed1"]
    assert (out / "runs/sagg_random" / aside / "metrics.parquet").read_bytes() == data[: len(data) // 3]
    assert _fingerprints(out, kept) == before
    assert _finished_runs(out) == RUNS
    order = ["condition", "seed", "metric", "step"]
    pd.testing.assert_frame_equal(
        res.frame().sort_values(order, ignore_index=True), full.sort_values(order, ignore_index=True), check_exact=True
    )


def test_load_study_is_tidy_over_the_grid(tiny, tmp_path):
    st = Study(tiny, "sagg_riac", (3,), grid={"n_subgoals": [3, 5], "g_max": [20, 40]})
    res = run_study(st, tmp_path / "grid", n_workers=1, progress=True)
    assert res.n_computed == 4
    assert sorted(p.name for p in (tmp_path / "grid/runs").iterdir()) == [
        "sagg_riac__g_max=20__n_subgoals=3",
        "sagg_riac__g_max=20__n_subgoals=5",
        "sagg_riac__g_max=40__n_subgoals=3",
        "sagg_riac__g_max=40__n_subgoals=5",
    ]
    frame = load_study(tmp_path / "grid")
    assert list(frame.columns) == ["condition", "seed", "g_max", "n_subgoals", "step", "metric", "value"]
    assert len(frame) == 4 * len(METRICS) * 6  # runs x metrics x evaluation points
    assert set(frame["metric"]) == {"reach_error", "pred_error", "dx_error", "n_goals", "n_regions"}
    assert set(zip(frame["g_max"], frame["n_subgoals"])) == {(20, 3), (20, 5), (40, 3), (40, 5)}
    one = frame[(frame.g_max == 40) & (frame.n_subgoals == 3) & (frame.metric == "reach_error")]
    m = saggriac.RunResult.load(tmp_path / "grid/runs/sagg_riac__g_max=40__n_subgoals=3/seed3").metrics
    assert one["step"].tolist() == m["step"].tolist() and one["value"].tolist() == m["reach_error"].tolist()
    assert frame["value"].dtype == "float64" and frame["seed"].dtype == "int64"


def test_a_different_study_in_the_same_folder_is_refused(finished, study, tiny, tmp_path):
    out = _copy(finished[0], tmp_path / "study")
    spec = (out / "study.json").read_bytes()
    with pytest.raises(StorageError, match=r"holds a different study \(seeds \[0, 1\] -> \[0, 1, 2\]\)"):
        run_study(Study(tiny, ("sagg_riac", "sagg_random"), (0, 1, 2)), out, progress=False)
    with pytest.raises(StorageError, match="base.n_steps 1500 -> 2000"):
        run_study(Study(tiny.replace(n_steps=2000), ("sagg_riac", "sagg_random"), (0, 1)), out, progress=False)
    assert (out / "study.json").read_bytes() == spec
    assert _finished_runs(out) == RUNS and _leftovers(out) == []
    # The same runs listed in another order are the same study.
    res = run_study(Study(tiny, ("sagg_random", "sagg_riac"), (1, 0)), out, progress=False)
    assert (res.n_computed, res.n_skipped) == (0, 4)
    # Run directories without a study.json were not made by run_study.
    (tmp_path / "other/runs").mkdir(parents=True)
    with pytest.raises(StorageError, match="no study.json"):
        run_study(study, tmp_path / "other", progress=False)
    (out / "study.json").write_text("{not json")
    with pytest.raises(StorageError, match="Cannot read"):
        run_study(study, out, progress=False)
    with pytest.raises(StorageError, match="not a study folder"):
        load_study(tmp_path / "nowhere")


@pytest.mark.skipif(sys.platform == "win32", reason="no flock")
def test_one_run_study_at_a_time_per_folder(finished, study, tmp_path):
    import fcntl

    out = _copy(finished[0], tmp_path / "study")
    with open(out / ".lock", "w") as held:
        fcntl.flock(held, fcntl.LOCK_EX | fcntl.LOCK_NB)
        with pytest.raises(StorageError, match="Another run_study is writing to"):
            run_study(study, out, progress=False)
    assert run_study(study, out, progress=False).n_skipped == 4


def test_failed_runs_are_reported_after_the_others_finish(finished, study, tmp_path):
    out = tmp_path / "study"
    (out / "runs").mkdir(parents=True)
    shutil.copy(finished[0] / "study.json", out / "study.json")
    (out / "runs/sagg_random").write_text("a file where a folder should be")
    with pytest.warns(IncompleteStudyWarning, match="4 of 4 runs"):
        empty = load_study(out)
    assert empty.empty and list(empty.columns) == ["condition", "seed", "step", "metric", "value"]
    with pytest.raises(StudyError) as e:
        run_study(study, out, n_workers=2, progress=False)
    msg = str(e.value)
    assert msg.startswith("2 of 4 runs failed; the others are saved in")
    assert "sagg_random/seed0: StorageError: Cannot create the output folder" in msg and "sagg_random/seed1" in msg
    assert set(e.value.failures) == {"sagg_random/seed0", "sagg_random/seed1"} and isinstance(e.value, SaggriacError)
    assert _finished_runs(out) == ["sagg_riac/seed0", "sagg_riac/seed1"]
    (out / "runs/sagg_random").unlink()
    res = run_study(study, out, n_workers=2, progress=False)
    assert (res.n_computed, res.n_skipped) == (2, 2)


def test_missing_dask_names_the_extra(study, tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)  # makes `import distributed` fail
    with pytest.raises(ImportError, match=r'pip install "saggriac\[dask\]"'):
        run_study(study, tmp_path / "out", backend="dask", progress=False)
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"conditions": ()}, "The 'conditions' parameter of Study must not be empty."),
        ({"conditions": ("best",)}, "The 'condition' parameter of Config must be one of"),
        ({"seeds": (0, 0)}, "The 'seeds' parameter of Study must not repeat a value. Got (0, 0) instead."),
        ({"seeds": (-1,)}, "The 'seed' parameter must be an int in"),
        ({"grid": {"gmax": [3]}}, "The 'gmax' parameter is not a parameter of Config."),
        ({"grid": {"condition": ["sagg_riac"]}}, "cannot hold 'condition'"),
        ({"grid": {"g_max": []}}, "The values of grid key 'g_max' must not be empty."),
        ({"grid": {"g_max": 40}}, "The values of grid key 'g_max' must be a list. Got 40 instead."),
        ({"grid": {"g_max": [1]}}, "The 'g_max' parameter of Config must be an int in [2, 1000000]. Got 1 instead."),
        ({"grid": {"knn_index": ["../x"]}}, "they name directories"),
    ],
)
def test_bad_study_messages(tiny, kwargs, message):
    args = {"base": tiny, "conditions": ("sagg_riac",), "seeds": (0,), **kwargs}
    with pytest.raises(ParameterError) as e:
        Study(**args)
    assert message in str(e.value)


def test_bad_run_study_arguments(study, tmp_path):
    with pytest.raises(ParameterError, match="'backend' parameter of run_study must be one of 'local', 'dask'"):
        run_study(study, tmp_path, backend="spark")
    with pytest.raises(ParameterError, match="'n_workers' parameter of run_study must be an int >= 1"):
        run_study(study, tmp_path, n_workers=0)
    with pytest.raises(ParameterError, match="needs backend='dask'"):
        run_study(study, tmp_path, scheduler="tcp://127.0.0.1:8786")
    with pytest.raises(ParameterError, match="'study' parameter of run_study must be a saggriac.Study"):
        run_study(study.base, tmp_path)
    assert list(tmp_path.iterdir()) == []


def test_tasks_are_small_picklable_and_idempotent(finished, study):
    tasks = study.tasks()
    assert [t.name for t in tasks] == ["sagg_riac/seed0", "sagg_random/seed0", "sagg_riac/seed1", "sagg_random/seed1"]
    assert tasks[1].path == "runs/sagg_random/seed0" and tasks[1].config["condition"] == "sagg_random"
    assert pickle.loads(pickle.dumps(tasks[1])) == tasks[1]
    out = finished[0]
    before = _fingerprints(out, ["sagg_random/seed0"])
    assert run_task(tasks[1], out) == str(out / "runs/sagg_random/seed0")
    assert _fingerprints(out, ["sagg_random/seed0"]) == before


@pytest.mark.slow
def test_study_killed_with_sigkill_resumes(tmp_path):
    import psutil  # a dependency of dask distributed

    out = tmp_path / "study"
    code = (
        "import sys, saggriac\n"
        "cfg = saggriac.Config.from_preset('exp1', n_steps=6000, n_test_goals=30, n_test_configs=30, n_evals=10)\n"
        "st = saggriac.Study(cfg, ('sagg_riac', 'sagg_random'), (0, 1, 2))\n"
        "saggriac.run_study(st, sys.argv[1], n_workers=2, progress=False)\n"
    )
    proc = subprocess.Popen([sys.executable, "-c", code, str(out)])
    try:
        deadline = time.monotonic() + 120
        while not _finished_runs(out):
            assert proc.poll() is None, "the study ended before it could be killed"
            assert time.monotonic() < deadline, "no run finished in time"
            time.sleep(0.002)
        workers = psutil.Process(proc.pid).children(recursive=True)
        proc.send_signal(signal.SIGKILL)
        proc.wait(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    # The pool's workers die with the study process, so no orphan keeps writing runs.
    gone, alive = psutil.wait_procs(workers, timeout=20)
    assert alive == []
    done = _finished_runs(out)
    assert 1 <= len(done) < 6
    before = _fingerprints(out, done)
    st = Study(Config.from_preset("exp1", n_steps=6000, n_test_goals=30, n_test_configs=30, n_evals=10), ("sagg_riac", "sagg_random"), (0, 1, 2))
    res = run_study(st, out, n_workers=2, progress=False)
    assert (res.n_computed, res.n_skipped) == (6 - len(done), len(done))
    assert _fingerprints(out, done) == before
    assert _leftovers(out) == [] and len(_finished_runs(out)) == 6
    assert len(res.frame()) == 6 * len(METRICS) * 11
    assert json.loads((out / "study.json").read_text())["study"]["seeds"] == [0, 1, 2]


def test_work_goes_seed_by_seed_costliest_condition_first(tiny):
    from saggriac.study import longest_first_by_seed

    s = Study(tiny, ("sagg_riac", "actuator_random", "sagg_random", "actuator_riac"), (3, 1))
    order = [(t.seed, t.condition) for t in longest_first_by_seed(s.tasks())]
    assert order == [(3, "actuator_riac"), (3, "actuator_random"), (3, "sagg_riac"), (3, "sagg_random"), (1, "actuator_riac"), (1, "actuator_random"), (1, "sagg_riac"), (1, "sagg_random")]
    # Longer runs of the same condition go first too.
    s = Study(tiny, ("sagg_riac",), (0,), grid={"n_steps": [1000, 3000]})
    assert [t.params["n_steps"] for t in longest_first_by_seed(s.tasks())] == [3000, 1000]


def test_a_lock_left_beside_a_finished_run_is_cleaned_on_resume_but_a_live_one_is_kept(tmp_path):
    import fcntl

    cfg = Config.from_preset("exp1", n_steps=300, n_test_goals=5, n_test_configs=5, n_evals=1)
    st = Study(cfg, ("sagg_random",), (0, 1))
    out = tmp_path / "study"
    run_study(st, out, n_workers=1, progress=False)
    # A process killed between writing run.json and removing its lock leaves this behind.
    stale = out / "runs" / "sagg_random" / ".seed0.lock"
    stale.touch()
    live = out / "runs" / "sagg_random" / ".seed1.lock"
    fd = os.open(live, os.O_RDWR | os.O_CREAT)
    fcntl.flock(fd, fcntl.LOCK_EX)
    try:
        res = run_study(st, out, n_workers=1, progress=False)
        assert (res.n_computed, res.n_skipped) == (0, 2)
        assert not stale.exists() and live.exists()
    finally:
        os.close(fd)


def test_the_local_dask_cluster_serves_no_http(tmp_path):
    """No HTTP server is left listening (so no fixed port is needed, and a busy 8787 changes
    nothing), and no warning is raised (pytest turns warnings into errors)."""
    import socket

    from saggriac.study import local_cluster

    pytest.importorskip("distributed")
    with local_cluster(1) as cluster:
        server = cluster.scheduler.http_server
        port = server.port
        assert port != 8787
        with socket.socket() as s:
            s.settimeout(2)
            assert s.connect_ex(("127.0.0.1", port)) != 0, "the scheduler's HTTP server still listens"
        assert "dashboard" not in cluster.scheduler_info.get("services", {}) or cluster.scheduler_info["services"].get("dashboard") == port


def _slurm_cluster():
    dask_jobqueue = pytest.importorskip("dask_jobqueue", reason='dask-jobqueue is not installed (pip install "saggriac[slurm]")')
    return dask_jobqueue.SLURMCluster(cores=1, memory="1GB", processes=1, scheduler_options={"dashboard_address": None, "host": "127.0.0.1"})


def test_a_slurm_cluster_without_sbatch_is_refused_before_anything_is_written(tiny, tmp_path, monkeypatch):
    """Before: Dask printed its own asynchronous FileNotFoundError and run_study waited forever."""
    monkeypatch.setenv("PATH", str(tmp_path / "empty-bin"))
    st = Study(tiny.replace(n_steps=600, n_evals=2), "sagg_riac", (4,))
    with _slurm_cluster() as cluster:
        t0 = time.monotonic()
        with pytest.raises(ParameterError, match=r"SLURMCluster whose jobs are submitted with 'sbatch', which is not on this machine's PATH"):
            run_study(st, tmp_path / "out", backend="dask", scheduler=cluster, progress=False)
        assert time.monotonic() - t0 < 10
    assert not (tmp_path / "out").exists()


def test_a_cluster_whose_workers_never_join_fails_at_the_deadline(tiny, tmp_path, monkeypatch):
    """A queue that takes the job and never starts it (an sbatch that only prints a job id)."""
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    for name, body in (("sbatch", "echo 'Submitted batch job 4242'"), ("scancel", "exit 0")):
        (bin_dir / name).write_text(f"#!/bin/sh\n{body}\n")
        (bin_dir / name).chmod(0o755)
    monkeypatch.setenv("PATH", f"{bin_dir}{os.pathsep}{os.environ['PATH']}")
    st = Study(tiny.replace(n_steps=600, n_evals=2), "sagg_riac", (4,))
    with _slurm_cluster() as cluster:
        cluster.scale(jobs=1)
        t0 = time.monotonic()
        with pytest.raises(ParameterError, match=r"SLURMCluster, where no Dask worker joined within 3 s: check that the cluster was given workers"):
            run_study(st, tmp_path / "out", backend="dask", scheduler=cluster, progress=False, worker_timeout=3)
        assert time.monotonic() - t0 < 30
    assert not list((tmp_path / "out").glob("runs/**/run.json"))  # nothing was run


@pytest.mark.parametrize("bad", [0, -1.0, float("inf"), float("nan"), "60", True])
def test_worker_timeout_is_checked(study, tmp_path, bad):
    with pytest.raises(ParameterError, match="'worker_timeout' parameter of run_study must be a number of seconds > 0"):
        run_study(study, tmp_path / "out", worker_timeout=bad, progress=False)
