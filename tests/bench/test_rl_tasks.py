"""The bench's deep-RL tasks (the sb3 extra): the first registered study's task, run through the
same code as its script, left out of the quick tier and out of a bench without the extra."""

import os

import pytest

from saggriac.bench import TASKS, TeacherSpec, run_bench, run_one
from saggriac.bench.runner import Job
from saggriac.bench.tasks import in_tier
from saggriac.errors import ParameterError
from tests import benchmark_scripts

RL = [n for n in TASKS if n.startswith("rl-")]


def test_deep_rl_is_not_in_the_quick_tier_and_is_refused_there(tmp_path):
    assert RL and not any(in_tier(n, "quick") for n in RL) and all(in_tier(n, "standard") and in_tier(n, "full") for n in RL)
    with pytest.raises(ParameterError, match="'rl-arm-dense' is not in the tier 'quick'"):
        run_bench(["random"], out=tmp_path / "b", tier="quick", tasks=["rl-arm-dense"], progress=False)


def test_without_the_extra_the_tasks_are_left_out_and_named(tmp_path, monkeypatch):
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "stable_baselines3" else real(name, *a))
    with pytest.raises(ParameterError, match=r"'rl-arm-sparse' needs the sb3 extra: pip install \"saggriac\[sb3\]\""):
        run_bench(["random"], out=tmp_path / "b", tier="standard", tasks=["rl-arm-sparse"], progress=False)
    from saggriac.bench.command import listing

    assert "not installed: rl-arm-dense needs the sb3 extra" in listing()


@pytest.mark.parametrize("reward", ["dense", "sparse"])
def test_the_random_teacher_gives_the_studys_own_random_run(reward, monkeypatch):
    """rl-arm-REWARD with the built-in random teacher asks the goals the study's script asks
    with its random teacher (the same seeds' derivation and code): the same distances."""
    if os.environ.get("SAGGRIAC_REQUIRE_EXTRAS") != "1":
        pytest.importorskip("stable_baselines3", reason='the SB3 extra is not installed (pip install "saggriac[sb3]")')
    name = f"rl-arm-{reward}"
    monkeypatch.setitem(TASKS[name].budgets, "standard", 1_200)
    row = run_one(Job(name, "standard", TeacherSpec("random"), 7))
    study = benchmark_scripts.load("rl_curriculum")
    rows = study.one_run((reward, "random", 7, 1_200, 120, study.THRESHOLDS[reward], "test"))
    assert [s for _, s in row["curve"]] == [-r["distance"] for r in rows[1:]]
    assert [t for t, _ in row["curve"]] == list(range(120, 1_201, 120))
