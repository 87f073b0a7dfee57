"""Expert knowledge at TeachMyAgent's levels: what every box task declares, turned into each
teacher's own parameters; the start the low level draws; the variants on the board, where high
knowledge lets ADR and SPDL learn the 2d hypercube, which they cannot from the box's centre."""

import numpy as np
import pytest

from saggriac.bench import TASKS, TeacherSpec, parse_teacher, run_bench
from saggriac.bench import expert
from saggriac.bench.runner import plan
from saggriac.bench.tasks import BenchTask
from saggriac.bench.teachers import Guarded, TeacherError
from saggriac.errors import ParameterError
from saggriac.teachers import available

from .teachers_module import write

BOX = [n for n, c in TASKS.items() if c.space == "box"]


@pytest.fixture
def module(tmp_path):
    (tmp_path / "user").mkdir()
    return write(tmp_path / "user")


def test_every_box_task_declares_an_easy_start_and_a_target_in_its_box():
    assert len(BOX) >= 15
    for name in BOX:
        cls = TASKS[name]
        assert cls.declares_knowledge(), name
        task = cls(0)
        k = task.expert_knowledge()
        assert isinstance(k, expert.Knowledge) and np.array_equal(k.low, task.low) and np.array_equal(k.high, task.high), name
        for region in (k.easy, k.target):
            assert region.low.shape == task.low.shape and np.all(region.width > 0), name
        # The easy start is a goal of the box; the target lies in the box.
        assert np.all(task.low <= k.easy.centre) and np.all(k.easy.centre <= task.high), name
        assert np.all(task.low <= k.target.low) and np.all(k.target.high <= task.high), name


def test_what_some_tasks_declare():
    def regions(name):
        k = TASKS[name](0).expert_knowledge()
        return k.easy.low.tolist(), k.easy.high.tolist(), k.target.low.tolist(), k.target.high.tolist()

    assert regions("2d") == ([0, 0], [0.1, 0.1], [0, 0], [1, 1])  # the origin's cell; every cell counts
    assert regions("2d-reach") == ([0, 0], [0.1, 0.1], [0, 0], [0.6, 0.6])  # the 21 cells i + j <= 5
    assert regions("niches-0") == ([0, 0], [0.25, 0.25], [0, 0], [0.75, 0.75])  # niche 1; the niches' 3 x 3 corner
    assert np.allclose(regions("trivial-90"), ([0.9, 0], [0.91, 0.1], [0.9, 0], [1, 1]), rtol=0, atol=1e-15)  # the strip's first cell; the strip
    # The 15-joint arm at rest is stretched along +x: its tip at (50, 0); the test goals in its reach.
    assert np.allclose(regions("arm-exp2"), ([45, -5], [55, 5], [0, -50], [50, 50]), rtol=1e-15)
    rugged = TASKS["rugged"](3)
    assert rugged.needs[rugged.easy_cells()[0]] == 5 == rugged.needs.min()  # the easiest cell of that seed


@pytest.mark.parametrize("name", BOX)
def test_each_level_gives_each_teacher_valid_parameters_that_are_what_the_task_declares(name):
    task = TASKS[name](0)
    lo, hi = task.low, task.high
    span = hi - lo
    declared = task.expert_knowledge()
    for level in expert.LEVELS:
        k = expert.knowledge(task, level, 7)
        if level == "high":
            assert all(np.array_equal(getattr(k, r).low, getattr(declared, r).low) and np.array_equal(getattr(k, r).high, getattr(declared, r).high) for r in ("easy", "target"))
        start = np.clip(k.easy.centre, lo, hi)
        first = (np.maximum(lo, k.easy.low), np.minimum(hi, k.easy.high))
        for ref in expert.BUILTIN:
            guard = Guarded(TeacherSpec(ref, (), level), task, seed=0, run_seed=7)  # built: the class took them
            teacher = guard.teacher
            if ref == "adr":  # one task, the easy centre: every goal is it until a bound moves
                assert np.allclose(teacher.bounds, (start, start)) and np.allclose(guard.ask(), start)
            elif ref == "spdl":  # the initial distribution: mean and sd of the easy region
                r = teacher.regions()
                sd = np.clip(0.25 * k.easy.width / span, 1e-4, 10) * span
                assert np.allclose(r["low"][0], start - sd) and np.allclose(r["high"][0], start + sd)
                p = expert.spdl_params(k)
                assert np.allclose(p["target_mean"], (k.target.centre - lo) / span) and np.allclose(p["target_std"], np.clip(0.25 * k.target.width / span, 1e-4, 10))
            else:  # the first goals, uniform in the easy region within the box
                goals = np.array([guard.ask() for _ in range(40)])
                assert np.all(goals >= first[0] - 1e-9 * span) and np.all(goals <= first[1] + 1e-9 * span)


