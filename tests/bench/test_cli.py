"""``saggriac bench`` on the command line: the listing and its errors."""

import pytest

from saggriac.bench import TASKS
from saggriac.cli import main
from saggriac.teachers import available


def test_list_prints_every_task_with_its_budgets_and_every_teacher(capsys):
    assert main(["bench", "--list"]) == 0
    out = capsys.readouterr().out
    for name, cls in TASKS.items():
        line = next(ln for ln in out.splitlines() if ln.split() and ln.split()[0] == name)
        assert cls.space in line and all(("-" if b is None else f"{b:,}") in line.split(cls.learner)[1] for b in cls.budgets.values())
    assert all(t in out for t in available())
    # Each tier's CPU hours, for one box teacher and every built-in one, from the shipped runs'
    # seconds (measured in quick, scaled by the budget in the others).
    from saggriac.bench.command import run_seconds, tier_hours

    seconds = run_seconds()
    quick_one = sum(s for n, (s, measured) in seconds["quick"].items() if TASKS[n].space == "box") * 5 / 3600
    assert all(measured for _, measured in seconds["quick"].values()) and tier_hours(seconds["quick"], "quick")[0] == pytest.approx(quick_one, rel=1e-12)
    # In the full tier a study's task counts its study's seeds (the SAC arm 24, not 20).
    from saggriac.bench.tasks import tier_seeds

    full_one = sum(s * len(tier_seeds(n, "full")) for n, (s, _) in seconds["full"].items() if TASKS[n].space == "box" and s == s) / 3600
    assert tier_hours(seconds["full"], "full")[0] == pytest.approx(full_one, rel=1e-12) and len(tier_seeds("rl-arm-sac-dense", "full")) == 24
    for tier in ("quick", "standard", "full"):
        one, every = tier_hours(seconds[tier], tier)
        assert f"  {tier} (" in out and f"one box teacher about {one:.2g} CPU h, every built-in teacher about {every:.2g} CPU h" in out and every > one > 0
    # A deep-RL task where no run ships (the standard tier's) is estimated from its study's
    # measured cost per step; in the full tier its study's runs ship and their seconds count.
    s, measured = seconds["standard"]["rl-arm-dense"]
    assert not measured and s == TASKS["rl-arm-dense"].budgets["standard"] * TASKS["rl-arm-dense"].cpu_per_unit
    from saggriac.bench import shipped

    full = shipped.load("full")[0]
    assert seconds["full"]["rl-arm-dense"] == (pytest.approx(full[full.task == "rl-arm-dense"].seconds.mean()), True)
    # The teachers given expert knowledge, at TeachMyAgent's levels.
    assert "with expert knowledge (box tasks, TeachMyAgent's levels; docs/bench.md): adr@low, adr@high, spdl@low, spdl@high, goal_gan@low, goal_gan@high" in out


def test_a_wrong_teacher_or_parameter_is_named(capsys, tmp_path):
    assert main(["bench", "--teacher", "nope", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert "The '--teacher' parameter of saggriac bench must be a built-in teacher's name" in err and "Got 'nope' instead." in err
    assert main(["bench", "--teacher", "random", "--teacher-param", "3=4", "--out", str(tmp_path)]) == 2
    assert "The '--teacher-param' parameter of saggriac bench must be KEY=VALUE with KEY a Python name. Got '3=4' instead." in capsys.readouterr().err
    assert main(["bench", "--teacher-param", "a=1", "--out", str(tmp_path)]) == 2
    assert "give --teacher too" in capsys.readouterr().err
    assert main(["bench", "--write-shipped", "--out", str(tmp_path)]) == 2
    assert "needs --rerun" in capsys.readouterr().err
