"""The built-in teachers' results that ship with the package: they say which saggriac and which
seeds made them, and a rerun on the same version gives the same numbers."""

import pandas as pd
import pytest

from saggriac import _core
from saggriac.bench import TASKS, TIERS, TeacherSpec, run_one, shipped
from saggriac.bench.runner import Job
from saggriac.bench.suite import compare_with_shipped
from saggriac.teachers import available

SHIP = shipped.load("quick")


def test_the_quick_results_ship_with_version_seeds_and_command():
    assert SHIP is not None, "python/saggriac/bench/results/quick_* are missing"
    runs, curves, meta = SHIP
    assert meta["seeds"] == list(range(TIERS["quick"])) and meta["tier"] == "quick" and meta["command"].startswith("saggriac bench --tier quick --rerun")
    assert set(meta["teachers"]) == set(runs.teacher) and set(runs.seed) == set(meta["seeds"])
    assert len(curves) >= len(runs) and {"task", "teacher", "seed", "step", "score"} <= set(curves.columns)


@pytest.mark.skipif(SHIP is None or SHIP[2]["version"] != _core.__version__, reason="the shipped results were made by another version")
@pytest.mark.parametrize("task", ["2d-reach", "niches-cells"])
def test_the_shipped_results_equal_a_rerun_on_this_version(task):
    runs = SHIP[0]
    seed = 1
    names = [n for n in available() if TeacherSpec(n).takes(TASKS[task].space) and n in set(runs.teacher)]
    assert len(names) >= 3
    for name in names:
        row = run_one(Job(task, "quick", TeacherSpec(name), seed))["row"]
        ship = runs[(runs.task == task) & (runs.teacher == name) & (runs.seed == seed)].iloc[0]
        assert (row["area"], row["final"]) == (ship.area, ship.final), name


STANDARD = shipped.load("standard")


def test_the_standard_results_ship_for_the_tasks_without_deep_rl():
    """The standard tier ships the tasks without deep RL (its deep-RL runs are hours of CPU a
    teacher): every such task, every seed of the tier, the built-in teachers that take it, and
    the command that made them naming those tasks. Its other rows are deep-RL studies' runs."""
    assert STANDARD is not None, "python/saggriac/bench/results/standard_* are missing"
    runs, curves, meta = STANDARD
    plain = sorted(n for n, c in TASKS.items() if c.budgets["standard"] is not None and not n.startswith("rl-"))
    assert sorted(set(runs.task)) == sorted(meta["tasks"]) and set(plain) <= set(runs.task)
    assert all(TASKS[t].study_seeds for t in set(runs.task) - set(plain))
    assert sorted(set(runs[runs.task.isin(plain)].seed)) == list(range(TIERS["standard"])) and meta["tier"] == "standard"
    assert meta["seeds"] == sorted(set(runs.seed))
    assert meta["command"].startswith("saggriac bench --tier standard --rerun --write-shipped")
    assert set(meta["command"].split("--tasks ")[1].split()[0].split(",")) == set(plain)
    for task in plain:
        sub = runs[runs.task == task]
        takers = {n for n in available() if TeacherSpec(n).takes(TASKS[task].space)}
        assert takers <= set(sub.teacher), task
        assert (sub.groupby("teacher").seed.nunique() == TIERS["standard"]).all(), task
    assert len(curves) >= len(runs)


@pytest.mark.skipif(STANDARD is None or STANDARD[2]["version"] != _core.__version__, reason="the shipped results were made by another version")
@pytest.mark.parametrize("task, names", [("2d-reach", None), ("arm-episodic", ["random", "sagg_riac"])])
def test_the_shipped_standard_results_equal_a_rerun_on_this_version(task, names):
    runs = STANDARD[0]
    seed = 7  # a seed only the standard tier has
    names = names or [n for n in available() if TeacherSpec(n).takes(TASKS[task].space) and n in set(runs.teacher)]
    for name in names:
        row = run_one(Job(task, "standard", TeacherSpec(name), seed))["row"]
        ship = runs[(runs.task == task) & (runs.teacher == name) & (runs.seed == seed)].iloc[0]
        assert (row["area"], row["final"]) == (ship.area, ship.final), name


