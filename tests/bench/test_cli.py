"""``saggriac bench`` on the command line: the listing and its errors."""

from saggriac.bench import TASKS
from saggriac.cli import main
from saggriac.teachers import available


def test_list_prints_every_task_with_its_budgets_and_every_teacher(capsys):
    assert main(["bench", "--list"]) == 0
    out = capsys.readouterr().out
    for name, cls in TASKS.items():
        line = next(ln for ln in out.splitlines() if ln.split() and ln.split()[0] == name)
        assert cls.space in line and all(("-" if b is None else f"{b:,}") in line.split(cls.learner)[1] for b in cls.budgets.values())
    assert all(t in out for t in available()) and "quick tier, one box teacher, all tasks: about" in out
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