def test_low_knowledge_is_a_start_drawn_from_the_runs_seed_and_the_whole_box_as_target():
    task = TASKS["2d+3"](0)
    one, again, other = (expert.knowledge(task, "low", s) for s in (1, 1, 2))
    assert np.array_equal(one.easy.centre, again.easy.centre) and not np.array_equal(one.easy.centre, other.easy.centre)
    assert np.allclose(one.easy.width, expert.LOW_WIDTH) and np.array_equal(one.target.low, task.low) and np.array_equal(one.target.high, task.high)
    starts = np.array([expert.knowledge(task, "low", s).easy.centre for s in range(4000)])
    assert starts.min() >= 0 and starts.max() <= 1 and np.allclose(starts.mean(axis=0), 0.5, atol=0.02) and np.allclose(np.median(starts, axis=0), 0.5, atol=0.03)
    # Every teacher of a run is given the same start: ADR's task is SPDL's mean.
    adr, spdl = (Guarded(TeacherSpec(r, (), "low"), task, seed=0, run_seed=1).teacher for r in ("adr", "spdl"))
    assert np.allclose(adr.bounds[0], one.easy.centre) and np.allclose(spdl.regions()["low"][0] + 0.1, one.easy.centre)


def test_the_variants_are_named_and_a_teacher_without_knowledge_has_none(module):
    spec = parse_teacher("adr@high")
    assert (spec.ref, spec.level, spec.label, spec.slug) == ("adr", "high", "adr@high", "adr@high")
    # The plain teachers keep their labels and folders: the shipped results stay theirs.
    assert all((TeacherSpec(n).label, TeacherSpec(n).slug) == (n, n) for n in available())
    assert [v.label for v in TeacherSpec("goal_gan").variants()] == ["goal_gan@low", "goal_gan@high"]
    assert TeacherSpec("adr", (("step", 0.1),), "low").label == "adr[step=0.1]@low"
    assert TeacherSpec("random").variants() == [] and TeacherSpec("adr", (), "high").variants() == []
    assert parse_teacher(f"{module}:Around@low").label == f"{module}:Around@low"
    with pytest.raises(ParameterError, match=r"The teacher random of saggriac bench takes no expert knowledge, so it has no '@high'"):
        parse_teacher("random@high")
    with pytest.raises(ParameterError, match=r"takes no expert knowledge"):
        parse_teacher(f"{module}:Uniform@high")
    with pytest.raises(ParameterError, match=r"takes an expert level after '@': low or high. Got 'medium'"):
        parse_teacher("adr@medium")


def test_variants_run_on_the_box_tasks_that_declare_knowledge(monkeypatch):
    class Silent(TASKS["2d"]):
        name = "silent"
        expert_knowledge = BenchTask.expert_knowledge

    monkeypatch.setitem(TASKS, "silent", Silent)
    jobs = plan([TeacherSpec("adr", (), "high"), TeacherSpec("adr")], ["2d", "2d-cells", "silent"], "quick", [0], 1.0)
    assert [(j.task, j.teacher.label) for j in jobs] == [("2d", "adr@high"), ("2d", "adr"), ("silent", "adr")]


def test_a_users_knowledge_that_fails_is_the_teachers_error(module):
    task = TASKS["2d"](0)
    with pytest.raises(TeacherError, match=r"on task '2d', seed 5 raised ValueError: cannot read it \(when it was given expert knowledge"):
        Guarded(parse_teacher(f"{module}:BadKnowledge@high"), task, seed=0, run_seed=5)
    with pytest.raises(TeacherError, match=r"the parameters \['start'\] are given both by --teacher-param and by the expert knowledge"):
        Guarded(parse_teacher(f"{module}:Around@high", {"start": 0.2}), task, seed=0, run_seed=5)


def test_the_board_holds_every_level_and_high_knowledge_lets_adr_and_spdl_learn_the_2d_hypercube(module, tmp_path):
    res = run_bench([f"{module}:Around"], out=tmp_path / "out", tasks=["2d"], seeds=2, workers=1, progress=False)
    board = res.board.set_index("teacher")
    mine = f"{module}:Around"
    with_level = {f"{t}@{lv}" for t in [*expert.BUILTIN, mine] for lv in expert.LEVELS}
    assert {t for t in board.index if "@" in t} == with_level and {*expert.BUILTIN, mine} <= set(board.index)
    # The built-in teachers' runs, plain and with a level, are the shipped ones (same labels);
    # the user's teacher's variants are computed.
    source = res.runs.groupby("teacher").source.first()
    builtin_levels = {f"{t}@{lv}" for t in expert.BUILTIN for lv in expert.LEVELS}
    assert all(source[t] == "shipped" for t in [*expert.BUILTIN, *builtin_levels])
    assert all(source[t] == "computed" for t in with_level - builtin_levels)
    # From the box's centre, a locked cell, ADR and SPDL learn nothing; from the origin's cell
    # (high) they follow the frontier, on every seed.
    runs = res.runs.set_index(["teacher", "seed"])
    for t in ("adr", "spdl"):
        assert board.loc[t, "area"] == 0.0 < board.loc[f"{t}@high", "area"]
        assert all(runs.loc[(f"{t}@high", s), "final"] > 0.3 for s in (0, 1))
    # A computed variant's run has its own folder, the level after the teacher's name.
    from saggriac.bench import parse_teacher

    mine_high = parse_teacher(f"{mine}@high")
    assert (tmp_path / "out" / "runs" / "quick" / mine_high.slug / "2d" / "seed0.json").is_file() and mine_high.slug.endswith("@high")