def test_a_rerun_says_whether_it_differs_and_which_versions_made_what():
    ship = pd.DataFrame([dict(task="2d", teacher="riac", seed=0, goals=10, area=0.5, final=0.9)])
    same = compare_with_shipped(ship.copy(), ship, {"version": "0.0.1"})
    assert same == ["Rerun: the 1 runs shipped for these teachers, tasks and seeds were recomputed and are the same numbers."]
    moved = ship.assign(area=0.25)
    (note,) = compare_with_shipped(moved, ship, {"version": "0.0.1"})
    assert note.startswith("Rerun: 1 of 1 shipped runs differ (riac; largest area change 0.25)") and f"made by saggriac 0.0.1, these by saggriac {_core.__version__}" in note


def test_the_guides_bench_numbers_are_the_shipped_results():
    """docs/choosing_a_teacher.md quotes the bench's shipped quick results for TSCL: each number
    as the leaderboard of the shipped runs gives it, so the two cannot drift apart."""
    from pathlib import Path

    from saggriac.bench.report import leaderboard

    # Compared with the lines' wrapping taken out.
    guide = " ".join((Path(__file__).resolve().parents[2] / "docs" / "choosing_a_teacher.md").read_text().split())
    board = leaderboard(SHIP[0]).set_index(["task", "teacher"])
    area = lambda task, teacher: board.loc[(task, teacher), "area"]  # noqa: E731
    sd = lambda task, teacher: board.loc[(task, teacher), "area_sd"]  # noqa: E731
    quoted = [
        f"`2d-cells` area {area('2d-cells', 'tscl'):.3f} ± {sd('2d-cells', 'tscl'):.3f} against PLR's {area('2d-cells', 'plr'):.3f} and random's {area('2d-cells', 'random'):.3f}",
        f"`niches-cells` area {area('niches-cells', 'tscl'):.3f} ± {sd('niches-cells', 'tscl'):.3f} against random's {area('niches-cells', 'random'):.3f} and discrete LP's {area('niches-cells', 'discrete_lp'):.3f}",
    ]
    missing = [q for q in quoted if q not in guide]
    assert not missing, missing


FULL = shipped.load("full")
REPO = __import__("pathlib").Path(__file__).resolve().parents[2]


def test_a_task_a_study_ran_takes_its_report_seeds_budget_and_scorings_in_the_full_tier():
    """The full tier reruns the registered studies: each study task's seeds, budget and points
    are its protocol's, and a task without a study keeps 0 .. N-1."""
    import json

    from saggriac.bench.tasks import tier_seeds

    from tests.benchmark_scripts import load

    checked = 0
    for protocol in sorted((REPO / "docs" / "figures" / "evidence").glob("*/protocol.json")):
        p = json.loads(protocol.read_text())
        for task, seeds in p["report"].items():
            a, _, b = seeds.partition("-")
            assert tier_seeds(task, "full") == list(range(int(a), int(b or a) + 1)), task
            assert TASKS[task].budgets["full"] == p["budget"][task] and TASKS[task].points == p["scorings"], task
            checked += 1
    rl = load("rl_curriculum")
    for reward, seeds in rl.REPORT_SEEDS.items():
        assert tier_seeds(f"rl-arm-{reward}", "full") == seeds and TASKS[f"rl-arm-{reward}"].budgets["full"] == rl.BUDGET
        assert TASKS[f"rl-arm-{reward}"].points == rl.SCORINGS
        checked += 1
    assert checked >= 6
    assert tier_seeds("2d", "full") == list(range(TIERS["full"]))


def test_the_tiers_are_nested_for_every_task():
    """Each tier's seeds begin the next one's: 0 .. N-1 for a task without a study, the study's
    first report seeds for one with (the standard tier of rl-arm-dense is 500-509)."""
    from saggriac.bench.tasks import in_tier, tier_seeds

    order = list(TIERS)
    for name in TASKS:
        tiers = [t for t in order if in_tier(name, t)]
        for small, big in zip(tiers, tiers[1:]):
            a, b = tier_seeds(name, small), tier_seeds(name, big)
            assert b[: len(a)] == a, (name, small, big)
        for t in tiers[:-1]:
            assert len(tier_seeds(name, t)) == TIERS[t], (name, t)
    assert tier_seeds("rl-arm-dense", "standard") == list(range(500, 510)) and tier_seeds("2d", "standard") == list(range(10))


STANDARD = shipped.load("standard")


