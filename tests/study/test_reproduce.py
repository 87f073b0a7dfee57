"""saggriac reproduce / plot / stats on a small study."""

import pandas as pd
import pytest

from saggriac.cli import main
from saggriac.study.reproduce import reproduce

PNG = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def study_dir(tmp_path_factory):
    out = tmp_path_factory.mktemp("rep") / "exp1"
    reproduce("exp1", out_dir=out, seeds=2, steps=1200, conditions=("sagg_riac", "sagg_random", "actuator_random"), n_workers=2, progress=False)
    return out


def test_reproduce_writes_figures_and_statistics(study_dir):
    figs = study_dir / "figures"
    names = sorted(p.name for p in figs.iterdir())
    assert names == ["arm.png", "curves.png", "goals_sagg_random_seed0.png", "goals_sagg_riac_seed0.png"]
    for p in figs.iterdir():
        assert p.read_bytes()[:8] == PNG and p.stat().st_size > 10_000
    table = pd.read_csv(study_dir / "stats.csv")
    end = table[table["step"] == 1200]
    # One ANOVA over the three conditions and three paired tests, per metric (three metrics).
    assert sorted(end["test"].value_counts().items()) == [("anova", 3), ("paired_t", 9)]
    assert set(end["metric"]) == {"reach_error", "pred_error", "dx_error"}
    # (Both SAGG conditions are one run before the first split: no spread, no p-value.)
    tested = end.dropna(subset=["p_value"])
    assert len(tested) >= 9 and tested["p_value"].between(0, 1).all() and (tested["p_holm"] >= tested["p_value"]).all()
    pairs = end[end["test"] == "paired_t"]
    assert (pairs["n"] == 2).all() and (pairs["ci_low"] <= pairs["mean_diff"]).all() and (pairs["mean_diff"] <= pairs["ci_high"]).all()
    assert "| reach_error | 1200 | anova |" in (study_dir / "stats.md").read_text()
    # The time budget: goals and exploration of the SAGG runs, babbling only for ACTUATOR.
    budget = pd.read_csv(study_dir / "time_budget.csv").set_index("condition")
    assert (budget.loc[["sagg_riac", "sagg_random"], "goals"] > 0).all()
    assert budget.loc["actuator_random", "share_exploration"] == 0.0
    assert budget.loc["sagg_riac", "share_exploration"] > 0.0
    # Fig. 3's split statistic beside its null model (SAGG-Random's measurements replayed).
    splits = pd.read_csv(study_dir / "splits.csv")
    assert set(splits["tree"]) == {"sagg_riac", "sagg_random_replayed"}
    assert len(splits) == 2 * 2 * 4 and splits["reachable_share"].dropna().between(0, 1).all()


def test_plot_and_stats_rebuild_from_saved_results(study_dir, capsys):
    for p in (study_dir / "figures").iterdir():
        p.unlink()
    (study_dir / "stats.md").unlink()
    assert main(["plot", str(study_dir)]) == 0
    assert (study_dir / "figures" / "curves.png").read_bytes()[:8] == PNG
    assert (study_dir / "stats.md").exists()
    capsys.readouterr()
    assert main(["stats", str(study_dir)]) == 0
    assert "| metric | step | test |" in capsys.readouterr().out


def test_reproduce_rejects_bad_arguments(tmp_path, capsys):
    assert main(["stats", str(tmp_path)]) == 2
    assert "is not a study folder" in capsys.readouterr().err
    with pytest.raises(Exception, match=r"The 'seeds' parameter of reproduce must be an int in \[1, 100000\]. Got 0 instead."):
        reproduce("exp1", out_dir=tmp_path / "x", seeds=0)


def test_cli_reproduce_with_a_subset_of_conditions(tmp_path, capsys):
    out = tmp_path / "sub"
    rc = main(["reproduce", "exp1", "--seeds", "1", "--steps", "300", "--conditions", "sagg_random", "--workers", "1", "--out", str(out), "--no-progress"])
    assert rc == 0
    assert sorted(p.name for p in (out / "runs").iterdir()) == ["sagg_random"]
    captured = capsys.readouterr()
    assert "saggriac: warning: No statistics can be computed" in captured.err
    lines = captured.out.splitlines()
    assert any(line.split()[:2] == ["reach_error", "sagg_random"] for line in lines)


def test_numpy_integers_count_as_the_ints_they_stand_for(tmp_path):
    """A seed count or a worker count from numpy (np.arange, an array's length) was refused."""
    import numpy as np

    from saggriac.study import IncompleteStudyWarning

    with pytest.warns(IncompleteStudyWarning, match="No statistics can be computed .* all of sagg_random"):
        reproduce("exp1", out_dir=tmp_path / "st", seeds=np.int64(1), steps=np.int64(300), conditions=("sagg_random",), n_workers=np.int32(1), progress=False)
    assert len(list((tmp_path / "st" / "runs").iterdir())) == 1


def test_cli_reproduce_from_a_first_seed(tmp_path, capsys):
    # A second, independent set of seeds (the replication of docs/reproduction.md): seeds 3 and 4.
    out = tmp_path / "later"
    rc = main(["reproduce", "exp1", "--seeds", "2", "--first-seed", "3", "--steps", "300", "--conditions", "sagg_random", "--workers", "1", "--out", str(out), "--no-progress"])
    assert rc == 0
    assert sorted(p.name for p in (out / "runs" / "sagg_random").iterdir()) == ["seed3", "seed4"]
    capsys.readouterr()
    with pytest.raises(Exception, match=r"The 'first_seed' parameter of reproduce must be an int in \[0, 100000\]. Got -1 instead."):
        reproduce("exp1", out_dir=tmp_path / "x", seeds=1, first_seed=-1)
