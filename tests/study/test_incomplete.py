"""Partial and missing runs in a study (issue 33, items 4 and 6): a result saved from a learner
stopped early says so, a study never counts it as finished, and load_study, plot and stats name
what they leave out instead of mixing it in or writing an empty table with exit status 0."""

import json
import shutil

import pytest

import saggriac as sg
from saggriac.cli import main
from saggriac.files import seal
from saggriac.study import IncompleteStudyWarning


def _cfg(**kw):
    return sg.Config.from_preset("exp1", **{"n_steps": 1500, "n_evals": 3, "n_test_goals": 5, "n_test_configs": 5, **kw})


def _partial(seed=0, **kw):
    learner = sg.Learner(_cfg(**kw), seed, threads=1)
    learner.run(until=500)
    return learner


@pytest.fixture(scope="module")
def study_dir(tmp_path_factory):
    out = tmp_path_factory.mktemp("incomplete") / "st"
    sg.run_study(sg.Study(base=_cfg(), conditions=("sagg_riac", "sagg_random"), seeds=(0, 1)), out, n_workers=1, progress=False)
    return out


def test_a_partial_result_says_how_far_it_got(tmp_path):
    learner = _partial()
    res = learner.result()
    assert not res.finished and res.steps_done == learner.steps < 1500
    assert f"partial: stopped at step {learner.steps} of 1500" in repr(res)
    loaded = sg.RunResult.load(res.save(tmp_path / "p"))
    assert loaded.manifest["steps"] == {"done": learner.steps, "of": 1500, "finished": False}
    assert not loaded.finished and loaded.steps_done == learner.steps
    learner.run()
    done = learner.result()
    assert done.finished and done.steps_done == 1500 and "partial" not in repr(done)
    assert sg.run(_cfg(), 0).manifest["steps"] == {"done": 1500, "of": 1500, "finished": True}


def test_a_partial_result_of_saggriac_0_5_is_told_by_its_curve(tmp_path):
    """run.json of 0.5.0 had no "steps": its last evaluation before the schedule's last tells."""
    path = _partial().result().save(tmp_path / "p")
    manifest = json.loads((path / "run.json").read_text())
    del manifest["steps"], manifest["checksum"]
    (path / "run.json").write_text(json.dumps(seal(manifest)))
    old = sg.RunResult.load(path)
    assert not old.finished and old.steps_done is None


def _copy(study_dir, tmp_path):
    out = tmp_path / "st"
    shutil.copytree(study_dir, out)
    return out


def test_a_study_never_counts_a_partial_member_as_finished(study_dir, tmp_path):
    out = _copy(study_dir, tmp_path)
    member = out / "runs/sagg_riac/seed1"
    shutil.rmtree(member)
    _partial(seed=1).result().save(member)
    with pytest.warns(IncompleteStudyWarning, match=r"1 of 4 runs .* runs/sagg_riac/seed1 \(it stopped at step \d+ of 1500"):
        frame = sg.load_study(out)
    assert set(zip(frame["condition"], frame["seed"])) == {("sagg_riac", 0), ("sagg_random", 0), ("sagg_random", 1)}
    res = sg.run_study(sg.Study.load(out), out, n_workers=1, progress=False)
    assert (res.n_computed, res.n_skipped) == (1, 3)
    assert "it stopped at step" in res.repaired["sagg_riac/seed1"]
    assert sg.RunResult.load(member).finished
    full = sg.load_study(out)
    assert full["step"].max() == 1500 and len(full) == len(sg.load_study(study_dir))


def test_plot_names_a_missing_run_and_exits_non_zero(study_dir, tmp_path, capsys):
    out = _copy(study_dir, tmp_path)
    shutil.rmtree(out / "runs/sagg_random/seed0")
    assert main(["plot", str(out)]) == 1
    err = capsys.readouterr().err
    assert "runs/sagg_random/seed0 (not finished: no run.json)" in err
    # One seed of sagg_random left: no paired test can be made, and stats.md is not written.
    assert "No statistics can be computed" in err and "sagg_random 1" in err
    assert not (out / "stats.md").exists() and (out / "figures" / "curves.png").is_file()
    assert main(["stats", str(out)]) == 2
    assert "No statistics can be computed" in capsys.readouterr().err


def test_stats_of_one_condition_is_refused(tmp_path, capsys):
    out = tmp_path / "one"
    sg.run_study(sg.Study(base=_cfg(n_steps=300), conditions=("sagg_random",), seeds=(0, 1)), out, n_workers=1, progress=False)
    assert main(["stats", str(out)]) == 2
    err = capsys.readouterr().err
    assert "No statistics can be computed" in err and "all of sagg_random" in err
    assert main(["stats", str(out / "study.json")]) == 2
    assert f"give the study folder ({out})" in capsys.readouterr().err


def test_a_complete_study_plots_with_exit_status_0(study_dir, tmp_path, capsys):
    out = _copy(study_dir, tmp_path)
    assert main(["plot", str(out)]) == 0
    assert "warning" not in capsys.readouterr().err
    assert (out / "stats.md").read_text().count("\n") > 2
