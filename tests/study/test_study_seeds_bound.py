"""A study's seeds are bounded as reproduce's are (issue 44, item 10): a million seeds are refused
at once, naming the rule, and the largest study allowed is built in seconds (each condition's
configuration is built and checked once, not once per seed). A study.json this version
cannot read names the version that wrote it."""

import itertools
import time

import pytest

import saggriac as sg
from saggriac.errors import ParameterError, StorageError
from saggriac.study import reproduce
from saggriac.study.spec import MAX_SEEDS


def _cfg():
    return sg.Config.from_preset("exp1", n_steps=3000)


def test_reproduce_and_study_share_one_bound():
    assert reproduce.MAX_SEEDS is MAX_SEEDS == 100_000


@pytest.mark.parametrize("seeds, got", [(range(10**6), "1000000 seeds"), (range(10**20), "more than 100000 seeds"), (itertools.count(), "more than 100000 seeds")])
def test_too_many_seeds_are_refused_at_once(seeds, got):
    t0 = time.perf_counter()
    with pytest.raises(ParameterError) as e:
        sg.Study(_cfg(), conditions=["sagg_riac", "sagg_random"], seeds=seeds)
    assert time.perf_counter() - t0 < 5
    assert str(e.value) == (
        "The 'seeds' parameter of Study must be a list of at most 100000 seeds (a study of more is a cluster's job: "
        f"the seed list and per-run bookkeeping are held in memory). Got {got} instead."
    )
    assert e.value.param == "seeds"


def test_seeds_that_are_not_a_list_are_named():
    with pytest.raises(ParameterError, match=r"'seeds' parameter of Study must be an int or a list of ints\. Got 1\.5 instead"):
        sg.Study(_cfg(), conditions=["sagg_riac"], seeds=1.5)


def test_the_most_seeds_allowed_build_fast_and_in_order():
    t0 = time.process_time()
    study = sg.Study(_cfg(), conditions=["sagg_riac", "sagg_random"], seeds=range(MAX_SEEDS))
    tasks = study.tasks()
    # About 1 s on the 2-core CI machine (before: a Config per run, about 0.25 ms each, 50 s).
    assert time.process_time() - t0 < 15
    assert len(tasks) == 2 * MAX_SEEDS
    assert [t.name for t in tasks[:3]] == ["sagg_riac/seed0", "sagg_random/seed0", "sagg_riac/seed1"]
    last = tasks[-1]
    assert (last.seed, last.condition, last.path) == (MAX_SEEDS - 1, "sagg_random", f"runs/sagg_random/seed{MAX_SEEDS - 1}")
    assert last.config == _cfg().replace(condition="sagg_random").to_dict()
    # Each task owns its dicts: changing one run's leaves the others' alone.
    tasks[0].config["n_steps"] = 1
    assert tasks[2].config["n_steps"] == 3000


def test_a_grid_gives_every_point_its_own_configuration():
    study = sg.Study(_cfg(), conditions=["sagg_riac"], seeds=[0, 1], grid={"g_max": [40, 80]})
    tasks = study.tasks()
    assert [t.name for t in tasks] == ["sagg_riac__g_max=40/seed0", "sagg_riac__g_max=80/seed0", "sagg_riac__g_max=40/seed1", "sagg_riac__g_max=80/seed1"]
    assert [t.config["g_max"] for t in tasks] == [40, 80, 40, 80]
    assert [t.params for t in tasks] == [{"g_max": 40}, {"g_max": 80}, {"g_max": 40}, {"g_max": 80}]


def test_a_study_json_this_version_cannot_read_names_its_writer(tmp_path):
    (tmp_path / "study.json").write_text('{"format": 1, "study": {"conditions": ["sagg_riac"]}, "created_with": {"saggriac": "0.9.0", "git_commit": "x"}}')
    with pytest.raises(StorageError) as e:
        sg.Study.load(tmp_path)
    assert f"does not describe a study this version of saggriac ({sg.__version__}) can read (it was written by saggriac 0.9.0): " in str(e.value)
