"""Messages of studies told in the user's terms (issue 44, item 10): saggriac stats names the
partial run it leaves out, Ctrl-C of reproduce speaks of runs, and the advice to wait longer
for workers names the command's flag."""

import shutil

import pytest

import saggriac as sg
import saggriac.study.reproduce as rep
from saggriac.cli import main


def _cfg(**kw):
    return sg.Config.from_preset("exp1", **{"n_steps": 1500, "n_evals": 3, "n_test_goals": 5, "n_test_configs": 5, **kw})


def test_stats_names_the_partial_run_it_leaves_out(tmp_path, capsys):
    out = tmp_path / "st"
    sg.run_study(sg.Study(base=_cfg(), conditions=("sagg_riac", "sagg_random"), seeds=(0, 1)), out, n_workers=1, progress=False)
    member = out / "runs/sagg_riac/seed1"
    shutil.rmtree(member)
    learner = sg.Learner(_cfg(), 1, threads=1)
    learner.run(until=500)
    learner.result().save(member)
    assert main(["stats", str(out)]) == 2
    err = capsys.readouterr().err
    assert "No statistics can be computed" in err and "sagg_riac 1" in err
    assert f"left out: runs/sagg_riac/seed1 (it stopped at step {learner.steps} of 1500" in err
    # A finished run is not named.
    assert "seed0" not in err


def test_ctrl_c_of_reproduce_speaks_of_runs(monkeypatch, capsys):
    def interrupted(*a, **kw):
        raise KeyboardInterrupt

    monkeypatch.setattr(rep, "reproduce", interrupted)
    assert main(["reproduce", "exp1", "--seeds", "2", "--no-progress"]) == 130
    err = capsys.readouterr().err
    assert "nothing was written for the unfinished runs; the finished ones are kept, and the same command resumes the study." in err


def test_the_advice_on_worker_timeout_names_the_flag(tmp_path, capsys):
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=0, processes=False, protocol="tcp", host="127.0.0.1", dashboard_address=None) as cluster:
        rc = main(["reproduce", "exp1", "--seeds", "2", "--steps", "300", "--backend", "dask", "--scheduler", cluster.scheduler_address, "--worker-timeout", "0.5", "--out", str(tmp_path / "st"), "--no-progress"])
    err = capsys.readouterr().err
    assert rc == 2 and "where no Dask worker joined within 0.5 s" in err
    assert "--worker-timeout gives the workers more time" in err and "worker_timeout=" not in err