@pytest.mark.skipif(STANDARD is None or FULL is None, reason="no standard or full tier ships")
def test_where_the_standard_budget_is_the_studys_its_built_in_rows_are_the_full_tiers_first_seeds():
    """SAC's standard budget is its study's (20,000 steps): the standard tier ships the study's
    rows of its first ten seeds, the same numbers as the full tier's; PPO's arm, whose standard
    budget is half the study's, ships none there."""
    key = ["task", "teacher", "seed"]
    for task in ("rl-arm-sac-dense", "rl-arm-sac-sparse"):
        std = STANDARD[0][STANDARD[0].task == task].sort_values(key).reset_index(drop=True)
        assert sorted(set(std.seed)) == list(TASKS[task].study_seeds[:10]) and len(set(std.teacher)) == 8
        full = FULL[0][(FULL[0].task == task) & FULL[0].seed.isin(set(std.seed))].sort_values(key).reset_index(drop=True)
        assert std[["teacher", "seed", "goals", "area", "final"]].equals(full[["teacher", "seed", "goals", "area", "final"]])
    assert not STANDARD[0].task.isin(["rl-arm-dense", "rl-arm-sparse"]).any()
    assert STANDARD[2]["command"].startswith("saggriac bench --tier standard") and "python benchmarks/ship_studies.py" in STANDARD[2]["command"]


def test_the_full_tier_ships_the_studies_rows_as_ship_studies_gives_them():
    assert FULL is not None, "python/saggriac/bench/results/full_* are missing: python benchmarks/ship_studies.py"
    runs, curves, meta = FULL
    assert meta["tier"] == "full" and meta["command"].startswith("python benchmarks/ship_studies.py")
    for task in ("rl-arm-dense", "rl-arm-sparse"):
        sub = runs[runs.task == task]
        assert sorted(set(sub.seed)) == list(TASKS[task].study_seeds) and (sub.goals == TASKS[task].budgets["full"]).all()
        assert "oracle" not in set(sub.teacher) and len(set(sub.teacher)) == 8
    from tests.benchmark_scripts import load

    assert load("ship_studies").main(["--check"]) == 0


@pytest.mark.skipif(FULL is None, reason="no full tier ships")
def test_a_bench_run_of_the_full_tier_is_the_studys_run():
    """rl-arm-dense, random, seed 500 (the deep-RL study's first dense seed), run by the bench's
    full tier and by the study's own script (its seed, budget and scorings): the same numbers, to
    the bit, on the machine running the test; the shipped row is the study's committed one.

    The committed row itself is not asserted: deep-RL runs are reproducible to the bit on one
    kind of CPU, not across kinds (PyTorch's MKL and oneDNN kernels follow the CPU's instruction
    set). On 2026-12-07 a machine with AVX-512 FP16 gave this run's final distance 0.5265 where the
    study's machine gave 0.5134, at the same commit, and 0.4895 with MKL and oneDNN held to AVX2."""
    pytest.importorskip("stable_baselines3", reason='the SB3 extra is not installed (pip install "saggriac[sb3]")')
    from tests.benchmark_scripts import load

    row = run_one(Job("rl-arm-dense", "full", TeacherSpec("random"), 500))
    study = load("rl_curriculum")
    budget = TASKS["rl-arm-dense"].budgets["full"]
    rows = study.one_run(("dense", "random", 500, budget, budget // study.SCORINGS, study.THRESHOLDS["dense"], "test"))
    assert [s for _, s in row["curve"]] == [-r["distance"] for r in rows[1:]]
    assert [t for t, _ in row["curve"]] == list(range(budget // study.SCORINGS, budget + 1, budget // study.SCORINGS))
    assert (row["row"]["goals"], budget, 500) == (study.BUDGET, study.BUDGET, study.REPORT_SEEDS["dense"][0])
    ship = FULL[0][(FULL[0].task == "rl-arm-dense") & (FULL[0].teacher == "random") & (FULL[0].seed == 500)].iloc[0]
    committed = pd.read_csv(REPO / "docs" / "figures" / "rl_curriculum" / "runs.csv")
    committed = committed[(committed.reward == "dense") & (committed.teacher == "random") & (committed.seed == 500)].iloc[0]
    assert -ship.final == committed.final_distance and ship.goals == committed.budget
    curve = FULL[1][(FULL[1].task == "rl-arm-dense") & (FULL[1].teacher == "random") & (FULL[1].seed == 500)]
    assert len(curve) == TASKS["rl-arm-dense"].points
